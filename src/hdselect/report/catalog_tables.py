"""Terminal tables of the catalog and of the catalog page's own duty method."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from rich.markup import escape

from hdselect.catalog.duty import DutyResult
from hdselect.catalog.units import (
    KG_M2_PER_KG_CM2,
    KG_M2_PER_LB_IN2,
    KG_PER_LB,
    NM_PER_LB_IN,
    SeriesRules,
    Unit,
)
from hdselect.report.size_tables import candidates_table, load_text
from hdselect.report.tables import Column, FittedTable
from hdselect.report.terminal import assumed_notes, life_text, selected_note
from hdselect.sizing.records import HOLD_NOTE, margin_text, mean_speed_note

MARKS = {"fallback": "*", "corrected": "†"}
"""The mark of a catalog value by the kind of its flag."""


LEGEND = {"fallback": "* stand-in for a blank in the source",
          "corrected": "† the source's two columns disagree",
          "not-rated": "n.r. not rated by the source"}
"""What each mark of the table means, by the kind of flag that makes it."""


def catalog_table(units: Iterable[Unit], imperial: bool = False) -> FittedTable:
    """The catalog as a table of the values used, flagged values marked with * or †.

    Imperial figures, and the notes under the table, are the SI values used,
    converted back.
    """
    units = list(units)
    if imperial:
        torque, torque_unit = 1.0 / NM_PER_LB_IN, "lb-in"
        inertia, inertia_unit = 1.0 / KG_M2_PER_LB_IN2, "lb-in²"
        mass, mass_unit = 1.0 / KG_PER_LB, "lb"
    else:
        torque, torque_unit = 1.0, "N m"
        inertia, inertia_unit = 1.0 / KG_M2_PER_KG_CM2, "kg cm²"
        mass, mass_unit = 1.0, "kg"
    title = (f"Gearhead catalog: output torques in {torque_unit}, max input speed in rpm, input "
             f"inertia in {inertia_unit}, mass in {mass_unit}")
    average = any(u.average_torque is not None for u in units)
    average_speed = any(u.max_average_input_speed is not None for u in units)
    speeds = {u.rules.rated_input_speed for u in units}
    rated = f"rated\n@{speeds.pop():g}" if len(speeds) == 1 else "rated"
    columns = [Column("unit", "left"), *(Column(h, group="torque") for h in (
        rated, "repeated", "momentary", "static")), Column("max\ninput", group="speed"),
        Column("input\ninertia", group="inertia"), Column("mass", group="mass"),
        *([Column("average", group="average")] if average else []),
        *([Column("max avg\ninput", group="average speed")] if average_speed else [])]
    rows = []
    for u in units:
        marks = {f.field: MARKS[f.kind] for f in u.flags if f.kind in MARKS}

        not_rated = {f.field for f in u.flags if f.kind == "not-rated"}

        def cell(field: str, value: float | None, scale: float, digits: int = 3,
                 marks: dict[str, str] = marks, not_rated: set[str] = not_rated) -> str:
            if value is None:
                return "n.r." if field in not_rated else "-"
            return f"{_figure(value * scale, digits)}{marks.get(field, '')}"

        cells = [escape(u.id), cell("rated_torque", u.rated_torque, torque),
                 cell("repeated_torque", u.repeated_torque, torque),
                 cell("momentary_torque", u.momentary_torque, torque),
                 cell("static_torque", u.static_torque, torque), f"{u.max_input_speed:.0f}",
                 cell("input_inertia", u.input_inertia, inertia, 3), cell("mass", u.mass, mass, 2)]
        cells += [cell("average_torque", u.average_torque, torque)] if average else []
        cells += [cell("", u.max_average_input_speed, 1.0, 4)] if average_speed else []
        rows.append(tuple(cells))
    notes = _flag_notes(units, imperial)
    rules = {u.rules: sorted({v.series for v in units if v.rules == u.rules}) for u in units}
    if len(rules) > 1:  # one set of rules needs no listing; several say which is whose
        notes += [f"{', '.join(series)}: {_rules_text(r)}" for r, series in rules.items()]
    for info, series in {u.catalog: u.series for u in units}.items():
        notes += [f"{info.name or series}: {text}" for text in (
            info.check, info.transcription and f"transcription: {info.transcription}") if text]
    kinds = {f.kind for u in units for f in u.flags}
    legend = [text for kind, text in LEGEND.items() if kind in kinds]
    if notes and legend:
        notes.insert(0, "   ".join(legend))
    return FittedTable(title, tuple(columns), tuple(rows), notes=tuple(notes))


def _figure(value: float, digits: int) -> str:
    """A value in `digits` significant figures, whole where that would need an exponent."""
    text = f"{value:.{digits}g}"
    return f"{value:.0f}" if "e+" in text else text


def _flag_notes(units: list[Unit], imperial: bool) -> list[str]:
    """Each unit's flag notes, but a catalog's transcription (said under the table).

    A note on every unit listed of one catalog file is said once, naming the catalog.
    """
    found: dict[str, list[Unit]] = {}
    for u in units:
        for f in u.flags:
            found.setdefault(f.text(imperial), []).append(u)
    notes: dict[str, None] = {}
    for u in units:
        for f in u.flags:
            text, on = f.text(imperial), found[f.text(imperial)]
            if f.kind == "transcription":
                continue
            if len(on) > 1 and on == [v for v in units if v.source == u.source]:
                notes[f"{u.catalog.name or u.series} (every unit): {text}"] = None
            else:
                notes[f"{u.id}: {text}"] = None
    return list(notes)


def catalog_list_table(document: dict[str, Any]) -> FittedTable:
    """The built-in catalogs in brief (`hdselect.report.export.catalog_list_json`)."""
    columns = (Column("name", "left"), Column("series", "left"), Column("units"),
               Column("sizes"), Column("ratios"), Column("repeated\nN m"),
               Column("bearing\nrated", "left"), Column("source", "left"))
    rows, notes = [], []
    for c in document["catalogs"]:
        low, high = c["repeated_torque_nm"]
        rows.append((escape(c["name"]), escape(c["series"]), str(c["units"]),
                     _span(c["sizes"]), _span(c["ratios"]), f"{_torque(low)}-{_torque(high)}",
                     c["bearing_rated"], "transcription" if c["transcription"] else "document"))
        sources = "; ".join(f"{d['title']} ({d['edition']})" for d in c["documents"])
        notes.append(f"{c['name']}: {sources or 'no source claimed'}"
                     + (f"; transcription: {c['transcription']}" if c["transcription"] else ""))
    notes.append("Load one with --catalog NAME (PSA-G is always loaded); choose only among "
                 "some series with --series NAME. Check the current vendor data before "
                 "ordering.")
    return FittedTable("Built-in catalogs: repeated-peak torque range in N m; source: the "
                       "vendor's document, or in part a public transcription of it",
                       columns, tuple(rows), notes=tuple(notes))


def _torque(value: float) -> str:
    """A torque [N m] in three figures, without an exponent: ``2.6``, ``20.3``, ``1260``."""
    return f"{value:.3g}" if value < 100.0 else f"{value:.0f}"


def _span(values: list[int]) -> str:
    """Whole numbers as their range, e.g. ``14-65``, or the one value."""
    return f"{values[0]}" if values[0] == values[-1] else f"{values[0]}-{values[-1]}"


def _rules_text(rules: SeriesRules) -> str:
    """A series' rules in one line, e.g. for the catalog listing."""
    text = (f"rated at {rules.rated_input_speed:g} rpm input for {rules.rated_life_hours:,.0f} h "
            f"{rules.life_basis}; {rules.mean_torque_limit} mean-torque limit; mean speed over "
            f"{rules.mean_speed.over}; "
            f"at most {rules.max_momentary_events:,.0f} momentary events ({rules.source.name})")
    return text if rules.flag is None else f"{text}; assumed: the catalog file states no [rules]"


def duty_table(result: DutyResult) -> FittedTable:
    """One row per unit: utilization of each rule, life, verdict; the selection marked."""
    cycle = result.cycle
    units = [c.unit for c in result.candidates]
    average = any(c.checks["average_speed"].value is not None for c in result.candidates)
    notes = [f"{selected_note(result.selected)} utilization = demand / limit, ✗ over the "
             "limit; mom. = momentary "
             f"(T4); {'avg speed = mean input speed; ' if average else ''}L10 = L50 / 5; "
             f"{mean_speed_note(units)}."]
    margin = max((c.required_margin for c in result.candidates), default=0.0)
    if margin > 0.0:
        notes.append(f"Design margin {margin_text(margin)}.")
    if result.hold_only:
        notes.append(HOLD_NOTE + ".")
    if cycle.life_hours is not None and cycle.life_basis != "L50":
        notes.append(f"life: the required {cycle.life_hours:,.0f} h {cycle.life_basis} over each "
                     f"unit's {cycle.life_basis} life.")
    selected = result.selected
    events = selected.checks["momentary"].detail.get("allowed_events") if selected else None
    if selected is not None and isinstance(events, float):
        cap = selected.unit.rules.max_momentary_events
        notes.append(f"The selected {selected.unit.id} allows {events:,.0f} momentary events like "
                     "the one given (10^4 / (2 n t), n its input speed in rev/s, t its "
                     f"duration{f'; at most {cap:,.0f} by its rules' if events >= cap else ''}).")
    notes += assumed_notes(result.candidates)
    return candidates_table(
        f"{cycle.path.name}: {load_text(result.load, units)}", result.candidates,
        result.selected, extra={"L10 h": lambda c: life_text(c.l10_hours, "")}, notes=notes,
        extra_group="life hours")
