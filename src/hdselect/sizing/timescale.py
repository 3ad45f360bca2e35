"""A joint's cycle run s times slower, and the exact set of s at which a unit passes.

Run a fixed path uniformly s times slower (s < 1: faster) and, per sample, with g
the gravity torque, v the velocity-product (Coriolis, centrifugal) part, i the
inertial part and e the inertial part of an emergency stop (deceleration
-qd / t_stop) at s = 1:

    tau(s) = g + (v + i) / s^2        stop(s) = g + v / s^2 + e / s

With y = 1/s each rule on single samples that gives its time-scale form
(`hdselect.catalog.rules.Rule.scale_rows`: peak, static, emergency stop, crash, input
speed) is a quadratic inequality in y: `exact_scales` solves them all and intersects the
solutions. Every rule (those on the whole cycle, mean torque and life, and any rule
without the form) is then checked with `hdselect.catalog.rules.check_unit` itself on a
grid inside what is left, and each change of verdict is bisected.
Feasibility is not monotone in s: gravity and dynamic torque may oppose.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    RULES,
    Candidate,
    ScaleTerms,
    check_unit,
    cycle_load,
    targets_of,
)
from hdselect.catalog.units import Unit
from hdselect.sizing.bearing import ScalableWrench
from hdselect.sizing.intervals import Interval, intersect, overlap, solve_quadratics
from hdselect.sizing.reflect import DEFAULT_EFFICIENCY, reflect, weighted_demand

S_MIN = 1e-3
"""Fastest scale searched [-]: 1000 times faster is as good as infinitely fast; no
faster scale is claimed, so a reported interval never starts below it."""
S_MAX = 1e3
"""Slowest scale searched [-]: 1000 times slower is as good as standing still. A piece
passing there runs on to its exact interval's upper end, often infinity: slower still,
life only grows and the mean-torque allowance reaches the repeated-peak cap."""
RTOL = 1e-6
"""Relative accuracy in s of an end set by a whole-cycle rule [-]."""
GRID_PER_DECADE = 12
"""Scales per decade at which the whole-cycle rules are first checked; a passing or
failing stretch shorter than one step (a factor 10^(1/12) = 1.21) can be missed."""

_CHUNK = 1 << 15
"""Samples whose quadratic inequalities are solved at a time by `exact_scales`."""


@dataclass(frozen=True, eq=False)
class ScaledCycle:
    """One joint's cycle run s times slower [-]: what `rules` and `reflect` take.

    Attributes t [s], dt [s], duration [s], qd [rad/s], qdd [rad/s^2], at_rest and idle [s]
    are those of `ScalableCycle` at scale s; torque and stop_torque [N m] are the output
    torque along the motion and of an emergency stop from each sample, shape (n,).
    """

    s: float
    t: np.ndarray
    dt: np.ndarray
    duration: float
    qd: np.ndarray
    qdd: np.ndarray
    at_rest: np.ndarray
    torque: np.ndarray
    stop_torque: np.ndarray
    idle: float = 0.0


@dataclass(frozen=True, eq=False)
class ScalableCycle:
    """One joint's cycle at s = 1, its torque split by how each part scales with s.

    Arrays are read-only, shape (n,) (scalars are broadcast); RNEA is the joint's row.

    Attributes:
        t: Sample times [s].
        dt: Duration of each sample [s].
        duration: Cycle time [s].
        qd: Speed [rad/s].
        qdd: Acceleration [rad/s^2].
        at_rest: Samples where the joint is held still; the same at every s.
        gravity: g = RNEA(q, 0, 0) [N m]; the same at every s.
        velocity: v = RNEA(q, qd, 0) - g [N m]; scales as 1/s^2.
        inertial: i = RNEA(q, qd, qdd) - RNEA(q, qd, 0) [N m]; scales as 1/s^2.
        stop_inertial: e = RNEA(q, qd, -qd / stop_time) - RNEA(q, qd, 0) [N m], an
            emergency stop's inertial part; scales as 1/s.
        stop_time: Emergency-stop and crash time t_stop [s]; the same at every s.
        idle: Time at rest that no sample stands for [s] (`hdselect.sizing.tasks.Samples`);
            scales as s, as every task's cycle does, so the shares of the time stay.
        wrench: The joint's wrench split likewise, for a unit that rates its bearing.
    """

    t: np.ndarray
    dt: np.ndarray
    duration: float
    qd: np.ndarray
    qdd: np.ndarray
    at_rest: np.ndarray
    gravity: np.ndarray
    velocity: np.ndarray
    inertial: np.ndarray
    stop_inertial: np.ndarray
    stop_time: float
    idle: float = 0.0
    wrench: ScalableWrench | None = None

    def __post_init__(self) -> None:
        n = np.shape(self.t)
        if len(n) != 1 or not self.stop_time > 0.0:
            raise ValueError("a cycle needs 1-D samples and a positive stop time")
        for name in ("t", "dt", "qd", "qdd", "gravity", "velocity", "inertial",
                     "stop_inertial"):
            object.__setattr__(self, name, _shared(getattr(self, name), n))
        rest = np.array(np.broadcast_to(self.at_rest, n), dtype=bool)
        rest.setflags(write=False)
        object.__setattr__(self, "at_rest", rest)

    @classmethod
    def split(cls, t: np.ndarray, dt: np.ndarray | float, duration: float, qd: np.ndarray,
              qdd: np.ndarray, at_rest: np.ndarray, *, torque: np.ndarray,
              stop_torque: np.ndarray, gravity: np.ndarray, coast: np.ndarray,
              stop_time: float, idle: float = 0.0) -> ScalableCycle:
        """The cycle from the joint's torques at s = 1 [N m].

        `torque` is RNEA(q, qd, qdd), `stop_torque` RNEA(q, qd, -qd / stop_time),
        `gravity` RNEA(q, 0, 0), `coast` RNEA(q, qd, 0); the rest are attributes.
        """
        return cls(t, np.asarray(dt, dtype=float), duration, qd, qdd, at_rest, gravity,
                   coast - gravity, torque - coast, stop_torque - coast, stop_time, idle)

    def terms(self, part: slice = slice(None), rotor_inertia: float = 0.0,
              motor: Motor | None = None,
              targets: Mapping[str, Any] | None = None) -> ScaleTerms:
        """A piece of the cycle as the rules' time-scale form reads it (`Rule.scale_rows`).

        Args:
            part: The samples of the piece.
            rotor_inertia: The motor's rotor inertia J_m [kg m^2].
            motor: The paired motor, if any.
            targets: The joint's precision targets and load inertia (`TARGETS`), if any.
        """
        return ScaleTerms(self.gravity[part], self.velocity[part], self.inertial[part],
                          self.stop_inertial[part], self.qd[part], self.at_rest[part],
                          self.stop_time, rotor_inertia, motor, **targets_of(targets))

    def at(self, s: float) -> ScaledCycle:
        """The cycle run s times slower (s < 1: faster): exact for a fixed path.

        Returns:
            t s, dt s, qd / s, qdd / s^2, tau(s) = g + (v + i) / s^2 and
            stop(s) = g + v / s^2 + e / s.
        """
        y = 1.0 / s
        arrays = (self.t * s, self.dt * s, self.qd * y, self.qdd * y**2,
                  self.gravity + (self.velocity + self.inertial) * y**2,
                  self.gravity + self.velocity * y**2 + self.stop_inertial * y)
        for array in arrays:
            array.setflags(write=False)
        t, dt, qd, qdd, torque, stop = arrays
        return ScaledCycle(s, t, dt, self.duration * s, qd, qdd, self.at_rest, torque, stop,
                           self.idle * s)


def _shared(value: np.ndarray | float, shape: tuple[int, ...]) -> np.ndarray:
    """`value` as a read-only float array of `shape`, copied only if it could still change.

    A read-only array of the right shape is kept as it is, and a scalar is broadcast (a
    view of one number): a long cycle is not duplicated.
    """
    array = np.asarray(value, dtype=float)
    if array.ndim == 0 or (array.shape == shape and not array.flags.writeable):
        return np.broadcast_to(array, shape)
    return frozen(np.broadcast_to(array, shape))


@dataclass(frozen=True)
class Slowdown:
    """The smallest uniform slow-down of the motion that lets a joint pass.

    Attributes:
        factor: Time scale s [-]: the smallest s >= 1 at which some unit passes; if
            none does, the largest s < 1 (the joint passes only when run faster);
            None when no scale in [S_MIN, S_MAX] helps.
        unit: The unit that passes at that factor.
        cycle_time: The scaled cycle time [s].
    """

    factor: float | None
    unit: str | None
    cycle_time: float | None


@dataclass(frozen=True, eq=False)
class JointScales:
    """The time scales at which one joint passes, unit by unit.

    Attributes:
        duration: Cycle time at s = 1 [s].
        fits: Unit id (with motors, the pair's ``"unit + motor"``) -> the closed
            intervals of s at which that unit passes every rule (see
            `feasible_scales`), in catalog order; empty where none does.
    """

    duration: float
    fits: Mapping[str, tuple[Interval, ...]]

    def smallest(self, at_least: float = 0.0) -> tuple[float, str] | None:
        """The smallest s >= `at_least` [-] at which some unit passes, and that unit.

        By default the fastest the joint can go; on a tie the first unit wins; None if none.
        """
        best: tuple[float, str] | None = None
        for unit, intervals in self.fits.items():
            ends = [max(lo, at_least) for lo, hi in intervals if hi >= at_least]
            if ends and (best is None or ends[0] < best[0]):
                best = (ends[0], unit)
        return best

    def slowdown(self) -> Slowdown:
        """The smallest s >= 1 that fits, else the largest s < 1; see `Slowdown`."""
        found = self.smallest(1.0) or max(
            ((hi, unit) for unit, intervals in self.fits.items() for _, hi in intervals),
            key=lambda pair: pair[0], default=None)
        if found is None:
            return Slowdown(None, None, None)
        return Slowdown(found[0], found[1], found[0] * self.duration)


def check_at(cycle: ScalableCycle, unit: Unit, s: float, *,
             efficiency: float = DEFAULT_EFFICIENCY, rotor_inertia: float = 0.0,
             check_options: Mapping[str, Any] | None = None, motor: Motor | None = None,
             pair_options: Mapping[str, Any] | None = None) -> Candidate:
    """Every rule of one unit on the cycle run s times slower [-], as the sizing checks.

    The keywords are those of `feasible_scales`. Returns the candidate with its motor
    demand; with a `motor`, the pair, its rotor inertia used and its rules checked.
    """
    at = cycle.at(s)
    load = cycle_load(at.torque, at.qd, at.dt, at.at_rest, idle=at.idle)
    (reflection,) = reflect([unit], at.t, at.torque, at.qd, at.qdd, at.stop_torque,
                            stop_time=cycle.stop_time, efficiency=efficiency,
                            rotor_inertia=rotor_inertia if motor is None
                            else motor.rotor_inertia, rest=at.at_rest)
    demand = reflection.motor
    if at.dt.size and np.ptp(at.dt) > 0.0:  # samples of unequal length: RMS weighted by it
        demand = weighted_demand(demand, reflection.motor_torque, at.qd, unit.ratio, at.dt)
    bearing = (None if cycle.wrench is None or unit.bearing is None else
               cycle.wrench.load(s, at.qd, at.dt, at.at_rest, unit.bearing.offset))
    candidate = check_unit(load, unit, momentary=reflection.momentary, motor=demand,
                           bearing=bearing, **(check_options or {}))
    if motor is None:
        return candidate
    return with_motor(candidate, motor, reflection.motor_torque,
                      np.abs(at.qd) * unit.ratio * RPM_PER_RAD_S, **(pair_options or {}))


def exact_scales(cycle: ScalableCycle, unit: Unit, *, rotor_inertia: float = 0.0,
                 motor: Motor | None = None, margin: float = 0.0,
                 targets: Mapping[str, Any] | None = None) -> tuple[Interval, ...]:
    """The scales at which every rule with a time-scale form holds, solved exactly.

    Each registered rule gives its rows in y = 1/s (`Rule.scale_rows`), piece by piece
    of the cycle: peak (moving samples) and static (at rest): |tau(s)| <= the limit;
    emergency stop: |stop(s)| <= momentary limit; crash: |tau(s)| + K |qd| / s <=
    momentary limit, K = (J_in + J_m) N^2 / t_stop [N m s]; input speed: max |qd| N / s
    <= the unit's maximum [rpm] (and the motor's, with a `motor`, whose rotor inertia is
    then J_m). The rows are solved and intersected. A rule without the form (the motor's
    torque-speed rule, the whole-cycle rules) is left to `feasible_scales`' grid. With a
    design `margin` every limit is derated (`Rule.derate`). The joint's precision
    `targets` (`hdselect.catalog.rules.forms.TARGETS`) reach the rules that read them.

    Returns:
        Sorted disjoint closed intervals of s in (0, inf) [-]; lo may be 0, hi inf.
    """
    if motor is not None:
        rotor_inertia = motor.rotor_inertia
    found: list[Interval] = [(0.0, math.inf)]
    for start in range(0, len(cycle.t), _CHUNK):  # pieces of bounded memory, intersected
        if not found:
            break
        part = slice(start, start + _CHUNK)
        terms = cycle.terms(part, rotor_inertia, motor, targets)
        rows = [row for rule in RULES
                if (form := rule.scale_rows(terms, unit, margin)) is not None for row in form]
        if rows:
            c2, c1, c0 = (np.concatenate(column) for column in zip(*rows, strict=True))
            found = overlap(found, intersect(*solve_quadratics(c2, c1, c0)))
    return tuple((1.0 / y_hi, 1.0 / y_lo if y_lo > 0.0 else math.inf)
                 for y_lo, y_hi in reversed(found) if y_hi > 0.0)


def feasible_scales(cycle: ScalableCycle, unit: Unit, *, efficiency: float = DEFAULT_EFFICIENCY,
                    rotor_inertia: float = 0.0, check_options: Mapping[str, Any] | None = None,
                    motor: Motor | None = None, pair_options: Mapping[str, Any] | None = None,
                    ) -> tuple[Interval, ...]:
    """Every time scale s at which one unit passes every rule of `check_unit`.

    Inside each interval of `exact_scales`, clipped to [S_MIN, S_MAX], `check_at` is
    evaluated on a geometric grid (GRID_PER_DECADE; the ends taken RTOL inside) and
    each change of verdict is bisected to RTOL. A piece that passes at the upper end of
    its searched range runs on to the exact interval's own upper end (see S_MAX).

    Args:
        cycle: The joint's cycle.
        unit: The gearhead.
        efficiency: Gear efficiency where the unit has no table [-].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].
        check_options: Keywords for `hdselect.catalog.rules.check_unit`, e.g. ``life_hours``.
        motor: A motor paired with the unit: its rotor inertia replaces `rotor_inertia`,
            and its rules (`hdselect.catalog.rules.check_motor`) must hold too.
        pair_options: Keywords for `hdselect.catalog.motor_rules.with_motor`.

    Returns:
        Sorted disjoint closed intervals (lo, hi) of s [-], lo >= S_MIN, hi may be
        math.inf; empty when no s in [S_MIN, S_MAX] passes.
    """

    def passes(s: float) -> bool:
        return check_at(cycle, unit, s, efficiency=efficiency, rotor_inertia=rotor_inertia,
                        check_options=check_options, motor=motor,
                        pair_options=pair_options).feasible

    found: list[Interval] = []
    for lo, hi in exact_scales(cycle, unit, rotor_inertia=rotor_inertia, motor=motor,
                               margin=float((check_options or {}).get("margin", 0.0)),
                               targets=check_options):
        first, last = max(lo, S_MIN), min(hi, S_MAX)
        if first <= last:
            found.extend(_passing(passes, first, last, hi))
    return tuple(found)


def joint_scales(cycle: ScalableCycle, units: Sequence[Unit], *,
                 efficiency: float = DEFAULT_EFFICIENCY, rotor_inertia: float = 0.0,
                 check_options: Mapping[str, Any] | None = None, motors: Sequence[Motor] = (),
                 pair_options: Mapping[str, Any] | None = None) -> JointScales:
    """`feasible_scales` of every unit for one joint (same arguments, one unit each).

    With `motors`, of every (unit, motor) pair, keyed ``"unit + motor"``, unit by unit.
    """
    if motors:
        return JointScales(cycle.duration, {
            f"{unit.id} + {motor.id}": feasible_scales(
                cycle, unit, efficiency=efficiency, check_options=check_options, motor=motor,
                pair_options=pair_options)
            for unit in units for motor in motors})
    return JointScales(cycle.duration, {
        unit.id: feasible_scales(cycle, unit, efficiency=efficiency,
                                 rotor_inertia=rotor_inertia, check_options=check_options)
        for unit in units})


def find_slowdown(cycle: ScalableCycle, units: Sequence[Unit], *,
                  efficiency: float = DEFAULT_EFFICIENCY, rotor_inertia: float = 0.0,
                  check_options: Mapping[str, Any] | None = None) -> Slowdown:
    """`joint_scales(...).slowdown()`: the smallest slow-down over all units (`Slowdown`)."""
    return joint_scales(cycle, units, efficiency=efficiency, rotor_inertia=rotor_inertia,
                        check_options=check_options).slowdown()


def _passing(passes: Callable[[float], bool], first: float, last: float,
             hi: float) -> list[Interval]:
    """Where `passes` holds in [first, last]; a piece reaching `last` runs on to `hi`."""
    inner = (first * (1.0 + RTOL), last / (1.0 + RTOL))
    if inner[0] < inner[1]:
        count = math.ceil(GRID_PER_DECADE * math.log10(inner[1] / inner[0])) + 1
        grid = [float(s) for s in np.geomspace(*inner, max(count, 2))]
    else:
        grid = [math.sqrt(first * last)]
    verdicts = [passes(s) for s in grid]
    found: list[Interval] = []
    start = first
    for k in range(1, len(grid)):
        if verdicts[k] != verdicts[k - 1]:
            low, high = _bisect(passes, grid[k - 1], grid[k], verdicts[k - 1])
            if verdicts[k]:
                start = high
            else:
                found.append((start, low))
    if verdicts[-1]:
        found.append((start, hi))
    return found


def _bisect(passes: Callable[[float], bool], low: float, high: float,
            verdict: bool) -> Interval:
    """Narrow [low, high] to a factor 1 + RTOL around a change of verdict of `passes`."""
    while high > low * (1.0 + RTOL):
        middle = math.sqrt(low * high)
        low, high = (middle, high) if passes(middle) == verdict else (low, middle)
    return low, high
