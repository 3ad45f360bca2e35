"""The rules over the whole cycle on TOPPRA's run: the smallest slow-down, the derating, the check.

TOPPRA (`hdselect.codesign.fastpath`) meets every rule on single samples that gives a path form
(`hdselect.codesign.pathbounds.path_bounds`). The rules over the whole cycle (mean
torque, life, average input speed), and any rule on single samples without a path form
(`after_solve`), are checked on its run with the sizing's own `check_unit`. Where one
fails, `smallest_scale` finds the smallest uniform slow-down s of the moves (dwells
keep their length) at which every rule of every joint passes, with the exact time
scaling of `hdselect.timescale`: the rules on single samples exactly, the whole-cycle
rules on 1 % steps, bisected to 1e-6. `derated` instead holds the failing joints to a
fraction of their repeated-peak limit (0.9, 0.8, ..., re-solved by TOPPRA, each with its
own smallest slow-down) and refines the best by golden section: the moves keep their
speed while the torque drops. `verified` samples the winner on the motion's grid and
checks it with `hdselect.sizing.core.check_units`, slowing it by the excess where a
sample lands on a peak the scaled model missed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

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
from hdselect.codesign.fastpath import (
    PathModel,
    cycle,
    kinematic_scales,
    slowdown_notes,
    solve,
)
from hdselect.codesign.pathbounds import JointLimits, PathInfeasible, joint_limits
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.motion.planning.toppra import Profile
from hdselect.robot.dynamics import cycle_torques
from hdselect.robot.model import Robot
from hdselect.sizing.core import check_units
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import reflect, weighted_demand
from hdselect.sizing.result import SizingResult
from hdselect.sizing.timescale import S_MAX, ScalableCycle, exact_scales

DERATINGS = (0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3)
"""Fractions of the repeated-peak limit tried, until the cycle stops getting shorter."""
DERATING_RESOLUTION = 0.01
"""Width to which the best derating is refined [-]."""
SCALE_STEP = 1.01
"""Step of the search for the smallest slow-down, before bisection [-]."""
SCALE_RTOL = 1e-6
"""Relative accuracy of the slow-down [-]."""
WRITTEN_MARGIN = 1e-7
"""Utilization a rule that scales with speed must stay below 1 by, so that the
trajectory written with 10 significant digits passes too [-]."""
_VERIFY_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class Trial:
    """TOPPRA's profiles for one derating, and the smallest slow-down that passes."""

    derating: Mapping[str, float]
    profiles: list[Profile | None]
    kinematic: list[float]
    moving: float
    dwell: float
    scale: float
    reason: tuple[str, str] | None
    whole_cycle_failing: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def cycle_time(self) -> float:
        """Its cycle at its slow-down [s]."""
        return self.moving * self.scale + self.dwell


def run_trial(model: PathModel, carrying: Robot, units: Mapping[str, Unit],
              masses: Mapping[str, float], derating: Mapping[str, float],
              options: Options, motors: Mapping[str, Motor] | None = None) -> Trial:
    """Solve TOPPRA at one derating and find the smallest slow-down at which all passes.

    `motors`: the motor behind the unit of some joints (its limits and rules apply).
    """
    motion = model.motion
    motors = motors or {}
    limits = joint_limits(model.robot, motion, units, options, derating, motors=motors)
    profiles = solve(model, limits, masses, stop_time=options.stop_time)
    kinematic = kinematic_scales(profiles, limits)
    trajectory, held = cycle(motion, profiles, kinematic, max_samples=options.max_samples)
    moving = sum(p.duration * r for p, r in zip(profiles, kinematic, strict=True)
                 if p is not None)
    cycles, held = _scalable(carrying, trajectory, held, units, options)
    scale, reason = smallest_scale(cycles, held, units, options, motion, motors)
    after = {name: after_solve(lim) for name, lim in zip(model.robot.joint_names, limits,
                                                          strict=True)}
    failing = {name for name, cycle_ in cycles.items()
               if any(not c.ok for rule, c in _check_scaled(cycle_, held, units[name], 1.0,
                                                             options, motors.get(name)
                                                             ).checks.items()
                      if rule in after[name])}
    return Trial(dict(derating), profiles, kinematic, moving, trajectory.duration - moving,
                 scale, reason, tuple(sorted(failing)),
                 slowdown_notes(motion.joint_names, profiles, limits))


def after_solve(limits: JointLimits) -> frozenset[str]:
    """The rules of a joint's unit that TOPPRA does not hold and a derating may fix.

    The gearhead's rules on the whole cycle (mean torque, life, average input speed,
    whatever else is registered), and every per-sample rule without a path form
    (`JointLimits.unbounded`): each is checked forward on TOPPRA's run.
    """
    return frozenset(rule.name for rule in RULES
                     if (rule.part is Part.GEARHEAD and rule.scope is Scope.CYCLE)
                     or rule.name in limits.unbounded)


def _scalable(carrying: Robot, trajectory: Trajectory, held: np.ndarray,
              units: Mapping[str, Unit],
              options: Options) -> tuple[dict[str, ScalableCycle], np.ndarray]:
    """Each sized joint's cycle split by how its torque scales with time (four passes).

    A dwell holds one pose at rest: it is kept as one sample that lasts the whole
    dwell, which every rule weighs alike (the motor's RMS torque, which assumes equal
    samples, is not a rule).

    Returns:
        The cycles by joint, and which of their samples are dwells.
    """
    keep = np.flatnonzero(~held | np.r_[True, ~held[:-1]])
    lasts = np.diff(np.r_[keep, len(held)]) * trajectory.dt
    q, qd, qdd = trajectory.q[keep], trajectory.qd[keep], trajectory.qdd[keep]
    dt = np.where(held[keep], lasts, trajectory.dt)
    torques = cycle_torques(carrying, q, qd, qdd, options.stop_time, split=True,
                            threads=options.threads)
    if torques.gravity is None or torques.coasting is None:
        raise RuntimeError("cycle_torques(split=True) returned no gravity or coasting part")
    out = {}
    for name in units:
        j = carrying.joint_index(name)
        out[name] = ScalableCycle.split(
            trajectory.t[keep], dt, trajectory.duration, qd[:, j], qdd[:, j],
            at_rest(qd[:, j], qdd[:, j]), torque=torques.tau[:, j],
            stop_torque=torques.stop[:, j], gravity=torques.gravity[:, j],
            coast=torques.coasting[:, j], stop_time=options.stop_time)
    return out, held[keep]


def _check_scaled(cycle_: ScalableCycle, held: np.ndarray, unit: Unit, s: float,
                  options: Options, motor: Motor | None = None) -> Candidate:
    """Every rule of `check_unit` on a joint's cycle with its moves run s times slower [-].

    As `hdselect.sizing.timescale.check_at`, except that dwells keep their length; with
    a motor, its rules too (`with_motor`), its RMS torque weighing each sample by the
    time it stands for.
    """
    at = cycle_.at(s)
    dt = np.where(held, cycle_.dt, at.dt)
    load = cycle_load(at.torque, at.qd, dt, at.at_rest)
    (reflection,) = reflect([unit], at.t, at.torque, at.qd, at.qdd, at.stop_torque,
                            stop_time=cycle_.stop_time, efficiency=options.efficiency,
                            rotor_inertia=(motor.rotor_inertia if motor is not None
                                           else options.rotor_inertia))
    if motor is None:
        return check_unit(load, unit, momentary=reflection.momentary, motor=reflection.motor,
                          life_hours=options.life_hours, life_basis=options.life_basis,
                          margin=options.margin)
    torque = reflection.motor_torque
    demand = weighted_demand(reflection.motor, torque, at.qd, unit.ratio, dt)
    candidate = check_unit(load, unit, momentary=reflection.momentary, motor=demand,
                           life_hours=options.life_hours, life_basis=options.life_basis,
                           margin=options.margin)
    return with_motor(candidate, motor, torque, np.abs(at.qd) * RPM_PER_RAD_S * unit.ratio)


def _failing(cycles: Mapping[str, ScalableCycle], held: np.ndarray,
             units: Mapping[str, Unit], options: Options, s: float,
             motors: Mapping[str, Motor] | None = None) -> tuple[str, str] | None:
    """The (joint, rule) that fails worst at scale s [-], or None when all pass."""
    worst: tuple[float, str, str] | None = None
    for name, cycle_ in cycles.items():
        candidate = _check_scaled(cycle_, held, units[name], s, options,
                                  (motors or {}).get(name))
        if not candidate.feasible:
            rule = candidate.binding
            utilization = candidate.checks[rule].utilization
            if worst is None or utilization > worst[0]:
                worst = (utilization, name, rule)
    return None if worst is None else (worst[1], worst[2])


def smallest_scale(cycles: Mapping[str, ScalableCycle], held: np.ndarray,
                   units: Mapping[str, Unit], options: Options, motion: Motion,
                   motors: Mapping[str, Motor] | None = None
                   ) -> tuple[float, tuple[str, str] | None]:
    """The smallest s >= 1 [-] at which every joint passes every rule, and what set it.

    The rules on single samples give exact intervals of s (`exact_scales`); inside
    them the whole-cycle rules are checked on steps of `SCALE_STEP` (20 % beyond
    s = 2) and the first pass is bisected to `SCALE_RTOL`.

    Returns:
        s, and the (joint, rule) failing just below it (None when s = 1).

    Raises:
        PathInfeasible: No s from 1 to `S_MAX` passes.
    """
    motors = motors or {}
    feasible: list[tuple[float, float]] = [(1.0, S_MAX)]
    for name, cycle_ in cycles.items():
        motor = motors.get(name)
        feasible = _intersect(feasible, list(exact_scales(
            cycle_, units[name], rotor_inertia=(motor.rotor_inertia if motor is not None
                                                else options.rotor_inertia),
            margin=options.margin)))
        if not feasible:
            failing = _failing({name: cycle_}, held, units, options, S_MAX, motors)
            raise hopeless(motion, name, failing[1] if failing else "peak", units[name])

    def fails(s: float) -> tuple[str, str] | None:
        return _failing(cycles, held, units, options, s, motors)

    last = [next(iter(cycles))]  # the joint that failed last: most likely to fail again

    def passes(s: float) -> bool:
        """Whether every joint passes at s: the last joint to fail is checked first."""
        for name in (last[0], *(name for name in cycles if name != last[0])):
            if not _check_scaled(cycles[name], held, units[name], s, options,
                                 motors.get(name)).feasible:
                last[0] = name
                return False
        return True

    found = first_passing(feasible, passes, fails)
    if found is not None:
        return found
    name, rule = fails(S_MAX) or (next(iter(cycles)), "mean")
    raise hopeless(motion, name, rule, units[name])


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


def hopeless(motion: Motion, joint: str, rule: str, unit: Unit) -> PathInfeasible:
    """The error for a rule no speed lets the unit pass."""
    return PathInfeasible(f"{motion.path}: joint '{joint}' fails its {rule} rule with "
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


def derated(model: PathModel, carrying: Robot, units: Mapping[str, Unit],
            masses: Mapping[str, float], first: Trial, options: Options,
            motors: Mapping[str, Motor] | None = None) -> Trial:
    """The derating of the failing joints' torque limits that gives the shortest cycle."""
    joints = first.whole_cycle_failing

    def attempt(fraction: float) -> Trial | None:
        try:
            return run_trial(model, carrying, units, masses, dict.fromkeys(joints, fraction),
                             options, motors)
        except PathInfeasible:
            return None

    tried: dict[float, Trial | None] = {1.0: first}
    best, previous = first, first.cycle_time
    for fraction in DERATINGS:
        found = tried[fraction] = attempt(fraction)
        if found is None or found.cycle_time > previous:
            break
        previous = found.cycle_time
        if found.cycle_time < best.cycle_time:
            best = found
    centre = max(best.derating.values(), default=1.0)
    lo, hi = max(centre - 0.1, 0.05), min(centre + 0.1, 1.0)
    golden = (math.sqrt(5.0) - 1.0) / 2.0

    def cycle_at(fraction: float) -> float:
        if fraction not in tried:
            tried[fraction] = attempt(fraction)
        found = tried[fraction]
        return math.inf if found is None else found.cycle_time

    x1, x2 = hi - golden * (hi - lo), lo + golden * (hi - lo)
    while hi - lo > DERATING_RESOLUTION:
        if cycle_at(x1) <= cycle_at(x2):
            hi, x2 = x2, x1
            x1 = hi - golden * (hi - lo)
        else:
            lo, x1 = x1, x2
            x2 = lo + golden * (hi - lo)
    for found in tried.values():
        if found is not None and found.cycle_time < best.cycle_time:
            best = found
    return best


def verified(model: PathModel, units: Mapping[str, Unit], trial: Trial,
             options: Options, motors: Mapping[str, Motor] | None = None
             ) -> tuple[Trajectory, np.ndarray, SizingResult, float]:
    """The trajectory on the motion's grid and its check, slowed until every rule passes.

    Returns:
        The trajectory, its dwell samples, its check and the slow-down [-].
    """
    scale = trial.scale
    passing = None
    for _ in range(_VERIFY_ROUNDS):
        trajectory, held = cycle(model.motion, trial.profiles,
                                 [r * scale for r in trial.kinematic],
                                 max_samples=options.max_samples, notes=trial.notes)
        check = check_units(model.robot, trajectory, units, options, motors=motors)
        candidates = [c for joint in check.joints for c in joint.candidates]
        excess = max((c.checks[rule].utilization for c in candidates for rule in c.checks
                      if rule != "static"), default=0.0) / (1.0 - options.margin)
        if check.feasible:
            passing = passing or (trajectory, held, check, scale)
            if excess <= 1.0 - WRITTEN_MARGIN:
                return trajectory, held, check, scale
        if any(not c.checks["static"].ok for c in candidates):
            break  # a held load: no speed helps
        scale *= max(math.sqrt(excess), 1.0 + 10.0 * WRITTEN_MARGIN)
    if passing is not None:  # at its limit to within the margin, whatever the speed
        return passing
    failing = [(joint.name, c.binding) for joint in check.joints for c in joint.candidates
               if not c.feasible]
    name, rule = failing[0] if failing else (next(iter(units)), "peak")
    raise hopeless(model.motion, name, rule, units[name])
