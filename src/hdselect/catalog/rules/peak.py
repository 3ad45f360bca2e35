"""``peak``: the largest torque while moving within the unit's repeated peak torque."""

from __future__ import annotations

from hdselect.catalog.rules.torque import TorqueLimit


class Peak(TorqueLimit):
    """|T| of every moving sample (the catalog's T1..T3) at most the repeated peak T_R."""

    name = "peak"
    label = "peak"
    words = "repeated peak torque"
    limit = "repeated_torque"
    at_rest = False


PEAK = Peak()
