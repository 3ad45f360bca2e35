"""What every terminal table shares: percentages, lives and verdicts as text.

Tables format; they do not compute. A number shown comes from a result.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable

from rich.console import Console

from hdselect.catalog.checks import LIFE_CAP, life_capped
from hdselect.catalog.rules import CHECK_LABELS, Candidate, Check, rule
from hdselect.report.tables import console_for

DEG_PER_RAD = 180.0 / math.pi


def console() -> Console:
    """A console for standard output.

    A terminal: its width (or ``COLUMNS``), in colour. Else ``COLUMNS`` or 80
    columns, no colour, no trailing spaces.
    """
    return console_for(sys.stdout)


def percent(utilization: float) -> str:
    """A utilization as a whole percentage."""
    return f"{utilization * 100:.0f}%"


def utilization_text(utilization: float, ok: bool) -> str:
    """A utilization as a percentage that never reads as its verdict's opposite.

    Whole percent, except next to the limit: a passing 99.96 % reads ``99.9%`` and a
    failing 100.04 % ``100.1%``, never ``100%`` either way.
    """
    text = percent(utilization)
    if text != "100%":
        return text
    tenths = math.floor(utilization * 1000.0) if ok else math.ceil(utilization * 1000.0)
    return f"{tenths / 10:.1f}%"


CAPPED_LIFE = f"> {LIFE_CAP:.0e}".replace("e+0", "e")
"""How a life at `hdselect.catalog.checks.LIFE_CAP` or beyond reads: ``> 1e6``."""


def life_text(hours: float | None, suffix: str = " h") -> str:
    """A life for a table: ``unlimited``, the hours, or ``> 1e6`` at `LIFE_CAP` and beyond."""
    if hours is None:
        return "unlimited"
    return f"{CAPPED_LIFE}{suffix}" if life_capped(hours) else f"{hours:,.0f}{suffix}"


def selected_note(selected: object, what: str = "unit") -> str:
    """The legend of the ▶ mark, or that nothing is selected (no `what` passes every rule)."""
    return "▶ selected." if selected is not None else (
        f"Nothing is selected: no {what} passes every rule.")


def verdict(candidate: Candidate) -> str:
    """``ok``, or the worst failing rule and how far it exceeds its limit.

    A rule within its limit but above what the design margin leaves reads e.g.
    ``peak 85% > 80%``.
    """
    if candidate.feasible:
        return "ok"
    worst = candidate.binding
    utilization = candidate.checks[worst].utilization
    name = CHECK_LABELS.get(worst, worst)
    if utilization <= 1.0:
        return f"{name} {percent(utilization)} > {percent(1.0 - candidate.required_margin)}"
    return f"{name} +{excess(utilization)}"


def binding_words(candidate: Candidate, name: str | None = None) -> str:
    """A rule and its utilization in words, e.g. ``motor RMS torque, 84 % of rated``.

    Args:
        candidate: The candidate.
        name: The check (default: the candidate's binding rule).
    """
    name = candidate.binding if name is None else name
    check = candidate.checks[name]
    share = utilization_text(check.utilization, check.ok).replace("%", " %")
    found = rule(name)
    return f"{found.words}, {share} of {found.share_of}"


def excess(utilization: float) -> str:
    """How far a failing utilization exceeds its limit, e.g. ``19%`` (``0.4%`` below 1 %)."""
    over = (utilization - 1.0) * 100.0
    return f"{over:.1f}%" if over < 0.95 else f"{over:.0f}%"


def assumed_notes(candidates: Iterable[Candidate]) -> list[str]:
    """Each assumption (rules a catalog file does not state) once, with the units it concerns.

    Stand-ins and corrections of catalog values are listed by ``hdselect catalog``.
    """
    units: dict[str, list[str]] = {}
    for c in candidates:
        for flag in c.flags:
            if flag.kind == "assumed":
                units.setdefault(flag.note, []).append(c.unit.id)
    return [f"{', '.join(ids)}: {note}" for note, ids in units.items()]


def utilization_cell(check: Check, pad: bool = False) -> str:
    """A utilization for a table; one over its limit is marked ✗ (and red, in colour).

    `pad` leaves room for the mark in a column where another cell has it.
    """
    if "not_rated" in check.detail:  # the unit's source gives no limit (or no K1): not checked
        return "not rated" + (" " if pad else "")
    if check.value is None:
        return "- " if pad else "-"
    text = utilization_text(check.utilization, check.ok)
    return (text + (" " if pad else "")) if check.ok else f"[red]{text}✗[/red]"


def shown(check: Check) -> bool:
    """Whether a table shows a check: it has a value, or the unit's source rates nothing.

    The second is a precision target on a unit whose catalog gives no stiffness: its cell
    says ``not rated`` rather than the column being left out.
    """
    return check.value is not None or "not_rated" in check.detail


def ratio_text(ratio: float | None) -> str:
    """An inertia ratio (load at the motor shaft over the rotor) for tables."""
    return "-" if ratio is None else f"{ratio:.3g}"
