"""A rule as an object: its names, what it judges, the margin, its check and its forms.

Every rule of the catalog (a gearhead's, its output bearing's, its motor's, the pair's)
is one `Rule` in a file of its own, registered in order in `hdselect.catalog.rules`
(`RULES`); the check tables (`CHECKS`, `CHECK_LABELS`, ...) derive from that registry.

A rule has one forward check, `Rule.check`: it reads what it needs of one `RuleInput`
(the cycle's load, the unit, the momentary event, the required life, the motor and its
demand, the bearing's figures) and returns its `Check`, or None where it is absent for
this case (``life`` without a required life). `Rule.judge` (through `Rule.verdict`) is
the one place the design margin is applied: a rule holds where its utilization is at
most 1 - margin (`Rule.share`), and every solver's limit is `Rule.derate`. `holds` and
`derated` below are the same arithmetic for code that judges no particular rule.

The solvers' forms are optional methods; each returns None where the rule does not
provide it, and the solver then falls back to the forward check (on a grid with
bisection, or simply not prefiltering), so no solver can ignore a rule:

- `Rule.scale_rows`: the rule on a cycle run s times slower as rows of quadratic
  inequalities c2 y^2 + c1 y + c0 <= 0 in y = 1/s (`hdselect.sizing.timescale`).
- `Rule.prefilter`: every unit at once, as each unit's utilization; never stricter than
  the forward check, and equal to its utilization wherever it gives one
  (`hdselect.sizing.joint`).
- `Rule.payload_masses`: the payload masses x at which it holds, with the torques affine
  in x (`hdselect.codesign.maxpayload`).
- `Rule.path_rows`: its bounds on one joint along a TOPPRA path, `PathBound`s that
  `hdselect.codesign.pathbounds` turns into TOPPRA's rows.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, ClassVar

import numpy as np

from hdselect.catalog.bearing_rules import BearingFigures
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.forms import (
    Interval,
    PathCase,
    PayloadCase,
    Rows,
    ScaleTerms,
    UnitBatch,
)
from hdselect.catalog.rules.load import (
    RPM_PER_RAD_S,
    CycleLoad,
    Momentary,
    MotorDemand,
    allowable_mean_torque,
    l50_life_hours,
)
from hdselect.catalog.units import NOT_RATED, Unit

Gear = tuple[Unit, CycleLoad]
"""A gearhead and the joint's cycle on its output side: what every gearhead rule reads."""

DEFAULT_MARGIN = 0.0
"""Design margin by default [-]: every rule holds at up to 100 % of its limit."""


class Part(Enum):
    """What a rule judges: the gearhead, its output bearing, its motor or the pair."""

    GEARHEAD = "gearhead"
    BEARING = "bearing"
    MOTOR = "motor"
    PAIR = "pair"


class Scope(Enum):
    """How a rule meets several samples and several tasks.

    SAMPLE: judged on single samples (or single poses); over a duty of several tasks,
    the worst task's. CYCLE: judged on figures pooled over the whole duty (a mean, a
    life, an RMS).
    """

    SAMPLE = "sample"
    CYCLE = "cycle"


@dataclass(frozen=True)
class Check:
    """One rule applied to one gearhead.

    Attributes:
        value: The demand ([N m], [N], input speed [rpm]), or for a life the life
            expected [h] and for a static safety the safety reached [-]; None if the
            rule does not apply to this cycle or this unit.
        limit: What the gearhead allows (for a life or a safety: what is required);
            infinite where the unit has no such limit.
        ok: The rule holds with the design margin (`Rule.judge`).
        utilization: Demand over allowance [-] (a life or a safety: required over
            reached); 0 if the rule does not apply, above 1 when it fails.
        detail: Extra figures for reports, e.g. ``{"kind": "crash"}``.
    """

    value: float | None
    limit: float
    ok: bool
    utilization: float
    detail: dict[str, object] = field(default_factory=dict)


def _share(margin: float, applies: bool = True) -> float:
    """The share of a limit usable [-]: 1 - margin, or 1 where the margin does not apply."""
    return 1.0 - margin if applies else 1.0


def holds(utilization: float, margin: float = DEFAULT_MARGIN) -> bool:
    """Whether a utilization [-] holds with a design margin: utilization <= 1 - margin."""
    return utilization <= _share(margin)


def derated(limit: float, margin: float = DEFAULT_MARGIN) -> float:
    """The usable part of a limit with a design margin, (1 - margin) x limit [same unit]."""
    return limit * _share(margin)


@dataclass(frozen=True, eq=False)
class RuleInput:
    """Everything a forward check may read; each rule reads what it needs.

    Attributes:
        unit: The gearhead; None where only a motor is judged (`check_motor`).
        load: The joint's cycle on the output side; None where only the motor or the
            pair is judged.
        margin: Design margin [-], in [0, 1).
        momentary: The worst momentary (T4) event for this unit, if any.
        life_hours: Required life [h] on `life_basis`, if any.
        life_basis: ``"L10"`` or ``"L50"``.
        bearing: The rated output bearing's figures, where the unit rates it and its
            loads are known.
        demand: What the motor behind the gearhead must deliver, if known.
        motor: The motor paired with the gearhead, if any.
        motor_torque: Motor torque per sample [N m], (n,), with a motor.
        motor_speed: Input speed per sample [rpm], (n,), with a motor.
        load_inertia: The joint's output-side load inertia [kg m^2], if known: the largest
            M_jj over the cycle's poses (the inertia ratio, the natural frequency).
        max_inertia_ratio: Largest load-to-rotor inertia ratio allowed [-], if any.
        max_torsion: The joint's largest twist allowed [rad], if any (`torsion`).
        min_frequency: The joint's lowest single-axis natural frequency asked for [Hz], if
            any (`natural_frequency`).
    """

    unit: Unit | None
    load: CycleLoad | None
    margin: float = DEFAULT_MARGIN
    momentary: Momentary | None = None
    life_hours: float | None = None
    life_basis: str = "L50"
    bearing: BearingFigures | None = None
    demand: MotorDemand | None = None
    motor: Motor | None = None
    motor_torque: np.ndarray | None = None
    motor_speed: np.ndarray | None = None
    load_inertia: float | None = None
    max_inertia_ratio: float | None = None
    max_torsion: float | None = None
    min_frequency: float | None = None

    @property
    def gear(self) -> Gear | None:
        """(unit, load) where both are known: what every gearhead rule reads; else None."""
        return None if self.unit is None or self.load is None else (self.unit, self.load)

    mean_input_rpm: float = field(init=False)
    """N_av, the mean input speed as the unit's series defines it [rpm]; 0 without both."""
    allowed_mean: tuple[float, bool] = field(init=False)
    """The allowable mean torque [N m] and whether the repeated peak capped it."""
    l50_hours: float | None = field(init=False)
    """The unit's L50 life on this cycle [h]; None when unlimited or not known."""

    def __post_init__(self) -> None:
        rpm, allowed, life = 0.0, (math.inf, False), None
        if self.unit is not None and self.load is not None:
            rpm = (self.load.mean_speed_under(self.unit.rules) * RPM_PER_RAD_S
                   * self.unit.ratio)
            allowed = allowable_mean_torque(self.unit, rpm)
            if self.load.mean_torque is not None:
                life = l50_life_hours(self.unit, self.load.mean_torque, rpm)
        object.__setattr__(self, "mean_input_rpm", rpm)
        object.__setattr__(self, "allowed_mean", allowed)
        object.__setattr__(self, "l50_hours", life)


class Rule:
    """One rule of the catalog: its names, what it judges, its check and its forms.

    A rule is a class with these class attributes and a `check`; its single instance is
    registered in `hdselect.catalog.rules` (`RULES`).

    Attributes:
        name: Its key in a candidate's checks and in JSON, e.g. ``"peak"``.
        label: Its short name in table headers, e.g. ``"peak"``.
        words: Its name in words, for titles and summaries, e.g. ``"repeated peak torque"``.
        part: What it judges (`Part`).
        scope: Single samples or the pooled cycle (`Scope`).
        margin_applies: Whether the design margin applies (not to a design choice).
        at_least: The value must reach the limit (a life, a safety): utilization is
            limit / value, and 0 where the value is None (unlimited).
        life: Its value is a life [h], reported within `hdselect.catalog.checks.LIFE_CAP`.
        unit: The unit of its value and limit in reports, e.g. ``"N m"``; ``""`` for none.
        share_of: What its utilization is a share of, in words, e.g. ``"rated"``.
    """

    name: ClassVar[str]
    label: ClassVar[str]
    words: ClassVar[str]
    part: ClassVar[Part]
    scope: ClassVar[Scope]
    margin_applies: ClassVar[bool] = True
    at_least: ClassVar[bool] = False
    life: ClassVar[bool] = False
    unit: ClassVar[str] = ""
    share_of: ClassVar[str] = "its limit"

    def __repr__(self) -> str:
        return f"<rule {self.name}>"

    def check(self, case: RuleInput) -> Check | None:
        """The forward check on one case; None where the rule is absent for it."""
        raise NotImplementedError

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """The unit's fields its check reads where it has a value (for the unit's flags)."""
        return ()

    def share(self, margin: float) -> float:
        """The share of its limit usable [-]: 1 - margin, or 1 where the margin does not apply."""
        return _share(margin, self.margin_applies)

    def derate(self, limit: float, margin: float) -> float:
        """Its limit as the solvers use it: `share` x limit [same unit]."""
        return limit * self.share(margin)

    def judge(self, value: float | None, limit: float, margin: float,
              **detail: object) -> Check:
        """The verdict on a value against its limit, with the design margin (`verdict`).

        Utilization is value / limit (with `at_least`: limit / value), 0 where the value
        is None.

        Args:
            value: The demand, or the life or safety reached; None if not applicable.
            limit: The allowance, or the life or safety required.
            margin: Design margin [-], in [0, 1).
            **detail: Extra figures for reports.
        """
        utilization = (0.0 if value is None
                       else limit / value if self.at_least else value / limit)
        return self.verdict(value, limit, utilization, margin, detail)

    def verdict(self, value: float | None, limit: float, utilization: float, margin: float,
                detail: dict[str, object] | None = None) -> Check:
        """The check of a utilization [-]: the one place the design margin is applied.

        The rule holds where the utilization is at most `share`. `judge` finds the
        utilization; a rule that finds it otherwise (the motor's worst sample) gives it.
        `detail` becomes the check's own: pass a dict made for it.
        """
        return Check(value, limit, utilization <= _share(margin, self.margin_applies),
                     utilization, {} if detail is None else detail)

    def not_rated(self, value: float | None, margin: float,
                  detail: dict[str, object] | None = None) -> Check:
        """The check of a limit the unit's source does not rate: it holds, saying so.

        No limit (inf), no share of the verdict (utilization 0), the words `NOT_RATED`
        in its detail (which every table, JSON and page shows).
        """
        return self.verdict(value, math.inf, 0.0, margin,
                            {**(detail or {}), "not_rated": NOT_RATED})

    def passes(self, utilization: np.ndarray, margin: float) -> np.ndarray:
        """`judge`'s verdict on many utilizations at once (a prefilter's) [-]."""
        return utilization <= self.share(margin)

    # The solvers' forms: each None where the rule does not provide it.

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows] | None:
        """The rule on the cycle run s times slower, as rows in y = 1/s.

        Exact: at every s, the rows all hold at y = 1/s exactly where `check` holds on
        the scaled cycle (`hdselect.sizing.timescale.check_at`). A rule on the whole
        cycle has none; `hdselect.sizing.timescale.feasible_scales` then checks it on a
        grid with bisection.

        Args:
            terms: A piece of the cycle's samples, split by how they scale.
            unit: The gearhead.
            margin: Design margin [-]: the limits are `derate`d.

        Returns:
            Rows (c2, c1, c0) of c2 y^2 + c1 y + c0 <= 0; None: no such form.
        """
        return None

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """Every unit's utilization [-] at once, (units,), judged by `passes`.

        Equal to `check`'s utilization for every unit (so a unit it rejects fails the
        forward check, and one it passes may still fail other rules); None where the
        rule gives no prefilter for this batch (the forward check decides).
        """
        return None

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...] | None:
        """The payload masses x [kg] at which the rule holds.

        Returns:
            Sorted disjoint closed intervals of x (an empty tuple: no mass); None: no such
            form (`hdselect.codesign.maxpayload` then checks the rule forward).
        """
        return None

    def path_rows(self, case: PathCase) -> list[Any] | None:
        """The rule's bounds on one joint along a TOPPRA path (`PathBound`s).

        Returns:
            The bounds (an empty list: none for this case, e.g. a motor's rule without a
            motor); None: no such form (`hdselect.codesign.cyclerules` then checks the rule
            forward on the planned cycle).
        """
        return None


class UnitLimit(Rule):
    """A gearhead rule on single samples: the cycle's largest |x| within one of the unit's limits.

    `peak`, `static`, `momentary` and `speed`. Each gives its largest value (`largest`);
    the check, the field it reads, the limit the solvers use (`allowed`) and every unit's
    utilization at once (`utilizations`, a prefilter's) are written here once. A unit
    whose source does not rate the limit (the field None, `rated`) is not checked: its
    check holds with the words `NOT_RATED` in its detail, and the solvers' forms bound
    nothing.

    Attributes:
        limit: The unit's field that is the limit, e.g. ``"repeated_torque"``.
    """

    limit: ClassVar[str]
    part = Part.GEARHEAD
    scope = Scope.SAMPLE

    def largest(self, case: RuleInput, gear: Gear) -> tuple[float | None, dict[str, object]]:
        """The cycle's largest |x| [the rule's unit] (None where nothing is read) and detail."""
        raise NotImplementedError

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None:
            return None
        value, detail = self.largest(case, gear)
        limit = getattr(gear[0], self.limit)
        if limit is None:
            return self.not_rated(value, case.margin, detail)
        return self.judge(value, limit, case.margin, **detail)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return (self.limit,)

    def rated(self, unit: Unit) -> bool:
        """Whether the unit's source rates its limit (else the rule is not checked)."""
        return getattr(unit, self.limit) is not None

    def allowed(self, unit: Unit, margin: float) -> float:
        """The unit's limit as the solvers use it (`derate`d) [the rule's unit]; a `rated` one."""
        return self.derate(getattr(unit, self.limit), margin)

    def utilizations(self, largest: float | np.ndarray, units: Sequence[Unit]) -> np.ndarray:
        """Every unit's utilization [-], (units,): its largest |x| over its limit (0: not rated)."""
        limits = [getattr(unit, self.limit) for unit in units]
        utilization: np.ndarray = largest / np.array([math.inf if limit is None else limit
                                                      for limit in limits])
        return utilization


def within(c2: np.ndarray, c1: np.ndarray, c0: np.ndarray, limit: float) -> tuple[Rows, Rows]:
    """|c2 y^2 + c1 y + c0| <= limit [same unit as c0] as two rows of `... <= 0`."""
    return (c2, c1, c0 - limit), (-c2, -c1, -c0 - limit)
