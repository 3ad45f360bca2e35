"""``life``: the gear's life at least the life required, where one is required."""

from __future__ import annotations

import math

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.rules.forms import Interval, PayloadCase
from hdselect.catalog.rules.masses import EVERY_MASS, spans
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

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...] | None:
        """T_av(x) at most the torque that gives the required life: the cubic mean's interval.

        L50 = L50_rated (n_rated / N_av) (T_N / T_av)^3 >= required / share: T_av <= T_N
        (L50_rated n_rated / (N_av required))^(1/3). Every mass without a required life or
        where the joint never moves; no form without the joint's cubic mean.
        """
        if case.life_hours is None or case.travel <= 0.0:
            return EVERY_MASS
        if case.mean is None:
            return None
        unit, rules, n_av = case.unit, case.unit.rules, case.mean_input_rpm
        required = (case.life_hours / self.share(case.margin)
                    * (L50_PER_L10 if case.life_basis == "L10" else 1.0))
        most = (unit.rated_torque * (rules.rated_l50_hours * rules.rated_input_speed
                                     / (n_av * required)) ** (1.0 / 3.0)
                if n_av > 0.0 else math.inf)
        return spans(case.mean.at_most(most))


LIFE = Life()
