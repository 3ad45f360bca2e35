"""The output bearing in the HTML report: every joint's loads, and its unit's rating."""

from __future__ import annotations

import base64
from collections.abc import Mapping

from hdselect.catalog.bearing_rules import NOT_RATED, BearingLoad
from hdselect.report.html_tables import esc, table
from hdselect.report.terminal import life_text
from hdselect.sizing.records import BEARING_RULE_NOTE
from hdselect.sizing.result import JointSizing, SizingResult

NO_UNIT = "no unit holds this joint: its loads are reported, not checked"
"""The rating cell and caption of a joint without a unit: no unit is named for it."""


def figure(value: float | None, unit: str = "") -> str:
    """A load for a table, three significant digits (``-`` for none)."""
    if value is None:
        return "-"
    text = f"{value:,.0f}" if abs(value) >= 1000.0 else f"{value:.3g}"
    return f"{text} {unit}".strip()


def bearing_section(result: SizingResult, figures: Mapping[str, bytes]) -> str:
    """Every sized joint's output-bearing loads and what its unit's catalog says of them.

    Each joint's bearing figure (PNG content by joint name) follows the table, two to a row
    on paper.
    """
    joints = [joint for joint in result.joints if joint.bearing is not None]
    if not joints:
        return ""
    header = ["joint", "unit", "flange along axis [m]", "tilting moment M [N m] max / mean",
              "radial F_r [N] max / mean", "axial F_a [N] max / mean", "bearing L10 life",
              "static safety C0 / P0", "P_c [N]", "rating"]
    rows = table(header, [_row(joint) for joint in joints], left=2, text=[9])
    return ("<section id=bearing><h2>Output bearings</h2><p>The force and moment through each "
            "sized joint, from the inverse dynamics of the cycle with the carried units and the "
            "payload, load its gearhead's output bearing: the tilting moment M, the radial force "
            "F_r and the axial force F_a, about the output flange. Largest over the cycle (held "
            "poses included) / the 10/3-power mean over the moving part weighted by |n| t. "
            "Where the unit's catalog rates the bearing, its checks join the unit's in the "
            f"tables above (b. = bearing), under the same design margin.</p>{rows}"
            f"<p>{esc(BEARING_RULE_NOTE)}.</p><div class=bearingfigs>"
            + "".join(_figure(joint, figures.get(joint.name)) for joint in joints)
            + "</div></section>")


def _row(joint: JointSizing) -> list[str]:
    load = joint.bearing
    if load is None:
        raise RuntimeError(f"joint {joint.name} has no bearing loads to show")
    shown = joint.selected or joint.strongest
    figures = shown.bearing
    if joint.selected is None:
        rating = f"<td class='t wrap'>{esc(NO_UNIT)}</td>"
        life = safety = equivalent = "-"
    elif shown.unit.bearing is None:
        rating = f"<td class='t wrap'>{esc(NOT_RATED)}</td>"
        life = safety = equivalent = "-"
    else:
        rating = "rated: checked" if figures else "rated"
        life = "-" if figures is None else life_text(figures.life_hours)
        safety = "-" if figures is None else figure(figures.static_safety)
        equivalent = "-" if figures is None else figure(figures.equivalent_load)
    unit = "none" if joint.selected is None else esc(shown.unit.id)
    return [esc(joint.name), unit, f"{load.offset:g}",
            *(_pair(a, b) for a, b in _loads(load)), esc(life).replace(" h", "&nbsp;h"),
            esc(safety), esc(equivalent), rating]


def _loads(load: BearingLoad) -> tuple[tuple[float, float | None], ...]:
    return ((load.max_moment, load.mean_moment), (load.max_radial, load.mean_radial),
            (load.max_axial, load.mean_axial))


def _pair(largest: float, mean: float | None) -> str:
    return esc(f"{figure(largest)} / {figure(mean)}")


def _figure(joint: JointSizing, png: bytes | None) -> str:
    """A joint's bearing figure, embedded, with its caption; empty without one."""
    if png is None or joint.bearing is None:
        return ""
    shown = joint.selected or joint.strongest
    data = base64.b64encode(png).decode("ascii")
    rated = (esc(NO_UNIT) if joint.selected is None
             else "its allowable loads drawn" if shown.unit.bearing is not None
             else f"{esc(shown.unit.id)}: {esc(NOT_RATED)}")
    return (f"<figure><img src='data:image/png;base64,{data}' alt='output bearing loads of "
            f"{esc(joint.name)} over the cycle'><figcaption>Output bearing of "
            f"{esc(joint.name)}: tilting moment, radial and axial force over the cycle, the "
            f"largest marked, the 10/3-power mean dotted; {rated}. Grey bands: at rest."
            "</figcaption></figure>")

