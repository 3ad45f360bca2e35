"""Straight tool moves turned into dense joint paths by inverse kinematics.

The tool's path from one pose to the next is a line in position and a slerp in
orientation (`hdselect.ik.poses.interpolate_pose`). `solve_line` walks it from
fraction 0 to 1, solving one pose per sample from the previous sample, with a spacing
that adapts: a step is halved until

- its pose solves (else a joint limit, or the edge of the arm's reach, is in the way);
- no joint moves more than `MAX_JOINT_RATE` times the scaled tool motion (else the joint
  speed blows up: a singularity);
- the scaled smallest singular value stays above `hdselect.ik.branches.SINGULAR`;
- the tool at the joint-space midpoint of the step is within the tolerance of the line's
  pose at the middle fraction,

and doubled after every accepted step. A step that moves the tool a tenth of the
tolerance and still fails stops the line there, with the reason (`LineStop`).

The planner joins the samples by a spline, which bends between them otherwise than the
joint-space chords checked here: `refine` adds a sample where that spline strays
(`hdselect.motion.planning.solve`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from hdselect.base.arrays import frozen
from hdselect.ik.branches import SINGULAR, singularity_kind
from hdselect.ik.poses import Tolerance, interpolate_pose, pose_error
from hdselect.ik.solver import solve_pose
from hdselect.ik.targets import Goal, Target, goal_between, goal_error
from hdselect.robot.kinematics import FrameKinematics, LimitContact

MAX_JOINT_RATE = 100.0
"""Joint move [rad or m] per unit of scaled tool motion [rad] above which the joint speed
is said to blow up (an arm away from singularities needs about 1) [-]."""
_FIRST_STEP = 0.02
"""Scaled tool motion of the first step [rad] (about 1 cm on a 0.5 m arm)."""


@dataclass(frozen=True, eq=False)
class LinePath:
    """A straight tool move solved into joint positions (arrays read-only).

    Attributes:
        last: The waypoint the line ends at; it starts at the one before.
        start: The tool pose at fraction 0, in the base frame, as a 4 x 4 matrix [m].
        end: The tool pose at fraction 1, in the base frame, as a 4 x 4 matrix [m].
        fractions: Fraction of the move at each sample, from 0 to 1, shape (m,).
        q: Joint positions at each sample [rad or m], shape (m, dof); the first and last
            are the waypoints' own.
        position_error: Tool distance from the line's pose at each sample [m], (m,).
        orientation_error: Tool angle from the line's orientation at each sample [rad].
        targets: For a line between under-determined poses: its two `Target`s (`start`
            and `end` then give the tool's poses at its two waypoints as solved); None for
            a line between full poses.
    """

    last: int
    start: np.ndarray
    end: np.ndarray
    fractions: np.ndarray
    q: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    targets: tuple[Target, Target] | None = None

    def pose(self, fraction: float) -> pin.SE3:
        """The line's pose at a fraction of the move [-], in the base frame."""
        return interpolate_pose(pin.SE3(self.start), pin.SE3(self.end), fraction)

    def goal(self, fraction: float) -> Goal:
        """What the line asks of the tool at a fraction of the move [-], in the base frame."""
        if self.targets is None:
            return self.pose(fraction)
        return self.targets[0].between(self.targets[1], fraction)

    @property
    def interior(self) -> np.ndarray:
        """The samples strictly between the two waypoints [rad or m], shape (m - 2, dof)."""
        return self.q[1:-1]


@dataclass(frozen=True)
class LineStop:
    """Where and why a straight move cannot be followed to its end.

    Attributes:
        fraction: Fraction of the move [-] of the first pose that fails the rules, to
            the resolution of a tenth of the tolerance.
        reason: ``"joint limit"``, ``"out of reach"`` or ``"singularity"``.
        limits: The joint limits in the way (for ``"joint limit"``).
        singularity: For ``"singularity"``: ``"wrist"``, ``"elbow"``, ``"shoulder"`` or ``""``.
        sigma: Scaled smallest singular value at the last sample reached [rad/rad].
    """

    fraction: float
    reason: str
    limits: tuple[LimitContact, ...] = ()
    singularity: str = ""
    sigma: float = float("nan")


def solve_line(kin: FrameKinematics, last: int, start: Goal, end: Goal,
               q_start: np.ndarray, tolerance: Tolerance) -> LinePath | LineStop:
    """Follow the straight move of the frame from `start` to `end` (base frame).

    Args:
        kin: The frame and the joint limits.
        last: The waypoint the line ends at (recorded in the result).
        start: Pose at fraction 0 (a full pose, or a `Target` of the same kind as `end`).
        end: Pose at fraction 1.
        q_start: Joint positions at (or near) the start pose [rad or m]: they fix the branch.
        tolerance: Largest tool deviation from the line at samples and chord midpoints.

    Returns:
        The samples, or where and why the line stops.
    """
    def solve(fraction: float, seed: np.ndarray):
        return solve_pose(kin, goal_between(start, end, fraction), seed,
                          tolerance=tolerance, wrap=False)

    first = solve(0.0, q_start)
    rows = [(0.0, first.q, first.position_error, first.orientation_error)]
    if not first.converged:
        return LineStop(0.0, "joint limit" if first.blocking else "out of reach",
                        first.blocking, sigma=kin.sigma_min(first.q))
    if isinstance(start, Target) and isinstance(end, Target):
        dp = float(np.linalg.norm(end.position - start.position))
        dtheta = start.angle_to(end)
        extent = dp / kin.length + dtheta
    else:
        extent = kin.tool_motion(start, end)
        dp, dtheta = pose_error(start, end)
    if extent == 0.0:
        return _path(kin, last, start, end, rows + [(1.0, *rows[0][1:])])
    shortest = 0.1 * min(tolerance.position / dp if dp else np.inf,
                         tolerance.orientation / dtheta if dtheta else np.inf)
    shortest = min(max(shortest, 1e-9), 1.0)
    step = min(1.0, max(_FIRST_STEP / extent, shortest))
    fraction, q = 0.0, first.q
    while fraction < 1.0:
        ahead = min(1.0, fraction + step)
        found = solve(ahead, q)
        verdict, sigma = "", float("nan")
        if not found.converged:
            verdict = "joint limit" if found.blocking else "out of reach"
        else:
            sigma = kin.sigma_min(found.q)
            rate = float(np.abs(found.q - q).max()) / (extent * (ahead - fraction))
            if rate > MAX_JOINT_RATE or sigma < SINGULAR:
                verdict = "singularity"
        if not verdict:
            middle = kin.placement(0.5 * (q + found.q))
            if not tolerance.holds(*goal_error(middle, goal_between(
                    start, end, 0.5 * (fraction + ahead)))) and step > shortest:
                step = max(0.5 * step, shortest)
                continue
            rows.append((ahead, found.q, found.position_error, found.orientation_error))
            fraction, q, step = ahead, found.q, min(2.0 * step, 1.0)
        elif step > shortest:
            step = max(0.5 * step, shortest)
        else:
            sigma_here = kin.sigma_min(q)
            kind = singularity_kind(kin, q, sigma_here) if verdict == "singularity" else ""
            return LineStop(ahead, verdict, found.blocking if verdict == "joint limit" else (),
                            kind, sigma_here)
    return _path(kin, last, start, end, rows)


def refine(kin: FrameKinematics, line: LinePath, fraction: float,
           tolerance: Tolerance) -> LinePath | None:
    """The line with one more sample at `fraction` [-], solved from its neighbour before.

    Returns:
        The refined line, or None when the pose there does not solve within the
        tolerance from that neighbour.
    """
    k = int(np.searchsorted(line.fractions, fraction))
    if not 0 < k < len(line.fractions) or fraction == line.fractions[k]:
        return None
    seed = 0.5 * (line.q[k - 1] + line.q[k])
    found = solve_pose(kin, line.goal(fraction), seed, tolerance=tolerance, wrap=False)
    if not found.converged:
        return None
    columns = [np.insert(line.fractions, k, fraction), np.insert(line.q, k, found.q, axis=0),
               np.insert(line.position_error, k, found.position_error),
               np.insert(line.orientation_error, k, found.orientation_error)]
    return replace(line, fractions=frozen(columns[0]), q=frozen(columns[1]),
                   position_error=frozen(columns[2]), orientation_error=frozen(columns[3]))


def _path(kin: FrameKinematics, last: int, start: Goal, end: Goal, rows: list) -> LinePath:
    """The accepted samples as a read-only LinePath."""
    targets = None
    if isinstance(start, Target) and isinstance(end, Target):
        targets = (start, end)
        start, end = kin.placement(rows[0][1]), kin.placement(rows[-1][1])
    if isinstance(start, Target) or isinstance(end, Target):
        raise TypeError("a line between a full pose and a target")
    return LinePath(last, frozen(start.homogeneous), frozen(end.homogeneous),
                    frozen(np.array([r[0] for r in rows])), frozen(np.array([r[1] for r in rows])),
                    frozen(np.array([r[2] for r in rows])), frozen(np.array([r[3] for r in rows])),
                    targets)
