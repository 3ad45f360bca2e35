"""Whole-arm precision targets: units raised for stiffness until the arm meets them.

After the per-joint selection, `stiffened` computes the precision figures
(`hdselect.sizing.precision.precision_of`) and judges the whole-arm targets on them: the
tool's deflection holding the payload still (``max_tool_deflection``) and the arm's
lowest mode over the cycle (``min_arm_frequency``). Where one is missed, units are raised
one step at a time. Each trial raises one joint to its next stiffer unit among those that
pass its own rules, its candidates then restricted to the units at least that stiff (K1),
and re-selects the joints nearer the base with the new carried masses. Of the trials that
leave every joint a unit and close some of the shortfall, the one closing most per added
kilogram is taken; a trial that meets every target is kept aside, and the search stops
where the next step would weigh as much as the lightest kept. Then each raise is undone
where the targets hold without it. Where no trial closes the shortfall, the target's check
says that the catalog cannot meet it, with the best reached.

The search re-sizes the arm for every trial, so it runs on the core's decimated samples
(`coarse`) and is then confirmed on the full ones, going on there where they still miss a
target. Every choice is made in the robot's joint order: the same problem gives the same
raises.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Protocol

from hdselect.catalog.motors import Motor
from hdselect.catalog.stiffness import unit_k1
from hdselect.catalog.units import Unit
from hdselect.sizing.options import Options
from hdselect.sizing.precision import Precision, Raise, TargetCheck, precision_of
from hdselect.sizing.result import JointSizing
from hdselect.sizing.torques import TorqueModel

TOOL_DEFLECTION = "tool_deflection"
"""The target on the tool's holding deflection [m]: at most ``max_tool_deflection``."""
ARM_FREQUENCY = "arm_frequency"
"""The target on the arm's lowest mode over the cycle [Hz]: at least ``min_arm_frequency``."""
REASONS = {TOOL_DEFLECTION: "tool deflection", ARM_FREQUENCY: "arm frequency"}
"""Each target's words in a `Raise`."""


class Selector(Protocol):
    """The core's selection, `hdselect.sizing.core.select_units`."""

    def __call__(self, model: TorqueModel, units: Mapping[str, tuple[Unit, ...]],
                 options: Options, motors: Mapping[str, Sequence[Motor]], *,
                 detail: bool = True, slowdowns: bool = True, per_task: bool = True,
                 ) -> tuple[list[JointSizing], dict[str, float]]:
        """The sized joints and the masses their units add [kg]."""


@dataclass(frozen=True, eq=False)
class Stiffened:
    """The sizing after the precision figures and the whole-arm targets.

    Attributes:
        joints: The sized joints (the per-joint selection where nothing was raised).
        masses: The mass each joint's unit and motor add [kg], as `select_units` gives them.
        precision: The figures of those units, the raises and the targets' checks in it;
            None where the options ask for no figures and set no target.
    """

    joints: list[JointSizing]
    masses: dict[str, float]
    precision: Precision | None


def targets_of(options: Options) -> dict[str, float]:
    """The whole-arm targets the options set: name -> limit [m or Hz]."""
    found = {TOOL_DEFLECTION: options.max_tool_deflection,
             ARM_FREQUENCY: options.min_arm_frequency}
    return {name: float(limit) for name, limit in found.items() if limit is not None}


def stiffened(model: TorqueModel, units: Mapping[str, tuple[Unit, ...]],
              joints: list[JointSizing], masses: dict[str, float], options: Options,
              motors: Mapping[str, Sequence[Motor]], *, select: Selector | None,
              coarse: TorqueModel | None = None, slowdowns: bool = True) -> Stiffened:
    """The precision figures of a selection, its units raised where a whole-arm target asks.

    Args:
        model: The torques along the full samples.
        units: Every sized joint's candidate units, as the selection took them.
        joints: The per-joint selection on `model` (`select_units`).
        masses: Its units' masses [kg].
        options: The assumptions (``prefer`` resolved; the targets among them).
        motors: Candidate motors per sized joint, as the selection took them.
        select: The core's selection (`hdselect.sizing.core.select_units`); None judges
            the targets on the given units, raising none (`check_units`).
        coarse: The same tasks on decimated samples, for the search; None searches on `model`.
        slowdowns: For a joint no unit fits after a raise, as `select_units`.

    Returns:
        The joints, masses and figures after the raises.
    """
    targets = targets_of(options)
    if not targets:
        figures = precision_of(model, joints, masses, options) if options.precision else None
        return Stiffened(joints, masses, figures)
    figures = precision_of(model, joints, masses, options)
    first = found = _Choice({}, joints, masses, figures)
    missing = [joint.name for joint in joints if joint.selected is None]
    if select is not None and not missing and _gap(figures, targets) > 0.0:
        search = _Search(units, targets, options, motors, select, slowdowns)
        if coarse is not None:
            rough = search.run(search.choice(coarse, {}, full=False), coarse, full=False)
            if rough.ladders:
                found = search.choice(model, rough.ladders, rough.reasons)
        if not found.ladders or not found.feasible:  # every candidate kept, to raise from
            found = search.choice(model, {})
        found = search.run(found, model, full=True)
        found = found if found.ladders else first
    unrated = [joint.name for joint in found.joints
               if unit_k1((joint.selected or joint.strongest).unit) is None]
    checks = _checks(found.precision, targets, missing=missing, unrated=unrated,
                     given=select is None)
    return Stiffened(found.joints, found.masses,
                     replace(found.precision or figures, raised=_raises(joints, found),
                             targets=checks))


Ladders = dict[str, tuple[Unit, ...]]
"""Each raised joint's raises in order: its candidates are the units at least as stiff."""


@dataclass(frozen=True)
class _Choice:
    """One state of the search: the raised joints' floors and the selection they give.

    Attributes:
        ladders: Each raised joint's raises in order.
        joints: The selection with those candidates.
        masses: Its units' masses [kg].
        precision: Its figures; None where a joint has no unit (not judged).
        reasons: The target each raised joint was raised for.
    """

    ladders: Ladders
    joints: list[JointSizing]
    masses: dict[str, float]
    precision: Precision | None
    reasons: Mapping[str, str] = field(default_factory=dict)

    @property
    def feasible(self) -> bool:
        """Every joint has a unit."""
        return all(joint.selected is not None for joint in self.joints)

    @property
    def mass(self) -> float:
        """The units' and paired motors' mass [kg] (the options' motor mass is the same for all)."""
        return sum(_own_mass(joint) for joint in self.joints)


@dataclass(frozen=True)
class _Search:
    """The raising step's trials: choices by their floors, the greedy, the trim."""

    units: Mapping[str, tuple[Unit, ...]]
    targets: Mapping[str, float]
    options: Options
    motors: Mapping[str, Sequence[Motor]]
    select: Selector
    slowdowns: bool

    def choice(self, model: TorqueModel, ladders: Ladders,
               reasons: Mapping[str, str] | None = None, *, detail: bool = True,
               full: bool = True, kept: Mapping[str, Unit] | None = None) -> _Choice:
        """The selection with each raised joint's candidates at least as stiff as its floor.

        Args:
            model: Where the torques come from.
            ladders: The raised joints' raises.
            reasons: The target each was raised for.
            detail: Keep every candidate (the next raise reads them).
            full: The final samples: slow-downs and per-task checks as the core's.
            kept: Joints whose unit cannot change (their carried units do not): that unit
                is their only candidate, which spares checking the others.
        """
        units = {name: _at_least(given, ladders[name][-1]) if name in ladders else given
                 for name, given in self.units.items()}
        units.update({name: (unit,) for name, unit in (kept or {}).items()})
        joints, masses = self.select(model, units, self.options, self.motors, detail=detail,
                                     slowdowns=full and detail and self.slowdowns,
                                     per_task=full and detail)
        feasible = all(joint.selected is not None for joint in joints)
        figures = precision_of(model, joints, masses, self.options) if feasible else None
        return _Choice(ladders, joints, masses, figures, dict(reasons or {}))

    def run(self, start: _Choice, model: TorqueModel, *, full: bool) -> _Choice:
        """Raise from `start` until the targets are met or no trial closes their shortfall.

        Each step takes the trial closing most per added kilogram; a trial that meets
        every target is kept aside, and the search stops where the next step would weigh
        as much as the lightest kept: that one is the answer.

        Args:
            start: The choice to raise from, its joints with every candidate.
            model: Where the torques come from.
            full: `model` is the final samples' (see `choice`).

        Returns:
            The lightest choice met (its raises trimmed), else the best reached.
        """
        current = self._rated(start, model, full=full)
        if _gap(current.precision, self.targets) == 0.0:
            return current
        met: tuple[str, _Choice] | None = None
        while _gap(current.precision, self.targets) > 0.0:
            trials = self._trials(current, model, full=full)
            for name, trial in trials:
                if _gap(trial.precision, self.targets) == 0.0 and (
                        met is None or trial.mass < met[1].mass):
                    met = (name, trial)
            if not trials:
                break
            name, best = self._best(current, trials)
            if met is not None and best.mass >= met[1].mass:
                name, best = met
            current = self.choice(model, best.ladders, {**current.reasons,
                                                        name: self._reason(current, best)},
                                  full=full)
        return self._trimmed(current, model, full=full)

    def _trials(self, current: _Choice, model: TorqueModel, *, full: bool
                ) -> list[tuple[str, _Choice]]:
        """Each joint raised one step, where every joint keeps a unit and the shortfall shrinks."""
        trials = []
        for k, joint in enumerate(current.joints):
            unit = self._next(joint, current)
            if unit is not None:
                ladders = {**current.ladders,
                           joint.name: (*current.ladders.get(joint.name, ()), unit)}
                # the joints after it in the robot's order carry no more than before
                kept = {j.name: j.selected.unit for j in current.joints[k + 1:] if j.selected}
                trial = self.choice(model, ladders, detail=False, full=full, kept=kept)
                if trial.feasible and (_gap(trial.precision, self.targets)
                                       < _gap(current.precision, self.targets)):
                    trials.append((joint.name, trial))
        return trials

    def _rated(self, current: _Choice, model: TorqueModel, *, full: bool) -> _Choice:
        """Where a unit rates no K1 (the figures unjudged): every such joint raised at once.

        Each to its least stiff rated unit that passes its rules; again while the
        re-selected joints nearer the base leave one unrated.
        """
        while current.feasible and math.isinf(_gap(current.precision, self.targets)):
            ladders = dict(current.ladders)
            for joint in current.joints:
                unit = self._next(joint, current)
                if unit is not None and joint.selected and unit_k1(joint.selected.unit) is None:
                    ladders[joint.name] = (*ladders.get(joint.name, ()), unit)
            if ladders == current.ladders:
                break
            why = REASONS[next(iter(self.targets))]
            trial = self.choice(model, ladders, {**dict.fromkeys(ladders, why),
                                                 **current.reasons}, full=full)
            if not trial.feasible:
                break
            current = trial
        return current

    def _next(self, joint: JointSizing, current: _Choice) -> Unit | None:
        """The joint's next stiffer unit among those that pass its rules, else None.

        The least stiff unit rated stiffer than its unit (any rated unit where its unit
        rates no K1); of equal K1, the lightest, then the first in the catalog.
        """
        if joint.selected is None:
            return None
        own = unit_k1(joint.selected.unit)
        order = {unit.id: k for k, unit in enumerate(self.units[joint.name])}
        stiffer = {c.unit.id: c.unit for c in joint.candidates
                   if c.feasible and (k1 := unit_k1(c.unit)) is not None
                   and (own is None or k1 > own)}
        if not stiffer:
            return None
        return min(stiffer.values(), key=lambda u: (unit_k1(u), u.mass, order.get(u.id, 0)))

    def _best(self, current: _Choice, trials: list[tuple[str, _Choice]]
              ) -> tuple[str, _Choice]:
        """The trial closing the targets' shortfall most per added kilogram.

        One that adds no mass first (the most closed); ties go to the first joint in the
        robot's order.
        """
        gap = _gap(current.precision, self.targets)

        def rate(k: int) -> tuple[bool, float, int]:
            trial = trials[k][1]
            closed = gap - _gap(trial.precision, self.targets)
            added = trial.mass - current.mass
            return (added <= 0.0, closed if added <= 0.0 else closed / added, -k)

        return trials[max(range(len(trials)), key=rate)]

    def _reason(self, current: _Choice, best: _Choice) -> str:
        """The target a raise closes most of (the tool deflection first on a tie)."""
        closed = {name: _term(current.precision, name, limit) - _term(best.precision, name, limit)
                  for name, limit in self.targets.items()}
        return REASONS[max(closed, key=lambda name: (closed[name], name == TOOL_DEFLECTION))]

    def _trimmed(self, current: _Choice, model: TorqueModel, *, full: bool) -> _Choice:
        """Undo the last raise of a joint while the targets hold without it: the lightest first."""
        while current.ladders and _gap(current.precision, self.targets) == 0.0:
            trials = []
            for name in (joint.name for joint in current.joints if joint.name in current.ladders):
                ladders = dict(current.ladders)
                ladders[name] = ladders[name][:-1]
                if not ladders[name]:
                    del ladders[name]
                trial = self.choice(model, ladders, detail=False, full=full)
                if (trial.feasible and _gap(trial.precision, self.targets) == 0.0
                        and trial.mass < current.mass):
                    trials.append(trial)
            if not trials:
                break
            best = min(trials, key=lambda trial: trial.mass)
            reasons = {name: why for name, why in current.reasons.items()
                       if name in best.ladders}
            current = self.choice(model, best.ladders, reasons, full=full)
        return current


def _at_least(units: tuple[Unit, ...], floor: Unit) -> tuple[Unit, ...]:
    """The units rated at least as stiff (K1) as `floor`."""
    least = unit_k1(floor)
    return tuple(unit for unit in units
                 if (k1 := unit_k1(unit)) is not None and least is not None and k1 >= least)


def _own_mass(joint: JointSizing) -> float:
    """The mass of a joint's unit and its paired motor [kg] (the selected, else the strongest)."""
    chosen = joint.selected or joint.strongest
    return chosen.unit.mass + (chosen.motor_unit.mass if chosen.motor_unit is not None else 0.0)


def _figure(precision: Precision | None, name: str) -> float | None:
    """What a target judges [m or Hz]; None where a sized joint's unit rates no K1."""
    if precision is None:
        return None
    if name == TOOL_DEFLECTION:
        return None if precision.tool is None else precision.tool.max_holding
    return None if precision.modes is None else precision.modes.lowest_frequency


def _term(precision: Precision | None, name: str, limit: float) -> float:
    """How far one target is missed, as a fraction of it [-]: 0 where met, inf where unjudged."""
    value = _figure(precision, name)
    if value is None:
        return math.inf
    miss = value - limit if name == TOOL_DEFLECTION else limit - value
    return max(0.0, miss / limit) if limit > 0.0 else (0.0 if miss <= 0.0 else math.inf)


def _gap(precision: Precision | None, targets: Mapping[str, float]) -> float:
    """How far the targets are missed together [-]: the sum of `_term`; 0 where all are met."""
    return sum(_term(precision, name, limit) for name, limit in targets.items())


def _raises(joints: Sequence[JointSizing], found: _Choice) -> tuple[Raise, ...]:
    """Every joint whose unit the targets changed, in the robot's order.

    A joint re-selected for the units it carries takes the reason of the nearest raised
    joint further out.
    """
    reasons = found.reasons
    out, why = [], REASONS[TOOL_DEFLECTION]
    for before, after in reversed(list(zip(joints, found.joints, strict=True))):
        old, new = ((j.selected or j.strongest).unit for j in (before, after))
        why = reasons.get(before.name, why)
        if old.id != new.id:
            out.append(Raise(before.name, old.id, new.id, why, new.mass - old.mass))
    return tuple(reversed(out))


def _checks(precision: Precision | None, targets: Mapping[str, float], *,
            missing: Sequence[str] = (), unrated: Sequence[str] = (),
            given: bool = False) -> tuple[TargetCheck, ...]:
    """Each target against what is reached, and why a missed one stays missed."""
    out = []
    for name, limit in targets.items():
        value = _figure(precision, name)
        ok = value is not None and _term(precision, name, limit) == 0.0
        against = f"{_quantity(name, value)} against " if value is not None else ""
        shortfall = None
        if ok:
            pass
        elif given:
            shortfall = (f"not met by the units given ({against}{_quantity(name, limit)})"
                         if value is not None else
                         f"cannot be judged: the unit given to {_joints(unrated)} rates no K1")
        elif missing:
            shortfall = f"not raised: no unit fits {_joints(missing)} by its own rules"
        elif value is None:
            shortfall = f"cannot be judged: no unit that fits {_joints(unrated)} rates K1"
        else:
            shortfall = (f"cannot be met by this catalog: no stiffer unit that fits "
                         f"{_WORDS[name]} (best reached {against}{_quantity(name, limit)})")
        out.append(TargetCheck(name, value, limit, ok, shortfall))
    return tuple(out)


_WORDS = {TOOL_DEFLECTION: "brings the tool's holding deflection lower",
          ARM_FREQUENCY: "raises the arm's lowest mode"}


def _quantity(name: str, value: float) -> str:
    """A target's figure in the designer's unit: mm or Hz."""
    return f"{value * 1e3:.3g} mm" if name == TOOL_DEFLECTION else f"{value:.3g} Hz"


def _joints(names: Sequence[str]) -> str:
    """``joint 'a'`` or ``joints 'a', 'b'``."""
    return f"joint{'s' if len(names) > 1 else ''} {', '.join(map(repr, names))}"
