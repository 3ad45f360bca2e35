"""What the solvers hand a rule's forms: a scalable cycle, a batch of units, a payload, a path.

Each is the input of one optional form of `hdselect.catalog.rules.base.Rule`:
`ScaleTerms` of `Rule.scale_rows` (`hdselect.sizing.timescale`), `UnitBatch` of
`Rule.prefilter` (`hdselect.sizing.joint`), `PayloadCase` of `Rule.payload_masses`
(`hdselect.codesign.maxpayload`), `PathCase` of `Rule.path_rows`
(`hdselect.codesign.pathbounds`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Protocol

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.load import CycleLoad
from hdselect.catalog.units import Unit

Interval = tuple[float, float]
"""A closed interval (lo, hi) of a scale or a mass; hi may be math.inf."""

Rows = tuple[np.ndarray, np.ndarray, np.ndarray]
"""(c2, c1, c0), each (k,): k inequalities c2 y^2 + c1 y + c0 <= 0 in y = 1/s."""


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
    (`hdselect.codesign.maxpayload.unit_bound`).

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
        mean: The joint's cubic mean torque of x, shared by its units; None if not built.
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


@dataclass(frozen=True, eq=False)
class PathCase:
    """One joint's limits along one TOPPRA path piece (`hdselect.codesign.pathbounds`).

    Attributes:
        piece: The path piece (`hdselect.motion.planning.toppra.PathPiece`).
        coefficients: (a, b, c, v) along the piece, each (m, dof): torque = a s'' + b s'^2
            + c, v = RNEA(p, p', 0) - c.
        joint: The joint's column.
        unit: The gearhead.
        margin: Design margin [-].
        stop_time: Emergency-stop and crash time [s].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].
        motor: The paired motor, if any.
        still: The joint does not move in this piece.
    """

    piece: Any
    coefficients: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    joint: int
    unit: Unit
    margin: float
    stop_time: float
    rotor_inertia: float = 0.0
    motor: Motor | None = None
    still: bool = False
