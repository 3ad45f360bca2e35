"""The output bearing in terminal tables: each joint's loads, and what its unit's rating says.

Tables format; they do not compute: every figure comes from
`hdselect.sizing.result.JointSizing.bearing` and the candidate's checks.
"""

from __future__ import annotations

from hdselect.catalog.bearing_rules import NOT_RATED, BearingLoad
from hdselect.catalog.rules import BEARING_CHECKS, CHECK_LABELS, Candidate
from hdselect.report.tables import Column
from hdselect.report.terminal import utilization_text
from hdselect.sizing.result import JointSizing, SizingResult

BEARING_COLUMNS = (Column("tilt M N m\nmax / mean", group="bearing"),
                   Column("radial N\nmax / mean", group="bearing"),
                   Column("axial N\nmax / mean", group="bearing"),
                   Column("bearing", "left", group="bearing"))
"""The size table's output-bearing columns: they move below together on a narrow terminal."""


def pair(largest: float, mean: float | None) -> str:
    """A load's largest and mean value, e.g. ``8.85 / 6.2`` (``-`` for no mean)."""
    return f"{largest:.3g} / {'-' if mean is None else f'{mean:.3g}'}"


def bearing_cells(joint: JointSizing, candidate: Candidate | None) -> tuple[str, ...]:
    """The joint's tilting moment, radial and axial force, and the rating's verdict.

    Args:
        joint: The joint, with its bearing loads (or none computed).
        candidate: The unit whose rating is judged (selected, else the strongest).

    Returns:
        One cell per `BEARING_COLUMNS`; ``-`` where the loads were not computed.
    """
    load = joint.bearing
    if load is None:
        return ("-", "-", "-", "-")
    return (pair(load.max_moment, load.mean_moment), pair(load.max_radial, load.mean_radial),
            pair(load.max_axial, load.mean_axial), rating_text(candidate))


def rating_text(candidate: Candidate | None) -> str:
    """``not rated``, or the unit's bearing check closest to its limit, e.g. ``life 64%``."""
    if candidate is None or candidate.unit.bearing is None:
        return "not rated"
    names = [name for name in BEARING_CHECKS if name in candidate.checks]
    if not names:
        return "rated, not checked"
    worst = max(names, key=lambda name: candidate.checks[name].utilization)
    check = candidate.checks[worst]
    label = CHECK_LABELS[worst].removeprefix("b.")
    text = f"{label} {utilization_text(check.utilization, check.ok)}"
    return text if check.ok else f"[red]{text}✗[/red]"


def load_line(load: BearingLoad) -> str:
    """The loads in a line, for a joint's heading."""
    return (f"bearing M {pair(load.max_moment, load.mean_moment)} N m, F_r "
            f"{pair(load.max_radial, load.mean_radial)} N, F_a "
            f"{pair(load.max_axial, load.mean_axial)} N (max / mean)")


def bearing_notes(result: SizingResult) -> list[str]:
    """What the bearing columns hold, and which units' bearings are not rated."""
    if all(joint.bearing is None for joint in result.joints):
        return []
    offsets = result.options.bearing_offset
    where = ("the joint origin" if not offsets else "the joint origin, moved along the axis "
             "for " + ", ".join(f"{name} by {value:g} m" for name, value in offsets.items()))
    chosen = [joint.selected or joint.strongest for joint in result.joints
              if joint.bearing is not None]
    unrated = sorted({c.unit.id for c in chosen if c.unit.bearing is None})
    notes = [f"bearing: tilting moment M, radial F_r and axial F_a through each joint about "
             f"its output flange ({where}), largest / 10/3-power mean (moving, weighted by "
             "|n| t); the unit's bearing check nearest its limit."
             + (f" not rated: {NOT_RATED} ({', '.join(unrated)})." if unrated else "")]
    return notes
