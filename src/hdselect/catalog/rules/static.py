"""``static``: the largest torque held at rest within the unit's static torque."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope, within
from hdselect.catalog.rules.forms import (
    Interval,
    PathBound,
    PathCase,
    PathKind,
    PayloadCase,
    Rows,
    ScaleTerms,
    UnitBatch,
)
from hdselect.catalog.rules.masses import masses_within, spans
from hdselect.catalog.units import Unit


class Static(Rule):
    """|T| of every sample at rest (input locked) at most the static torque; None if never."""

    name = "static"
    label = "static"
    words = "static torque"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE
    unit = "N m"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None:
            return None
        unit, load = gear
        return self.judge(load.static_torque, unit.static_torque, case.margin)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return ("static_torque",)

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """|g + (v + i) y^2| <= the static torque at every sample at rest."""
        rest = terms.at_rest
        g = terms.gravity[rest]
        return within(terms.velocity[rest] + terms.inertial[rest], np.zeros_like(g), g,
                      self.derate(unit.static_torque, margin))

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """See `Rule.prefilter`."""
        if batch.load.static_torque is None:
            return None  # never at rest: the check holds for every unit
        return batch.load.static_torque / np.array([unit.static_torque for unit in batch.units])

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """|tau0 + x tau1| <= the static torque at every sample at rest."""
        return spans(masses_within(case.tau0[case.rest], case.tau1[case.rest],
                                   self.derate(case.unit.static_torque, case.margin)))

    def path_rows(self, case: PathCase) -> list[Any]:
        """|tau| <= the static torque in a piece where the joint does not move."""
        return [PathBound(PathKind.STATIC, self.derate(case.unit.static_torque, case.margin))]


STATIC = Static()
