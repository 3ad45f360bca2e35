"""``life``: the gear's life at least the life required, where one is required."""

from __future__ import annotations

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.units import L50_PER_L10


class Life(Rule):
    """The L50 life (an L10 one on the L10 basis: L50 / 5) at least the required life [h].

    Absent without a required life; utilization required / expected, 0 when unlimited.
    """

    name = "life"
    label = "life"
    words = "life"
    part = Part.GEARHEAD
    scope = Scope.CYCLE
    unit = "h"
    at_least = True
    life = True
    share_of = "the expected life required"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if case.gear is None or case.life_hours is None:
            return None
        life = case.l50_hours
        expected = life if life is None or case.life_basis == "L50" else life / L50_PER_L10
        return self.judge(expected, case.life_hours, case.margin, basis=case.life_basis)


LIFE = Life()
