"""The rules over the whole cycle on TOPPRA's runs: the smallest common slow-down.

TOPPRA (`hdselect.codesign.fastpath`) meets every rule on single samples that gives a
path form (`hdselect.codesign.pathbounds`). The rules over the whole cycle (mean torque,
life, average input speed), and any rule on single samples without a path form
(`after_solve`), are checked on its runs with the sizing's own `check_unit`, every task
of a duty pooled at its share of the time (`check_scaled`; one task is a duty of one).
Where one fails, `smallest_scale` finds the smallest common slow-down s of every task's
moves (dwells keep their length) at which every rule of every joint passes, with the
exact time scaling of `hdselect.sizing.timescale`: the rules on single samples exactly
(each task's intervals intersected), the whole-cycle rules on 1 % steps, bisected to 1e-6.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    RULES,
    Candidate,
    Part,
    Scope,
    at_rest,
    check_unit,
    cycle_load,
)
from hdselect.catalog.units import Unit
from hdselect.codesign.fastpath import PathModel
from hdselect.codesign.pathbounds import JointLimits, PathInfeasible
from hdselect.motion.planning.toppra import Profile
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import reflect, weighted_demand
from hdselect.sizing.timescale import S_MAX, ScalableCycle, exact_scales

SCALE_STEP = 1.01
"""Step of the search for the smallest slow-down, before bisection [-]."""
SCALE_RTOL = 1e-6
"""Relative accuracy of the slow-down [-]."""
WRITTEN_MARGIN = 1e-7
"""Utilization a rule that scales with speed must stay below 1 by, so that the
trajectory written with 10 significant digits passes too [-]."""


@dataclass(frozen=True, eq=False)
class Leg:
    """One task's path run at one derating: TOPPRA's profiles and the cycle they give.

    Attributes:
        model: The task's path.
        share: The task's share of the time [-].
        profiles: TOPPRA's profile of each piece (None: a piece that does not move).
        kinematic: Each piece's slow-down that keeps its speeds and accelerations [-].
        moving: The time of the moves [s].
        dwell: The time of the dwells [s].
        cycles: Each sized joint's cycle, split by how its torque scales with time.
        held: Which samples of `cycles` are dwells (their time does not scale).
        notes: The planner's lines for pieces slowed beyond its tolerance.
    """

    model: PathModel
    share: float
    profiles: list[Profile | None]
    kinematic: list[float]
    moving: float
    dwell: float
    cycles: Mapping[str, ScalableCycle]
    held: np.ndarray
    notes: tuple[str, ...] = ()

    @property
    def optimum(self) -> float:
        """Its cycle at the kinematic slow-downs alone [s]."""
        return self.moving + self.dwell


def after_solve(limits: JointLimits) -> frozenset[str]:
    """The rules of a joint's unit that TOPPRA does not hold and a derating may fix.

    The gearhead's rules on the whole cycle (mean torque, life, average input speed,
    whatever else is registered), and every per-sample rule without a path form
    (`JointLimits.unbounded`): each is checked forward on TOPPRA's run.
    """
    return frozenset(rule.name for rule in RULES
                     if (rule.part is Part.GEARHEAD and rule.scope is Scope.CYCLE)
                     or rule.name in limits.unbounded)


def check_scaled(legs: Sequence[Leg], name: str, unit: Unit, s: float, options: Options,
                 motor: Motor | None = None, idle: float = 0.0) -> Candidate:
    """Every rule of `check_unit` on a joint's duty with every task's moves s times slower [-].

    As `hdselect.sizing.timescale.check_at`, except that dwells keep their length. Each
    task's samples weigh by how often its cycle runs at its share (share / cycle time at
    s), as `hdselect.sizing.tasks.pooled` weighs them; the idle time is a pause. With a
    motor, its rules too (`with_motor`), its RMS torque weighing each sample by the time
    it stands for.
    """
    parts = []
    for leg in legs:
        cycle_ = leg.cycles[name]
        at = cycle_.at(s)
        dt = np.where(leg.held, cycle_.dt, at.dt)
        parts.append((at, dt, leg.share / float(dt.sum())))
    reference = parts[0][2]
    dt = _joined([step * (rate / reference) for _, step, rate in parts])

    def joined(field: str) -> np.ndarray:
        return _joined([getattr(at, field) for at, _, _ in parts])

    torque, qd, rest = joined("torque"), joined("qd"), joined("at_rest")
    load = cycle_load(torque, qd, dt, rest, idle=idle / reference)
    (reflection,) = reflect([unit], joined("t"), torque, qd, joined("qdd"),
                            joined("stop_torque"), stop_time=options.stop_time,
                            efficiency=options.efficiency,
                            rotor_inertia=(motor.rotor_inertia if motor is not None
                                           else options.rotor_inertia),
                            rest=_joined([at_rest(at.qd, at.qdd) for at, _, _ in parts]))
    if motor is None:  # the motor demand is carried, not judged: no weights needed
        return check_unit(load, unit, momentary=reflection.momentary, motor=reflection.motor,
                          life_hours=options.life_hours, life_basis=options.life_basis,
                          margin=options.margin, **_twist(options, name))
    demand = weighted_demand(reflection.motor, reflection.motor_torque, qd, unit.ratio, dt)
    candidate = check_unit(load, unit, momentary=reflection.momentary, motor=demand,
                           life_hours=options.life_hours, life_basis=options.life_basis,
                           margin=options.margin, **_twist(options, name))
    return with_motor(candidate, motor, reflection.motor_torque,
                      np.abs(qd) * RPM_PER_RAD_S * unit.ratio)


def _twist(options: Options, name: str) -> dict[str, Any]:
    """The joint's largest twist, the precision target a time scale changes.

    Its natural frequency does not change with the time scale: the sizing that chose
    the units judged it.
    """
    return {"max_torsion": options.joint_value("max_torsion", name)}


def _joined(arrays: Sequence[np.ndarray]) -> np.ndarray:
    """The tasks' arrays end to end (one task's as it is)."""
    return arrays[0] if len(arrays) == 1 else np.concatenate(arrays)


def _failing(legs: Sequence[Leg], names: Sequence[str], units: Mapping[str, Unit],
             options: Options, s: float, motors: Mapping[str, Motor], idle: float
             ) -> tuple[str, str] | None:
    """The (joint, rule) of `names` that fails worst at scale s [-], or None when all pass."""
    worst: tuple[float, str, str] | None = None
    for name in names:
        candidate = check_scaled(legs, name, units[name], s, options, motors.get(name), idle)
        if not candidate.feasible:
            rule = candidate.binding
            utilization = candidate.checks[rule].utilization
            if worst is None or utilization > worst[0]:
                worst = (utilization, name, rule)
    return None if worst is None else (worst[1], worst[2])


def smallest_scale(legs: Sequence[Leg], units: Mapping[str, Unit], options: Options,
                   where: str, motors: Mapping[str, Motor] | None = None, idle: float = 0.0
                   ) -> tuple[float, tuple[str, str] | None]:
    """The smallest common s >= 1 [-] at which every joint passes every rule, and what set it.

    The rules on single samples give exact intervals of s (`exact_scales`), intersected
    over the tasks; inside them the whole-cycle rules are checked on steps of
    `SCALE_STEP` (20 % beyond s = 2) and the first pass is bisected to `SCALE_RTOL`.

    Returns:
        s, and the (joint, rule) failing just below it (None when s = 1).

    Raises:
        PathInfeasible: No s from 1 to `S_MAX` passes (the message names `where`).
    """
    motors = motors or {}
    names = list(units)
    duty = len(legs) > 1
    feasible: list[tuple[float, float]] = [(1.0, S_MAX)]
    for name in names:
        motor = motors.get(name)
        for leg in legs:
            feasible = _intersect(feasible, list(exact_scales(
                leg.cycles[name], units[name],
                rotor_inertia=(motor.rotor_inertia if motor is not None
                               else options.rotor_inertia), margin=options.margin,
                targets=_twist(options, name))))
        if not feasible:
            failing = _failing(legs, [name], units, options, S_MAX, motors, idle)
            raise hopeless(where, name, failing[1] if failing else "peak", units[name], duty)

    def fails(s: float) -> tuple[str, str] | None:
        return _failing(legs, names, units, options, s, motors, idle)

    last = [names[0]]  # the joint that failed last: most likely to fail again

    def passes(s: float) -> bool:
        """Whether every joint passes at s: the last joint to fail is checked first."""
        for name in (last[0], *(name for name in names if name != last[0])):
            if not check_scaled(legs, name, units[name], s, options, motors.get(name),
                                idle).feasible:
                last[0] = name
                return False
        return True

    found = first_passing(feasible, passes, fails)
    if found is not None:
        return found
    name, rule = fails(S_MAX) or (names[0], "mean")
    raise hopeless(where, name, rule, units[name], duty)


def first_passing(feasible: Sequence[tuple[float, float]], passes: Callable[[float], bool],
                  fails: Callable[[float], tuple[str, str] | None]
                  ) -> tuple[float, tuple[str, str] | None] | None:
    """The smallest slow-down s [-] within `feasible` at which `passes` holds, and why not below.

    s steps up through each interval by `SCALE_STEP` (20 % beyond s = 2); the first step
    that passes is bisected (geometrically) down to `SCALE_RTOL`.

    Args:
        feasible: Intervals of s where the rules of single samples pass, ascending.
        passes: Whether every rule passes at s.
        fails: The (joint, rule) that fails at s, or None.

    Returns:
        s and the (joint, rule) failing just below it (None at s = 1); None when no s
        within `feasible` passes.
    """
    for lo, hi in feasible:
        below: float | None = None
        s = lo
        while True:
            if passes(s):
                if below is None:
                    return s, (fails(s / (1.0 + 1e-3)) if s > 1.0 else None)
                low, high = below, s
                while high > low * (1.0 + SCALE_RTOL):
                    middle = math.sqrt(low * high)
                    low, high = (low, middle) if passes(middle) else (middle, high)
                return high, fails(low)
            below = s
            if s >= hi:
                break
            s = min(hi, s * (SCALE_STEP if s < 2.0 else 1.2))
    return None


def hopeless(where: str, joint: str, rule: str, unit: Unit,
             duty: bool = False) -> PathInfeasible:
    """The error for a rule no speed lets the unit pass (`duty`: over several tasks)."""
    over = " over the duty" if duty else ""
    return PathInfeasible(f"{where}: joint '{joint}' fails its {rule} rule{over} with "
                          f"{unit.id} at every speed (from as fast as the limits allow to "
                          f"{S_MAX:g} times slower)", joint=joint, limit=rule,
                          gravity=rule in ("static", "peak", "momentary"))


def _intersect(a: list[tuple[float, float]],
               b: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Intersection of two sorted lists of disjoint closed intervals."""
    out = []
    for lo1, hi1 in a:
        for lo2, hi2 in b:
            lo, hi = max(lo1, lo2), min(hi1, hi2)
            if lo <= hi:
                out.append((lo, hi))
    return sorted(out)
