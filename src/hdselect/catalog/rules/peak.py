"""``peak``: the largest torque while moving within the unit's repeated peak torque."""

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


class Peak(Rule):
    """|T| of every moving sample (the catalog's T1..T3) at most the repeated peak T_R."""

    name = "peak"
    label = "peak"
    words = "repeated peak torque"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE
    unit = "N m"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None:
            return None
        unit, load = gear
        return self.judge(load.peak_torque, unit.repeated_torque, case.margin)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return ("repeated_torque",)

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """|g + (v + i) y^2| <= T_R at every moving sample."""
        moving = ~terms.at_rest
        g = terms.gravity[moving]
        return within(terms.velocity[moving] + terms.inertial[moving], np.zeros_like(g), g,
                      self.derate(unit.repeated_torque, margin))

    def prefilter(self, batch: UnitBatch) -> np.ndarray:
        """See `Rule.prefilter`."""
        return batch.load.peak_torque / np.array([unit.repeated_torque for unit in batch.units])

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """|tau0 + x tau1| <= T_R at every moving sample."""
        moving = ~case.rest
        return spans(masses_within(case.tau0[moving], case.tau1[moving],
                                   self.derate(case.unit.repeated_torque, case.margin)))

    def path_rows(self, case: PathCase) -> list[Any]:
        """|tau| <= T_R where the joint moves."""
        return [PathBound(PathKind.TORQUE, self.derate(case.unit.repeated_torque, case.margin))]


PEAK = Peak()
