"""``torsion``: the unit's twist at the cycle's largest torque within the joint's target."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
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
from hdselect.catalog.rules.masses import EVERY_MASS
from hdselect.catalog.rules.torque import torque_masses, torque_rows
from hdselect.catalog.stiffness import rates_torsion, torque_at_torsion, torsion
from hdselect.catalog.units import RAD_PER_ARCMIN, Stiffness, Unit


def largest_torque(load: CycleLoad) -> float:
    """The cycle's largest |T| [N m], moving or held (the unit twists under either)."""
    return max(load.peak_torque, load.static_torque or 0.0)


class MaxTorsion(Rule):
    """phi(|T|max) <= phi_max: the unit's twist at the cycle's largest |T| within a target.

    The twist is the catalog's three-segment curve (`hdselect.catalog.stiffness.torsion`)
    at the largest |T| of every sample, moving or held. Present where the joint has a
    target (``max_torsion``); not rated where the unit's source rates no K1. The target
    is a design choice, not a rating: the design margin does not apply. Value and limit
    are in arcmin, as reports show them. The solvers' forms take the target as the torque
    at which the unit twists by it (`torque_at_torsion`): the curve rises with |T|, so
    |T| within that torque at every sample is the rule exactly.
    """

    name = "torsion"
    label = "twist"
    words = "largest torsion"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE
    margin_applies = False
    unit = "arcmin"
    share_of = "target"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None or case.max_torsion is None:
            return None
        unit, load = gear
        if unit.stiffness is None or not rates_torsion(unit.stiffness):
            return self.not_rated(None, case.margin)
        return self.judge(self.twist(unit.stiffness, largest_torque(load)),
                          case.max_torsion / RAD_PER_ARCMIN, case.margin)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return ("stiffness",)

    @staticmethod
    def twist(stiffness: Stiffness, torque: float) -> float:
        """The unit's twist under |T| [arcmin]."""
        return float(torsion(stiffness, torque)) / RAD_PER_ARCMIN

    @staticmethod
    def torque_limit(unit: Unit, target: float | None) -> float | None:
        """The torque at which the unit twists by the target [N m]; None: no bound."""
        if target is None or unit.stiffness is None or not rates_torsion(unit.stiffness):
            return None
        return torque_at_torsion(unit.stiffness, target)

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """|g + (v + i) y^2| <= the torque limit at every sample; none without a bound."""
        limit = self.torque_limit(unit, terms.max_torsion)
        return [] if limit is None else torque_rows(terms, slice(None), limit)

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """Each unit's twist over the target (0: not rated); None without a target."""
        if batch.max_torsion is None:
            return None
        torque, target = largest_torque(batch.load), batch.max_torsion / RAD_PER_ARCMIN
        return np.array([self.twist(unit.stiffness, torque) / target
                         if unit.stiffness is not None and rates_torsion(unit.stiffness)
                         else 0.0 for unit in batch.units])

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """|tau0 + x tau1| <= the torque limit at every sample; every mass without a bound."""
        limit = self.torque_limit(case.unit, case.max_torsion)
        return EVERY_MASS if limit is None else torque_masses(case, slice(None), limit)

    def path_rows(self, case: PathCase) -> list[Any]:
        """|tau| within the torque limit, moving and at rest; none without a bound."""
        limit = self.torque_limit(case.unit, case.max_torsion)
        if limit is None:
            return []
        return [PathBound(PathKind.TORQUE, limit), PathBound(PathKind.STATIC, limit)]


TORSION = MaxTorsion()
