"""What the solvers hand a rule's forms: a scalable cycle, a batch of units, a payload, a path.

Each is the input of one optional form of `hdselect.catalog.rules.base.Rule`:
`ScaleTerms` of `Rule.scale_rows` (`hdselect.sizing.timescale`), `UnitBatch` of
`Rule.prefilter` (`hdselect.sizing.joint`), `PayloadCase` of `Rule.payload_masses`
(`hdselect.codesign.maxpayload`), `PathCase` of `Rule.path_rows`
(`hdselect.codesign.pathbounds`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from functools import cached_property
from typing import Any, Protocol

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.load import RPM_PER_RAD_S, CycleLoad
from hdselect.catalog.units import Unit

Interval = tuple[float, float]
"""A closed interval (lo, hi) of a scale or a mass; hi may be math.inf."""

Rows = tuple[np.ndarray, np.ndarray, np.ndarray]
"""(c2, c1, c0), each (k,): k inequalities c2 y^2 + c1 y + c0 <= 0 in y = 1/s."""

TARGETS = ("max_torsion", "min_frequency", "load_inertia")
"""A joint's precision targets and the load inertia they read: keywords of `check_unit`,
fields of `RuleInput` and of every form's input (None: no target, or not known)."""


def targets_of(given: Mapping[str, Any] | None) -> dict[str, Any]:
    """The `TARGETS` among keywords (e.g. a solver's ``check_options``), where given."""
    return {key: given[key] for key in TARGETS if given is not None and key in given}


@dataclass(frozen=True, eq=False)
class ScaleTerms:
    """A piece of one joint's cycle split by how it scales when run s times slower.

    With y = 1/s, per sample: tau(s) = g + (v + i) y^2, stop(s) = g + v y^2 + e y,
    speed |qd| y (`hdselect.sizing.timescale.ScalableCycle`).

    Attributes:
        gravity: g [N m], (k,).
        velocity: v [N m], (k,).
        inertial: i [N m], (k,).
        stop_inertial: e [N m], (k,).
        qd: Output speed at s = 1 [rad/s], (k,).
        at_rest: Where the joint is held still, (k,).
        stop_time: Emergency-stop and crash time [s].
        rotor_inertia: The motor's rotor inertia J_m [kg m^2] (the paired motor's).
        motor: The paired motor, if any.
        max_torsion: The joint's largest twist allowed [rad], if any (`torsion`).
        min_frequency: The joint's lowest natural frequency asked for [Hz], if any.
        load_inertia: The joint's load inertia J [kg m^2] (`natural_frequency`), if known.
    """

    gravity: np.ndarray
    velocity: np.ndarray
    inertial: np.ndarray
    stop_inertial: np.ndarray
    qd: np.ndarray
    at_rest: np.ndarray
    stop_time: float
    rotor_inertia: float = 0.0
    motor: Motor | None = None
    max_torsion: float | None = None
    min_frequency: float | None = None
    load_inertia: float | None = None


@dataclass(frozen=True, eq=False)
class UnitBatch:
    """One joint's cycle against every unit at once, for the rules' prefilters.

    Attributes:
        units: The units, in catalog order.
        load: The joint's cycle on the output side.
        t: Sample times [s], (n,).
        torque: Output torque per sample [N m], (n,).
        stop: Output torque at the start of an emergency stop from each sample [N m], (n,).
        qd: Output speed per sample [rad/s], (n,).
        stop_time: Emergency-stop and crash time [s].
        rotor_inertia: The motor's rotor inertia J_m [kg m^2]; None where each unit
            has several motors (pairs): a rule that depends on it then does not prefilter.
        memo: Arrays a form derives once and another reuses (e.g. the crash torques).
        max_torsion: The joint's largest twist allowed [rad], if any (`torsion`).
        min_frequency: The joint's lowest natural frequency asked for [Hz], if any.
        load_inertia: The joint's load inertia J [kg m^2] (`natural_frequency`), if known.
    """

    units: tuple[Unit, ...]
    load: CycleLoad
    t: np.ndarray
    torque: np.ndarray
    stop: np.ndarray
    qd: np.ndarray
    stop_time: float
    rotor_inertia: float | None
    memo: dict[str, Any] = field(default_factory=dict)
    max_torsion: float | None = None
    min_frequency: float | None = None
    load_inertia: float | None = None

    @cached_property
    def ratio(self) -> np.ndarray:
        """Each unit's ratio [-], (units,)."""
        return np.array([unit.ratio for unit in self.units], dtype=float)


class MeanOfMass(Protocol):
    """A joint's cubic mean torque as a function of payload mass (`codesign.cubicmean`)."""

    def at_most(self, limit: float) -> Interval | None:
        """The masses at which the mean torque is at most `limit` [N m]; None if none."""


@dataclass(frozen=True, eq=False)
class PayloadCase:
    """One unit on one joint whose torques are affine in the payload mass x [kg].

    tau = tau0 + x tau1 and stop = stop0 + x stop1 per sample [N m]
    (`hdselect.codesign.payloadbounds.unit_bound`); the speeds do not depend on x.

    Attributes:
        unit: The gearhead.
        dt: What each sample stands for [s], (n,).
        rest: Where the joint is held still, (n,).
        qd: The joint's speed [rad/s], (n,).
        tau0, tau1: Torque at x = 0 and its change per kg [N m], (n,).
        stop0, stop1: The same of the emergency-stop torque [N m], (n,).
        margin: Design margin [-].
        stop_time: Emergency-stop and crash time [s].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].
        idle: Time at rest no sample stands for [s].
        life_hours: Required life [h] on `life_basis`, if any.
        life_basis: ``"L10"`` or ``"L50"``.
        mean: The joint's cubic mean torque of x, shared by its units; None if not built
            (the mean torque and life then give no form).
        efficiency: Gear efficiency where the unit has no table [-], for the forward
            check's motor demand; None: no demand is handed to the rules.
        t: Sample times [s], (n,), for the forward check's momentary event; None: from dt.
        qdd: The joint's acceleration [rad/s^2], (n,), for the forward check's motor
            demand; None: no demand is handed to the rules.
        wrench0: The joint's whole force and moment at x = 0 in its axis frame [N, N m],
            (6, n) (`hdselect.robot.wrenches.axis_wrenches`), for the forward check of a
            rated output bearing; None: its rules are absent.
        wrench1: Its change per kg [N, N m], (6, n).
        offset: The output flange along the axis from the joint origin [m].
        max_torsion: The joint's largest twist allowed [rad], if any (`torsion`).
        min_frequency: The joint's lowest natural frequency asked for [Hz], if any.
        load_inertia: Unused here: the load inertia depends on x (`inertia0`, `inertia1`).
        inertia0: The joint's load inertia M_jj at each of the cycle's poses at x = 0
            [kg m^2], (m,), where it has a frequency target: M_jj is affine in x too.
        inertia1: Its change per unit of x [kg m^2], (m,).
    """

    unit: Unit
    dt: np.ndarray
    rest: np.ndarray
    qd: np.ndarray
    tau0: np.ndarray
    tau1: np.ndarray
    stop0: np.ndarray
    stop1: np.ndarray
    margin: float
    stop_time: float
    rotor_inertia: float = 0.0
    idle: float = 0.0
    life_hours: float | None = None
    life_basis: str = "L50"
    mean: MeanOfMass | None = None
    efficiency: float | None = None
    t: np.ndarray | None = None
    qdd: np.ndarray | None = None
    wrench0: np.ndarray | None = None
    wrench1: np.ndarray | None = None
    offset: float = 0.0
    max_torsion: float | None = None
    min_frequency: float | None = None
    load_inertia: float | None = None
    inertia0: np.ndarray | None = None
    inertia1: np.ndarray | None = None

    def inertia_at(self, mass: float) -> float | None:
        """The joint's load inertia carrying `mass` [kg m^2]: the largest M_jj of its poses."""
        if self.inertia0 is None or self.inertia1 is None:
            return None
        return float(np.max(self.inertia0 + mass * self.inertia1))

    @cached_property
    def travel(self) -> float:
        """The travel, the sum of |qd| dt over the moving samples [rad]."""
        return float((np.abs(self.qd) * self.dt * ~self.rest).sum())

    @cached_property
    def max_input_rpm(self) -> float:
        """The largest input speed [rpm]; the same at every mass."""
        return float(np.abs(self.qd).max(initial=0.0)) * RPM_PER_RAD_S * self.unit.ratio

    @cached_property
    def mean_input_rpm(self) -> float:
        """N_av as the unit's series averages it [rpm] (`CycleLoad.mean_speed_under`)."""
        moving_time = float(self.dt[~self.rest].sum())
        whole = float(self.dt.sum()) + self.idle
        mean_speed = self.travel / moving_time if moving_time > 0.0 else 0.0
        cycle_speed = self.travel / whole if whole > 0.0 else 0.0
        return (self.unit.rules.mean_speed.of(mean_speed, cycle_speed) * RPM_PER_RAD_S
                * self.unit.ratio)


@dataclass(frozen=True, eq=False)
class PathCase:
    """One joint's unit (and motor) as the TOPPRA path solver bounds it, along every piece.

    (`hdselect.codesign.pathbounds.joint_limits`.)

    Attributes:
        unit: The gearhead.
        margin: Design margin [-].
        stop_time: Emergency-stop and crash time [s].
        efficiency: Gear efficiency where the unit has no table [-].
        rotor_inertia: Motor rotor inertia J_m [kg m^2] (the paired motor's, with one).
        motor: The paired motor, if any.
        max_torsion: The joint's largest twist allowed [rad], if any (`torsion`).
        min_frequency: The joint's lowest natural frequency asked for [Hz], if any.
        load_inertia: The joint's load inertia J [kg m^2] (`natural_frequency`), if known.
    """

    unit: Unit
    margin: float
    stop_time: float
    efficiency: float
    rotor_inertia: float = 0.0
    motor: Motor | None = None
    max_torsion: float | None = None
    min_frequency: float | None = None
    load_inertia: float | None = None


class PathKind(Enum):
    """What a `PathBound` bounds on one joint along the path."""

    SPEED = "speed"
    """|qd| <= limit [rad/s]."""
    TORQUE = "torque"
    """|tau| <= limit [N m] where the joint moves in a piece."""
    STATIC = "static"
    """|tau| <= limit [N m] in a piece where the joint does not move."""
    MOMENTARY = "momentary"
    """An emergency stop's |tau| <= limit [N m], and the crash's |tau| + gain |qd|."""
    MOTOR_TORQUE = "motor torque"
    """|k tau + inertia qdd| <= limit [N m] for each gear factor k."""


@dataclass(frozen=True)
class PathBound:
    """One bound a rule puts on one joint along a TOPPRA path (`Rule.path_rows`).

    `hdselect.codesign.pathbounds` turns each kind into TOPPRA's rows; a limit is already
    derated by the design margin.

    Attributes:
        kind: What it bounds.
        limit: The limit [rad/s or N m].
        source: For a speed: whose it is (``"unit"``, ``"motor"``), as reports name it.
        gain: For a momentary bound: the crash torque per rad/s, (J_in + J_m) N^2 / t_stop
            [N m s].
        factors: For the motor torque: the gear factors k, 1 / (N eta_low) and
            eta_high / N [-].
        inertia: For the motor torque: (J_in + J_m) N [kg m^2], motor torque per rad/s^2.
    """

    kind: PathKind
    limit: float
    source: str = ""
    gain: float = 0.0
    factors: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0
