"""``speed``: the largest input speed within the unit's maximum input speed."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules.base import Gear, RuleInput, UnitLimit
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
from hdselect.catalog.rules.load import RPM_PER_RAD_S
from hdselect.catalog.rules.masses import EVERY_MASS
from hdselect.catalog.units import Unit


class Speed(UnitLimit):
    """max |qd| N at most the unit's maximum input speed [rpm]."""

    name = "speed"
    label = "speed"
    words = "input speed"
    unit = "rpm"
    limit = "max_input_speed"

    def largest(self, case: RuleInput, gear: Gear) -> tuple[float | None, dict[str, object]]:
        """See `UnitLimit.largest`: the largest input speed [rpm]."""
        unit, load = gear
        return load.max_speed * RPM_PER_RAD_S * unit.ratio, {}

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """The largest |qd| N y at most the maximum input speed [rpm]."""
        return (speed_row(terms, unit, self.allowed(unit, margin)),)

    def prefilter(self, batch: UnitBatch) -> np.ndarray:
        """See `Rule.prefilter`."""
        return self.utilizations(batch.load.max_speed * RPM_PER_RAD_S * batch.ratio,
                                 batch.units)

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """Every mass or none: the speeds do not depend on it."""
        passes = case.max_input_rpm <= self.allowed(case.unit, case.margin)
        return EVERY_MASS if passes else ()

    def path_rows(self, case: PathCase) -> list[Any]:
        """|qd| <= the maximum input speed over the ratio [rad/s]."""
        return [PathBound(PathKind.SPEED, self.allowed(case.unit, case.margin)
                          / case.unit.ratio / RPM_PER_RAD_S, "unit")]


def speed_row(terms: ScaleTerms, unit: Unit, top: float) -> Rows:
    """The largest |qd| N y at most `top` [rpm], as one row in y = 1/s (the input speed's rules)."""
    speed = float(np.abs(terms.qd).max(initial=0.0)) * unit.ratio * RPM_PER_RAD_S
    return np.zeros(1), np.array([speed]), np.array([-top])


SPEED = Speed()
