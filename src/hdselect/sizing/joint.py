"""One joint's cycle against every unit (or every gearhead and motor pair), and the choice.

The joint's torques come from the core, for the masses of the units already chosen
further out. Every unit is reflected (`hdselect.sizing.reflect`), checked by its
series' rules (`check_unit`) and the preferred feasible one selected. Where only
the selection is wanted (a study's case), the rules' prefilters (`Rule.prefilter`: peak,
input speed, momentary, static) are first applied to every unit at once, and the
whole-cycle rules judged only for the units that can still be chosen: the same
choice, with the figures of the selected unit (or of the strongest, when none fits).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen, readonly
from hdselect.catalog.bearing_rules import BearingLoad
from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    RULES,
    Candidate,
    CycleLoad,
    UnitBatch,
    check_unit,
    cycle_load,
)
from hdselect.catalog.rules.forms import TARGETS
from hdselect.catalog.rules.momentary import worst_events
from hdselect.catalog.select import select
from hdselect.catalog.units import Unit
from hdselect.sizing.bearing import SampledWrench, cycle_bearing
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import Reflection, reflect, reflect_motors, weighted_demand
from hdselect.sizing.result import JointSizing
from hdselect.sizing.tasks import Samples, alone, task_rows


@dataclass(frozen=True, eq=False)
class JointCycle:
    """One joint's samples and the torques it carries along them.

    Attributes:
        samples: The pooled samples of the robot's tasks.
        column: The joint's column in the samples' arrays.
        torque: Output torque along the samples [N m], shape (n,).
        stop: Output torque at the start of an emergency stop from each sample [N m], (n,).
        wrench: The whole force and moment through the joint along the samples, in its
            axis frame about the joint origin; None when not computed.
        offset: Where the output flange sits along the axis from the joint origin [m].
    """

    samples: Samples
    column: int
    torque: np.ndarray
    stop: np.ndarray
    wrench: SampledWrench | None = None
    offset: float = 0.0

    @property
    def qd(self) -> np.ndarray:
        """The joint's speed [rad/s], shape (n,)."""
        return self.samples.qd[:, self.column]

    @property
    def qdd(self) -> np.ndarray:
        """The joint's acceleration [rad/s^2], shape (n,)."""
        return self.samples.qdd[:, self.column]

    @property
    def rest(self) -> np.ndarray:
        """Where the joint is held still in its own task, shape (n,)."""
        return self.samples.rest[:, self.column]

    def load(self) -> CycleLoad:
        """The cycle on the output side, by the catalog page's formulas."""
        return cycle_load(self.torque, self.qd, self.samples.dt, self.rest,
                          idle=self.samples.idle)

    def bearing(self, spread: float = 0.0) -> BearingLoad | None:
        """The output bearing's loads about the flange, or `spread` from it either way.

        Args:
            spread: A unit's distance from its output flange to its bearing centre [m]
                (the side is not known: the larger moment of both sides per sample).

        Returns:
            The loads over the cycle; None without the wrench.
        """
        if self.wrench is None:
            return None
        return cycle_bearing(self.wrench, self.offset, spread, self.qd, self.samples.dt,
                             self.samples.rest[:, self.column])


def size_joint(name: str, cycle: JointCycle, units: tuple[Unit, ...], options: Options, *,
               motors: Sequence[Motor] = (), detail: bool = True,
               load_inertia: float | None = None) -> JointSizing:
    """Check every unit (every pair, with `motors`) against one joint; select one.

    Args:
        name: The joint's name.
        cycle: The joint's samples and torques.
        units: The candidate units.
        options: The assumptions, with ``prefer`` resolved.
        motors: The joint's candidate motors: then every (gearhead, motor) pair is checked.
        detail: Keep every candidate checked; False keeps only the selected one (or the
            strongest, when none fits), judged exactly as with detail.
        load_inertia: The joint's load inertia M_jj [kg m^2], the largest over the cycle's
            poses, where motors are given or the joint has a ``min_natural_frequency``:
            each pair's inertia ratio, the ``inertia_ratio`` rule where a largest ratio is
            given, the ``natural_frequency`` rule.

    Returns:
        The joint's candidates and selection; its carried mass and gravity figures are
        for the core to fill in.
    """
    load = cycle.load()
    bearings = _Bearings(cycle)
    targets = joint_targets(name, options, load_inertia)
    if motors and not detail:
        joint = _selected_pair(name, cycle, load, bearings, units, motors, options, targets)
    elif motors:
        joint = _size_pairs(name, cycle, load, bearings, units, motors, options, targets)
    elif detail:
        candidates = [_candidate(load, r, cycle, bearings, options, targets)
                      for r in _reflect(units, cycle, options)]
        joint = JointSizing(name, load, tuple(candidates),
                            select(candidates, _prefer(options),
                                   inertia_target=options.inertia_target),
                            0.0, False, 0.0, readonly(cycle.torque), readonly(cycle.stop))
    else:
        joint = _selected_only(name, cycle, load, bearings, units, options, targets)
    return replace(joint, bearing=bearings.of(None), wrench=cycle.wrench,
                   load_inertia=load_inertia)


def joint_targets(name: str, options: Options,
                  load_inertia: float | None = None) -> dict[str, Any]:
    """A joint's precision targets as `check_unit` takes them (`TARGETS`).

    Args:
        name: The joint.
        options: The assumptions (``max_torsion``, ``min_natural_frequency``).
        load_inertia: The joint's load inertia [kg m^2], where known.

    Raises:
        ValueError: A ``min_natural_frequency`` for the joint without its load inertia.
    """
    frequency = options.joint_value("min_natural_frequency", name)
    if frequency is not None and load_inertia is None:
        raise ValueError(f"joint {name}: a natural frequency target needs its load inertia")
    return dict(zip(TARGETS, (options.joint_value("max_torsion", name), frequency,
                              load_inertia), strict=True))


class _Bearings:
    """A joint's output-bearing loads about each centre asked for, computed once each."""

    def __init__(self, cycle: JointCycle) -> None:
        self.cycle = cycle
        self._found: dict[float, BearingLoad | None] = {}

    def of(self, unit: Unit | None) -> BearingLoad | None:
        """About the unit's bearing centre where it rates its bearing, else the flange."""
        spread = unit.bearing.offset if unit is not None and unit.bearing is not None else 0.0
        if spread not in self._found:
            self._found[spread] = self.cycle.bearing(spread)
        return self._found[spread]


def task_checks(cycle: JointCycle, chosen: Candidate, options: Options,
                load_inertias: Sequence[float] | None = None, *,
                name: str = "") -> tuple[Candidate, ...]:
    """The chosen unit (or pair) against each counted task's samples alone: the same rules.

    Args:
        cycle: The joint's pooled samples and torques.
        chosen: The selected candidate (or the strongest, where none fits).
        options: The assumptions (the design margin and the largest inertia ratio too).
        load_inertias: With a motor or a ``min_natural_frequency``, the joint's load
            inertia M_jj in each counted task [kg m^2]: each task's own inertia ratio and
            natural frequency (the duty's are at the largest).
        name: The joint, for its precision targets (`joint_targets`).

    Returns:
        One candidate per counted task, in the samples' task order; empty for one task.
    """
    samples = cycle.samples
    if len(samples.tasks) < 2:
        return ()
    out = []
    for k in range(len(samples.tasks)):
        rows = task_rows(samples, k)
        wrench = (None if cycle.wrench is None
                  else SampledWrench(np.ascontiguousarray(cycle.wrench.full()[:, rows])))
        part = JointCycle(alone(samples, k), cycle.column, cycle.torque[rows], cycle.stop[rows],
                          wrench, cycle.offset)
        load = part.load()
        bearings = _Bearings(part)
        motor = chosen.motor_unit
        targets = joint_targets(name, options,
                                None if load_inertias is None else load_inertias[k])
        if motor is None:
            (reflection,) = _reflect([chosen.unit], part, options)
            out.append(_candidate(load, reflection, part, bearings, options, targets))
            continue
        ((reflection,),) = reflect_motors([chosen.unit], [motor.rotor_inertia], part.samples.t,
                                          part.torque, part.qd, part.qdd, part.stop,
                                          stop_time=options.stop_time,
                                          efficiency=options.efficiency, rest=part.rest)
        out.append(with_motor(_candidate(load, reflection, part, bearings, options, targets),
                              motor,
                              reflection.motor_torque,
                              np.abs(part.qd) * RPM_PER_RAD_S * chosen.unit.ratio,
                              load_inertia=None if load_inertias is None else load_inertias[k],
                              max_inertia_ratio=options.max_inertia_ratio))
    return tuple(out)


def _prefer(options: Options) -> str:
    if options.prefer is None:
        raise RuntimeError("options.prefer is unresolved (the core resolves it before selecting)")
    return options.prefer


def _reflect(units: Sequence[Unit], cycle: JointCycle, options: Options) -> list[Reflection]:
    return reflect(units, cycle.samples.t, cycle.torque, cycle.qd, cycle.qdd, cycle.stop,
                   stop_time=options.stop_time, efficiency=options.efficiency,
                   rotor_inertia=options.rotor_inertia, rest=cycle.rest)


def _candidate(load: CycleLoad, reflection: Reflection, cycle: JointCycle,
               bearings: _Bearings, options: Options,
               targets: dict[str, Any]) -> Candidate:
    """`check_unit` with the motor demand and the joint's precision targets.

    The demand's RMS is weighted where samples differ in length; the targets are
    `joint_targets`'.
    """
    demand = reflection.motor
    if cycle.samples.weight is not None:
        demand = weighted_demand(demand, reflection.motor_torque, cycle.qd,
                                 reflection.unit.ratio, cycle.samples.weight)
    unit = reflection.unit
    return check_unit(load, unit, momentary=reflection.momentary,
                      life_hours=options.life_hours, life_basis=options.life_basis,
                      motor=demand, bearing=_rated(bearings, unit), margin=options.margin,
                      **targets)


def _rated(bearings: _Bearings, unit: Unit) -> BearingLoad | None:
    """The loads `check_unit` checks: only a unit that rates its bearing needs them."""
    return None if unit.bearing is None else bearings.of(unit)


def _size_pairs(name: str, cycle: JointCycle, load: CycleLoad, bearings: _Bearings,
                units: tuple[Unit, ...], motors: Sequence[Motor], options: Options,
                targets: dict[str, Any]) -> JointSizing:
    """Every (gearhead, motor) pair: each motor's rotor inertia in the motor torque and crash."""
    behind = reflect_motors(units, [m.rotor_inertia for m in motors], cycle.samples.t,
                            cycle.torque, cycle.qd, cycle.qdd, cycle.stop,
                            stop_time=options.stop_time, efficiency=options.efficiency,
                            rest=cycle.rest)
    speed = np.abs(cycle.qd) * RPM_PER_RAD_S
    pairs, reflections = [], {}
    for u, unit in enumerate(units):
        input_speed = speed * unit.ratio
        for m, motor in enumerate(motors):
            r = behind[m][u]
            torque, starts = r.distinct_motor_torque()  # the motor's peak: once per dwell
            pair = with_motor(_candidate(load, r, cycle, bearings, options, targets), motor,
                              torque, input_speed if starts is None else input_speed[starts],
                              load_inertia=targets["load_inertia"],
                              max_inertia_ratio=options.max_inertia_ratio)
            pairs.append(pair)
            reflections[id(pair)] = r
    selected = select(pairs, _prefer(options), inertia_target=options.inertia_target)
    joint = JointSizing(name, load, tuple(pairs), selected, 0.0, False, 0.0,
                        readonly(cycle.torque), readonly(cycle.stop))
    chosen = reflections[id(selected or joint.strongest)]
    return replace(joint, motor_torque=frozen(chosen.motor_torque))


def _selected_pair(name: str, cycle: JointCycle, load: CycleLoad, bearings: _Bearings,
                   units: tuple[Unit, ...], motors: Sequence[Motor], options: Options,
                   targets: dict[str, Any]) -> JointSizing:
    """The selected pair, from the pairs whose gearhead passes the rules no motor changes.

    Those are the rules whose prefilter needs no motor's rotor inertia (peak, input
    speed, static, the precision targets); where no such pair fits, every pair is
    checked. A pair whose gearhead fails one of them is infeasible with any motor, so the
    selection is the one among every pair; the strongest (where none fits) is found
    among every pair, as with detail.
    """
    passes = _prefilter(UnitBatch(units, load, cycle.samples.t, cycle.torque, cycle.stop,
                                  cycle.qd, options.stop_time, None, **targets), options)
    survivors = tuple(unit for unit, ok in zip(units, passes, strict=True) if ok)
    if survivors and len(survivors) < len(units):
        found = _size_pairs(name, cycle, load, bearings, survivors, motors, options, targets)
        if found.selected is not None:
            return found
    return _size_pairs(name, cycle, load, bearings, units, motors, options, targets)


def _selected_only(name: str, cycle: JointCycle, load: CycleLoad, bearings: _Bearings,
                   units: tuple[Unit, ...], options: Options,
                   targets: dict[str, Any]) -> JointSizing:
    """The selection, judging the whole-cycle rules only where they can change it.

    A unit failing a rule on single figures is infeasible whatever its whole-cycle
    rules say. Of the rest, ``prefer = "size"`` needs only the smallest size that has
    a feasible unit; a motor order needs every survivor's motor demand.
    """
    prefer = _prefer(options)
    batch = UnitBatch(units, load, cycle.samples.t, cycle.torque, cycle.stop, cycle.qd,
                      options.stop_time, options.rotor_inertia, **targets)
    passes = _prefilter(batch, options)
    survivors = [k for k in range(len(units)) if passes[k]]
    motor_order = prefer.startswith("motor")
    if motor_order:
        checked = [_candidate(load, r, cycle, bearings, options, targets)
                   for r in _reflect([units[k] for k in survivors], cycle, options)]
    else:
        checked = []
        sizes = sorted({units[k].size for k in survivors})
        for size in sizes if prefer == "size" else sizes[:1]:
            checked += [check_unit(load, units[k],
                                   momentary=worst_events(batch).event(k),
                                   life_hours=options.life_hours, life_basis=options.life_basis,
                                   bearing=_rated(bearings, units[k]), margin=options.margin,
                                   **targets)
                        for k in survivors if units[k].size == size or prefer != "size"]
            if prefer != "size" or any(c.feasible for c in checked):
                break
    selected = select(checked, prefer, inertia_target=options.inertia_target)
    if selected is None or not motor_order:  # the figures of the selected, else the strongest
        unit = _strongest(units) if selected is None else selected.unit
        (reflection,) = _reflect([unit], cycle, options)
        chosen = _candidate(load, reflection, cycle, bearings, options, targets)
        selected = None if selected is None else chosen
    else:
        chosen = selected
    return JointSizing(name, load, (chosen,), selected, 0.0, False, 0.0, cycle.torque,
                       cycle.stop)


def _prefilter(batch: UnitBatch, options: Options) -> np.ndarray:
    """Which units may pass, by every registered rule's prefilter (`Rule.prefilter`).

    A unit a prefilter rejects fails that rule's forward check; a rule without the form
    rejects none (the forward check decides).
    """
    passes = np.ones(len(batch.units), dtype=bool)
    for rule in RULES:
        utilization = rule.prefilter(batch)
        if utilization is not None:
            passes &= rule.passes(utilization, options.margin)
    return passes


def _strongest(units: tuple[Unit, ...]) -> Unit:
    """The unit of the largest repeated peak (then momentary, then rated) torque."""
    return max(units, key=lambda unit: (unit.repeated_torque, unit.momentary_torque or 0.0,
                                        unit.rated_torque))
