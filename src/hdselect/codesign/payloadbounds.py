"""One unit's payload masses on one joint: every registered rule, by its form or forward.

For a fixed trajectory the joint's torques are affine in the payload mass x,
tau = tau0 + x tau1 (and the emergency stop's). A rule's payload form
(`hdselect.catalog.rules.Rule.payload_masses`) gives the masses at which it holds
exactly; a rule without one is checked forward (`check_unit` on the cycle carrying x,
`forward_masses`) on a grid of masses inside what the other rules allow, each change of
its verdict bisected, so that no rule of the registry is left out. A rule absent for the
case (a motor's without a motor, a rated bearing's without the joint's wrench) bounds
nothing here: `hdselect.codesign.payloadsizing` judges those with the sizing itself.

`duty_bounds` gives every unit's interval on every joint of a duty, its tasks pooled:
the payload solver of `hdselect.codesign.maxpayload`, and the "less payload" step of
a diagnosis (`hdselect.sizing.diagnosis`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hdselect.catalog.rules import (
    RULES,
    Candidate,
    CycleLoad,
    Momentary,
    MotorDemand,
    Part,
    Rule,
    check_unit,
    cycle_load,
)
from hdselect.catalog.rules.forms import Interval, PayloadCase
from hdselect.catalog.rules.masses import meet
from hdselect.catalog.units import Unit
from hdselect.codesign.cubicmean import CubicMean
from hdselect.codesign.scaledpart import scaled_part, with_part
from hdselect.robot.dynamics import CycleTorques, cycle_torques, joint_inertias
from hdselect.robot.model import Robot
from hdselect.robot.wrenches import axis_wrenches
from hdselect.sizing.bearing import SampledWrench, cycle_bearing
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import DEFAULT_EFFICIENCY, reflect, weighted_demand
from hdselect.sizing.tasks import Task, over_states, pooled
from hdselect.sizing.torques import inertia_poses

MASS_GRID = 25
"""Masses at which a rule without a payload form is first checked forward [-]."""
MASS_RTOL = 1e-9
"""Relative width to which each change of its verdict is bisected [-]."""
MASS_MAX = 1e4
"""Heaviest payload searched where no other rule bounds the mass [kg]: a rule without a
payload form that still passes there is taken to pass at any mass."""


@dataclass(frozen=True)
class UnitBound:
    """The payload masses at which one unit passes every rule on one joint.

    Attributes:
        unit: The unit.
        masses: The interval of masses [kg], or None when no mass >= 0 passes.
        ends: For each rule, the interval of masses it allows [kg] (None: none).
    """

    unit: Unit
    masses: Interval | None
    ends: Mapping[str, Interval | None]

    def limiting(self, mass: float) -> str:
        """The rule whose interval ends at (or closest above) `mass` [kg]."""
        hi = {rule: span[1] if span is not None else -math.inf
              for rule, span in self.ends.items()}
        return min(hi, key=lambda rule: abs(hi[rule] - mass))


def joint_mean(dt: float | np.ndarray, rest: np.ndarray, qd: np.ndarray, tau0: np.ndarray,
               tau1: np.ndarray) -> CubicMean:
    """A joint's cubic mean torque as a function of x, tau = tau0 + x tau1 [N m].

    The catalog's weights, |qd| dt over the moving samples, do not depend on the unit:
    one `CubicMean` (one sort of the samples' roots) serves every unit of the joint.

    Args:
        dt: What each sample stands for [s], a number or (n,).
        rest: Where the joint is held still, (n,).
        qd: The joint's speed [rad/s], (n,).
        tau0: Torque at x = 0 [N m], (n,).
        tau1: Its change per unit of x [N m], (n,).
    """
    step = np.broadcast_to(np.asarray(dt, dtype=float), np.shape(qd))
    return CubicMean(tau0, tau1, np.abs(qd) * step * ~rest)


def unit_bound(unit: Unit, dt: float | np.ndarray, rest: np.ndarray, qd: np.ndarray,
               tau0: np.ndarray, tau1: np.ndarray, stop0: np.ndarray, stop1: np.ndarray,
               options: Options, idle: float = 0.0, *, cubic: CubicMean | None = None,
               t: np.ndarray | None = None, qdd: np.ndarray | None = None,
               wrench: tuple[np.ndarray, np.ndarray, float] | None = None,
               targets: Mapping[str, Any] | None = None) -> UnitBound:
    """Every registered rule as an interval of x, with tau = tau0 + x tau1 [N m].

    Each rule's payload form gives its masses; a rule without one is checked forward
    (`forward_masses`): the gearhead's, and its output bearing's where the joint's wrench
    is given (`check_unit` judges no motor, and the bearing only on its loads). A unit's
    masses are the lowest interval where every rule holds (a later one, beyond a gap, is
    not claimed: no shipped form gives one).

    Args:
        unit: The unit.
        dt: What each sample stands for [s] (pooled samples: `hdselect.sizing.tasks`).
        rest: Where the joint is held still, (n,).
        qd: The joint's speed [rad/s], (n,).
        tau0: Torque at x = 0 [N m], (n,).
        tau1: Its change per unit of x [N m], (n,).
        stop0: Emergency-stop torque at x = 0 [N m], (n,).
        stop1: Its change per unit of x [N m], (n,).
        options: The assumptions.
        idle: Time at rest no sample stands for [s] (a pause in a whole-cycle mean speed).
        cubic: The joint's mean torque (`joint_mean` of the same samples), shared by its
            units; None builds it where the joint moves.
        t: Sample times [s], (n,), for the forward checks' momentary event; None: from dt.
        qdd: The joint's acceleration [rad/s^2], (n,): the forward checks then carry the
            motor's demand.
        wrench: The joint's wrench at x = 0 and per kg [N, N m], each (6, n), and its
            output flange's offset [m]: the forward checks then judge a rated bearing.
        targets: The joint's precision targets (``max_torsion``, ``min_frequency``) and,
            with a frequency target, its load inertia at each pose at x = 0 and per unit
            of x (``inertia0``, ``inertia1``), as `PayloadCase` takes them.
    """
    step = np.broadcast_to(np.asarray(dt, dtype=float), np.shape(qd))
    case = PayloadCase(unit, step, rest, qd, tau0, tau1, stop0, stop1, options.margin,
                       options.stop_time, options.rotor_inertia, idle, options.life_hours,
                       options.life_basis, cubic, options.efficiency, t, qdd,
                       *(wrench or (None, None, 0.0)), **(targets or {}))
    if cubic is None and case.travel > 0.0:
        case = replace(case, mean=joint_mean(step, rest, qd, tau0, tau1))
    judged = (Part.GEARHEAD, Part.BEARING) if case.wrench0 is not None else (Part.GEARHEAD,)
    ends: dict[str, Interval | None] = {}
    unformed = []
    masses: Interval | None = (0.0, math.inf)
    for rule in RULES:
        found = rule.payload_masses(case)
        if found is None:
            if rule.part in judged:  # `check_unit` judges no other part
                unformed.append(rule)
            continue
        ends[rule.name] = found[0] if found else None
        masses = meet(masses, ends[rule.name])
    if unformed and masses is not None:
        for name, span in forward_masses(case, unformed, masses).items():
            ends[name] = span
            masses = meet(masses, span)
    return UnitBound(unit, masses, ends)


def forward_check(case: PayloadCase, mass: float) -> Candidate:
    """Every rule of `check_unit` on the cycle carrying `mass` [kg], as the sizing checks.

    The momentary event is `reflect`'s; the motor's demand is handed to the rules only
    with the joint's acceleration and an efficiency (`PayloadCase.qdd`, `.efficiency`),
    the output bearing's loads only with the joint's wrench (`PayloadCase.wrench0`).
    """
    tau = case.tau0 + mass * case.tau1
    stop = case.stop0 + mass * case.stop1
    load = cycle_load(tau, case.qd, case.dt, case.rest, idle=case.idle)
    t = np.cumsum(case.dt) - case.dt if case.t is None else case.t
    known = case.qdd is not None and case.efficiency is not None
    efficiency = case.efficiency if case.efficiency is not None else DEFAULT_EFFICIENCY
    bearing = None
    if case.wrench0 is not None and case.wrench1 is not None and case.unit.bearing is not None:
        bearing = cycle_bearing(SampledWrench(case.wrench0 + mass * case.wrench1), case.offset,
                                case.unit.bearing.offset, case.qd, case.dt, case.rest)
    (reflection,) = reflect([case.unit], t, tau, case.qd,
                            case.qdd if case.qdd is not None else np.zeros_like(tau), stop,
                            stop_time=case.stop_time, efficiency=efficiency,
                            rotor_inertia=case.rotor_inertia, rest=case.rest)
    demand = reflection.motor
    if known and case.dt.size and np.ptp(case.dt) > 0.0:  # unequal samples: RMS weighted
        demand = weighted_demand(demand, reflection.motor_torque, case.qd, case.unit.ratio,
                                 case.dt)
    return check_unit(load, case.unit, momentary=reflection.momentary,
                      motor=demand if known else None, bearing=bearing,
                      life_hours=case.life_hours, life_basis=case.life_basis,
                      margin=case.margin, max_torsion=case.max_torsion,
                      min_frequency=case.min_frequency, load_inertia=case.inertia_at(mass))


def forward_masses(case: PayloadCase, rules: Sequence[Rule],
                   inside: Interval) -> dict[str, Interval | None]:
    """The masses at which each rule without a payload form holds, by its forward check.

    `forward_check` on `MASS_GRID` masses from `inside`'s lower end, spaced geometrically
    in their distance from it up to its upper end (`MASS_MAX` where that is infinite);
    the first passing stretch's ends are bisected to `MASS_RTOL`, each on the passing side.
    A rule that passes at the grid's last mass is taken to pass up to `inside`'s end; a
    later passing stretch, after one that fails, is not claimed (conservative).

    Args:
        case: The unit on the joint.
        rules: The rules without a payload form.
        inside: The masses the other rules allow [kg], lo >= 0.

    Returns:
        Per rule present for the case (its check not None), its interval or None.
    """
    lo, hi = inside
    top = hi if math.isfinite(hi) else max(MASS_MAX, 2.0 * lo)
    grid = [lo, *(lo + (top - lo) * np.geomspace(1e-6, 1.0, MASS_GRID - 1))] \
        if top > lo else [lo]
    judged = _present(case)
    present = [rule for rule in rules if rule.name in judged]
    if not present:
        return {}

    def verdicts(mass: float) -> dict[str, bool]:
        checks = forward_check(case, mass).checks
        return {rule.name: checks[rule.name].ok for rule in present}

    table = [verdicts(float(mass)) for mass in grid]
    out: dict[str, Interval | None] = {}
    for name in table[0]:
        def passes(mass: float, name: str = name) -> bool:
            return verdicts(mass)[name]

        ok = [row[name] for row in table]
        if not any(ok):
            out[name] = None
            continue
        i = ok.index(True)
        start = lo if i == 0 else _bisect(passes, float(grid[i - 1]), float(grid[i]))[1]
        j = next((k for k in range(i + 1, len(grid)) if not ok[k]), None)
        end = hi if j is None else _bisect(passes, float(grid[j]), float(grid[j - 1]))[1]
        out[name] = (start, end)
    return out


def _present(case: PayloadCase) -> Collection[str]:
    """The rules `forward_check` judges on this case, whatever the mass.

    A rule is absent for a case by what the case gives (a required life, a motor's demand,
    a rated bearing's loads), not by its numbers (`Rule.check`): the check of a stand-in
    cycle with the case's inputs (no sample summed) names them, and a rated bearing's
    loads are taken at no payload.
    """
    if case.wrench0 is not None and case.unit.bearing is not None:
        return forward_check(case, 0.0).checks.keys()
    moving = case.travel > 0.0
    load = CycleLoad(0.0, 0.0 if moving else None, 0.0, 0.0, 0.0, 0.0,
                     0.0 if bool(case.rest.any()) else None)
    demand = (MotorDemand(0.0, 0.0, 0.0, case.efficiency)
              if case.qdd is not None and case.efficiency is not None else None)
    return check_unit(load, case.unit, momentary=Momentary(0.0, "emergency stop"),
                      motor=demand, life_hours=case.life_hours, life_basis=case.life_basis,
                      margin=case.margin, max_torsion=case.max_torsion,
                      min_frequency=case.min_frequency,
                      load_inertia=case.inertia_at(0.0)).checks.keys()


def _bisect(passes: Callable[[float], bool], failing: float,
            passing: float) -> tuple[float, float]:
    """Narrow a failing and a passing mass [kg] to `MASS_RTOL`: (failing, passing)."""
    while abs(passing - failing) > MASS_RTOL * max(abs(passing), abs(failing), 1e-9):
        middle = 0.5 * (failing + passing)
        if passes(middle):
            passing = middle
        else:
            failing = middle
    return failing, passing


_ROUNDOFF = 1e-12
"""Per-kg torque below this fraction of a joint's torques is rounding, not load [-]."""


def duty_bounds(tasks: Sequence[Task], idle: float, scaled: Sequence[str],
                masses: Mapping[str, float], units: Sequence[Unit],
                options: Options) -> dict[str, tuple[UnitBound, ...]]:
    """Each unit's interval of x on each sized joint, gearhead masses fixed.

    The payloads of `scaled` tasks are x times theirs (mass and inertia), the others'
    fixed: every task's torque is affine in x on its fixed trajectory, so two batched
    passes per task give each rule as an interval of x, over the tasks' samples pooled at
    their shares (`hdselect.sizing.tasks.pooled`): the rules of single samples on every
    sample, the mean torque and life on the pooled cubic mean.

    Args:
        tasks: The duty's tasks, payloads at x = 1.
        idle: The fraction of the time no task runs [-].
        scaled: The tasks whose payload scales, by name.
        masses: The gearhead (and motor) mass per joint's unit [kg].
        units: The catalog.
        options: The assumptions.
    """
    counted = [task for task in tasks if task.share > 0.0]
    samples = pooled(counted, idle)
    robot = counted[0].robot
    names = list(robot.sized_joints)
    bearings = options.bearing_loads and any(unit.bearing is not None for unit in units)
    parts = [_task_parts(task, task.label in scaled, masses, names, options, bearings)
             for task in counted]
    out = {}
    for k, name in enumerate(names):
        j = robot.joint_index(name)
        tau0 = np.concatenate([none.tau[:, j] for none, _, _, _ in parts])
        stop0 = np.concatenate([none.stop[:, j] for none, _, _, _ in parts])
        tau1 = np.concatenate([_per_kg(full.tau[:, j], none.tau[:, j])
                               for none, full, _, _ in parts])
        stop1 = np.concatenate([_per_kg(full.stop[:, j], none.stop[:, j])
                                for none, full, _, _ in parts])
        wrench = None if not bearings else (
            np.concatenate([w[0][k] for _, _, w, _ in parts if w is not None], axis=1),
            np.concatenate([w[1][k] - w[0][k] for _, _, w, _ in parts if w is not None],
                           axis=1),
            options.bearing_offset.get(name, 0.0))
        frequency = options.joint_value("min_natural_frequency", name)
        targets: dict[str, Any] = {"max_torsion": options.joint_value("max_torsion", name),
                                   "min_frequency": frequency}
        if frequency is not None:
            targets["inertia0"] = np.concatenate([m[0][:, k] for _, _, _, m in parts
                                                  if m is not None])
            targets["inertia1"] = np.concatenate([m[1][:, k] for _, _, _, m in parts
                                                  if m is not None])
        rest, qd = samples.rest[:, j], samples.qd[:, j]
        cubic = joint_mean(samples.dt, rest, qd, tau0, tau1)
        out[name] = tuple(unit_bound(unit, samples.dt, rest, qd, tau0, tau1, stop0, stop1,
                                     options, samples.idle, cubic=cubic, t=samples.t,
                                     qdd=samples.qdd[:, j], wrench=wrench, targets=targets)
                          for unit in units)
    return out


def _task_parts(task: Task, scales: bool, masses: Mapping[str, float], names: Sequence[str],
                options: Options, bearings: bool) -> tuple[Any, ...]:
    """One task's torques without its scaled part and with it at x = 1, by carried state.

    Returns:
        The `CycleTorques` at x = 0 and at x = 1 (the same where the task's part does not
        scale), the sized joints' wrenches at both (or None) and M_jj at the inertia poses
        at x = 0 and per unit of x (or None).
    """
    traj = task.trajectory
    # without the scaled part and with it; a task that keeps its payload: one pass
    ends = [with_part(task, None), task] if scales and scaled_part(task) is not None else [task]

    def along(evaluate: Callable[[Robot, Any], tuple[np.ndarray, ...]], *, axis: int = 0,
              rows: np.ndarray | None = None) -> list[tuple[np.ndarray, ...]]:
        return [over_states(end, end.robot.with_gearheads(masses), evaluate, rows, axis)
                for end in ends]

    def motion(robot: Robot, at: Any) -> tuple[np.ndarray, ...]:
        found = cycle_torques(robot, traj.q[at], traj.qd[at], traj.qdd[at], options.stop_time,
                              threads=options.threads)
        return found.tau, found.stop

    torques = along(motion)  # each the motion's and a stop's, (n, dof)
    wrenches = None  # a rated output bearing is judged on the joint's wrench, affine in m
    if bearings:
        found = along(lambda robot, at: (axis_wrenches(robot, traj.q[at], traj.qd[at],
                                                       traj.qdd[at], names,
                                                       threads=options.threads),), axis=2)
        wrenches = [found[0][0], found[-1][0]]
    inertias = None  # M_jj of every pose, affine in x too, where a frequency target asks
    if any(options.joint_value("min_natural_frequency", name) is not None for name in names):
        found = along(lambda robot, at: (joint_inertias(robot, traj.q[at], names,
                                                        threads=options.threads),),
                      rows=inertia_poses(traj))
        inertias = (found[0][0], found[-1][0] - found[0][0])
    return CycleTorques(*torques[0]), CycleTorques(*torques[-1]), wrenches, inertias


def _per_kg(loaded: np.ndarray, empty: np.ndarray) -> np.ndarray:
    """The torque of 1 kg [N m]: loaded - empty, zero where it is within their roundoff.

    A payload on a joint's axis (its centre of mass on it, no inertia) loads it with
    nothing; the difference of two dynamics passes is then rounding, ~1e-16 of the
    torques, which would read as a limit of ~1e16 kg rather than none.
    """
    difference = loaded - empty
    scale = float(np.max(np.abs(loaded), initial=0.0) + np.max(np.abs(empty), initial=0.0))
    return np.where(np.abs(difference) <= _ROUNDOFF * scale, 0.0, difference)
