"""Turn a motion into a trajectory sampled on a uniform time grid.

Three planners, chosen by the motion file, one module each:

- ``ruckig`` (`hdselect.motion.planning.ruckig`): jerk-limited, time-synchronized moves
  from rest to rest between consecutive waypoints, then each waypoint's dwell.
- ``toppra`` (`hdselect.motion.planning.toppra`): a time-optimal traversal of a spline
  through the waypoints, split where the arm dwells.
- ``samples`` (`hdselect.motion.planning.samples`): a logged trajectory.

Tool poses are solved for the robot's mounting first (`hdselect.motion.planning.solve`), a
straight line is checked at every planned sample (`hdselect.motion.planning.toolpath`),
and so is every move into or out of a pose for a singularity on the way
(`hdselect.motion.planning.crossings`).
Every planned trajectory is checked against the robot's position limits, mimic
followers' included. What the planner noticed (`Trajectory.notes`: a piece slowed down
beyond its tolerance) is logged as a warning of this package's logger.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES, check_max_samples
from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.followers import outside as follower_outside
from hdselect.motion.followers import outside_reason
from hdselect.motion.motionfile import ANGLE_UNITS, Motion
from hdselect.motion.motionfile import PLANNERS as PLANNER_NAMES
from hdselect.motion.planning.crossings import check_crossings
from hdselect.motion.planning.ruckig import plan_ruckig
from hdselect.motion.planning.samples import plan_samples
from hdselect.motion.planning.solve import solve_motion
from hdselect.motion.planning.toolpath import LineDeviation, plan_lines
from hdselect.motion.planning.toppra import plan_toppra
from hdselect.motion.planning.trajectory import Trajectory
from hdselect.robot.model import Robot

logger = logging.getLogger(__name__)

PLANNERS: dict[str, Callable[..., Trajectory]] = {
    "ruckig": plan_ruckig,
    "toppra": plan_toppra,
    "samples": plan_samples,
}
"""Planner functions by the name a motion file's ``planner`` key gives: each takes the robot,
the motion and a keyword ``max_samples``."""
if tuple(PLANNERS) != PLANNER_NAMES:
    raise RuntimeError(f"PLANNERS {tuple(PLANNERS)} differ from PLANNER_NAMES {PLANNER_NAMES}")

__all__ = ["PLANNERS", "Planned", "Trajectory", "check_within_limits", "plan", "plan_motion"]


@dataclass(frozen=True, eq=False)
class Planned:
    """A motion planned: the motion as solved for the robot, and its trajectory.

    Attributes:
        motion: The motion with its tool poses solved for the robot's mounting and its
            lines refined as planned (the motion itself when it has no tool poses).
        trajectory: The trajectory, sampled every ``motion.dt``.
        lines: For each straight line, the tool's deviation from it at every planned
            sample.
    """

    motion: Motion
    trajectory: Trajectory
    lines: tuple[LineDeviation, ...] = ()


def plan(robot: Robot, motion: Motion, *, max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Plan the motion for the robot and sample it on its time grid.

    The grid is checked before it is allocated (`hdselect.motion.planning.grid`): it must
    resolve every move and dwell, and have at most `max_samples` samples.

    Args:
        robot: The robot as the motion runs it (its payload matters to TOPPRA's
            torque limits).
        motion: A validated motion read for the robot's joints.
        max_samples: Most samples the trajectory may have.

    Returns:
        The trajectory, sampled every ``motion.dt`` [s]. Tool poses are solved for the
        robot's mounting on the way (`plan_motion` returns them too).

    Raises:
        InputError: The arguments are not a Robot and a Motion, the motion was read
            for other joints, a tool pose cannot be solved, a planned move into or out of
            a pose passes a singularity where the file does not allow it (field
            ``waypoint[i]``), or the grid is too coarse or too large (field ``dt``).
        PlanningError: The planner failed, the limits cannot be met, the trajectory
            leaves a joint's position limits, or strays from a straight line.
    """
    return plan_motion(robot, motion, max_samples=max_samples).trajectory


def plan_motion(robot: Robot, motion: Motion, *,
                max_samples: int = DEFAULT_MAX_SAMPLES) -> Planned:
    """Solve the motion's tool poses for the robot, plan it, and check its straight lines.

    Arguments, and what it raises, as `plan`.

    Returns:
        The solved motion, the trajectory and each line's deviation at the planned samples.
    """
    if not isinstance(robot, Robot):
        raise InputError(f"expected a Robot, got {type(robot).__name__}", field="robot")
    if not isinstance(motion, Motion):
        raise InputError(f"expected a Motion, got {type(motion).__name__}", field="motion")
    max_samples = check_max_samples(max_samples)
    motion = solve_motion(robot, motion)

    def planned(solved: Motion) -> Trajectory:
        trajectory = PLANNERS[solved.planner](robot, solved, max_samples=max_samples)
        check_within_limits(robot, solved, trajectory)
        return trajectory

    solved, trajectory, lines = plan_lines(robot, motion, planned)
    for note in trajectory.notes:
        logger.warning("%s: %s", motion.path, note)
    return Planned(check_crossings(robot, solved, trajectory), trajectory, lines)


def check_within_limits(robot: Robot, motion: Motion, trajectory: Trajectory, *,
                        what: str | None = None) -> None:
    """Refuse a trajectory that is not finite or leaves a joint's position limits (by > 1e-9).

    Mimic followers too: their positions follow from their leaders'.

    Args:
        robot: The robot (its position limits).
        motion: The motion it was planned from (its file, units and waypoints).
        trajectory: The trajectory.
        what: What made it, for the message (default: the motion's planner).

    Raises:
        PlanningError: A position, velocity or acceleration is not finite; or naming
            the joint, how far past which limit, when, and the waypoint to move.
    """
    for name in ("q", "qd", "qdd"):
        if not np.all(np.isfinite(getattr(trajectory, name))):
            raise PlanningError(f"{motion.path}: the {what or motion.planner} trajectory has a "
                                f"{name} that is not finite")
    q = trajectory.q
    outside = (q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)
    if outside.any():
        raise PlanningError(_outside_message(robot, motion, trajectory, outside,
                                             what or motion.planner))
    follower = follower_outside(robot, q)
    if follower is not None:
        name, k, position = follower
        reason = outside_reason(robot, name, position, ANGLE_UNITS[motion.angle_unit],
                                          motion.angle_unit)
        raise PlanningError(f"{motion.path}: the {what or motion.planner} trajectory: {reason} "
                            f"(t = {trajectory.t[k]:.4g} s)")


def _outside_message(robot: Robot, motion: Motion, trajectory: Trajectory,
                     outside: np.ndarray, what: str) -> str:
    """Where the first joint to leave its limits goes furthest, in the file's units, and why."""
    j = int(np.argwhere(outside)[0][1])
    name, q = robot.joint_names[j], trajectory.q[:, j]
    over = np.maximum(robot.lower[j] - q, q - robot.upper[j])
    k = int(np.argmax(over))
    side, limit = ("upper", robot.upper[j]) if q[k] > robot.upper[j] else ("lower", robot.lower[j])
    scale = ANGLE_UNITS[motion.angle_unit] if robot.revolute[j] else 1.0
    unit = motion.angle_unit if robot.revolute[j] else "m"
    text = (f"{motion.path}: the {what} trajectory takes joint '{name}' "
            f"{over[k] / scale:.3g} {unit} past its {side} limit {limit / scale:g} {unit} "
            f"(t = {trajectory.t[k]:.4g} s")
    if motion.planner == "samples" or not len(motion.waypoints):
        return text + "); correct the log, or give the robot file the range the log uses"
    near = int(np.argmin(np.linalg.norm(motion.waypoints - trajectory.q[k], axis=1)))
    at_limit = abs(motion.waypoints[near, j] - limit) <= 1e-9 + 1e-6 * abs(limit)
    return text + (f", near waypoint[{near}], which lies "
                   + ("on that limit" if at_limit else
                      f"{abs(motion.waypoints[near, j] - limit) / scale:.3g} {unit} inside it")
                   + f"); move waypoint[{near}].{name} at least {over[k] / scale:.3g} {unit} "
                   "further inside, or add a waypoint that keeps the path away from the limit")
