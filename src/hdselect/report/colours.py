"""The heat-map scale of a report: colour-blind safe, blue below 100 %, orange to brown above."""

from __future__ import annotations

PASS_COLOURS = ((0.0, "#f7fbff"), (0.5, "#9ecae1"), (1.0, "#2166ac"))
"""Utilization (0 to 1) -> colour of a passing cell: ColorBrewer Blues."""


FAIL_COLOURS = ((1.0, "#fdb863"), (1.5, "#e66101"), (2.0, "#7f3b08"))
"""Utilization (above 1, clipped at 2) -> colour of a failing cell: ColorBrewer PuOr's oranges."""


def utilization_colour(utilization: float) -> str:
    """The colour of a utilization on the report's scale, as ``#rrggbb``.

    Args:
        utilization: Demand over limit [-]; above 1 fails.
    """
    anchors = PASS_COLOURS if utilization <= 1.0 else FAIL_COLOURS
    u = min(max(utilization, anchors[0][0]), anchors[-1][0])
    for (u0, c0), (u1, c1) in zip(anchors, anchors[1:], strict=False):
        if u <= u1:
            f = (u - u0) / (u1 - u0)
            rgb = [round(a + f * (b - a)) for a, b in zip(_rgb(c0), _rgb(c1), strict=True)]
            return "#" + "".join(f"{v:02x}" for v in rgb)
    return anchors[-1][1]


def _rgb(colour: str) -> tuple[int, int, int]:
    return int(colour[1:3], 16), int(colour[3:5], 16), int(colour[5:7], 16)


def ink(colour: str) -> str:
    """Black or white, whichever reads on `colour`."""
    r, g, b = _rgb(colour)
    return "#000" if 0.299 * r + 0.587 * g + 0.114 * b > 140 else "#fff"
