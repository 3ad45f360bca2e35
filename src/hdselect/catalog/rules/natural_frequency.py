"""``natural_frequency``: the joint's single-axis resonance at least the target."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.rules.forms import (
    Interval,
    PayloadCase,
    Rows,
    ScaleTerms,
    UnitBatch,
)
from hdselect.catalog.rules.masses import EVERY_MASS, masses_within, spans
from hdselect.catalog.stiffness import natural_frequency, unit_k1
from hdselect.catalog.units import Unit

_NEVER: Rows = (np.zeros(1), np.zeros(1), np.ones(1))
"""One row that holds at no time scale: 0 y^2 + 0 y + 1 <= 0."""


class MinNaturalFrequency(Rule):
    """sqrt(K1 / J) / 2 pi >= f_min: Harmonic Drive's single-axis resonance of the joint.

    J is the joint's load inertia, the largest M_jj over the cycle's poses (the lowest
    frequency); K1 the unit's stiffness below T1. Present where the joint has a target
    (``min_natural_frequency``); not rated where the unit's source rates no K1. The
    target is a design choice: the design margin does not apply. Neither a time scale
    nor the path changes it: its time-scale form is exact (every scale or none); the
    payload's is exact too, the load inertia of every pose affine in the payload mass.
    It has no path form: the sizing that chose the units judged it.
    """

    name = "natural_frequency"
    label = "f_n"
    words = "single-axis natural frequency"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE
    margin_applies = False
    at_least = True
    unit = "Hz"
    share_of = "target"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`.

        Raises:
            ValueError: A target without the load inertia (a caller's omission).
        """
        if case.gear is None or case.min_frequency is None:
            return None
        if case.load_inertia is None:
            raise ValueError("natural_frequency needs the joint's load inertia")
        frequency = self.frequency(case.gear[0], case.load_inertia)
        if frequency is None:
            return self.not_rated(None, case.margin)
        return self.judge(frequency if math.isfinite(frequency) else None,  # J = 0: no mass
                          case.min_frequency, case.margin, load_inertia_kg_m2=case.load_inertia)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return ("stiffness",)

    @staticmethod
    def frequency(unit: Unit, load_inertia: float) -> float | None:
        """f_n of the unit under the load inertia [Hz]; None where K1 is not rated."""
        k1 = unit_k1(unit)
        return None if k1 is None else float(natural_frequency(k1, load_inertia))

    def utilization(self, unit: Unit, load_inertia: float, target: float) -> float:
        """The target over f_n [-], as `check` finds it; 0 where K1 is not rated."""
        frequency = self.frequency(unit, load_inertia)
        return 0.0 if frequency is None else target / frequency

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """No row where it holds (or is absent), else one that holds at no scale."""
        if terms.min_frequency is None or terms.load_inertia is None:
            return []
        ok = self.utilization(unit, terms.load_inertia, terms.min_frequency) <= 1.0
        return [] if ok else [_NEVER]

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...] | None:
        """J0 + x J1 <= K1 / (2 pi f_min)^2 at every pose: M_jj is affine in x.

        Every mass where there is no target or K1 is not rated; None without the poses'
        inertias (the forward check then decides).
        """
        k1 = unit_k1(case.unit)
        if case.min_frequency is None or k1 is None:
            return EVERY_MASS
        if case.inertia0 is None or case.inertia1 is None:
            return None
        largest = k1 / (2.0 * math.pi * case.min_frequency) ** 2  # J at f_n = f_min
        return spans(masses_within(case.inertia0, case.inertia1, largest))

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """Each unit's target over f_n (0: not rated); None without a target."""
        if batch.min_frequency is None or batch.load_inertia is None:
            return None
        return np.array([self.utilization(unit, batch.load_inertia, batch.min_frequency)
                         for unit in batch.units])


NATURAL_FREQUENCY = MinNaturalFrequency()
