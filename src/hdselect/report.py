"""Terminal tables of catalogs and results; they format, they do not compute."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable

from rich import box
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from hdselect.catalog import (
    KG_M2_PER_KG_CM2,
    KG_M2_PER_LB_IN2,
    KG_PER_LB,
    NM_PER_LB_IN,
    SeriesRules,
    Unit,
)
from hdselect.duty import DutyResult
from hdselect.export import assumptions, base_text, mean_speed_note
from hdselect.joints import JointInfo
from hdselect.loads import JointLoad
from hdselect.robot import Robot
from hdselect.rules import (
    CHECK_LABELS,
    CHECKS,
    RPM_PER_RAD_S,
    Candidate,
    Check,
    CycleLoad,
    MotorDemand,
)
from hdselect.sizing import JointSizing, SizingResult

DEG_PER_RAD = 180.0 / math.pi


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
    return f"{CHECK_LABELS.get(worst, worst)} +{percent(candidate.checks[worst].utilization - 1)}"


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
    average = any(u.average_torque is not None for u in units)
    average_speed = any(u.max_average_input_speed is not None for u in units)
    speeds = {u.rules.rated_input_speed for u in units}
    rated = f"rated @{speeds.pop():g}" if len(speeds) == 1 else "rated"
    headers = ["unit", rated, "repeated", "momentary", "static", "max input", "input inertia",
               "mass", *(["average"] if average else []),
               *(["max avg input"] if average_speed else [])]
    for header in headers:
        table.add_column(header, justify="left" if header == "unit" else "right")
    for u in units:
        marks = {f.field: "*" if f.kind == "fallback" else "†" for f in u.flags}

        def cell(field: str, value: float | None, scale: float, digits: int = 3,
                 marks: dict[str, str] = marks) -> str:
            return "-" if value is None else f"{value * scale:.{digits}g}{marks.get(field, '')}"

        cells = [u.id, cell("rated_torque", u.rated_torque, torque),
                 cell("repeated_torque", u.repeated_torque, torque),
                 cell("momentary_torque", u.momentary_torque, torque),
                 cell("static_torque", u.static_torque, torque), f"{u.max_input_speed:.0f}",
                 cell("input_inertia", u.input_inertia, inertia, 3), cell("mass", u.mass, mass, 2)]
        cells += [cell("average_torque", u.average_torque, torque)] if average else []
        cells += [cell("", u.max_average_input_speed, 1.0, 4)] if average_speed else []
        table.add_row(*cells)
    notes = [f"{u.id}: {f.note}" for u in units for f in u.flags]
    rules = {u.rules: sorted({v.series for v in units if v.rules == u.rules}) for u in units}
    if len(rules) > 1:  # one set of rules needs no listing; several say which is whose
        notes += [f"{', '.join(series)}: {_rules_text(r)}" for r, series in rules.items()]
    if notes:
        table.caption = escape("* stand-in for a blank in the source   † the source's two "
                               "columns disagree\n" + "\n".join(notes))
        table.caption_justify = "left"
    return table


def _rules_text(rules: SeriesRules) -> str:
    """A series' rules in one line, e.g. for the catalog listing."""
    text = (f"rated at {rules.rated_input_speed:g} rpm input for {rules.rated_life_hours:,.0f} h "
            f"{rules.life_basis}; {rules.mean_torque_limit} mean-torque limit; mean speed over "
            f"{'the whole cycle' if rules.mean_speed == 'whole-cycle' else 'the moving part'}; "
            f"at most {rules.max_momentary_events:,.0f} momentary events ({rules.source.name})")
    return text if rules.flag is None else f"{text}; assumed: the catalog file states no [rules]"


def duty_table(result: DutyResult) -> Table:
    """One row per unit: utilization of each rule, life, verdict; the selection marked."""
    cycle = result.cycle
    units = [c.unit for c in result.candidates]
    table = _candidates_table(
        f"{cycle.path.name}: {_load_text(result.load, units)}", result.candidates,
        result.selected, extra={"L10 h": lambda c: life_text(c.l10_hours, "")})
    average = any(c.checks["average_speed"].value is not None for c in result.candidates)
    notes = [f"▶ selected. utilization = demand / limit; mom. = momentary (T4); "
             f"{'avg speed = mean input speed; ' if average else ''}L10 = L50 / 5; "
             f"{mean_speed_note(units)}."]
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
    notes += _assumed_notes(result.candidates)
    table.caption = escape("\n".join(notes))
    table.caption_justify = "left"
    return table


def _assumed_notes(candidates: Iterable[Candidate]) -> list[str]:
    """Each assumption (rules a catalog file does not state) once, with the units it concerns.

    Stand-ins and corrections of catalog values are listed by ``hdselect catalog``.
    """
    units: dict[str, list[str]] = {}
    for c in candidates:
        for flag in c.flags:
            if flag.kind == "assumed":
                units.setdefault(flag.note, []).append(c.unit.id)
    return [f"{', '.join(ids)}: {note}" for note, ids in units.items()]


def _candidates_table(title: str, candidates: Iterable[Candidate], selected: Candidate | None,
                      *, extra: dict[str, Callable[[Candidate], str]]) -> Table:
    """Every candidate's utilization per rule, its L50 life, `extra` columns and verdict.

    A rule has a column when some candidate has a value for it.
    """
    candidates = list(candidates)
    names = [name for name in CHECKS
             if any(name in c.checks and c.checks[name].value is not None for c in candidates)]
    table = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False,
                  collapse_padding=True)
    columns = ["unit", *(CHECK_LABELS[name] for name in names), "L50 h", *extra, "result"]
    for header in columns:
        table.add_column(header, justify="left" if header in ("unit", "result") else "right",
                         no_wrap=True)
    for c in candidates:
        chosen = c is selected
        cells = [("▶" if chosen else " ") + c.unit.id]
        cells += [_utilization_cell(c.checks[name]) for name in names]
        cells += [life_text(c.life_hours, ""), *(cell(c) for cell in extra.values()), verdict(c)]
        table.add_row(*cells, style="bold" if chosen else None)
    return table


def _load_text(load: CycleLoad, units: Iterable[Unit]) -> str:
    """The cycle in a line; the whole-cycle mean speed too where a unit's rules use it."""
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    text = (f"peak {load.peak_torque:.3g} N m, mean torque {mean}, mean output speed "
            f"{load.mean_speed * RPM_PER_RAD_S:.3g} rpm")
    if any(u.rules.mean_speed == "whole-cycle" for u in units):
        text += f" moving, {load.cycle_mean_speed * RPM_PER_RAD_S:.3g} rpm over the whole cycle"
    return text


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
    table.caption = escape("\n".join(_size_notes(result)))
    table.caption_justify = "left"
    return table


def compare_table(result: SizingResult, joint: JointSizing) -> Table:
    """One row per unit for one joint: every rule's utilization, life and motor demand."""
    table = _candidates_table(
        f"Joint {joint.name}: {_load_text(joint.load, result.units)}, carries "
        f"{joint.carried_mass:.2f} kg of gearheads", joint.candidates, joint.selected,
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


def time_scale_text(joint: JointSizing) -> str:
    """For a joint no unit fits: the uniform time scale that would fit, and each unit's range."""
    slowdown, scales = joint.slowdown, joint.scales
    if slowdown is None or slowdown.factor is None or scales is None:
        return ("Gravity alone is too much: no slow-down helps (no time scale from 1000x faster "
                "to 1000x slower fits any unit)")
    factor = slowdown.factor
    speed = (f"{factor:.3f}x slower" if factor >= 1.0 else f"{1.0 / factor:.3f}x faster")
    ranges = [f"{unit} for s in " + " or ".join(f"[{lo:.3g}, {hi:.3g}]" for lo, hi in intervals)
              for unit, intervals in scales.fits.items() if intervals]
    return (f"Run {speed} (cycle {slowdown.cycle_time:.3f} s) and {slowdown.unit} fits; "
            f"run s times slower, it fits: {'; '.join(ranges)}")


def _size_title(result: SizingResult) -> str:
    return (f"{result.title}: cycle {result.cycle_time:.3f} s, "
            f"{len(result.trajectory.t):,} samples\n{base_text(result.robot)}")


def loads_table(result: SizingResult) -> Table:
    """Every joint of the robot over the cycle, sized or not, beside its file's limits.

    Angles and speeds are in the motion file's angle unit (degrees without a motion).
    A value above the file's limit is red; why a joint is not sized is noted below.
    """
    angle = result.motion.angle_unit if result.motion is not None else "deg"
    table = Table(title="Every joint over the cycle (peak torque or force with the gearheads "
                        "carried), beside the robot file's limits",
                  title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False,
                  collapse_padding=True)
    for header in ("joint", "type", "sized", "peak / file effort", "speed / file limit",
                   "travel"):
        table.add_column(header, no_wrap=header in ("joint", "type"), justify="left" if header in (
            "joint", "type", "sized", "travel") else "right")
    for load in result.loads:
        table.add_row(load.name, load.kind, "yes" if load.sized else "no",
                      *_load_cells(load, angle))
    notes = [f"{load.name}: {load.note}" for load in result.loads if load.note]
    if notes:
        table.caption = escape("\n".join(notes))
        table.caption_justify = "left"
    return table


def _load_cells(load: JointLoad, angle: str) -> list[str]:
    """Peak and effort limit, speed and velocity limit, travel of one joint, with units."""
    if load.linear:
        force, length, scale = "N", "m", 1.0
    else:
        force, length, scale = "N m", angle, (DEG_PER_RAD if angle == "deg" else 1.0)

    def pair(value: float | None, limit: float, unit: str, over: bool) -> str:
        if value is None:
            return "-"
        shown = f"[red]{value:.3g}[/red]" if over else f"{value:.3g}"
        return f"{shown} / {f'{limit:.3g}' if math.isfinite(limit) else '-'} {unit}"

    low, high = (x * scale for x in load.travel)
    return [pair(load.peak, load.effort_limit, force, load.above_effort),
            pair(load.max_speed * scale, load.velocity_limit * scale, f"{length}/s",
                 load.above_velocity),
            f"{low:.3g} .. {high:.3g} {length}"]


def joints_table(robot: Robot, infos: Iterable[JointInfo]) -> Table:
    """A robot's joints in list order: type, limits, the file's speed and effort, mass moved."""
    infos = list(infos)
    table = Table(title=f"{robot.path.name}: {robot.dof} joints; # is the position in a motion "
                        "file's lists (q = [...]); tables keyed by name need no order",
                  title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False,
                  collapse_padding=True)
    for header in ("#", "joint", "type", "range\nrad or m", "range\ndeg", "max speed\ndeg/s, m/s",
                   "effort\nN m, N", "moves\nkg", "sized"):
        table.add_column(header, no_wrap=header in ("joint", "#", "type"),
                         justify="left" if header in ("joint", "type", "sized") else "right")
    notes = []
    for info in infos:
        linear = info.kind == "prismatic"
        if info.leader is not None:
            offset = f" {info.offset:+g}" if info.offset else ""
            notes.append(f"{info.name} follows {info.leader} (x {info.multiplier:g}{offset}): no "
                         "gearhead of its own; its leader carries its load")
            table.add_row("-", info.name, "mimic", "-", "-", "-", "-", f"{info.moved_mass:.3g}",
                          "no")
            continue
        limited = math.isfinite(info.lower) and math.isfinite(info.upper)
        span = f"{info.lower:.3g} .. {info.upper:.3g}" if limited else "none"
        degrees = (f"{info.lower * DEG_PER_RAD:.3g} .. {info.upper * DEG_PER_RAD:.3g}"
                   if limited and not linear else "-")
        speed = info.velocity_limit * (1.0 if linear else DEG_PER_RAD)
        table.add_row(
            str(info.index), info.name, info.kind, span, degrees,
            f"{speed:.3g}" if math.isfinite(speed) else "-",
            f"{info.effort_limit:.3g}" if math.isfinite(info.effort_limit) else "-",
            f"{info.moved_mass:.3g}", "yes" if info.sized else "no")
        if not info.sized:
            notes.append(f"{info.name}: not sized: " + (
                "the catalog is rotary" if linear else
                "a mimic follower Pinocchio could not couple" if info.name in
                robot.uncoupled_followers else "excluded"))
    notes.append(f"base: '{robot.root_link}' held fixed; a payload goes on "
                 f"'{robot.default_payload_frame}' unless its frame is given; moves: the mass a "
                 "joint moves, links further out included")
    if robot.file_order is not None and robot.file_order != robot.joint_names:
        notes.append(f"the robot file writes the joints in another order "
                     f"({', '.join(robot.file_order)}): lists follow # above")
    notes += [f"robot file: {note}" for note in robot.notes]
    table.caption = escape("\n".join(notes))
    table.caption_justify = "left"
    return table


def _size_notes(result: SizingResult) -> list[str]:
    notes = ["Assumptions: " + "; ".join(f"{k}: {v}" for k, v in assumptions(result).items())]
    for joint in result.joints:
        if joint.selected is None:
            strongest = joint.strongest
            check = strongest.checks[strongest.binding]
            line = (f"{joint.name}: no unit fits; the strongest, {strongest.unit.id}, fails "
                    f"{strongest.binding} at {percent(check.utilization)} of its limit. ")
            notes.append(line + time_scale_text(joint) + ".")
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.joints
               for c in [joint.selected] if c is not None for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    notes += list(result.warnings)
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    if loaded:
        notes.append(f"gravity: {', '.join(loaded)} carry gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes
