"""For a joint no candidate holds: what falls short, whether gravity alone does, what works.

One `Diagnosis` per joint without a unit, computed once from what the sizing computed
(`diagnose`) and rendered the same by every front end (table lines, JSON, report, parts
list):

- the shortfalls: each rule that even its strongest candidate fails (the one whose check
  comes closest), as the demand against that unit's limit in the rule's own unit (N m,
  rpm, h), torque rules first and a life last, stated as a consequence;
- gravity alone: the largest torque holding the cycle's poses still, and whether it is
  over every unit's limit (then no slow-down helps, and the time scales agree);
- the next steps, each checked before it is offered: the smallest unit of a shipped series
  that holds the joint (the exact command, verified by sizing with that catalog), less
  payload (the payload solver's largest mass, verified by sizing at it), the joint left
  out (``--exclude``), and a slow-down where the time-scale solver found one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from hdselect.catalog.builtin import DEFAULT, builtin_catalogs
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import RULES, Candidate, Part, Rule, Scope, rule
from hdselect.catalog.rules.peak import PEAK
from hdselect.catalog.rules.static import STATIC
from hdselect.catalog.units import Unit
from hdselect.sizing.core import added_mass
from hdselect.sizing.nextsteps import (
    NextStep,
    PayloadBounds,
    catalog_steps,
    exclude_step,
    payload_steps,
    slowdown_step,
)
from hdselect.sizing.options import Options
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.tasks import Task, carrying, over_states, pooled
from hdselect.sizing.torques import gravity_at


@dataclass(frozen=True)
class Shortfall:
    """One rule the joint's candidates fail: the demand against its strongest unit's limit.

    Attributes:
        rule: The rule's name (its key in the checks), e.g. ``"peak"``.
        unit: The candidate closest to holding it (its label, ``unit + motor`` for a pair).
        value: The demand [the rule's unit]; for a life the life reached [h].
        limit: What that unit allows [the rule's unit]; for a life the life required [h].
        usable: The limit with the design margin (a life: the life needed) [the rule's unit].
        si: The rule's unit: ``"N m"``, ``"rpm"``, ``"N"``, ``"h"`` or ``""``.
        utilization: Demand over limit [-] (a life: required over reached).
    """

    rule: str
    unit: str
    value: float
    limit: float
    usable: float
    si: str
    utilization: float

    @property
    def is_life(self) -> bool:
        """The rule judges a life (shown as a consequence, never as a percentage)."""
        return rule(self.rule).life

    def short(self) -> str:
        """The shortfall in a table cell, e.g. ``peak 87.3 > 20.3 N m``, ``life 643 < 20,000 h``."""
        sign = "<" if rule(self.rule).at_least else ">"
        return " ".join(filter(None, (self.rule, _number(self.value), sign,
                                      _number(self.usable), self.si)))

    def text(self) -> str:
        """In words, e.g. ``repeated peak torque 87.3 N m over PSA-14-100's 20.3 N m``.

        A life or a safety (which must reach its figure): ``life 643 h of the 20,000 h
        required (PSA-14-100)``.
        """
        found = rule(self.rule)
        value, usable = (" ".join(filter(None, (_number(x), self.si)))
                         for x in (self.value, self.usable))
        if found.at_least:
            return f"{found.words} {value} of the {usable} required ({self.unit})"
        return f"{found.words} {value} over {self.unit}'s {usable}"


@dataclass(frozen=True)
class GravityLoad:
    """What holding the cycle's poses still takes, against the strongest unit.

    Attributes:
        torque: The largest |gravity torque| over the cycle's poses, payload and carried
            units included [N m]; where it exceeds, the largest over the poses the
            exceeded limit judges (moving: repeated peak; at rest: static).
        limit: The largest usable limit that applies to it: repeated peak while moving,
            static (where rated) at rest, of any candidate [N m].
        unit: The unit of that limit.
        exceeds: Gravity alone is over every unit's limit.
    """

    torque: float
    limit: float
    unit: str
    exceeds: bool


@dataclass(frozen=True)
class Diagnosis:
    """Why a joint has no unit, and what would give it one.

    Attributes:
        joint: The joint's name.
        shortfalls: The rules failed, torque rules first, then speeds, the bearing's, the
            motor's, lives last (`Shortfall`).
        combined: Every rule has a candidate that holds it, but none holds them all: the
            shortfalls are those of the closest candidate.
        gravity: Gravity alone against the strongest unit; None where not computed.
        steps: The next steps that work, in the order `NEXT_STEPS`.
        what: What the candidates are: ``"unit"``, or ``"pair"`` (a gearhead and a motor).
    """

    joint: str
    shortfalls: tuple[Shortfall, ...]
    combined: bool
    gravity: GravityLoad | None
    steps: tuple[NextStep, ...] = ()
    what: str = "unit"

    @property
    def headline(self) -> Shortfall:
        """The first shortfall: a torque rule wherever one fails, a life only when alone."""
        return self.shortfalls[0]

    def summary(self) -> str:
        """In a line, e.g. ``no unit holds it: peak 87.3 > 20.3 N m``."""
        return f"no {self.what} holds it: {self.headline.short()}"

    def lines(self) -> list[str]:
        """The diagnosis as sentences, as every front end prints it."""
        what = (f"no {self.what} holds every rule; the closest" if self.combined
                else f"no {self.what} holds it")
        first = f"{self.joint}: {what}: " + "; ".join(s.text() for s in self.shortfalls) + "."
        lines = [first]
        unit = f"{self.what}'s" if self.what == "unit" else "gearhead's"
        if self.gravity is not None and self.gravity.exceeds:
            helps = ("" if any(step.kind == "slowdown" for step in self.steps)
                     else ": no slow-down or lower speed/acceleration limit helps")
            lines.append(f"{self.joint}: gravity alone needs {_number(self.gravity.torque)} N m, "
                         f"over every {unit} limit ({self.gravity.unit}: "
                         f"{_number(self.gravity.limit)} N m){helps}.")
        lines += [f"{self.joint}: {step.text}" + (f": {step.command}" if step.command else "")
                  for step in self.steps]
        return lines

    def to_dict(self) -> dict[str, Any]:
        """As JSON: plain numbers and strings, every number finite or None."""
        def finite(x: float | None) -> float | None:
            return x if x is not None and math.isfinite(x) else None
        return {
            "headline": self.headline.short(),
            "combined": self.combined,
            "candidates": self.what,
            "shortfalls": [{"rule": s.rule, "unit": s.unit, "value": finite(s.value),
                            "limit": finite(s.limit), "usable_limit": finite(s.usable),
                            "si_unit": s.si, "utilization": finite(s.utilization),
                            "text": s.text()} for s in self.shortfalls],
            "gravity": None if self.gravity is None else {
                "torque_nm": self.gravity.torque, "limit_nm": finite(self.gravity.limit),
                "unit": self.gravity.unit, "exceeds": self.gravity.exceeds},
            "next_steps": [{"kind": s.kind, "text": s.text, "command": s.command,
                            "unit": s.unit, "value": s.value, "catalog": s.catalog}
                           for s in self.steps],
        }


def diagnose(result: SizingResult, *, catalogs: Mapping[str, Sequence[Unit]] | None = None,
             payload_bounds: PayloadBounds | None = None,
             command: Sequence[str] | None = None) -> dict[str, Diagnosis]:
    """A diagnosis of every sized joint that no candidate holds.

    Only those joints are looked at, once: the shortfalls and gravity from the sizing's
    own checks and one gravity pass; a shipped series by one check of the joint's cycle
    per catalog and one sizing with the chosen catalog; less payload by the payload solver
    and one sizing at its mass.

    Args:
        result: The sizing (`hdselect.size`), with its tasks.
        catalogs: Shipped catalogs to look for a unit in, by their ``--catalog`` argument
            (default: `shipped_catalogs`); a catalog whose units are all candidates
            already is skipped.
        payload_bounds: The payload solver (`PayloadBounds`); None offers no payload step.
        command: The command line of the run, program name first: each step's command is
            it with one option set (the output options left out); None (from Python):
            ``hdselect size FILE`` with the option.

    Returns:
        Joint name -> its diagnosis, in the robot's order; empty where every joint has a
        unit.
    """
    missing = [joint for joint in result.joints if joint.selected is None]
    if not missing:
        return {}
    options = result.options
    masses = ({joint.name: added_mass(joint, options) for joint in result.joints}
              if options.mass_coupling else {})
    tasks = result.counted or (Task(result.robot, result.trajectory),)
    gravity = _gravity(tasks, masses, result.robot.sized_joints)
    rest = pooled(tasks, result.idle).rest
    out: dict[str, Diagnosis] = {}
    for joint in missing:
        j = result.robot.joint_index(joint.name)
        shortfalls, combined = _shortfalls(joint.candidates)
        held = _gravity_load(joint, gravity[:, j], rest[:, j], options)
        what = "pair" if any(c.motor_unit is not None for c in joint.candidates) else "unit"
        out[joint.name] = Diagnosis(joint.name, shortfalls, combined, held, what=what)
    found = catalog_steps(result, missing, tasks,
                           shipped_catalogs() if catalogs is None else catalogs, command)
    payload = payload_steps(result, missing, tasks, masses, payload_bounds, command)
    exclude = exclude_step(result, [joint.name for joint in missing], command)
    for joint in missing:
        steps = (*found.get(joint.name, ()), *payload.get(joint.name, ()),
                 exclude, slowdown_step(result, joint))
        out[joint.name] = replace(out[joint.name],
                                  steps=tuple(step for step in steps if step is not None))
    return out


def shipped_catalogs() -> dict[str, tuple[Unit, ...]]:
    """The catalogs shipped with hdselect but the default, by name (``--catalog NAME``).

    Each with its own units only (`hdselect.catalog.builtin.builtin_catalogs`): the one
    place the diagnosis learns which series are shipped.
    """
    return {catalog.name: tuple(unit for unit in load_catalog([catalog.name])
                                if unit.source == catalog.file)
            for catalog in builtin_catalogs() if catalog.name != DEFAULT}


def diagnosis_of(result: SizingResult, joint: str) -> Diagnosis | None:
    """The diagnosis of a joint kept on a result (`with_diagnoses`), or None."""
    found = result.diagnoses.get(joint)
    return found if isinstance(found, Diagnosis) else None


def with_diagnoses(result: SizingResult, **keywords: Any) -> SizingResult:
    """The result with `diagnose`'s diagnoses kept on it (its ``diagnoses``).

    A result that has them already, or has a unit on every joint, is returned as it is:
    every front end may call this, and the diagnoses are computed once.

    Args:
        result: The sizing.
        **keywords: `diagnose`'s keywords (``catalogs``, ``payload_bounds``).
    """
    if result.diagnoses or result.feasible:
        return result
    return replace(result, diagnoses=diagnose(result, **keywords))


def _order(found: Rule) -> tuple[int, ...]:
    """Where a rule's shortfall comes in a diagnosis.

    The gearhead's torque rules of single samples, its averaged torque, its speeds, then
    the bearing's, the motor's and the pair's rules; every life last.
    """
    parts = list(Part)
    return (int(found.life), parts.index(found.part), int(found.unit != "N m"),
            int(found.scope is Scope.CYCLE), list(RULES).index(found))


def _shortfalls(candidates: Sequence[Candidate]) -> tuple[tuple[Shortfall, ...], bool]:
    """Each rule no candidate holds, against the candidate closest to holding it.

    Where every rule has a candidate that holds it, the closest candidate overall (the
    smallest largest utilization among the rules that are not a life) and its failures.
    """
    names = sorted({name for c in candidates for name in c.checks}, key=lambda n: _order(rule(n)))
    out = []
    for name in names:
        judged = [c for c in candidates if name in c.checks and c.checks[name].value is not None]
        if not judged or any(c.checks[name].ok for c in judged):
            continue
        best = min(judged, key=lambda c: c.checks[name].utilization)
        out.append(_shortfall(best, name))
    if out:
        return tuple(out), False

    def worst(c: Candidate) -> float:
        return max((check.utilization for n, check in c.checks.items()
                    if not rule(n).at_least), default=0.0)
    closest = min(candidates, key=worst)
    failed = [name for name in names if name in closest.checks and not closest.checks[name].ok]
    return tuple(_shortfall(closest, name) for name in failed or [closest.binding]), True


def _shortfall(candidate: Candidate, name: str) -> Shortfall:
    check = candidate.checks[name]
    found = rule(name)
    share = found.share(candidate.required_margin)
    usable = check.limit / share if found.at_least else check.limit * share
    return Shortfall(name, candidate.label, float(check.value or 0.0), float(check.limit),
                     float(usable), found.unit, float(check.utilization))


# gravity

def _gravity(tasks: Sequence[Task], masses: Mapping[str, float],
             sized: Sequence[str]) -> np.ndarray:
    """RNEA(q, 0, 0) of every pooled sample, the units' masses carried [N m], (n, dof)."""
    return np.concatenate([over_states(task, carrying(task, masses, sized),
                                       partial(gravity_at, task.trajectory, None))[0]
                           for task in tasks])


def _gravity_load(joint: JointSizing, gravity: np.ndarray, rest: np.ndarray,
                  options: Options) -> GravityLoad:
    """Gravity alone against the largest usable repeated peak (moving) and static (at rest).

    The limits are those the sizing judges (`PEAK`, `STATIC`), with the design margin.
    """
    held = np.abs(gravity)
    units = list(dict.fromkeys(c.unit for c in joint.candidates))
    out = []
    for limit, read in ((PEAK, ~rest), (STATIC, rest)):
        if not read.any():
            continue
        rated = [u for u in units if _finite(getattr(u, limit.limit, None))]
        if not rated:
            continue
        strongest = max(rated, key=lambda u: limit.allowed(u, options.margin))
        allowed = limit.allowed(strongest, options.margin)
        largest = float(held[read].max())
        out.append((largest > allowed, largest, allowed, strongest.id))
    exceeds = [found for found in out if found[0]]
    _, largest, allowed, unit = (exceeds or out or [(False, 0.0, math.inf, "")])[0]
    return GravityLoad(largest if exceeds else float(held.max(initial=0.0)), float(allowed),
                       unit, bool(exceeds))


def _finite(x: object) -> bool:
    return isinstance(x, int | float) and math.isfinite(x)


def _number(x: float) -> str:
    """A figure as reports show it: 3 significant digits, thousands separated."""
    if not math.isfinite(x):
        return "unlimited"
    return f"{x:,.0f}" if abs(x) >= 1000 else f"{x:.3g}"

