"""TOPPRA: a time-optimal traversal of a spline path through the waypoints.

The path is a clamped cubic spline through the waypoints (chord-length
parametrised), with 200 cosine-spaced TOPPRA gridpoints per spline segment. A
waypoint with a dwell splits the path into pieces that each start and end at
rest. A cubic spline overshoots its waypoints: where that would take a joint
past its position limit (a waypoint on or near the limit, such as a home pose
on a stop), that joint alone follows a shape-preserving cubic instead (PCHIP
slopes, zero at the ends), which never leaves the range of its neighbouring
waypoints. TOPPRA's constant-acceleration parametrisation overshoots the limits
between gridpoints (measured up to 2.5e-3 relative); each piece is therefore
slowed down uniformly by its overshoot (plus 1e-4), which keeps the sampled
velocity and acceleration within ``TOPPRA_TOLERANCE`` of the limits (measured:
never above them on 30 random 6-DOF paths) for a cycle at most that much longer
than TOPPRA's. Torque limits hold within ``TOPPRA_TORQUE_TOLERANCE`` (measured up
to 6e-5 relative).
"""

from __future__ import annotations

import logging
import math
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

from hdselect.bounds import DEFAULT_MAX_SAMPLES
from hdselect.dynamics import rnea_function
from hdselect.errors import PlanningError
from hdselect.motion import Motion
from hdselect.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot import Robot

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


def plan_toppra(robot: Robot, motion: Motion, *,
                max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Plan the motion's path time-optimally and sample it every ``motion.dt``.

    Raises:
        InputError: The grid does not resolve a path piece or exceeds `max_samples`.
        PlanningError: The limits make a piece of the path infeasible (the message
            names the constraint set at fault) or TOPPRA fails.
    """
    return assemble(motion, _toppra_pieces(robot, motion), max_samples=max_samples)


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


def _toppra_pieces(robot: Robot, motion: Motion) -> list[Move]:
    """Time-optimal pieces of the spline path, split at waypoints with a dwell."""
    with _quiet():
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
            rnea_function(robot), np.column_stack([-motion.torque_limit,
                                                        motion.torque_limit]),
            np.zeros(robot.dof), discretization_scheme=interpolation))
    splits = [0, *np.flatnonzero(motion.dwells[1:-1] > 0.0) + 1, len(motion.waypoints) - 1]
    pieces: list[Move] = []
    for first, last in zip(splits[:-1], splits[1:], strict=True):
        points = motion.waypoints[first:last + 1]
        keep = np.r_[True, np.any(np.diff(points, axis=0) != 0.0, axis=1)]
        points = points[keep]
        if len(points) < 2:
            pieces.append(Move(first, last, 0.0, None))
            continue
        chord = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))]
        grid = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, _GRID_PER_SEGMENT * len(points) + 1))
        with _quiet():
            try:
                path = _Path(chord / chord[-1], points, robot.lower, robot.upper)
            except (ValueError, ArithmeticError) as err:
                raise PlanningError(f"{motion.path}: toppra: no spline through waypoint[{first}]"
                                    f" to waypoint[{last}]: {err}") from err
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
        try:
            pieces.append(Move(first, last, *_toppra_sampler(found, motion, len(grid))))
        except (ValueError, ArithmeticError) as err:
            raise PlanningError(f"{motion.path}: toppra: the path from waypoint[{first}] to "
                                f"waypoint[{last}] cannot be timed with these limits "
                                f"({type(err).__name__}: {err})") from err
    return pieces


class _Path:
    """A geometric path through waypoints, as TOPPRA evaluates it: q(s) and its derivatives.

    Each joint follows the clamped cubic spline through its waypoints unless that
    spline leaves the joint's position limits; then it follows a monotone piecewise
    cubic (PCHIP's slopes inside, zero slope at both ends), which stays between
    neighbouring waypoints.

    Args:
        ss: Path parameter at each waypoint, increasing from 0 to 1 [-].
        points: Waypoints [rad or m], shape (k, dof).
        lower: Lower position limits [rad or m], shape (dof,).
        upper: Upper position limits [rad or m], shape (dof,).
    """

    def __init__(self, ss: np.ndarray, points: np.ndarray, lower: np.ndarray,
                 upper: np.ndarray):
        from scipy.interpolate import CubicHermiteSpline, CubicSpline, PchipInterpolator

        spline = CubicSpline(ss, points, bc_type="clamped")
        dense = spline(np.linspace(ss[0], ss[-1], _GRID_PER_SEGMENT * len(ss) + 1))
        leaves = np.any((dense < lower - 1e-12) | (dense > upper + 1e-12), axis=0)
        self.shape_preserving = tuple(int(j) for j in np.flatnonzero(leaves))
        if self.shape_preserving:
            slopes = PchipInterpolator(ss, points, axis=0).derivative()(ss)
            slopes[[0, -1]] = 0.0
            monotone = CubicHermiteSpline(ss, points, slopes, axis=0)
            spline.c[:, :, leaves] = monotone.c[:, :, leaves]
        self._splines = (spline, spline.derivative(), spline.derivative(2))
        self._ss, self._points = ss, points

    def __call__(self, path_positions, order: int = 0):
        """Positions (order 0) or their first or second derivative along the path."""
        return self._splines[order](path_positions)

    def eval(self, ss):  # noqa: D102  (TOPPRA's path interface)
        return self(ss, 0)

    def evald(self, ss):  # noqa: D102
        return self(ss, 1)

    def evaldd(self, ss):  # noqa: D102
        return self(ss, 2)

    @property
    def dof(self) -> int:
        """Degrees of freedom."""
        return int(self._points.shape[1])

    @property
    def path_interval(self) -> np.ndarray:
        """First and last path parameter."""
        return np.array([self._ss[0], self._ss[-1]])

    @property
    def waypoints(self):
        """Path parameters and positions of the waypoints."""
        return self._ss, self._points


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
