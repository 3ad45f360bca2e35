"""Turn results into terminal tables and JSON; no physics here."""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.table import Table

from hdselect.catalog import KG_M2_PER_KG_CM2, KG_M2_PER_LB_IN2, KG_PER_LB, NM_PER_LB_IN, Unit
from hdselect.duty import DutyResult
from hdselect.errors import InputError
from hdselect.rules import Candidate, Check

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)
MEAN_SPEED_NOTE = ("mean speed averages the moving part of the cycle only (the catalog page's "
                   "t1..t3); dwells do not dilute it, which is the conservative reading")


def console() -> Console:
    """A console for tables: the terminal's width, or 100 columns when piped."""
    return Console(width=None if sys.stdout.isatty() else 100, highlight=False)


def write_output(target: str | Path, write: Callable[[Any], None]) -> None:
    """Write a file atomically (temporary file, then rename); ``-`` is standard output.

    Raises:
        InputError: The file cannot be written.
    """
    if str(target) == "-":
        write(sys.stdout)
        return
    target = Path(target)
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent or Path("."), prefix=f".{target.name}.")
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror})", path=target) from err
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as stream:
            write(stream)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_json(target: str | Path, document: dict[str, Any]) -> None:
    """Write a JSON document to a file or ``-`` (standard output)."""
    write_output(target, lambda stream: (json.dump(document, stream, indent=2),
                                         stream.write("\n")))


def percent(utilization: float) -> str:
    """A utilization as a whole percentage."""
    return f"{utilization * 100:.0f}%"


def life_text(hours: float | None) -> str:
    """An L50 life for a table."""
    if hours is None:
        return "unlimited"
    return f"{hours:,.0f} h" if hours < 1e6 else f"{hours:.2g} h"


def verdict(candidate: Candidate) -> str:
    """``ok``, or the worst failing rule and how far it exceeds its limit."""
    if candidate.feasible:
        return "ok"
    worst = candidate.binding
    return f"{worst} +{percent(candidate.checks[worst].utilization - 1)}"


def flag_marks(candidate: Candidate) -> str:
    """Short marks for a table cell: the catalog fields whose values are stand-ins."""
    return " ".join(sorted({flag.code for flag in candidate.flags}))


# ----------------------------------------------------------------------------- JSON


def check_json(check: Check) -> dict[str, Any]:
    """One check as JSON: value, limit, ok, utilization and any detail."""
    document: dict[str, Any] = {"value": _finite(check.value), "limit": check.limit,
                                "ok": check.ok, "utilization": _finite(check.utilization)}
    document.update({key: _finite(value) for key, value in check.detail.items()})
    return document


def candidate_json(candidate: Candidate) -> dict[str, Any]:
    """One candidate as JSON, the shape shared by ``duty`` and ``size``."""
    unit = candidate.unit
    return {
        "unit": unit.id,
        "size": unit.size,
        "ratio": unit.ratio,
        "feasible": candidate.feasible,
        "life_hours": _finite(candidate.life_hours),
        "flags": sorted({flag.code for flag in candidate.flags}),
        "notes": [flag.note for flag in candidate.flags],
        "binding": candidate.binding,
        "checks": {name: check_json(check) for name, check in candidate.checks.items()},
    }


def duty_json(result: DutyResult) -> dict[str, Any]:
    """A duty-cycle result as JSON."""
    load = result.load
    return {
        "profile": str(result.cycle.path),
        "mean_torque_nm": _finite(load.mean_torque),
        "mean_output_speed_rpm": load.mean_speed * RPM_PER_RAD_S,
        "peak_torque_nm": load.peak_torque,
        "mean_speed_rule": MEAN_SPEED_NOTE,
        "selected": result.selected.unit.id if result.selected else None,
        "candidates": [candidate_json(c) for c in result.candidates],
    }


def catalog_json(units: Iterable[Unit]) -> dict[str, Any]:
    """The catalog as JSON, in SI, with flags."""
    return {"units": [{
        "unit": u.id, "series": u.series, "size": u.size, "ratio": u.ratio,
        "rated_torque_nm": u.rated_torque, "repeated_torque_nm": u.repeated_torque,
        "momentary_torque_nm": u.momentary_torque, "static_torque_nm": u.static_torque,
        "max_input_speed_rpm": u.max_input_speed, "input_inertia_kg_m2": u.input_inertia,
        "mass_kg": u.mass, "efficiency_table": u.efficiency is not None,
        "flags": [{"field": f.field, "kind": f.kind, "note": f.note} for f in u.flags],
        "source": str(u.source),
    } for u in units]}


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


# ----------------------------------------------------------------------------- tables


def catalog_table(units: Iterable[Unit], imperial: bool = False) -> Table:
    """The catalog as a table of the values used, flagged values marked with * or †.

    Imperial figures are the SI values used, converted back.
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
    table = Table(title=f"Gearhead catalog: output torques in {torque_unit}, max input speed "
                        f"in rpm, input inertia in {inertia_unit}, mass in {mass_unit}",
                  title_justify="left")
    for header in ("unit", "rated @1750", "repeated", "momentary", "static", "max input",
                   "input inertia", "mass"):
        table.add_column(header, justify="left" if header == "unit" else "right")
    for u in units:
        marks = {f.field: "*" if f.kind == "fallback" else "†" for f in u.flags}

        def cell(field: str, value: float, scale: float, digits: int = 3,
                 marks: dict[str, str] = marks) -> str:
            return f"{value * scale:.{digits}g}{marks.get(field, '')}"

        table.add_row(u.id, cell("rated_torque", u.rated_torque, torque),
                      cell("repeated_torque", u.repeated_torque, torque),
                      cell("momentary_torque", u.momentary_torque, torque),
                      cell("static_torque", u.static_torque, torque),
                      f"{u.max_input_speed:.0f}",
                      cell("input_inertia", u.input_inertia, inertia, 2),
                      cell("mass", u.mass, mass, 2))
    notes = [f"{u.id}: {f.note}" for u in units for f in u.flags]
    if notes:
        table.caption = ("* stand-in for a blank in the source   † the source's two columns "
                         "disagree\n" + "\n".join(notes))
        table.caption_justify = "left"
    return table


def duty_table(result: DutyResult) -> Table:
    """One row per unit: utilization of each rule, life, verdict; the selection marked."""
    life_required = result.cycle.life_hours is not None
    load = result.load
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    table = Table(
        title=(f"Duty cycle {result.cycle.path.name}: peak {load.peak_torque:.3g} N m, mean "
               f"torque {mean}, mean output speed {load.mean_speed * RPM_PER_RAD_S:.3g} rpm"),
        title_justify="left")
    columns = ["", "unit", "peak", "mean", "speed", "momentary", "static"]
    columns += ["life"] if life_required else []
    columns += ["L50 life", "result"]
    for header in columns:
        table.add_column(header, justify="right" if header not in ("", "unit", "result")
                         else "left", no_wrap=True)
    for c in result.candidates:
        chosen = c is result.selected
        cells = ["▶" if chosen else "", c.unit.id]
        cells += [_utilization_cell(c.checks[name])
                  for name in ("peak", "mean", "speed", "momentary", "static")]
        cells += [_utilization_cell(c.checks["life"])] if life_required else []
        cells += [life_text(c.life_hours), verdict(c)]
        table.add_row(*cells, style="bold" if chosen else None)
    table.caption = (f"▶ selected. utilization = demand / limit; {MEAN_SPEED_NOTE}.")
    table.caption_justify = "left"
    return table


def _utilization_cell(check: Check) -> str:
    if check.value is None:
        return "-"
    text = percent(check.utilization)
    return text if check.ok else f"[red]{text}[/red]"
