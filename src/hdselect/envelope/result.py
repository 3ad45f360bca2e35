"""What an envelope gives: per joint the unit for any motion within the spec, and why."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from hdselect.catalog.rules import Candidate, Scope, UnitLimit, rule
from hdselect.envelope.dutycycle import Duty
from hdselect.envelope.search import SearchSettings, Worst
from hdselect.envelope.spec import Spec
from hdselect.robot.model import Robot
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


def no_unit_note(joint: JointEnvelope, result: EnvelopeResult) -> str:
    """Why no unit holds a joint for every motion within the spec, and what helps.

    Gravity alone over the joint's range beyond every unit's repeated-peak limit [N m]:
    no lower limit helps. Else the strongest unit's failing rules, each demand against
    its limit; lowering the velocity and acceleration limits is suggested only where it
    helps every one of them: a speed, a torque rule whose gravity part is within the
    limit, or a mean or life on the default duty (moves at the limits).
    """
    margin = result.sizing.options.margin
    gravity = abs(joint.gravity.torque)
    peak = cast(UnitLimit, rule("peak"))
    strongest = joint.sizing.strongest
    best = max((c.unit for c in joint.sizing.candidates),
               key=lambda unit: peak.allowed(unit, margin))
    head = f"{joint.name}: no unit holds for every motion within the spec"
    away = (f"leave it out with --exclude {joint.name}, or give a catalog with a stronger "
            "unit (--catalog)")
    if gravity > peak.allowed(best, margin):
        return (f"{head}: gravity alone needs {gravity:.3g} N m over the joint's range, over "
                f"every unit's repeated-peak limit (the strongest, {best.id}, allows "
                f"{peak.allowed(best, margin):.3g} N m): no lower velocity or acceleration "
                f"limit helps; {away}.")
    failing = [name for name, check in strongest.checks.items() if not check.ok]
    figures = ", ".join(f"{rule(name).words} {_figure(strongest.checks[name], rule(name).unit)}"
                        for name in failing)
    stuck = [name for name in failing if not _lowering_helps(
        name, gravity, strongest, margin, result.duty.default)]
    said = (f"{head}; the strongest, {strongest.unit.id}, fails {figures}. Gravity alone "
            f"needs at most {gravity if gravity >= 5e-5 else 0.0:.3g} N m over the "
            "joint's range")
    if not stuck:
        return (f"{said}, within its limits: the speed and acceleration terms fail, so lower "
                "the velocity and acceleration limits.")
    cycle = any(rule(name).scope is Scope.CYCLE for name in stuck)
    return (f"{said}; lower velocity and acceleration limits are not shown to help its "
            f"{', '.join(rule(name).words for name in stuck)}"
            + (f" (judged on the {result.duty.label}, which they do not change)" if cycle
               else "") + f"; {away}.")


def _lowering_helps(name: str, gravity: float, candidate: Candidate, margin: float,
                    default_duty: bool) -> bool:
    """Lower velocity and acceleration limits bring a failing rule within, in the limit.

    A torque rule of single samples tends to the gravity torque [N m]; the input speed to
    0; a rule over the duty follows the limits only on the default duty (moves at them).
    """
    if name in GRAVITY_RULES:
        return gravity <= cast(UnitLimit, rule(name)).allowed(candidate.unit, margin)
    if rule(name).scope is Scope.CYCLE:
        return default_duty
    return name == "speed"


def _figure(check, unit: str) -> str:
    """A failing check: its demand against its limit, in the rule's unit."""
    if check.value is None or not np.isfinite(check.limit):
        return f"at {check.utilization:.0%} of its limit"
    return f"({check.value:.3g} against {check.limit:.3g}{' ' + unit if unit else ''})"
