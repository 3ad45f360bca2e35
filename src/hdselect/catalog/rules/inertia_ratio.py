"""``inertia_ratio``: a gearhead and motor pair's load-to-rotor inertia ratio, bounded."""

from __future__ import annotations

import math

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.units import Unit


class InertiaRatio(Rule):
    """(J_load / N^2 + J_in) / J_m at most the largest ratio allowed.

    Present where the joint's load inertia and a largest ratio (given, else the motor's
    own) are known. A motor without rotor inertia cannot be matched, so fails. The design
    margin does not apply: the largest ratio is itself a design choice, not a rating.
    """

    name = "inertia_ratio"
    label = "inertia"
    words = "load-to-rotor inertia ratio"
    part = Part.PAIR
    scope = Scope.SAMPLE
    margin_applies = False
    share_of = "largest allowed"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        motor, unit, load_inertia = case.motor, case.unit, case.load_inertia
        if motor is None or unit is None or load_inertia is None:
            return None
        largest = (case.max_inertia_ratio if case.max_inertia_ratio is not None
                   else motor.max_inertia_ratio)
        if largest is None:
            return None
        return self.of(inertia_ratio(load_inertia, unit, motor), largest)

    def of(self, ratio: float | None, largest: float) -> Check:
        """The check of a pair's ratio [-] (None: no rotor inertia, a failure) at most `largest`."""
        if ratio is None:
            return Check(None, largest, False, math.inf, {"reason": "no rotor inertia"})
        return self.judge(ratio, largest, 0.0)  # the margin does not apply


def inertia_ratio(load_inertia: float, unit: Unit, motor: Motor) -> float | None:
    """Load inertia at the motor shaft over the rotor inertia [-].

    The load at the motor shaft is the joint's output inertia through the ratio plus
    the gearhead's own input inertia, J_load / N^2 + J_in.

    Args:
        load_inertia: The joint's output-side inertia J_load [kg m^2].
        unit: The gearhead.
        motor: The motor.

    Returns:
        (J_load / N^2 + J_in) / J_m; None when the rotor inertia is zero.
    """
    if motor.rotor_inertia <= 0.0:
        return None
    return (load_inertia / unit.ratio**2 + unit.input_inertia) / motor.rotor_inertia


INERTIA_RATIO = InertiaRatio()
