"""``mean``: the cubic mean torque within the series' allowable mean torque."""

from __future__ import annotations

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.rules.forms import Interval, PayloadCase
from hdselect.catalog.rules.load import allowable_mean_torque
from hdselect.catalog.rules.masses import EVERY_MASS, spans
from hdselect.catalog.units import Unit


class Mean(Rule):
    """T_av over the moving part at most the allowable mean torque (`allowable_mean_torque`)."""

    name = "mean"
    label = "mean"
    words = "mean torque"
    part = Part.GEARHEAD
    scope = Scope.CYCLE
    unit = "N m"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if (gear := case.gear) is None:
            return None
        allowed, capped = case.allowed_mean
        return self.judge(gear[1].mean_torque, allowed, case.margin,
                          mean_input_speed_rpm=case.mean_input_rpm, capped_by_repeated=capped)

    def fields(self, unit: Unit) -> tuple[str, ...]:
        """See `Rule.fields`."""
        return (("average_torque",) if unit.rules.mean_torque_limit == "tabulated"
                else ("rated_torque",))

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...] | None:
        """T_av(x) <= the allowance (which does not depend on x): the cubic mean's interval.

        Every mass where the joint never moves; no form without the joint's cubic mean.
        """
        if case.travel <= 0.0:
            return EVERY_MASS
        if case.mean is None:
            return None
        allowed, _ = allowable_mean_torque(case.unit, case.mean_input_rpm)
        return spans(case.mean.at_most(self.derate(allowed, case.margin)))


MEAN = Mean()
