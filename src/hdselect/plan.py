"""Turn a motion into a trajectory sampled on a uniform time grid.

Three planners, chosen by the motion file:

- ``ruckig``: jerk-limited, time-synchronized point-to-point moves between
  consecutive waypoints, each from rest to rest, then the waypoint's dwell. The
  profiles are evaluated on the grid with numpy from Ruckig's own segment data;
  this equals ``ruckig.Trajectory.at_time`` to rounding (tested to 1e-9) and
  respects the velocity, acceleration and jerk limits to rounding.
- ``toppra``: a time-optimal traversal of a clamped cubic spline through the
  waypoints (chord-length parametrised), 200 cosine-spaced TOPPRA gridpoints per
  spline segment. A waypoint with a dwell splits the path into pieces that each
  start and end at rest. TOPPRA's constant-acceleration parametrisation overshoots
  the limits between gridpoints (measured up to 2.5e-3 relative); each piece is
  therefore slowed down uniformly by its overshoot (plus 1e-4), which keeps the
  sampled velocity and acceleration within ``TOPPRA_TOLERANCE`` of the limits
  (measured: never above them on 30 random 6-DOF paths) for a cycle at most that
  much longer than TOPPRA's. Torque limits hold within ``TOPPRA_TORQUE_TOLERANCE``
  (measured up to 6e-5 relative).
- ``samples``: a logged trajectory (see `_plan_samples`).

Grid: t_k = k dt for k = 0..ceil(T/dt), T the cycle time; samples past T hold
the final state at rest.
"""

from __future__ import annotations

import logging
import math
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import ruckig

from hdselect.errors import PlanningError
from hdselect.motion import Motion

TOPPRA_TOLERANCE = 1e-6
"""Relative amount by which a TOPPRA trajectory may exceed its velocity and
acceleration limits [-]."""

TOPPRA_TORQUE_TOLERANCE = 1e-3
"""Relative amount by which a TOPPRA trajectory may exceed its torque limits [-]."""

_GRID_PER_SEGMENT = 200
"""TOPPRA gridpoints per spline segment (cosine-spaced, dense near the rest ends)."""

_DENSE_CHECK = 10
"""Check points per TOPPRA gridpoint when measuring its overshoot."""

_MARGIN = 1e-4
"""Extra time scaling of a TOPPRA piece for peaks between the check points [-]."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A joint trajectory sampled at t_k = k dt.

    Attributes:
        joint_names: Name of every degree of freedom, in the columns' order.
        dt: Sample period [s].
        duration: Cycle time T [s]; samples after it are at rest.
        t: Sample times [s], shape (n,).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
    """

    joint_names: tuple[str, ...]
    dt: float
    duration: float
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


def plan(motion: Motion) -> Trajectory:
    """Plan the motion and sample it on its time grid.

    Args:
        motion: A validated motion.

    Returns:
        The trajectory, sampled every ``motion.dt`` [s].

    Raises:
        PlanningError: The planner failed, the limits cannot be met (TOPPRA names the
            constraint set at fault), or the path leaves a joint's position limits.
    """
    if motion.planner == "samples":
        return _plan_samples(motion)
    if motion.planner == "ruckig":
        pieces = _ruckig_moves(motion)
    else:
        pieces = _toppra_pieces(motion)
    wp, dwells = motion.waypoints, motion.dwells
    starts, ends, rest = [], [], [wp[0]]
    clock = dwells[0]
    for _, last, duration, _ in pieces:
        starts.append(clock)
        ends.append(clock + duration)
        rest.append(wp[last])
        clock += duration + dwells[last]
    t = np.arange(math.ceil(clock / motion.dt - 1e-9) + 1) * motion.dt
    q = np.asarray(rest)[np.searchsorted(ends, t, side="right")]
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    for (_, _, _, sample), start, end in zip(pieces, starts, ends, strict=True):
        k0, k1 = np.searchsorted(t, [start, end], side="left")
        if k1 > k0:
            q[k0:k1], qd[k0:k1], qdd[k0:k1] = sample(t[k0:k1] - start)
    robot = motion.robot
    outside = (q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)
    if outside.any():
        k, j = np.argwhere(outside)[0]
        raise PlanningError(
            f"{motion.path}: the {motion.planner} path leaves the limits of joint "
            f"'{robot.joint_names[j]}' [{robot.lower[j]:g}, {robot.upper[j]:g}] at t = {t[k]:g} s "
            f"(q = {q[k, j]:g}); add or move waypoints")
    return _trajectory(motion, clock, t, q, qd, qdd)


def _trajectory(motion: Motion, duration: float, t, q, qd, qdd) -> Trajectory:
    for array in (t, q, qd, qdd):
        array.setflags(write=False)
    return Trajectory(motion.robot.joint_names, motion.dt, float(duration), t, q, qd, qdd)


def _ruckig_moves(motion: Motion):
    """One rest-to-rest Ruckig move per pair of waypoints: (first, last, duration, sampler)."""
    dof = motion.robot.dof
    v, a, j = motion.velocity_limit, motion.acceleration_limit, motion.jerk_limit
    assert v is not None and a is not None and j is not None  # load_motion requires them
    moves = []
    for i in range(len(motion.waypoints) - 1):
        inp = ruckig.InputParameter(dof)
        inp.current_position = motion.waypoints[i].tolist()
        inp.target_position = motion.waypoints[i + 1].tolist()
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = v.tolist(), a.tolist(), j.tolist()
        traj = ruckig.Trajectory(dof)
        try:
            result = ruckig.Ruckig(dof).calculate(inp, traj)
        except (ruckig.RuckigError, RuntimeError) as err:
            reason = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
            raise PlanningError(f"{motion.path}: ruckig failed on the move from waypoint[{i}] "
                                f"to waypoint[{i + 1}]: {reason}") from err
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise PlanningError(f"{motion.path}: ruckig failed on the move from waypoint[{i}] "
                                f"to waypoint[{i + 1}] ({result.name})")
        moves.append((i, i + 1, traj.duration, lambda times, tr=traj: _sample_profiles(tr, times)))
    return moves


def _integrate(t, p, v, a, j):
    """Ruckig's constant-jerk integration, elementwise [s, m or rad, ...]."""
    return (p + t * (v + t * (a / 2 + t * j / 6)), v + t * (a + t * j / 2), a + t * j)


def _sample_profiles(traj: ruckig.Trajectory, times: np.ndarray):
    """Evaluate a one-section Ruckig trajectory at many times, vectorised.

    Mirrors ``Trajectory.at_time``: the brake pre-trajectory (two constant-jerk
    segments), then the seven segments of the profile, then constant acceleration.

    Args:
        traj: A calculated Ruckig trajectory without intermediate waypoints.
        times: Times from the start of the trajectory [s], shape (n,).

    Returns:
        Positions, velocities and accelerations, each of shape (n, dof).
    """
    times = np.asarray(times, dtype=float)
    out = np.empty((3, times.size, traj.degrees_of_freedom))
    for dof, profile in enumerate(traj.profiles[0]):
        brake = profile.brake
        local = times - brake.duration
        tsum = np.cumsum(profile.t)
        index = np.searchsorted(tsum, local, side="right")
        start = np.concatenate(([0.0], tsum))[index]
        p, v, a = (np.asarray(x)[index] for x in (profile.p, profile.v, profile.a))
        columns = _integrate(local - start, p, v, a, np.append(profile.j, 0.0)[index])
        if brake.duration > 0.0:
            in_brake = times < brake.duration
            second = times >= brake.t[0]
            p, v, a, j = (np.where(second, x[1], x[0]) for x in (brake.p, brake.v, brake.a,
                                                                 brake.j))
            braking = _integrate(times - np.where(second, brake.t[0], 0.0), p, v, a, j)
            columns = [np.where(in_brake, x, y) for x, y in zip(braking, columns, strict=True)]
        out[:, :, dof] = columns
    return out[0], out[1], out[2]


def _sample_at_time(traj: ruckig.Trajectory, times: np.ndarray):
    """Reference for `_sample_profiles`: one ``at_time`` call per sample (slow)."""
    states = [traj.at_time(float(time)) for time in np.asarray(times, dtype=float)]
    shape = (len(states), traj.degrees_of_freedom)
    return tuple(np.array([s[i] for s in states]).reshape(shape) for i in range(3))


@contextmanager
def _quiet() -> Iterator[None]:
    """Silence TOPPRA's log records and numerical warnings."""
    log = logging.getLogger("toppra")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        log.setLevel(level)


def _toppra_pieces(motion: Motion):
    """Time-optimal pieces of the spline path, split at waypoints with a dwell."""
    with _quiet():
        import toppra
        import toppra.algorithm as algorithm
        import toppra.constraint as constraint
    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    assert velocity is not None and acceleration is not None  # load_motion requires them
    interpolation = constraint.DiscretizationType.Interpolation
    kinematic = [
        constraint.JointVelocityConstraint(np.column_stack([-velocity, velocity])),
        constraint.JointAccelerationConstraint(np.column_stack([-acceleration, acceleration]),
                                               discretization_scheme=interpolation),
    ]
    dynamic = []
    if motion.torque_limit is not None:
        dynamic.append(constraint.JointTorqueConstraint(
            _inverse_dynamics(motion), np.column_stack([-motion.torque_limit,
                                                        motion.torque_limit]),
            np.zeros(motion.robot.dof), discretization_scheme=interpolation))
    splits = [0, *np.flatnonzero(motion.dwells[1:-1] > 0.0) + 1, len(motion.waypoints) - 1]
    pieces = []
    for first, last in zip(splits[:-1], splits[1:], strict=True):
        points = motion.waypoints[first:last + 1]
        keep = np.r_[True, np.any(np.diff(points, axis=0) != 0.0, axis=1)]
        points = points[keep]
        if len(points) < 2:
            pieces.append((first, last, 0.0, None))
            continue
        chord = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))]
        grid = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, _GRID_PER_SEGMENT * len(points) + 1))
        with _quiet():
            path = toppra.SplineInterpolator(chord / chord[-1], points, bc_type="clamped")
            found = _toppra_solve(algorithm, kinematic + dynamic, path, grid, motion, first, last)
            if found is None and dynamic:
                if _toppra_solve(algorithm, kinematic, path, grid, motion, first,
                                 last) is not None:
                    raise PlanningError(
                        f"{motion.path}: toppra: the torque limits (limits.torque) make the path "
                        f"from waypoint[{first}] to waypoint[{last}] infeasible; it is feasible "
                        "with the velocity and acceleration limits alone")
        if found is None:
            raise PlanningError(
                f"{motion.path}: toppra: the velocity and acceleration limits (limits.velocity, "
                f"limits.acceleration) make the path from waypoint[{first}] to "
                f"waypoint[{last}] infeasible")
        pieces.append((first, last, *_toppra_sampler(found, motion, len(grid))))
    return pieces


def _toppra_solve(algorithm, constraints, path, grid, motion, first, last):
    try:
        instance = algorithm.TOPPRA(constraints, path, parametrizer="ParametrizeConstAccel",
                                    gridpoints=grid)
        return instance.compute_trajectory()
    except Exception as err:  # toppra raises assorted solver errors
        raise PlanningError(f"{motion.path}: toppra failed on the path from waypoint[{first}] "
                            f"to waypoint[{last}]: {err}") from err


def _toppra_sampler(found, motion: Motion, gridpoints: int):
    """Duration [s] and sampler of a TOPPRA piece, slowed down uniformly by its overshoot.

    TOPPRA's constant-acceleration parametrisation exceeds the limits slightly
    between gridpoints; the overshoot found on a dense time grid sets a time scale
    r >= 1 (q(t / r)), which brings velocity and acceleration back within the limits.
    """
    with _quiet():
        dense = np.linspace(0.0, found.duration, _DENSE_CHECK * gridpoints + 1)
        speed = np.max(np.abs(found(dense, 1)) / motion.velocity_limit)
        accel = np.max(np.abs(found(dense, 2)) / motion.acceleration_limit)
    scale = max(1.0, float(speed), math.sqrt(accel)) * (1.0 + _MARGIN)

    def sample(times: np.ndarray):
        with _quiet():
            s = times / scale
            return found(s), found(s, 1) / scale, found(s, 2) / scale**2
    return float(found.duration) * scale, sample


def _inverse_dynamics(motion: Motion):
    """Joint torques of the robot for one state, as TOPPRA's torque constraint wants [N m]."""
    import pinocchio as pin

    robot = motion.robot
    data = robot.model.createData()

    def inverse_dynamics(q, qd, qdd):
        config = robot.configuration(np.asarray(q)[None, :])[:, 0]
        return pin.rnea(robot.model, data, config, np.asarray(qd, float), np.asarray(qdd, float))
    return inverse_dynamics


def _plan_samples(motion: Motion) -> Trajectory:
    """Put a logged trajectory on the dt grid.

    Time is shifted to start at 0. When the log is uniformly spaced (within 1e-6
    relative) at the motion's dt, its samples are used as they are; otherwise
    positions (and logged velocities, accelerations) are resampled onto the grid
    with a not-a-knot cubic spline (``scipy.interpolate.CubicSpline``). Velocities
    and accelerations that were not logged are the first and second derivatives
    of the cubic spline through the positions (accelerations from the spline
    through logged velocities when those exist). Differentiation amplifies
    measurement noise: filter the log first.
    """
    from scipy.interpolate import CubicSpline

    log = motion.samples
    assert log is not None  # load_motion reads it for the samples planner
    t = log.t - log.t[0]
    if np.all(np.abs(np.diff(t) - motion.dt) <= 1e-6 * motion.dt):
        uniform, grid, at = True, np.arange(len(t)) * motion.dt, t
        duration, inside = float(grid[-1]), np.ones(len(t), dtype=bool)
    else:
        duration = float(t[-1])
        uniform, grid = False, np.arange(math.ceil(duration / motion.dt - 1e-9) + 1) * motion.dt
        at, inside = np.minimum(grid, duration), grid <= duration

    def resample(values, order=0):
        if uniform and order == 0:
            return np.array(values)
        result = CubicSpline(t, values, axis=0)(at, order)
        result[~inside] = values[-1] if order == 0 else 0.0
        return result

    q = resample(log.q)
    qd = resample(log.q, 1) if log.qd is None else resample(log.qd)
    if log.qdd is not None:
        qdd = resample(log.qdd)
    else:
        qdd = resample(log.q if log.qd is None else log.qd, 2 if log.qd is None else 1)
    return _trajectory(motion, duration, grid, q, qd, qdd)
