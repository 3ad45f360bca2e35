"""Singularities on the planned path of a tool-pose motion, refused as a change of branch is.

The solved waypoints are checked for a change of branch on the straight joint move between
them (`hdselect.ik.branches.check_branch`); the planner follows another path: TOPPRA
a spline through the waypoints and the lines' samples, which swings past their joints,
Ruckig jerk-limited moves. `check_crossings` follows the planned samples of every move
into or out of a tool pose (`hdselect.ik.branches.path_crossing`): a move that passes
a singularity swings the arm through it, or changes its branch and back, which the task
as written does not ask for. It is an error naming the move, unless the waypoint the
move ends at says ``reconfigure = true``; then it is a note.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from hdselect.base.errors import InputError
from hdselect.ik.branches import SINGULAR, SINGULARITY_NAMES, check_branch, path_crossing
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.trajectory import Trajectory
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import Robot

logger = logging.getLogger(__name__)


def check_crossings(robot: Robot, motion: Motion, trajectory: Trajectory) -> Motion:
    """Refuse a planned move into or out of a tool pose that passes a singularity.

    Args:
        robot: The robot the motion was solved for.
        motion: The solved motion (a motion without tool poses is not checked).
        trajectory: Its planned trajectory.

    Returns:
        The motion, with a note for each crossing that ``reconfigure`` allows.

    Raises:
        InputError: A move passes a singularity; field ``waypoint[i]``, i the waypoint the
            move ends at.
    """
    tool, reached = motion.tool, trajectory.waypoint_times
    if tool is None or motion.solution is None or reached is None:
        return motion
    kin = FrameKinematics(robot, motion.solution.frame)
    notes = []
    for i in range(1, len(motion.waypoints)):
        if tool.at(i) is None and tool.at(i - 1) is None:
            continue  # joints to joints: as the file gives them
        leave = reached[i - 1] + motion.dwells[i - 1]
        inside = np.flatnonzero((trajectory.t > leave) & (trajectory.t < reached[i]))
        path = np.vstack([motion.waypoints[i - 1], trajectory.q[inside], motion.waypoints[i]])
        found = path_crossing(kin, path)
        if found is None:
            continue
        t = float(np.interp(found.position, np.arange(len(path)),
                            np.r_[leave, trajectory.t[inside], reached[i]]))
        changed = [n for n in found.changed if n != "det"]
        why = (f"scaled smallest singular value {found.sigma:.2g}"
               + (f" < {SINGULAR:g}" if found.sigma < SINGULAR else "")
               + (f"; the {', '.join(changed)} indicator{'s' if len(changed) > 1 else ''} "
                  "changes sign" if changed else ""))
        what = (f"the planned path from waypoint[{i - 1}] to waypoint[{i}] passes "
                f"{SINGULARITY_NAMES[found.kind]} at t = {t:.4g} s ({why})")
        if i in tool.reconfigure:
            if not any(f"allowed by waypoint[{i}].reconfigure" in w for w in motion.warnings):
                notes.append(f"{what}; allowed by waypoint[{i}].reconfigure")
            continue
        raise InputError(f"{what}; {_advice(kin, motion, i)}, or allow it with "
                         "reconfigure = true", path=motion.path, field=f"waypoint[{i}]")
    for note in notes:
        logger.warning("%s: %s", motion.path, note)
    return replace(motion, warnings=motion.warnings + tuple(notes)) if notes else motion


def _advice(kin: FrameKinematics, motion: Motion, i: int) -> str:
    """What keeps the move into waypoint `i` away from the singularity it passes."""
    if motion.tool is None:
        raise RuntimeError("a singularity advice for a motion without tool poses")
    if i in motion.tool.lines:
        return "move the line away from it, or drop line = true"
    last = len(motion.waypoints) - 1
    if all(k in (0, last) or motion.dwells[k] > 0.0 for k in (i - 1, i)):
        # between two rests the planned path is the straight joint move itself
        return "move the poses, or add a waypoint between them that keeps the arm away from it"
    straight = check_branch(kin, motion.waypoints[i - 1], motion.waypoints[i])
    if motion.planner == "toppra" and not straight.flipped:
        return ("the straight move between the two waypoints' joints stays clear of it: the "
                "planner's spline swings past them; add a waypoint between them that keeps "
                f"the arm away, or dwell at waypoint[{i - 1}] and waypoint[{i}] (the move "
                "between two rests runs straight in joint space)")
    return "move the poses, or add a waypoint between them that keeps the arm away from it"
