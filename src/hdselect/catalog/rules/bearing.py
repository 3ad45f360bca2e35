"""The rated output bearing's five rules (`hdselect.catalog.bearing_rules` has its figures).

Each is present where the unit's catalog gives the rating it needs and the bearing's
loads are known: the largest tilting moment, radial and axial force against the
allowable ones (on single samples), the L10 life against the life required (with a
required life) and the static safety against the series' factor (on the pooled duty).
"""

from __future__ import annotations

from hdselect.catalog.bearing_rules import BearingFigures
from hdselect.catalog.rules.base import DEFAULT_MARGIN, Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.units import BearingRating, SeriesRules


class BearingRule(Rule):
    """A rule of the rated output bearing: judged from its figures (`judge_bearing`)."""

    part = Part.BEARING

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if case.unit is None or case.unit.bearing is None or case.bearing is None:
            return None
        return self.judge_bearing(case.bearing, case.unit.bearing, case.unit.rules,
                                  life_hours=case.life_hours, margin=case.margin)

    def judge_bearing(self, figures: BearingFigures, rating: BearingRating,
                      rules: SeriesRules, *, life_hours: float | None,
                      margin: float) -> Check | None:
        """The check from the bearing's figures; None where its rating is not given."""
        raise NotImplementedError


class _Largest(BearingRule):
    """A largest load over every sample against its allowable value, where rated."""

    scope = Scope.SAMPLE
    figure: str

    def judge_bearing(self, figures: BearingFigures, rating: BearingRating,
                      rules: SeriesRules, *, life_hours: float | None,
                      margin: float) -> Check | None:
        """See `BearingRule.judge_bearing`."""
        limit = getattr(rating, self.figure)
        if limit is None:
            return None
        return self.judge(getattr(figures.load, self.figure), limit, margin)


class BearingMoment(_Largest):
    """The largest tilting moment M [N m] at most the allowable one."""

    name = "bearing_moment"
    label = "b.moment"
    words = "bearing tilting moment"
    unit = "N m"
    figure = "max_moment"


class BearingRadial(_Largest):
    """The largest radial force F_r [N] at most the allowable one."""

    name = "bearing_radial"
    label = "b.radial"
    words = "bearing radial load"
    unit = "N"
    figure = "max_radial"


class BearingAxial(_Largest):
    """The largest axial force |F_a| [N] at most the allowable one."""

    name = "bearing_axial"
    label = "b.axial"
    words = "bearing axial load"
    unit = "N"
    figure = "max_axial"


class BearingLife(BearingRule):
    """The L10 life at least the required life [h], where C is rated and a life required.

    The bearing's life is an L10 life; against a required L50 it is conservative.
    """

    name = "bearing_life"
    label = "b.life"
    words = "bearing life"
    scope = Scope.CYCLE
    at_least = True
    life = True
    unit = "h"
    share_of = "the expected L10 life required"

    def judge_bearing(self, figures: BearingFigures, rating: BearingRating,
                      rules: SeriesRules, *, life_hours: float | None,
                      margin: float) -> Check | None:
        """See `BearingRule.judge_bearing`."""
        if life_hours is None or rating.dynamic_rating is None:
            return None
        return self.judge(figures.life_hours, life_hours, margin, basis="L10",
                          equivalent_load_n=figures.equivalent_load,
                          mean_output_speed_rpm=figures.mean_speed)


class BearingStatic(BearingRule):
    """The static safety C0 / P_0 at least the series' factor, where C0 is rated."""

    name = "bearing_static"
    label = "b.static"
    words = "bearing static safety"
    scope = Scope.CYCLE
    at_least = True
    share_of = "the safety reached required"

    def judge_bearing(self, figures: BearingFigures, rating: BearingRating,
                      rules: SeriesRules, *, life_hours: float | None,
                      margin: float) -> Check | None:
        """See `BearingRule.judge_bearing`."""
        if rating.static_rating is None:
            return None
        return self.judge(figures.static_safety, rules.bearing_static_safety, margin,
                          static_load_n=figures.static_load)


BEARING_RULES = (BearingMoment(), BearingRadial(), BearingAxial(), BearingLife(),
                 BearingStatic())
"""The bearing's rules, in the order of `hdselect.catalog.rules.BEARING_CHECKS`."""


def bearing_checks(figures: BearingFigures, rating: BearingRating, rules: SeriesRules, *,
                   life_hours: float | None = None,
                   margin: float = DEFAULT_MARGIN) -> dict[str, Check]:
    """The checks of a rated bearing, each where its rating is given, in `BEARING_RULES` order.

    Args:
        figures: The bearing's figures over the cycle (`bearing_figures`).
        rating: What the catalog rates it for.
        rules: The series' rules (the required static safety).
        life_hours: Required life [h]: adds ``bearing_life`` where C is rated.
        margin: Design margin [-], in [0, 1): each check holds at (1 - margin) of its
            limit, a life and a safety as the gear's life: required over reached.

    Returns:
        Check name -> check.
    """
    checks = {}
    for rule in BEARING_RULES:
        check = rule.judge_bearing(figures, rating, rules, life_hours=life_hours, margin=margin)
        if check is not None:
            checks[rule.name] = check
    return checks
