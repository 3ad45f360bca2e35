"""Terminal tables of catalogs and results; they format, they do not compute."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable

from rich import box
from rich.console import Console
from rich.table import Table

from hdselect.catalog import KG_M2_PER_KG_CM2, KG_M2_PER_LB_IN2, KG_PER_LB, NM_PER_LB_IN, Unit
from hdselect.duty import DutyResult
from hdselect.export import MEAN_SPEED_NOTE, assumptions
from hdselect.reflect import MotorDemand
from hdselect.rules import RPM_PER_RAD_S, Candidate, Check, CycleLoad
from hdselect.sizing import JointSizing, SizingResult

RULES = ("peak", "mean", "speed", "momentary", "static")
SHORT = {"peak": "peak", "mean": "mean", "speed": "speed", "momentary": "mom.",
         "static": "static"}


def console() -> Console:
    """A console for tables: the terminal's width, or 100 columns when piped."""
    return Console(width=None if sys.stdout.isatty() else 100, highlight=False)


def percent(utilization: float) -> str:
    """A utilization as a whole percentage."""
    return f"{utilization * 100:.0f}%"


def life_text(hours: float | None, suffix: str = " h") -> str:
    """An L50 life for a table; beyond a million hours the digits stop mattering."""
    if hours is None:
        return "unlimited"
    return f"{hours:,.0f}{suffix}" if hours < 1e6 else f"> 1e6{suffix}"


def verdict(candidate: Candidate) -> str:
    """``ok``, or the worst failing rule and how far it exceeds its limit."""
    if candidate.feasible:
        return "ok"
    worst = candidate.binding
    return f"{SHORT.get(worst, worst)} +{percent(candidate.checks[worst].utilization - 1)}"


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
                      cell("input_inertia", u.input_inertia, inertia, 3),
                      cell("mass", u.mass, mass, 2))
    notes = [f"{u.id}: {f.note}" for u in units for f in u.flags]
    if notes:
        table.caption = ("* stand-in for a blank in the source   † the source's two columns "
                         "disagree\n" + "\n".join(notes))
        table.caption_justify = "left"
    return table


def duty_table(result: DutyResult) -> Table:
    """One row per unit: utilization of each rule, life, verdict; the selection marked."""
    table = _candidates_table(
        f"{result.cycle.path.name}: {_load_text(result.load)}", result.candidates,
        result.selected, life_required=result.cycle.life_hours is not None,
        extra={"L10 h": lambda c: life_text(c.l10_hours, "")})
    notes = [f"▶ selected. utilization = demand / limit; mom. = momentary (T4); L10 = L50 / 5; "
             f"{MEAN_SPEED_NOTE}."]
    selected = result.selected
    events = selected.checks["momentary"].detail.get("allowed_events") if selected else None
    if selected is not None and isinstance(events, float):
        notes.append(f"The selected {selected.unit.id} allows {events:,.0f} momentary events like "
                     "the one given (10^4 / (2 n t), n its input speed in rev/s, t its "
                     "duration).")
    table.caption = "\n".join(notes)
    table.caption_justify = "left"
    return table


def _candidates_table(title: str, candidates: Iterable[Candidate], selected: Candidate | None,
                      *, life_required: bool,
                      extra: dict[str, Callable[[Candidate], str]]) -> Table:
    """Every candidate's utilization per rule, its L50 life, `extra` columns and verdict."""
    table = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False,
                  collapse_padding=True)
    columns = ["unit", *SHORT.values(), *(["life"] if life_required else []), "L50 h", *extra,
               "result"]
    for header in columns:
        table.add_column(header, justify="left" if header in ("unit", "result") else "right",
                         no_wrap=True)
    for c in candidates:
        chosen = c is selected
        cells = [("▶" if chosen else " ") + c.unit.id]
        cells += [_utilization_cell(c.checks[name]) for name in RULES]
        cells += [_utilization_cell(c.checks["life"])] if life_required else []
        cells += [life_text(c.life_hours, ""), *(cell(c) for cell in extra.values()), verdict(c)]
        table.add_row(*cells, style="bold" if chosen else None)
    return table


def _load_text(load: CycleLoad) -> str:
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    return (f"peak {load.peak_torque:.3g} N m, mean torque {mean}, mean output speed "
            f"{load.mean_speed * RPM_PER_RAD_S:.3g} rpm")


def _utilization_cell(check: Check) -> str:
    if check.value is None:
        return "-"
    text = percent(check.utilization)
    return text if check.ok else f"[red]{text}[/red]"


def size_table(result: SizingResult) -> Table:
    """One row per joint: the unit chosen, why, its life and what the motor must do."""
    table = Table(title=_size_title(result), title_justify="left", box=box.SIMPLE_HEAD,
                  pad_edge=False)
    for header in ("joint", "unit", "binding", "L50 life", "motor\npeak N m",
                   "motor\nrms N m", "motor\nmax rpm", "notes"):
        table.add_column(header, no_wrap=header != "notes",
                         justify="left" if header in ("joint", "unit", "binding", "notes")
                         else "right")
    for joint in result.joints:
        chosen = joint.selected
        notes = ["gravity"] if joint.gravity_loaded else []
        if chosen is None:
            strongest = joint.strongest
            table.add_row(joint.name, "[red]none[/red]", f"[red]{verdict(strongest)}[/red]",
                          "", "", "", "", ", ".join(notes))
            continue
        motor = _motor(chosen)
        check = chosen.checks[chosen.binding]
        mark = "*" if chosen.flags else ""
        table.add_row(
            joint.name, chosen.unit.id + mark, f"{chosen.binding} {percent(check.utilization)}",
            life_text(chosen.life_hours), f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}",
            f"{motor.max_speed:,.0f}", ", ".join(notes))
    table.caption = "\n".join(_size_notes(result))
    table.caption_justify = "left"
    return table


def compare_table(result: SizingResult, joint: JointSizing) -> Table:
    """One row per unit for one joint: every rule's utilization, life and motor demand."""
    table = _candidates_table(
        f"Joint {joint.name}: {_load_text(joint.load)}, carries {joint.carried_mass:.2f} kg of "
        "gearheads", joint.candidates, joint.selected,
        life_required=result.options.life_hours is not None,
        extra={"motor\npeak N m": lambda c: f"{_motor(c).peak_torque:.3g}",
               "motor\nrms N m": lambda c: f"{_motor(c).rms_torque:.3g}",
               "motor\nmax rpm": lambda c: f"{_motor(c).max_speed:,.0f}"})
    table.caption = ("▶ selected. utilization = demand / limit; mom. = momentary (T4): the "
                     "worse of an emergency stop and a crash.")
    table.caption_justify = "left"
    return table


def _motor(candidate: Candidate) -> MotorDemand:
    assert candidate.motor is not None  # every size candidate carries its motor demand
    return candidate.motor


def _size_title(result: SizingResult) -> str:
    motion = result.motion
    return (f"{result.robot.path.name} running {motion.path.name} ({motion.planner}): cycle "
            f"{result.cycle_time:.3f} s, {len(result.trajectory.t):,} samples")


def _size_notes(result: SizingResult) -> list[str]:
    notes = ["Assumptions: " + "; ".join(f"{k}: {v}" for k, v in assumptions(result).items())]
    for joint in result.joints:
        if joint.selected is None:
            strongest = joint.strongest
            check = strongest.checks[strongest.binding]
            line = (f"{joint.name}: no unit fits; the strongest, {strongest.unit.id}, fails "
                    f"{strongest.binding} at {percent(check.utilization)} of its limit. ")
            slowdown = joint.slowdown
            if slowdown is None or slowdown.factor is None:
                line += "Gravity alone is too much: no slow-down helps."
            else:
                line += (f"Run {slowdown.factor:.3f}x slower (cycle {slowdown.cycle_time:.3f} s) "
                         f"and {slowdown.unit} fits.")
            notes.append(line)
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.joints
               for c in [joint.selected] if c is not None for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    if loaded:
        notes.append(f"gravity: {', '.join(loaded)} carry gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes
