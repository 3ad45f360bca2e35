"""``static``: the largest torque held at rest within the unit's static torque."""

from __future__ import annotations

from hdselect.catalog.rules.torque import TorqueLimit


class Static(TorqueLimit):
    """|T| of every sample at rest (input locked) at most the static torque; None if never."""

    name = "static"
    label = "static"
    words = "static torque"
    limit = "static_torque"
    at_rest = True


STATIC = Static()
