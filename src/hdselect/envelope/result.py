"""What an envelope gives: per joint the unit for any motion within the spec, and why."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import cast

import numpy as np

from hdselect.catalog.rules import Candidate, Scope, UnitLimit, rule
from hdselect.envelope.dutycycle import Duty
from hdselect.envelope.search import SearchSettings, Worst
from hdselect.envelope.spec import Spec
from hdselect.robot.model import Robot
from hdselect.sizing.diagnosis import Diagnosis, GravityLoad, diagnose
from hdselect.sizing.nextsteps import NextStep
from hdselect.sizing.result import JointSizing, SizingResult

FIGURES = ("peak", "static", "stop")
"""The worst states reported per joint: the largest torque while moving (repeated peak),
while held (static), and at the start of an emergency stop."""


@dataclass(frozen=True)
class WorstState:
    """A state of the box and what one joint carries there: check it with a motion through it.

    Attributes:
        figure: ``"peak"``, ``"static"`` or ``"stop"`` (see `FIGURES`).
        q: Positions [rad or m], shape (dof,).
        qd: Velocities [rad/s or m/s], shape (dof,).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (dof,); for ``stop``, the state's own
            (0: coasting); the stop decelerates at -qd / stop_time from it.
        torque: The joint's torque there, signed [N m or N]: RNEA(q, qd, qdd) for peak and
            static, RNEA(q, qd, -qd / stop_time) for stop, with the chosen units' masses.
        source: ``"search"`` (a worst state found), or where in the duty it lies, e.g.
            ``"duty t = 3.141 s"``, led by its task's name in a duty of several tasks (a
            mix): ``"duty pick t = 4.234 s"``.
    """

    figure: str
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    torque: float
    source: str


@dataclass(frozen=True)
class Convergence:
    """How settled one joint's worst values are.

    Attributes:
        by_demand: The search's result per demand (``peak``, ``held``, ``stop``,
            ``gravity``): the worst value from N, 4N, ... starts.
        converged: Every demand's last two rounds agree within the tolerance, and no
            other state (another joint's, or the duty's) beats the joint's own worst by more.
        note: Why it did not converge, if it did not.
    """

    by_demand: dict[str, Worst]
    converged: bool
    note: str = ""


@dataclass(frozen=True, eq=False)
class JointEnvelope:
    """One joint's envelope.

    Attributes:
        name: Joint name.
        sizing: The selection on the duty and the worst states (every candidate checked).
        worst: The worst states, by figure (`FIGURES`).
        gravity: The largest gravity torque over the joint box [N m] (the backdriving
            warning's figure), and the pose where it acts.
        convergence: How settled the worst values are.
        duty: What the duty alone selects for this joint (None when nothing fits it).
    """

    name: str
    sizing: JointSizing
    worst: dict[str, WorstState]
    gravity: WorstState
    convergence: Convergence
    duty: Candidate | None

    @property
    def selected(self) -> Candidate | None:
        """The unit that holds for any motion within the spec (None when none does)."""
        return self.sizing.selected


@dataclass(frozen=True, eq=False)
class EnvelopeResult:
    """Everything `hdselect envelope` prints, as values.

    Attributes:
        robot: The robot (payload and mounting applied, no gearhead masses).
        spec: The limits.
        duty: The duty the averaged rules were judged on.
        joints: One per sized joint, in the robot's order.
        sizing: The envelope's selection as a sizing result (its trajectory the duty's).
        duty_sizing: What the duty alone selects (`hdselect size` of the duty).
        masses: The mass each sized joint's unit adds [kg] (empty without mass coupling).
        settings: How hard the search looked.
        states: How many states the search evaluated.
        rounds: Full searches run until the carried masses settled (1: the first guess held).
        settled: The last search ran with the masses of the units chosen.
        seconds: Wall time of the whole envelope [s].
        executor: Where the search's quasi-random states were computed, in words.
    """

    robot: Robot
    spec: Spec
    duty: Duty
    joints: tuple[JointEnvelope, ...]
    sizing: SizingResult
    duty_sizing: SizingResult
    masses: dict[str, float]
    settings: SearchSettings
    states: int
    rounds: int
    settled: bool
    seconds: float
    executor: str = "this process"

    @property
    def feasible(self) -> bool:
        """Every joint has a unit that holds for any motion within the spec."""
        return all(joint.selected is not None for joint in self.joints)

    @property
    def converged(self) -> bool:
        """Every joint's search converged and the masses settled."""
        return self.settled and all(joint.convergence.converged for joint in self.joints)


GRAVITY_RULES = ("peak", "static", "momentary")
"""The torque rules of single samples whose demand tends to the gravity torque as the speed
and acceleration limits tend to 0: lowering them helps only where gravity is within."""


def envelope_diagnoses(sizing: SizingResult, joints: Sequence[JointEnvelope],
                       duty: Duty) -> dict[str, Diagnosis]:
    """The diagnosis of every joint no unit holds for every motion within the spec.

    The sizing's own (`hdselect.sizing.diagnosis.diagnose`: the shortfalls over the worst
    states and the duty), with the envelope's facts: gravity alone is the largest over the
    joint's range (the search's) against every unit's repeated-peak limit while moving;
    the next steps are the envelope's: lower velocity and acceleration limits where that
    helps every failing rule (`lowering_helps`), and the joint left out (``--exclude``)
    where another joint is sized.
    A shipped series is not offered: its verification would be another envelope.

    Args:
        sizing: The envelope's selection (the duty and the worst states).
        joints: Each joint's envelope (its gravity over the range).
        duty: The duty the averaged rules are judged on.
    """
    found = diagnose(sizing, catalogs={})
    margin = sizing.options.margin
    peak = cast(UnitLimit, rule("peak"))
    out = {}
    for joint in joints:
        if joint.name not in found:
            continue
        torque = abs(joint.gravity.torque)
        strongest = max((c.unit for c in joint.sizing.candidates),
                        key=lambda unit: peak.allowed(unit, margin))
        limit = peak.allowed(strongest, margin)
        gravity = GravityLoad(torque if torque >= 5e-5 else 0.0, limit, strongest.id,
                              torque > limit)
        steps = []
        if not gravity.exceeds and lowering_helps(joint.sizing.strongest, gravity.torque,
                                                  margin, duty.default):
            steps.append(NextStep(
                "limits", "lower the velocity and acceleration limits: the speed and "
                "acceleration terms fail; " + (
                    f"gravity alone needs at most {gravity.torque:.3g} N m over the joint's "
                    f"range, within {joint.sizing.strongest.unit.id}'s limits"
                    if gravity.torque > 0.0 else "gravity does not load it")))
        if len(sizing.robot.sized_joints) > 1:  # else nothing would be left to size
            steps.append(NextStep("exclude", f"leave it out with --exclude {joint.name}"))
        out[joint.name] = replace(found[joint.name], gravity=gravity, steps=tuple(steps))
    return out


def lowering_helps(candidate: Candidate, gravity: float, margin: float,
                   default_duty: bool) -> bool:
    """Lower velocity and acceleration limits bring every rule a candidate fails within.

    In the limit of slow motion: a torque rule of single samples tends to the gravity
    torque [N m] (within its limit, or not); the input speed to 0; a rule over the duty
    follows the limits only on the default duty (moves at them); any other rule (an output
    bearing's, a motor's) is not shown to.
    """
    for name, check in candidate.checks.items():
        if check.ok:
            continue
        found = rule(name)
        if name in GRAVITY_RULES:
            helps = gravity <= cast(UnitLimit, found).allowed(candidate.unit, margin)
        elif found.scope is Scope.CYCLE:
            helps = default_duty
        else:
            helps = name == "speed"
        if not helps:
            return False
    return True
