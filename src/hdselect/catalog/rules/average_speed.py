"""``average_speed``: the mean input speed within the unit's limit for it, where it has one."""

from __future__ import annotations

import math

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.rules.forms import Interval, PayloadCase
from hdselect.catalog.rules.masses import EVERY_MASS


class AverageSpeed(Rule):
    """N_av (as the series averages it) at most the maximum average input speed [rpm].

    Value None (and utilization 0) where the unit gives no such limit; where its series'
    rules say a limit the source does not give is not rated (``missing_limits =
    "not-rated"``), `Rule.not_rated`, as a `UnitLimit`'s.
    """

    name = "average_speed"
    label = "avg speed"
    words = "average input speed"
    part = Part.GEARHEAD
    scope = Scope.CYCLE
    unit = "rpm"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None:
            return None
        unit = gear[0]
        limit = unit.max_average_input_speed
        if limit is None and unit.rules.missing_limits == "not-rated":
            return self.not_rated(case.mean_input_rpm, case.margin)
        return self.judge(None if limit is None else case.mean_input_rpm,
                          math.inf if limit is None else limit, case.margin)

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """Every mass or none: N_av does not depend on it."""
        limit = case.unit.max_average_input_speed
        passes = limit is None or case.mean_input_rpm <= self.derate(limit, case.margin)
        return EVERY_MASS if passes else ()


AVERAGE_SPEED = AverageSpeed()
