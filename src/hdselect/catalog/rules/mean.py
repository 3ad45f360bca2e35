"""``mean``: the cubic mean torque within the series' allowable mean torque."""

from __future__ import annotations

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
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


MEAN = Mean()
