"""Straight lines checked where the trajectory is sampled, and refined until they hold.

After planning, the tool's pose at every planned sample along a line is compared with
the line (`hdselect.motion.planning.linefit.deviation`: the distance from the segment, the angle
from the slerp arc). Where a sample strays beyond the tolerance, the line gets an IK
sample in the middle of the step around it and the motion is planned again
(`MAX_REPLANS` times at most).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.errors import PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.linefit import deviation, fit_lines, refined
from hdselect.motion.planning.trajectory import Trajectory
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import Robot

MAX_REPLANS = 4
"""Plannings after the first one while a line strays at a planned sample [-]."""


@dataclass(frozen=True, eq=False)
class LineDeviation:
    """How far the planned tool strays from one straight line, sample by sample.

    Attributes:
        last: The waypoint the line ends at (it starts at the one before).
        index: The trajectory samples along the line, shape (n,).
        position: The tool origin's distance from the line's segment [m], shape (n,).
        orientation: The tool orientation's angle from the line's slerp arc [rad], (n,).
        fraction: The fraction of the line each sample is nearest [-], shape (n,).
    """

    last: int
    index: np.ndarray
    position: np.ndarray
    orientation: np.ndarray
    fraction: np.ndarray


def line_deviations(robot: Robot, motion: Motion,
                    trajectory: Trajectory) -> tuple[LineDeviation, ...]:
    """The tool's deviation from every line of a solved motion at the planned samples.

    A line's samples are those from when the arm leaves the waypoint before it (after
    its dwell) to when it reaches the line's own waypoint.
    """
    if not motion.lines or motion.solution is None or trajectory.waypoint_times is None:
        return ()
    kin = FrameKinematics(robot, motion.solution.frame)
    reached = trajectory.waypoint_times
    out = []
    for line in motion.lines:
        leave = reached[line.last - 1] + motion.dwells[line.last - 1]
        index = np.flatnonzero((trajectory.t >= leave - 1e-12)
                               & (trajectory.t <= reached[line.last] + 1e-12))
        position, orientation, fraction = deviation(
            line, [kin.placement(q) for q in trajectory.q[index]])
        out.append(LineDeviation(line.last, index, frozen(position), frozen(orientation),
                                 frozen(fraction)))
    return tuple(out)


def plan_lines(robot: Robot, motion: Motion, planner: Callable[[Motion], Trajectory]
               ) -> tuple[Motion, Trajectory, tuple[LineDeviation, ...]]:
    """Plan a solved motion and refine its lines until every planned sample is on them.

    Args:
        robot: The robot the motion was solved for.
        motion: The solved motion.
        planner: Plans a motion into a trajectory.

    Returns:
        The motion with its lines as planned, the trajectory, and each line's deviation.

    Raises:
        PlanningError: A line still strays after `MAX_REPLANS` refinements.
    """
    trajectory = planner(motion)
    if not motion.lines or motion.tool is None or motion.solution is None:
        return motion, trajectory, ()
    tolerance = motion.tool.tolerance
    kin = FrameKinematics(robot, motion.solution.frame)
    for _ in range(MAX_REPLANS + 1):
        deviations = line_deviations(robot, motion, trajectory)
        wanted: dict[int, list[float]] = {}
        lines = {line.last: line for line in motion.lines}
        for found in deviations:
            off = (found.position > tolerance.position) | (found.orientation
                                                          > tolerance.orientation)
            fractions = lines[found.last].fractions
            steps = np.unique(np.clip(np.searchsorted(fractions, found.fraction[off]) - 1, 0,
                                      len(fractions) - 2))
            if len(steps):
                wanted[found.last] = [0.5 * (fractions[k] + fractions[k + 1]) for k in steps]
        if not wanted:
            return motion, trajectory, deviations
        motion = fit_lines(kin, refined(kin, motion, wanted, tolerance), tolerance)
        trajectory = planner(motion)
    worst = max(deviations, key=lambda d: float(d.position.max(initial=0.0)))
    raise PlanningError(f"{motion.path}: the planned path strays up to "
                        f"{worst.position.max() * 1e3:.3g} mm from the straight line to "
                        f"waypoint[{worst.last}] after {MAX_REPLANS} refinements")
