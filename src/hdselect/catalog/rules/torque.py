"""The largest |T| of some of the cycle's samples against one of the unit's torque limits.

`peak` reads the moving samples (against the repeated peak torque), `static` those at
rest (against the static torque); both are judged, solved in time scale and prefiltered
alike.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from hdselect.catalog.rules.base import Gear, RuleInput, UnitLimit, within
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
from hdselect.catalog.rules.load import CycleLoad
from hdselect.catalog.rules.masses import EVERY_MASS, masses_within, spans
from hdselect.catalog.units import Unit


def torque_rows(terms: ScaleTerms, read: np.ndarray | slice, limit: float) -> Sequence[Rows]:
    """|g + (v + i) y^2| <= limit [N m] at the samples read, as time-scale rows in y = 1/s."""
    g = terms.gravity[read]
    return within(terms.velocity[read] + terms.inertial[read], np.zeros_like(g), g, limit)


def torque_masses(case: PayloadCase, read: np.ndarray | slice,
                  limit: float) -> tuple[Interval, ...]:
    """The payload masses x [kg] at which |tau0 + x tau1| <= limit [N m] at the samples read."""
    return spans(masses_within(case.tau0[read], case.tau1[read], limit))


class TorqueLimit(UnitLimit):
    """The largest |T| of the samples at rest (or of the moving ones) within a unit's limit.

    Attributes:
        at_rest: True: the samples at rest (input locked); False: the moving samples.
    """

    at_rest: ClassVar[bool]
    unit = "N m"

    def torque(self, load: CycleLoad) -> float | None:
        """The cycle's largest |T| of these samples [N m]; None where there is none."""
        return load.static_torque if self.at_rest else load.peak_torque

    def largest(self, case: RuleInput, gear: Gear) -> tuple[float | None, dict[str, object]]:
        """See `UnitLimit.largest`."""
        return self.torque(gear[1]), {}

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """|g + (v + i) y^2| <= the limit at every sample read; no rows where not rated."""
        if not self.rated(unit):
            return []
        return torque_rows(terms, terms.at_rest if self.at_rest else ~terms.at_rest,
                           self.allowed(unit, margin))

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """See `Rule.prefilter`; None where no sample is read (the check then holds)."""
        torque = self.torque(batch.load)
        if torque is None:
            return None
        return self.utilizations(torque, batch.units)

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """|tau0 + x tau1| <= the limit at every sample read; every mass where not rated."""
        if not self.rated(case.unit):
            return EVERY_MASS
        return torque_masses(case, case.rest if self.at_rest else ~case.rest,
                             self.allowed(case.unit, case.margin))

    def path_rows(self, case: PathCase) -> list[Any]:
        """|tau| <= the limit in a piece where the joint does not move (at rest) or moves.

        No bound where the limit is not rated.
        """
        if not self.rated(case.unit):
            return []
        return [PathBound(PathKind.STATIC if self.at_rest else PathKind.TORQUE,
                          self.allowed(case.unit, case.margin))]
