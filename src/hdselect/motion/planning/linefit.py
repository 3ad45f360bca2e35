"""Straight lines as the planner follows them: the spline through their samples, checked.

The TOPPRA planner joins a line's joint samples by a clamped cubic spline
(`hdselect.motion.planning.spline.SplinePath`), which bends between samples otherwise than the
joint-space chords `hdselect.ik.lines.solve_line` checked, and is pulled by the
waypoints around the line. `fit_lines` evaluates that spline at `CHECKS_PER_STEP` points
between every two samples of a line, compares the tool's pose there with the line's pose
at the matching fraction (linear in the path position s between samples), and adds an
IK sample in the middle of every step that strays beyond the tolerance, until none does.

`deviation` measures how far tool poses are from a line, without a fraction to match:
the distance of the tool origin from the segment, and the angle of its orientation
from the nearest orientation of the slerp arc. It is never more than the error against
the line's pose at any fraction, so a path that `fit_lines` accepted stays within the
tolerance by this measure too; the planner reports it at every planned sample.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.ik.lines import LinePath, refine
from hdselect.ik.poses import Tolerance
from hdselect.ik.targets import goal_error
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.spline import SplinePath, piece_bounds, piece_geometry
from hdselect.robot.kinematics import FrameKinematics

CHECKS_PER_STEP = 8
"""Points between two samples of a line at which the spline is checked [-]."""
MAX_ROUNDS = 12
"""Rounds of refinement before a line is declared impossible to follow [-]."""


def fit_lines(kin: FrameKinematics, motion: Motion, tolerance: Tolerance) -> Motion:
    """The motion with samples added to its lines until the planner's spline follows them.

    Args:
        kin: The tool frame of the robot the motion was solved for.
        motion: A solved motion with lines.
        tolerance: The tool's largest deviation from a line.

    Returns:
        The motion with refined `Motion.lines`.

    Raises:
        InputError: A line cannot be followed within the tolerance after `MAX_ROUNDS`
            rounds (the tolerance is too tight for the solver); field
            ``tool.position_tolerance``.
    """
    for _ in range(MAX_ROUNDS):
        wanted = strays(kin, motion, tolerance)
        if not wanted:
            return motion
        motion = refined(kin, motion, wanted, tolerance)
    worst = max(strays(kin, motion, tolerance).values(), key=len, default=[])
    raise InputError(f"the planner's path cannot be made to follow the line to waypoint"
                     f"[{next(iter(strays(kin, motion, tolerance)), '?')}] within "
                     f"{tolerance.position * 1e3:g} mm and {np.degrees(tolerance.orientation):g}"
                     f" deg ({len(worst)} steps still stray); use a larger tolerance",
                     path=motion.path, field="tool.position_tolerance")


def strays(kin: FrameKinematics, motion: Motion,
           tolerance: Tolerance) -> dict[int, list[float]]:
    """The fractions, per line, at the middle of every step where the spline strays."""
    lines = {line.last: line for line in motion.lines}
    out: dict[int, list[float]] = {}
    for first, last in piece_bounds(motion):
        geometry = piece_geometry(motion, first, last)
        if not geometry.line_knots:
            continue
        path = SplinePath(geometry.knots, geometry.points, kin.lower, kin.upper)
        for end, knots in geometry.line_knots.items():
            line = lines[end]
            for k in range(len(knots) - 1):
                inner = np.linspace(knots[k], knots[k + 1], CHECKS_PER_STEP + 2)[1:-1]
                fractions = np.interp(inner, knots, line.fractions)
                for q, fraction in zip(path(inner), fractions, strict=True):
                    if not tolerance.holds(*goal_error(kin.placement(q), line.goal(fraction))):
                        middle = 0.5 * (line.fractions[k] + line.fractions[k + 1])
                        out.setdefault(end, []).append(float(middle))
                        break
    return out


def refined(kin: FrameKinematics, motion: Motion, fractions: dict[int, list[float]],
            tolerance: Tolerance) -> Motion:
    """The motion with a sample added to each line at each of `fractions` [-].

    Raises:
        InputError: A pose between two samples does not solve from them.
    """
    lines = []
    for line in motion.lines:
        for fraction in fractions.get(line.last, ()):
            better = refine(kin, line, fraction, tolerance)
            if better is None:
                raise InputError(f"the line to waypoint[{line.last}] cannot be followed at "
                                 f"{100 * fraction:.2f} % of the way: the pose there does not "
                                 "solve from its neighbours", path=motion.path,
                                 field=f"waypoint[{line.last}].line")
            line = better
        lines.append(line)
    return replace(motion, lines=tuple(lines))


def deviation(line: LinePath, poses: list[pin.SE3]) -> tuple[np.ndarray, np.ndarray,
                                                             np.ndarray]:
    """How far tool poses (base frame) are from a line, with the fraction each is nearest.

    Args:
        line: The line.
        poses: Tool poses.

    Returns:
        The origin's distance from the segment [m], the orientation's angle from the
        nearest orientation of the slerp arc [rad], and the fraction [-] of the nearest
        point (by position; by orientation for a turn on the spot), each shape (n,).
        A line between under-determined poses measures what they fix: the approach
        axis from the slerp of the directions, the yaw from its constant turn, nothing
        for positions alone (angle 0).
    """
    if line.targets is not None:
        return _target_deviation(line, poses)
    start, end = pin.SE3(line.start), pin.SE3(line.end)
    p0, step = start.translation, end.translation - start.translation
    turn = pin.log3(start.rotation.T @ end.rotation)
    angle = float(np.linalg.norm(turn))
    axis = turn / angle if angle > 0.0 else np.zeros(3)
    distance, tilt, nearest = (np.empty(len(poses)) for _ in range(3))
    for n, pose in enumerate(poses):
        along = float(np.clip((pose.translation - p0) @ step / (step @ step), 0.0, 1.0)) \
            if step @ step > 0.0 else 0.0
        distance[n] = float(np.linalg.norm(pose.translation - p0 - along * step))
        # The arc R0 exp(f angle axis), as unit quaternions [cos(f angle/2), sin(f angle/2)
        # axis], meets the relative orientation [w, v] at rho cos(f angle / 2 - phi): the
        # nearest point is at f = 2 phi / angle, or at an end of the arc.
        relative = start.rotation.T @ pose.rotation
        quaternion = pin.Quaternion(relative)
        v = np.array([quaternion.x, quaternion.y, quaternion.z])
        phi = float(np.arctan2(axis @ v, quaternion.w)) if angle > 0.0 else 0.0
        phi = (phi + np.pi / 2) % np.pi - np.pi / 2  # q and -q are the same orientation
        candidates = {0.0, 1.0, float(np.clip(2.0 * phi / angle, 0.0, 1.0))} \
            if angle > 0.0 else {0.0}
        turned, tilt[n] = min(((f, float(np.linalg.norm(pin.log3(
            pin.exp3(f * turn).T @ relative)))) for f in candidates), key=lambda c: c[1])
        nearest[n] = along if step @ step > 0.0 else turned
    return distance, tilt, nearest


def _target_deviation(line: LinePath, poses: list[pin.SE3]) -> tuple[np.ndarray, np.ndarray,
                                                                     np.ndarray]:
    """`deviation` for a line between under-determined poses (`LinePath.targets`)."""
    if line.targets is None:
        raise RuntimeError("a line between full poses")
    start, end = line.targets
    p0, step = start.position, end.position - start.position
    moves = float(step @ step) > 0.0
    distance, angle, nearest = (np.empty(len(poses)) for _ in range(3))
    for n, pose in enumerate(poses):
        along = float(np.clip((pose.translation - p0) @ step / (step @ step), 0.0, 1.0)) \
            if moves else 0.0
        distance[n] = float(np.linalg.norm(pose.translation - p0 - along * step))
        angle[n], turned = start.nearest_turn(end, pose)
        nearest[n] = along if moves else turned
    return distance, angle, nearest
