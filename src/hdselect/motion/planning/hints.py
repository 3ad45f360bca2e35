"""A tool-pose motion's words and hints: the ``near`` hints honoured, or refused.

Joints and limits are named in the file's units (`Words`), for the messages of
`hdselect.motion.planning.solve` and this module.

A ``near`` hint starts the solver with some joints at chosen positions, to choose a
branch of the arm. The hint is honoured when each hinted joint solves within
`HINT_SPAN` of its hint. Where the solver lands farther away, the pose is solved again
with the hinted joints held within that span; when that fails too, the branch the hint
asks for cannot reach the pose within the joint limits: an error naming the waypoint,
the joint and the limits in the way, or with ``allow_flip`` (``[tool] allow_flip`` in the
motion file, ``--allow-flip`` on the command line) a warning, and the solver's branch.
Never dropped silently.
"""

from __future__ import annotations

import copy
import math
from dataclasses import replace
from typing import overload

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.ik.branches import SINGULARITY_NAMES
from hdselect.ik.lines import LineStop
from hdselect.ik.poses import Tolerance, base_in_world
from hdselect.ik.solver import PoseSolution, solve_pose
from hdselect.ik.targets import Goal, goal_between, goal_position
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import ANGLE_UNITS, Motion
from hdselect.motion.toolposes import PoseWaypoint
from hdselect.robot.kinematics import FrameKinematics, LimitContact
from hdselect.robot.mounting import NAMED_BASES, BasePose, mounting_name

HINT_SPAN = math.pi / 2
"""How far from its ``near`` hint a revolute joint may solve before the hint counts as not
honoured: a quarter turn [rad] (a prismatic joint: a quarter of its range)."""
RESTARTS = 8
"""Random restarts of a pose solved again with its hinted joints held [-]."""


class Words:
    """Joint positions, limits and the reasons a pose or a line fails, in the file's units.

    Args:
        kin: The tool frame and the joint limits.
        motion: The motion (its file and ``angle_unit``).
        base: The mounting solved for.
    """

    def __init__(self, kin: FrameKinematics, motion: Motion, base: BasePose) -> None:
        self.kin, self.motion, self.base = kin, motion, base
        self.unit = ANGLE_UNITS[motion.angle_unit]

    def unreachable(self, solution: PoseSolution) -> str:
        """Why a pose does not solve: the error left and the joint limits in the way."""
        text = (f"the tool frame '{self.kin.frame}' cannot reach this pose on "
                f"{mounting_name(self.base)}: the closest it comes is "
                f"{solution.position_error * 1e3:.3g} mm and "
                f"{self.angle_text(solution.orientation_error)} from it")
        if solution.blocking:
            text += f"; in the way: {self.limits(solution.blocking)}"
        else:
            text += ("; no joint limit is in the way: the pose is out of the arm's reach, "
                     "or needs an orientation the arm cannot take there")
        if self.base == NAMED_BASES["floor"]:
            return text
        xyz = ", ".join(f"{x:.4g}" for x in self.base.xyz)
        rpy = ", ".join(f"{a / self.unit + 0.0:.4g}" for a in pin.rpy.matrixToRpy(self.base.matrix))
        return (f"{text}; the base is at ({xyz}) m, rpy ({rpy}) {self.motion.angle_unit} in "
                "the world, and the poses are world poses: move the base (base = {xyz, rpy} "
                "in the motion file, or --base) to bring the poses within reach")

    def line_message(self, i: int, start: Goal, end: Goal, stop: LineStop) -> str:
        """Where along the line from waypoint i - 1 to i it stops, and why."""
        x, y, z = base_in_world(self.base).act(
            goal_position(goal_between(start, end, stop.fraction)))
        where = (f"the straight line from waypoint[{i - 1}] stops {100 * stop.fraction:.1f} % "
                 f"of the way, with the tool at ({x:.4f}, {y:.4f}, {z:.4f}) m in the world")
        if stop.reason == "joint limit":
            return f"{where}: {self.limits(stop.limits)} is in the way"
        if stop.reason == "singularity":
            return (f"{where}: it runs into {SINGULARITY_NAMES[stop.singularity]}, where the "
                    "joint speed blows up; move the line away from it, or drop line = true")
        return f"{where}: the line leaves the arm's reach"

    def limits(self, limits: tuple[LimitContact, ...]) -> str:
        """Joint limits in words: ``the upper limit of elbow (160 deg)``."""
        return ", ".join(f"the {c.side} limit of {c.joint} "
                         f"({self.joint(self.kin.robot.joint_index(c.joint), c.value)}"
                         + (f", where mimic follower '{c.follower}' reaches its own limit)"
                            if c.follower else ")") for c in limits)

    def joint(self, j: int, value: float, signed: bool = False) -> str:
        """A joint position or move in the file's units."""
        unit = self.motion.angle_unit if self.kin.robot.revolute[j] else "m"
        return f"{self.number(j, value):{'+' if signed else ''}g} {unit}"

    def number(self, j: int, value: float) -> float:
        """A joint position or move in the file's units, to 4 digits."""
        scale = self.unit if self.kin.robot.revolute[j] else 1.0
        return float(f"{value / scale:.4g}")

    def angle_text(self, value: float) -> str:
        """An angle [rad] in the file's unit."""
        return f"{value / self.unit:.3g} {self.motion.angle_unit}"


def hint_span(kin: FrameKinematics, name: str) -> float:
    """How far from its ``near`` hint a joint may solve [rad or m].

    `HINT_SPAN` for a revolute joint, a quarter of its range for a prismatic one.
    """
    j = kin.robot.joint_index(name)
    return HINT_SPAN if kin.robot.revolute[j] else 0.25 * float(kin.upper[j] - kin.lower[j])


def honour(kin: FrameKinematics, written: PoseWaypoint, target: Goal, seed: np.ndarray,
           found: PoseSolution, tolerance: Tolerance, words: Words,
           allow_flip: bool) -> tuple[PoseSolution, str | None]:
    """The solution with every ``near`` joint within `hint_span` of its hint.

    Args:
        kin: The tool frame and the joint limits.
        written: The pose waypoint and its hints.
        target: Its pose in the base frame.
        seed: The seed it was solved from [rad or m].
        found: The solver's solution from that seed.
        tolerance: How close the pose must be reached.
        words: Names the joints and limits.
        allow_flip: A hint that cannot be honoured is a note, not an error.

    Returns:
        The solution (the solver's, or one solved again with the hinted joints held near
        their hints), and the note where the hint could not be honoured and flips are
        allowed (else None).

    Raises:
        InputError: The hint cannot be honoured and flips are not allowed; field
            ``waypoint[i].near.JOINT``.
    """
    robot = kin.robot
    missed = [(name, hint) for name, hint in written.hints
              if abs(found.q[robot.joint_index(name)] - hint) > hint_span(kin, name)]
    if not missed:
        return found, None
    held = copy.copy(kin)  # the same frame, the hinted joints' ranges narrowed
    held.lower, held.upper = kin.lower.copy(), kin.upper.copy()
    for name, hint in written.hints:
        j = robot.joint_index(name)
        held.lower[j] = max(kin.lower[j], hint - hint_span(kin, name))
        held.upper[j] = min(kin.upper[j], hint + hint_span(kin, name))
    held.full_turn = kin.full_turn & (held.upper - held.lower >= 2 * np.pi)
    again = solve_pose(held, target, held.clip(seed), tolerance=tolerance, restarts=RESTARTS,
                       rng_seed=written.index)
    if again.converged:
        return again, None
    real = tuple(c for c in again.blocking if c.value in (
        kin.lower[robot.joint_index(c.joint)], kin.upper[robot.joint_index(c.joint)]))
    name, hint = missed[0]
    j = robot.joint_index(name)
    where = f"waypoint[{written.index}].near.{name}"
    text = (f"no solution of the pose keeps {name} within "
            f"{words.joint(j, hint_span(kin, name))} of its hint {words.joint(j, hint)}; the "
            f"solver lands at {name} = {words.joint(j, found.q[j])}, on another branch; "
            + (f"{words.limits(real)} rules that branch out" if real else
               "no joint limit is in the way: that branch does not reach the pose"))
    if allow_flip:
        return found, (f"{where}: {text}; the solver's branch taken, as --allow-flip (or [tool] "
                       "allow_flip) allows")
    raise InputError(f"{text}; change or remove the hint, or allow the other branch with "
                     "--allow-flip (or [tool] allow_flip = true)", path=words.motion.path,
                     field=where)


@overload
def allowing_flips(source: Motion, asked: bool = True) -> Motion: ...
@overload
def allowing_flips(source: Mix, asked: bool = True) -> Mix: ...
def allowing_flips(source: Motion | Mix, asked: bool = True) -> Motion | Mix:
    """The motion (a mix's every task's) with ``allow_flip`` set, as ``--allow-flip`` asks.

    `source` itself where not `asked` (no ``--allow-flip``).

    Raises:
        InputError: No waypoint of it is a tool pose, where a flip could be allowed; field
            ``--allow-flip``.
    """
    if not asked:
        return source
    if isinstance(source, Mix):
        if not any(task.motion.tool is not None for task in source.tasks):
            raise InputError("no task's motion has a tool pose: there is no near hint to "
                             "honour", field="--allow-flip")
        return replace(source, tasks=tuple(replace(task, motion=replace(
            task.motion, allow_flip=True)) for task in source.tasks))
    if source.tool is None:
        raise InputError(f"{source.path.name} has no tool pose: there is no near hint to "
                         "honour", field="--allow-flip")
    return replace(source, allow_flip=True)
