"""Terminal tables of a study: the unit chosen per case, pivoted on its parameters."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from hdselect.report.codesign_tables import short
from hdselect.report.tables import Column, FittedTable


def study_tables(pivots: Iterable[Any], constant: dict[str, str]) -> list[FittedTable | str]:
    """The unit selected per joint against the first two varied parameters of a study.

    Args:
        pivots: `hdselect.study.store.Pivot` of each joint whose unit varies.
        constant: Joint -> unit for the joints whose unit is the same in every case.

    Returns:
        A table per pivot, then a line for the joints that never change.
    """
    out: list[FittedTable | str] = []
    for pivot in pivots:
        across = f", {pivot.columns} across" if pivot.columns else ""
        # each column its own group: on a narrow terminal the columns that do not fit go
        # into tables below, each repeating the row's value
        columns = (Column(pivot.rows), *(Column(value or "unit", "left", group=f"{k}")
                                         for k, value in enumerate(pivot.column_values)))
        rows = tuple((row, *("/".join(short(u) for u in pivot.cells.get((row, c), [])) or "-"
                             for c in pivot.column_values))
                     for row in pivot.row_values)
        out.append(FittedTable(f"{pivot.joint}: unit selected ({pivot.rows} down{across})",
                               columns, rows))
    if constant:
        out.append("the same unit in every case: " + ", ".join(
            f"{joint} {unit}" for joint, unit in constant.items()))
    return out


def study_value_table(pivot: Any, what: str) -> FittedTable:
    """One number per case against the first two varied parameters of a study.

    Args:
        pivot: `hdselect.study.store.value_pivot` of one computation.
        what: What the number is, with its unit (``fastest cycle s``).
    """
    across = f", {pivot.columns} across" if pivot.columns else ""
    columns = (Column(pivot.rows), *(Column(value or what, group=f"{k}")
                                     for k, value in enumerate(pivot.column_values)))
    rows = tuple((row, *("/".join(pivot.cells.get((row, c), [])) or "-"
                         for c in pivot.column_values))
                 for row in pivot.row_values)
    return FittedTable(f"{what} ({pivot.rows} down{across})", columns, rows)
