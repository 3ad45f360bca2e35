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

from hdselect.bounds import DEFAULT_MAX_SAMPLES, check_max_samples
from hdselect.errors import InputError, PlanningError
from hdselect.motion import PLANNERS as PLANNER_NAMES
from hdselect.motion import Motion
from hdselect.planning.ruckig import plan_ruckig
from hdselect.planning.samples import plan_samples
from hdselect.planning.toppra import plan_toppra
from hdselect.planning.trajectory import Trajectory
from hdselect.robot import Robot

PLANNERS: dict[str, Callable[..., Trajectory]] = {
    "ruckig": plan_ruckig,
    "toppra": plan_toppra,
    "samples": plan_samples,
}
"""Planner functions by the name a motion file's ``planner`` key gives: each takes the robot,
the motion and a keyword ``max_samples``."""
assert tuple(PLANNERS) == PLANNER_NAMES

__all__ = ["PLANNERS", "Trajectory", "plan"]


def plan(robot: Robot, motion: Motion, *, max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Plan the motion for the robot and sample it on its time grid.

    The grid is checked before it is allocated (`hdselect.planning.grid`): it must
    resolve every move and dwell, and have at most `max_samples` samples.

    Args:
        robot: The robot as the motion runs it (its payload matters to TOPPRA's
            torque limits).
        motion: A validated motion read for the robot's joints.
        max_samples: Most samples the trajectory may have.

    Returns:
        The trajectory, sampled every ``motion.dt`` [s].

    Raises:
        InputError: The arguments are not a Robot and a Motion, the motion was read
            for other joints, or the grid is too coarse or too large (field ``dt``).
        PlanningError: The planner failed, the limits cannot be met, or the
            trajectory leaves a joint's position limits.
    """
    if not isinstance(robot, Robot):
        raise InputError(f"expected a Robot, got {type(robot).__name__}", field="robot")
    if not isinstance(motion, Motion):
        raise InputError(f"expected a Motion, got {type(motion).__name__}", field="motion")
    max_samples = check_max_samples(max_samples)
    motion.check_joints(robot)
    trajectory = PLANNERS[motion.planner](robot, motion, max_samples=max_samples)
    for name in ("q", "qd", "qdd"):
        if not np.all(np.isfinite(getattr(trajectory, name))):
            raise PlanningError(f"{motion.path}: the {motion.planner} trajectory has a "
                                f"{name} that is not finite")
    q = trajectory.q
    outside = (q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)
    if outside.any():
        k, j = np.argwhere(outside)[0]
        raise PlanningError(
            f"{motion.path}: the {motion.planner} trajectory leaves the limits of joint "
            f"'{robot.joint_names[j]}' [{robot.lower[j]:g}, {robot.upper[j]:g}] at "
            f"t = {trajectory.t[k]:g} s (q = {q[k, j]:g}); "
            + ("correct the log" if motion.planner == "samples" else "add or move waypoints"))
    return trajectory
