"""Terminal tables of a robot and a planned motion: the joints, what a plan did."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np
from rich.markup import escape

from hdselect.motion.logderivatives import peak_uncertainty
from hdselect.motion.motionfile import ANGLE_UNITS, Motion
from hdselect.motion.planning import Trajectory
from hdselect.motion.planning.toolpath import LineDeviation
from hdselect.motion.toolposes import free_note
from hdselect.report.tables import Column, FittedTable, Paragraphs
from hdselect.report.terminal import DEG_PER_RAD
from hdselect.robot.joints import JointInfo
from hdselect.robot.model import Robot
from hdselect.robot.mounting import mounting_name
from hdselect.sizing.records import HOLD_NOTE


def joints_table(robot: Robot, infos: Iterable[JointInfo]) -> FittedTable:
    """A robot's joints in list order: type, limits, the file's speed and effort, mass moved.

    On a narrow terminal the ranges, then the file's limits, then the mass moved go below.
    """
    columns = (Column("joint", "left"), Column("#"), Column("type", "left"),
               Column("sized", "left"), Column("range\nrad or m", group="range"),
               Column("range\ndeg", group="range"),
               Column("max speed\ndeg/s, m/s", group="limits"),
               Column("effort\nN m, N", group="limits"), Column("moves\nkg", group="moves"))
    rows, notes = [], []
    for info in infos:
        linear = info.kind == "prismatic" or (info.kind == "mimic"
                                              and not robot.mimic[info.name].revolute)
        limited = math.isfinite(info.lower) and math.isfinite(info.upper)
        span = f"{info.lower:.3g} .. {info.upper:.3g}" if limited else "none"
        degrees = (f"{info.lower * DEG_PER_RAD:.3g} .. {info.upper * DEG_PER_RAD:.3g}"
                   if limited and not linear else "-")
        if info.leader is not None:
            offset = f" {info.offset:+g}" if info.offset else ""
            notes.append(f"{info.name} follows {info.leader} (x {info.multiplier:g}{offset}): no "
                         "gearhead of its own; its leader carries its load; its range holds "
                         "along the motion")
            rows.append((escape(info.name), "-", "mimic", "no", span, degrees, "-", "-",
                         f"{info.moved_mass:.3g}"))
            continue
        speed = info.velocity_limit * (1.0 if linear else DEG_PER_RAD)
        rows.append((
            escape(info.name), str(info.index), info.kind, "yes" if info.sized else "no", span,
            degrees, f"{speed:.3g}" if math.isfinite(speed) else "-",
            f"{info.effort_limit:.3g}" if math.isfinite(info.effort_limit) else "-",
            f"{info.moved_mass:.3g}"))
        if not info.sized:
            notes.append(f"{info.name}: not sized: " + (
                "the catalog is rotary" if linear else
                "a mimic follower Pinocchio could not couple" if info.name in
                robot.uncoupled_followers else "not among the joints asked for" if
                info.name in robot.payload_chain else "excluded"))
    notes.append(f"base: '{robot.root_link}' held fixed; a payload goes on "
                 f"'{robot.default_payload_frame}' unless its frame is given; moves: the mass a "
                 "joint moves, links further out included")
    if robot.file_order is not None and robot.file_order != robot.joint_names:
        notes.append(f"the robot file writes the joints in another order "
                     f"({', '.join(robot.file_order)}): lists follow # above")
    notes += [f"robot file: {note}" for note in robot.notes]
    return FittedTable(f"{robot.path.name}: {robot.dof} joints; # is the position in a motion "
                       "file's lists (q = [...]); tables keyed by name need no order", columns,
                       tuple(rows), notes=tuple(notes))


def plan_text(robot: Robot, motion: Motion, trajectory: Trajectory,
              lines: Iterable[LineDeviation] = ()) -> Paragraphs:
    """What ``hdselect plan`` planned, and what a reader must know about it."""
    count = len(trajectory.t)
    return Paragraphs((f"{robot.path.name} running {motion.path.name} ({motion.planner}): cycle "
                       f"{trajectory.duration:.3f} s, {count:,} sample{'s' if count != 1 else ''}"
                       + refined_note(motion.dt, trajectory.dt),
                       *tool_pose_notes(motion, lines), *case_notes(robot, trajectory),
                       *derived_notes(trajectory)))


def derived_notes(trajectory: Trajectory) -> list[str]:
    """Where accelerations derived from a log's positions are not known to 1 %, a note."""
    if trajectory.qdd_uncertainty is None:
        return []
    shares = [(name, peak_uncertainty(trajectory.qdd[:, j], trajectory.qdd_uncertainty[:, j])
               / peak) for j, name in enumerate(trajectory.joint_names)
              if (peak := float(np.abs(trajectory.qdd[:, j]).max(initial=0.0))) > 0.0]
    uncertain = [f"{share:.1%} for '{name}'" for name, share in shares if share > 0.01]
    if not uncertain:
        return []
    return ["the log gives positions only, and the peak accelerations derived from them are "
            f"uncertain by up to {', '.join(uncertain)} (hdselect size states what that does to "
            "each peak torque); log the qd_ and qdd_ columns too (or sample faster)"]


def refined_note(asked: float, sampled: float) -> str:
    """Where the file's dt [s] was refined to `sampled` [s], a clause saying so; else empty."""
    if sampled >= asked * (1.0 - 1e-12):
        return ""
    return (f" every {sampled:.3g} s (the file's dt {asked:g} s, refined so that the samples "
            "resolve every move)")


def case_notes(robot: Robot, trajectory: Trajectory | Sequence[Trajectory]) -> list[str]:
    """What a reader must know about the case before trusting a result.

    The joints not sized, mimic followers, a payload frame chosen by default,
    joints that never move, and a motion that moves no joint at all (a hold).

    Args:
        robot: The robot as planned and sized.
        trajectory: Its trajectory, or every task's (a duty of several tasks: a joint is
            still only when it moves in none).

    Returns:
        One sentence per fact; empty when there is nothing to say.
    """
    notes = []
    skipped = [(name, revolute) for name, revolute in zip(robot.joint_names, robot.revolute,
                                                          strict=True)
               if name not in robot.sized_joints]
    prismatic = [name for name, revolute in skipped if not revolute]
    uncoupled = [name for name, revolute in skipped
                 if revolute and name in robot.uncoupled_followers]
    left_out = [name for name, revolute in skipped
                if revolute and name not in robot.uncoupled_followers]
    if prismatic:
        notes.append(f"not sized: {', '.join(prismatic)} (prismatic; these gearheads are "
                     f"rotary). The dynamics include {_it(prismatic)}.")
    if left_out:
        notes.append(f"not sized: {', '.join(left_out)} (not among the joints asked for, or "
                     f"excluded). The dynamics include {_it(left_out)}.")
    if uncoupled:
        notes.append(f"not sized: {', '.join(uncoupled)} (mimic followers Pinocchio could not "
                     "couple to their leaders: each moves on its own here).")
    notes += [f"{name} follows {mimic.leader} (mimic): no gearhead of its own; {mimic.leader} "
              "carries its load." for name, mimic in robot.mimic.items()]
    payload = robot.payload
    if payload is not None and payload.frame is None:
        notes.append(f"payload: {payload.mass:g} kg on {robot.payload_frame}, the tip of the "
                     "longest chain of joints not excluded, since no frame was given.")
    tasks = [trajectory] if isinstance(trajectory, Trajectory) else list(trajectory)
    still = [name for name in robot.sized_joints
             if not any(np.any(traj.qd[:, robot.joint_index(name)]) for traj in tasks)]
    if still and len(still) == len(robot.sized_joints):
        notes.append(HOLD_NOTE + ".")
    elif still:
        where = "this motion" if len(tasks) == 1 else "any task"
        notes.append(f"still: {', '.join(still)} {'does' if len(still) == 1 else 'do'} not move "
                     f"in {where}, so only holding (static) and an emergency stop are checked "
                     "there; mean torque, speed and life do not apply.")
    return notes


def tool_pose_notes(motion: Motion | None, lines: Iterable[LineDeviation] = ()) -> list[str]:
    """How a motion's tool poses were solved, and how closely its straight lines were planned.

    Args:
        motion: The motion as solved (None, or without tool poses: nothing to say).
        lines: Each line's deviation at the planned samples, when known.

    Returns:
        One sentence for the poses, one for the lines when there are lines.
    """
    if motion is None or motion.tool is None or motion.solution is None:
        return []
    solution, tolerance = motion.solution, motion.tool.tolerance
    count = len(motion.tool.poses)
    notes = [f"tool poses: {count} waypoint{'s' if count != 1 else ''} solved for "
             f"'{solution.frame}' on {mounting_name(solution.base)}, within "
             f"{np.nanmax(solution.position_error) * 1e3:.2g} mm and "
             f"{np.nanmax(solution.orientation_error) * DEG_PER_RAD:.2g} deg of the poses "
             f"(tolerance {tolerance.position * 1e3:g} mm, "
             f"{tolerance.orientation * DEG_PER_RAD:.3g} deg)."]
    free = free_note(motion.tool, solution, ANGLE_UNITS[motion.angle_unit], motion.angle_unit)
    notes += [free] if free else []
    if motion.lines:
        samples = sum(len(line.interior) for line in motion.lines)
        text = (f"straight lines: {len(motion.lines)}, through {samples} joint samples solved "
                "along them")
        lines = list(lines)
        if lines:
            distance = max(float(d.position.max(initial=0.0)) for d in lines)
            angle = max(float(d.orientation.max(initial=0.0)) for d in lines)
            text += (f"; the planned tool strays at most {distance * 1e3:.2g} mm and "
                     f"{angle * DEG_PER_RAD:.2g} deg from them")
        notes.append(text + ".")
    return notes


def _it(names: list[str]) -> str:
    return "them" if len(names) > 1 else "it"
