"""Ruckig: jerk-limited, time-synchronized moves from rest to rest between waypoints.

Each pair of consecutive waypoints is one Ruckig calculation (the community
edition plans no intermediate waypoints itself); the waypoint's dwell follows.
The profiles are evaluated on the time grid with numpy from Ruckig's own segment
data: equal to ``ruckig.Trajectory.at_time`` to rounding (tested to 1e-9) and
within the velocity, acceleration and jerk limits to rounding.
"""

from __future__ import annotations

import re
from functools import partial

import numpy as np
import ruckig

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot.model import Robot


def plan_ruckig(robot: Robot, motion: Motion, *,
                max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Plan the motion's waypoints as Ruckig moves and sample them every ``motion.dt``.

    Raises:
        InputError: The grid does not resolve a move or exceeds `max_samples`.
        PlanningError: Ruckig rejects a move.
    """
    dof = robot.dof
    v, a, j = motion.velocity_limit, motion.acceleration_limit, motion.jerk_limit
    if v is None or a is None or j is None:
        raise InputError("the ruckig planner needs velocity, acceleration and jerk limits",
                         path=motion.path, field="limits")
    moves = []
    for i in range(len(motion.waypoints) - 1):
        inp = ruckig.InputParameter(dof)
        inp.current_position = motion.waypoints[i].tolist()
        inp.target_position = motion.waypoints[i + 1].tolist()
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = v.tolist(), a.tolist(), j.tolist()
        traj = ruckig.Trajectory(dof)
        try:
            result = ruckig.Ruckig(dof).calculate(inp, traj)
        except ValueError as err:  # a result code the Python binding's enum lacks
            raise PlanningError(f"{motion.path}: ruckig failed on the move from waypoint[{i}] "
                                f"to waypoint[{i + 1}]: {_result_text(err)}") from err
        except (ruckig.RuckigError, RuntimeError) as err:
            reason = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
            raise PlanningError(f"{motion.path}: ruckig failed on the move from waypoint[{i}] "
                                f"to waypoint[{i + 1}]: {reason}") from err
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise PlanningError(f"{motion.path}: ruckig failed on the move from waypoint[{i}] "
                                f"to waypoint[{i + 1}] ({result.name})")
        moves.append(Move(i, i + 1, traj.duration, partial(sample_profiles, traj),
                          peak_accelerations(traj)))
    return assemble(motion, moves, max_samples=max_samples)


RESULT_CODES = {
    -1: "an unclassified error",
    -100: "an input Ruckig finds invalid",
    -101: "the move would last longer than Ruckig can plan (its numerical limit on a move's "
          "duration, about 7,600 s); raise limits.velocity, limits.acceleration or "
          "limits.jerk",
    -110: "the move's duration could not be calculated",
    -111: "the joints' moves could not be synchronised",
}
"""Ruckig's error results (its ``Result`` enum in C++), some missing from the Python enum."""


def _result_text(err: ValueError) -> str:
    """What a Ruckig result code the Python binding could not name means."""
    found = re.search(r"-?\d+", str(err))
    code = int(found.group()) if found else None
    return RESULT_CODES.get(code, f"result {code}") if code is not None else str(err)


def _integrate(t, p, v, a, j):
    """Ruckig's constant-jerk integration, elementwise [s, m or rad, ...]."""
    return (p + t * (v + t * (a / 2 + t * j / 6)), v + t * (a + t * j / 2), a + t * j)


def peak_accelerations(traj: ruckig.Trajectory) -> np.ndarray:
    """Each joint's largest |acceleration| over a one-section Ruckig trajectory, exact.

    Jerk is constant on every segment, so the acceleration is piecewise linear and its
    extremes are among the values at the segments' ends (the profile's, the brake's).

    Returns:
        Peak |acceleration| per joint [rad/s^2 or m/s^2], shape (dof,).
    """
    peaks = []
    for profile in traj.profiles[0]:
        values = [*profile.a, profile.af]
        if profile.brake.duration > 0.0:
            values += [*profile.brake.a]
        peaks.append(float(np.max(np.abs(values))))
    return np.array(peaks)


def sample_profiles(traj: ruckig.Trajectory, times: np.ndarray):
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
