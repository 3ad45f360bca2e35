"""Turn a motion into a trajectory sampled on a uniform time grid.

Three planners, chosen by the motion file, one module each:

- ``ruckig`` (`hdselect.planning.ruckig`): jerk-limited, time-synchronized moves
  from rest to rest between consecutive waypoints, then each waypoint's dwell.
- ``toppra`` (`hdselect.planning.toppra`): a time-optimal traversal of a spline
  through the waypoints, split where the arm dwells.
- ``samples`` (`hdselect.planning.samples`): a logged trajectory.

Every planned trajectory is checked against the robot's position limits.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from hdselect.errors import PlanningError
from hdselect.motion import ANGLE_UNITS, Motion
from hdselect.motion import PLANNERS as PLANNER_NAMES
from hdselect.planning.ruckig import plan_ruckig
from hdselect.planning.samples import plan_samples
from hdselect.planning.toppra import plan_toppra
from hdselect.planning.trajectory import Trajectory
from hdselect.robot import Robot

PLANNERS: dict[str, Callable[[Robot, Motion], Trajectory]] = {
    "ruckig": plan_ruckig,
    "toppra": plan_toppra,
    "samples": plan_samples,
}
"""Planner functions by the name a motion file's ``planner`` key gives."""
assert tuple(PLANNERS) == PLANNER_NAMES

__all__ = ["PLANNERS", "Trajectory", "check_within_limits", "plan"]


def plan(robot: Robot, motion: Motion) -> Trajectory:
    """Plan the motion for the robot and sample it on its time grid.

    Args:
        robot: The robot as the motion runs it (its payload matters to TOPPRA's
            torque limits).
        motion: A validated motion read for the robot's joints.

    Returns:
        The trajectory, sampled every ``motion.dt`` [s].

    Raises:
        InputError: The motion was read for other joints.
        PlanningError: The planner failed, the limits cannot be met, or the
            trajectory leaves a joint's position limits.
    """
    motion.check_joints(robot)
    trajectory = PLANNERS[motion.planner](robot, motion)
    check_within_limits(robot, motion, trajectory)
    return trajectory


def check_within_limits(robot: Robot, motion: Motion, trajectory: Trajectory, *,
                        what: str | None = None) -> None:
    """Refuse a trajectory that leaves a joint's position limits (by more than 1e-9).

    Args:
        robot: The robot (its position limits).
        motion: The motion it was planned from (its file, units and waypoints).
        trajectory: The trajectory.
        what: What made it, for the message (default: the motion's planner).

    Raises:
        PlanningError: Naming the joint, how far past which limit, when, and the
            waypoint to move.
    """
    q = trajectory.q
    outside = (q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)
    if outside.any():
        raise PlanningError(_outside_message(robot, motion, trajectory, outside,
                                             what or motion.planner))


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
