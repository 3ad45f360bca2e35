"""Terminal tables of catalogs and results; they format, they do not compute."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
from rich.console import Console
from rich.markup import escape

from hdselect.catalog import (
    KG_M2_PER_KG_CM2,
    KG_M2_PER_LB_IN2,
    KG_PER_LB,
    NM_PER_LB_IN,
    SeriesRules,
    Unit,
)
from hdselect.codesign import FastestResult, JointRatios, RatioComparison
from hdselect.duty import DutyResult
from hdselect.export import HOLD_NOTE, assumptions, base_text, mean_speed_note
from hdselect.joints import JointInfo
from hdselect.loads import JointLoad
from hdselect.maxpayload import MaxPayloadResult
from hdselect.motion import Motion
from hdselect.planning import Trajectory
from hdselect.robot import Robot
from hdselect.rules import (
    CHECK_LABELS,
    CHECKS,
    MOTOR_CHECKS,
    RPM_PER_RAD_S,
    Candidate,
    Check,
    CycleLoad,
    MotorDemand,
)
from hdselect.sizing import JointSizing, SizingResult
from hdselect.tables import Column, FittedTable, Paragraphs, console_for

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
    return f"{CHECK_LABELS.get(worst, worst)} +{excess(candidate.checks[worst].utilization)}"


def excess(utilization: float) -> str:
    """How far a failing utilization exceeds its limit, e.g. ``19%`` (``0.4%`` below 1 %)."""
    over = (utilization - 1.0) * 100.0
    return f"{over:.1f}%" if over < 0.95 else f"{over:.0f}%"


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
        marks = {f.field: "*" if f.kind == "fallback" else "†" for f in u.flags}

        def cell(field: str, value: float | None, scale: float, digits: int = 3,
                 marks: dict[str, str] = marks) -> str:
            return "-" if value is None else f"{value * scale:.{digits}g}{marks.get(field, '')}"

        cells = [escape(u.id), cell("rated_torque", u.rated_torque, torque),
                 cell("repeated_torque", u.repeated_torque, torque),
                 cell("momentary_torque", u.momentary_torque, torque),
                 cell("static_torque", u.static_torque, torque), f"{u.max_input_speed:.0f}",
                 cell("input_inertia", u.input_inertia, inertia, 3), cell("mass", u.mass, mass, 2)]
        cells += [cell("average_torque", u.average_torque, torque)] if average else []
        cells += [cell("", u.max_average_input_speed, 1.0, 4)] if average_speed else []
        rows.append(tuple(cells))
    notes = [f"{u.id}: {f.text(imperial)}" for u in units for f in u.flags]
    rules = {u.rules: sorted({v.series for v in units if v.rules == u.rules}) for u in units}
    if len(rules) > 1:  # one set of rules needs no listing; several say which is whose
        notes += [f"{', '.join(series)}: {_rules_text(r)}" for r, series in rules.items()]
    if notes:
        notes.insert(0, "* stand-in for a blank in the source   † the source's two columns "
                        "disagree")
    return FittedTable(title, tuple(columns), tuple(rows), notes=tuple(notes))


def _rules_text(rules: SeriesRules) -> str:
    """A series' rules in one line, e.g. for the catalog listing."""
    text = (f"rated at {rules.rated_input_speed:g} rpm input for {rules.rated_life_hours:,.0f} h "
            f"{rules.life_basis}; {rules.mean_torque_limit} mean-torque limit; mean speed over "
            f"{'the whole cycle' if rules.mean_speed == 'whole-cycle' else 'the moving part'}; "
            f"at most {rules.max_momentary_events:,.0f} momentary events ({rules.source.name})")
    return text if rules.flag is None else f"{text}; assumed: the catalog file states no [rules]"


def duty_table(result: DutyResult) -> FittedTable:
    """One row per unit: utilization of each rule, life, verdict; the selection marked."""
    cycle = result.cycle
    units = [c.unit for c in result.candidates]
    average = any(c.checks["average_speed"].value is not None for c in result.candidates)
    notes = [f"▶ selected. utilization = demand / limit, ✗ over the limit; mom. = momentary "
             f"(T4); {'avg speed = mean input speed; ' if average else ''}L10 = L50 / 5; "
             f"{mean_speed_note(units)}."]
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
    notes += _assumed_notes(result.candidates)
    return _candidates_table(
        f"{cycle.path.name}: {_load_text(result.load, units)}", result.candidates,
        result.selected, extra={"L10 h": lambda c: life_text(c.l10_hours, "")}, notes=notes,
        extra_group="life hours")


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
                      *, extra: dict[str, Callable[[Candidate], str]],
                      notes: Iterable[str] = (), extra_group: str = "extra") -> FittedTable:
    """Every candidate's utilization per rule, its L50 life, `extra` columns and verdict.

    A rule has a column when some candidate has a value for it. On a narrow terminal
    the `extra` columns, then the life and the rules, move below; the unit and its
    verdict stay.
    """
    candidates = list(candidates)
    names = [name for name in CHECKS
             if any(name in c.checks and c.checks[name].value is not None for c in candidates)]
    columns = [Column("unit", "left"), *(Column(CHECK_LABELS[name], group=name) for name in names),
               Column("L50 h", group="life hours"),
               *(Column(header, group=extra_group) for header in extra),
               Column("result", "left")]
    failing = {name for name in names for c in candidates if not c.checks[name].ok}
    rows, styles = [], []
    for c in candidates:
        chosen = c is selected
        cells = [("▶" if chosen else " ") + escape(c.unit.id)]
        cells += [_utilization_cell(c.checks[name], pad=name in failing) for name in names]
        cells += [life_text(c.life_hours, ""), *(cell(c) for cell in extra.values()),
                  verdict(c)]
        rows.append(tuple(cells))
        styles.append("bold" if chosen else None)
    return FittedTable(title, tuple(columns), tuple(rows), tuple(styles), tuple(notes))


def _load_text(load: CycleLoad, units: Iterable[Unit]) -> str:
    """The cycle in a line; the whole-cycle mean speed too where a unit's rules use it."""
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    text = (f"peak {load.peak_torque:.3g} N m, mean torque {mean}, mean output speed "
            f"{load.mean_speed * RPM_PER_RAD_S:.3g} rpm")
    if any(u.rules.mean_speed == "whole-cycle" for u in units):
        text += f" moving, {load.cycle_mean_speed * RPM_PER_RAD_S:.3g} rpm over the whole cycle"
    return text


def _utilization_cell(check: Check, pad: bool = False) -> str:
    """A utilization for a table; one over its limit is marked ✗ (and red, in colour).

    `pad` leaves room for the mark in a column where another cell has it.
    """
    if check.value is None:
        return "- " if pad else "-"
    text = utilization_text(check.utilization, check.ok)
    return (text + (" " if pad else "")) if check.ok else f"[red]{text}✗[/red]"


def size_table(result: SizingResult) -> FittedTable:
    """One row per joint: the unit chosen, why, its life and what the motor must do.

    On a narrow terminal the motor figures and the notes move into a second table;
    without a note on any joint there is no notes column. Where motors are given: the
    pair chosen and the binding rule on either side (`_pairs_table`).
    """
    if result.motors:
        return _pairs_table(result)
    columns = (Column("joint", "left"), Column("unit", "left"), Column("binding", "left"),
               Column("L50 life"), Column("motor\npeak N m", group="motor"),
               Column("motor\nrms N m", group="motor"), Column("motor\nmax rpm", group="motor"),
               Column("notes", "left", group="notes"))
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        notes = ["gravity"] if joint.gravity_loaded else []
        if joint.load.max_speed == 0.0:
            notes.append("still")
        if chosen is None:
            strongest = joint.strongest
            rows.append((escape(joint.name), "[red]none[/red]",
                         f"[red]{verdict(strongest)}[/red]", "-", "-", "-", "-",
                         ", ".join(notes)))
            continue
        motor = _motor(chosen)
        check = chosen.checks[chosen.binding]
        mark = "*" if chosen.flags else ""
        rows.append((
            escape(joint.name), escape(chosen.unit.id) + mark,
            f"{chosen.binding} {utilization_text(check.utilization, True)}",
            life_text(chosen.life_hours),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            ", ".join(notes)))
    shown = len(columns) if any(row[-1] for row in rows) else -1  # no empty notes column
    return FittedTable(_size_title(result), columns[:shown], tuple(row[:shown] for row in rows),
                       notes=tuple(_size_notes(result)))


def ratio_text(ratio: float | None) -> str:
    """An inertia ratio (load at the motor shaft over the rotor) for tables."""
    return "-" if ratio is None else f"{ratio:.3g}"


def _joint_notes(joint: JointSizing) -> list[str]:
    """A joint's notes column: gravity-loaded, still."""
    notes = ["gravity"] if joint.gravity_loaded else []
    if joint.load.max_speed == 0.0:
        notes.append("still")
    return notes


def _pairs_table(result: SizingResult) -> FittedTable:
    """`size_table` where motors are given: one row per joint, its gearhead and motor.

    The joint, the pair and the binding rule on either side stay; on a narrow terminal
    the inertia ratio, the life, the motor figures and the notes move below, in that
    order.
    """
    columns = (Column("joint", "left"), Column("unit", "left"), Column("motor", "left"),
               Column("binding", "left"), Column("motor\nbinding", "left"),
               Column("load/\nrotor", group="inertia"), Column("L50 life", group="life"),
               Column("motor\npeak N m", group="motor"),
               Column("motor\nrms N m", group="motor"), Column("motor\nmax rpm", group="motor"),
               Column("notes", "left", group="notes"))
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        notes = _joint_notes(joint)
        if chosen is None:
            strongest = joint.strongest
            rows.append((escape(joint.name), "[red]none[/red]", "[red]none[/red]",
                         f"[red]{verdict(strongest)}[/red]", "-", "-", "-", "-", "-", "-",
                         ", ".join(notes)))
            continue
        motor = _motor(chosen)
        side = chosen.motor_binding
        rows.append((
            escape(joint.name), escape(chosen.unit.id) + ("*" if chosen.flags else ""),
            "-" if chosen.motor_unit is None else escape(chosen.motor_unit.id),
            _binding_text(chosen, chosen.gearhead_binding),
            "-" if side is None else _binding_text(chosen, side).removeprefix("motor_"),
            ratio_text(joint.inertia_ratio(chosen)), life_text(chosen.life_hours),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            ", ".join(notes)))
    shown = len(columns) if any(row[-1] for row in rows) else -1  # no empty notes column
    return FittedTable(_size_title(result), columns[:shown], tuple(row[:shown] for row in rows),
                       notes=tuple(_size_notes(result)))


def _binding_text(candidate: Candidate, name: str) -> str:
    """A rule's name and utilization, e.g. ``momentary 88%`` (never 100% when it passes)."""
    check = candidate.checks[name]
    return f"{name} {utilization_text(check.utilization, check.ok)}"


def compare_table(result: SizingResult, joint: JointSizing) -> FittedTable:
    """One row per unit for one joint: every rule's utilization, life and motor demand.

    Where the joint has motors, one row per (unit, motor) pair: the motor's rules appear
    among the rules, with the inertia ratio and the motor's torques (`_pairs_compare_table`).
    """
    if joint.name in result.motors:
        return _pairs_compare_table(result, joint)
    return _candidates_table(
        f"Joint {joint.name}: {_load_text(joint.load, result.units)}, carries "
        f"{joint.carried_mass:.2f} kg of gearheads", joint.candidates, joint.selected,
        extra={"motor\npeak N m": lambda c: f"{_motor(c).peak_torque:.3g}",
               "motor\nrms N m": lambda c: f"{_motor(c).rms_torque:.3g}",
               "motor\nmax rpm": lambda c: f"{_motor(c).max_speed:,.0f}"},
        notes=["▶ selected. utilization = demand / limit, ✗ over the limit; mom. = momentary "
               "(T4): the worse of an emergency stop and a crash."])


def _pairs_compare_table(result: SizingResult, joint: JointSizing) -> FittedTable:
    """`compare_table` for a joint with motors: one row per (gearhead, motor) pair.

    The pair, its gearhead's worst rule, the three motor rules and the verdict stay;
    on a narrow terminal the inertia ratio, the life and the motor's torques and speed
    move below, each table repeating the pair.
    """
    columns = (Column("pair", "left"), Column("gearhead", "left"),
               *(Column(CHECK_LABELS[name]) for name in MOTOR_CHECKS),
               Column("load/\nrotor", group="inertia"), Column("L50 h", group="life"),
               Column("motor\npeak N m", group="motor"), Column("motor\nrms N m", group="motor"),
               Column("motor\nmax rpm", group="motor"), Column("result", "left"))
    failing = {name for name in MOTOR_CHECKS for c in joint.candidates
               if name in c.checks and not c.checks[name].ok}
    rows, styles = [], []
    for c in joint.candidates:
        chosen = c is joint.selected
        side = c.gearhead_binding
        check = c.checks[side]
        gearhead = f"{CHECK_LABELS.get(side, side)} {utilization_text(check.utilization, check.ok)}"
        motor = _motor(c)
        rows.append((
            ("▶" if chosen else " ") + escape(c.label),
            gearhead if check.ok else f"[red]{gearhead}✗[/red]",
            *(_utilization_cell(c.checks[name], pad=name in failing) for name in MOTOR_CHECKS),
            ratio_text(joint.inertia_ratio(c)), life_text(c.life_hours, ""),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            verdict(c)))
        styles.append("bold" if chosen else None)
    notes = ("▶ selected. gearhead: its rule with the highest utilization behind this motor "
             "(the crash case carries the motor's rotor inertia), ✗ over the limit; m. = the "
             "motor's rules: peak under its torque-speed curve, RMS over the cycle against its "
             "rated torque, speed; load/rotor = (M_jj / N² + J_in) / J_m, M_jj the joint's "
             "largest over the cycle. --json gives every rule of every pair.",)
    return FittedTable(f"Joint {joint.name}: {_load_text(joint.load, result.units)}, carries "
                       f"{joint.carried_mass:.2f} kg of gearheads and motors", columns,
                       tuple(rows), tuple(styles), notes)


def _motor(candidate: Candidate) -> MotorDemand:
    assert candidate.motor is not None  # every size candidate carries its motor demand
    return candidate.motor


def time_scale_text(joint: JointSizing) -> str:
    """For a joint no unit fits: the uniform time scale that would fit, and each unit's range."""
    slowdown, scales = joint.slowdown, joint.scales
    if slowdown is None or slowdown.factor is None or scales is None:
        what = "pair" if any(c.motor_unit is not None for c in joint.candidates) else "unit"
        return ("Gravity alone is too much: no slow-down helps (no time scale from 1000x faster "
                f"to 1000x slower fits any {what})")
    factor = slowdown.factor
    speed = (f"{factor:.3f}x slower" if factor >= 1.0 else f"{1.0 / factor:.3f}x faster")
    ranges = [f"{unit} for s in " + " or ".join(f"[{lo:.3g}, {hi:.3g}]" for lo, hi in intervals)
              for unit, intervals in scales.fits.items() if intervals]
    return (f"Run {speed} (cycle {slowdown.cycle_time:.3f} s) and {slowdown.unit} fits; "
            f"run s times slower, it fits: {'; '.join(ranges)}")


def _size_title(result: SizingResult) -> str:
    count = len(result.trajectory.t)
    return (f"{result.title}: cycle {result.cycle_time:.3f} s, "
            f"{count:,} sample{'s' if count != 1 else ''}\n{base_text(result.robot)}")


def loads_table(result: SizingResult) -> FittedTable:
    """Every joint of the robot over the cycle, sized or not, beside its file's limits.

    Angles and speeds are in the motion file's angle unit (degrees without a motion).
    A value above the file's limit is red; why a joint is not sized is noted below.
    On a narrow terminal the speeds, then the travel, move below.
    """
    angle = result.motion.angle_unit if result.motion is not None else "deg"
    columns = (Column("joint", "left"), Column("type", "left"), Column("sized", "left"),
               Column("peak / file effort"), Column("speed / file limit", group="speed"),
               Column("travel", "left", group="travel"))
    rows = tuple((escape(load.name), load.kind, "yes" if load.sized else "no",
                  *_load_cells(load, angle)) for load in result.loads)
    notes = [f"{load.name}: {load.note}" for load in result.loads if load.note]
    if any(load.above_effort or load.above_velocity for load in result.loads):
        notes.insert(0, "✗ above the robot file's limit")
    carried = "gearheads and motors" if result.motors else "gearheads"
    return FittedTable(f"Every joint over the cycle (peak torque or force with the {carried} "
                       "carried), beside the robot file's limits", columns, rows,
                       notes=tuple(notes))


def _load_cells(load: JointLoad, angle: str) -> list[str]:
    """Peak and effort limit, speed and velocity limit, travel of one joint, with units."""
    force, length, scale = load.units(angle)

    def pair(value: float | None, limit: float, unit: str, over: bool) -> str:
        if value is None:
            return "-"
        shown = f"[red]{value:.3g}✗[/red]" if over else f"{value:.3g}"
        return f"{shown} / {f'{limit:.3g}' if math.isfinite(limit) else '-'} {unit}"

    low, high = (x * scale for x in load.travel)
    return [pair(load.peak, load.effort_limit, force, load.above_effort),
            pair(load.max_speed * scale, load.velocity_limit * scale, f"{length}/s",
                 load.above_velocity),
            f"{low:.3g} .. {high:.3g} {length}"]


def joints_table(robot: Robot, infos: Iterable[JointInfo]) -> FittedTable:
    """A robot's joints in list order: type, limits, the file's speed and effort, mass moved.

    On a narrow terminal the ranges, then the file's limits, then the mass moved go below.
    """
    columns = (Column("joint", "left"), Column("#"), Column("type", "left"),
               Column("sized", "left"), Column("range\nrad or m", group="range"),
               Column("range\ndeg", group="range"),
               Column("max speed\ndeg/s, m/s", group="limits"),
               Column("effort\nN m, N", group="limits"), Column("moves\nkg", group="moves"))
    rows, notes = [], []
    for info in infos:
        linear = info.kind == "prismatic"
        if info.leader is not None:
            offset = f" {info.offset:+g}" if info.offset else ""
            notes.append(f"{info.name} follows {info.leader} (x {info.multiplier:g}{offset}): no "
                         "gearhead of its own; its leader carries its load")
            rows.append((escape(info.name), "-", "mimic", "no", "-", "-", "-", "-",
                         f"{info.moved_mass:.3g}"))
            continue
        limited = math.isfinite(info.lower) and math.isfinite(info.upper)
        span = f"{info.lower:.3g} .. {info.upper:.3g}" if limited else "none"
        degrees = (f"{info.lower * DEG_PER_RAD:.3g} .. {info.upper * DEG_PER_RAD:.3g}"
                   if limited and not linear else "-")
        speed = info.velocity_limit * (1.0 if linear else DEG_PER_RAD)
        rows.append((
            escape(info.name), str(info.index), info.kind, "yes" if info.sized else "no", span,
            degrees, f"{speed:.3g}" if math.isfinite(speed) else "-",
            f"{info.effort_limit:.3g}" if math.isfinite(info.effort_limit) else "-",
            f"{info.moved_mass:.3g}"))
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
    return FittedTable(f"{robot.path.name}: {robot.dof} joints; # is the position in a motion "
                       "file's lists (q = [...]); tables keyed by name need no order", columns,
                       tuple(rows), notes=tuple(notes))


def plan_text(robot: Robot, motion: Motion, trajectory: Trajectory) -> Paragraphs:
    """What ``hdselect plan`` planned, and what a reader must know about it."""
    count = len(trajectory.t)
    return Paragraphs((f"{robot.path.name} running {motion.path.name} ({motion.planner}): cycle "
                       f"{trajectory.duration:.3f} s, {count:,} sample{'s' if count != 1 else ''}",
                       *case_notes(robot, trajectory)))


def case_notes(robot: Robot, trajectory: Trajectory) -> list[str]:
    """What a reader must know about the case before trusting a result.

    The joints not sized, mimic followers, a payload frame chosen by default,
    joints that never move, and a motion that moves no joint at all (a hold).

    Args:
        robot: The robot as planned and sized.
        trajectory: Its trajectory.

    Returns:
        One sentence per fact; empty when there is nothing to say.
    """
    notes = []
    skipped = [(name, revolute) for name, revolute in zip(robot.joint_names, robot.revolute,
                                                          strict=True)
               if name not in robot.sized_joints]
    prismatic = [name for name, revolute in skipped if not revolute]
    uncoupled = [name for name, revolute in skipped
                 if revolute and name in robot.uncoupled_followers]
    left_out = [name for name, revolute in skipped
                if revolute and name not in robot.uncoupled_followers]
    if prismatic:
        notes.append(f"not sized: {', '.join(prismatic)} (prismatic; these gearheads are "
                     "rotary). The dynamics include it.")
    if left_out:
        notes.append(f"not sized: {', '.join(left_out)} (not among the joints asked for, or "
                     "excluded). The dynamics include it.")
    if uncoupled:
        notes.append(f"not sized: {', '.join(uncoupled)} (mimic followers Pinocchio could not "
                     "couple to their leaders: each moves on its own here).")
    notes += [f"{name} follows {mimic.leader} (mimic): no gearhead of its own; {mimic.leader} "
              "carries its load." for name, mimic in robot.mimic.items()]
    payload = robot.payload
    if payload is not None and payload.frame is None:
        notes.append(f"payload: {payload.mass:g} kg on {robot.payload_frame}, the tip of the "
                     "longest chain of sized joints, since no frame was given.")
    still = [name for name in robot.sized_joints
             if not np.any(trajectory.qd[:, robot.joint_index(name)])]
    if still and len(still) == len(robot.sized_joints):
        notes.append(HOLD_NOTE + ".")
    elif still:
        notes.append(f"still: {', '.join(still)} {'does' if len(still) == 1 else 'do'} not move "
                     "in this motion, so only holding (static) and an emergency stop are checked "
                     "there; mean torque, speed and life do not apply.")
    return notes


def _size_notes(result: SizingResult) -> list[str]:
    notes = ["Assumptions: " + "; ".join(f"{k}: {v}" for k, v in assumptions(result).items())]
    notes += case_notes(result.robot, result.trajectory)
    for joint in result.joints:
        if joint.selected is None:
            strongest = joint.strongest
            check = strongest.checks[strongest.binding]
            what = "pair" if strongest.motor_unit is not None else "unit"
            line = (f"{joint.name}: no {what} fits; the strongest, {strongest.label}, fails "
                    f"{strongest.binding} at {percent(check.utilization)} of its limit. ")
            notes.append(line + time_scale_text(joint) + ".")
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.joints
               for c in [joint.selected] if c is not None for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    if result.motors:
        notes.append("motor binding: the motor's rule with the highest utilization: peak (every "
                     "sample under its torque-speed curve), rms (RMS torque of one cycle "
                     "repeated, against the rated torque; no thermal model) or speed. "
                     "load/rotor: load inertia at the motor shaft over rotor inertia, "
                     "(M_jj / N^2 + J_in) / J_m, M_jj the joint's largest over the cycle. "
                     "`hdselect compare` and --json give every pair's figures.")
    notes += list(result.warnings)
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    if loaded:
        notes.append(f"gravity: {', '.join(loaded)} carry gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes


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
        rows = tuple((row, *("/".join(_short(u) for u in pivot.cells.get((row, c), [])) or "-"
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


def _short(unit: str) -> str:
    """PSA-14-100 -> 14-100: a series prefix common to a catalog adds nothing in a pivot."""
    return unit.split("-", 1)[1] if unit.startswith("PSA-") else unit


_SOURCES = {"motion": "motion", "robot": "robot", "unit": "unit"}
_SHORT_LIMITS = {"velocity (motion file)": "speed", "velocity (robot file)": "speed",
                 "max input speed": "speed", "acceleration": "accel.", "torque": "torque",
                 "emergency stop": "e-stop", "crash": "crash"}


def fastest_table(result: FastestResult) -> FittedTable:
    """One row per sized joint: its unit, the limits it ran under, what bound it, its rules.

    On a narrow terminal the limits, then what binds longest, then the life move below;
    the joint, its unit and its highest rule stay.
    """
    robot, motion = result.robot, result.motion
    pieces = 1 + int(np.count_nonzero(motion.dwells[1:-1] > 0.0))
    title = (f"{motion.path.name} on {robot.path.name}: fastest cycle {result.cycle_time:.3f} s "
             f"({len(motion.waypoints)} waypoints, {pieces} piece{'s' if pieces > 1 else ''})"
             f"\n{base_text(robot)}")
    columns = (Column("joint", "left"), Column("unit", "left"), Column("rule", "left"),
               Column("speed\nlimit", "left", group="limits"),
               Column("torque\nlimit", group="limits"),
               Column("binds\nlongest", "left", group="binds"), Column("L50 h", group="life"))
    shares: dict[str, tuple[str, float]] = {}
    for name, limit, share in result.binding_shares():  # longest first
        shares.setdefault(name, (limit, share))
    rows, styles = [], []
    for joint in result.check.joints:
        (candidate,) = joint.candidates
        lim = result.limits[joint.name]
        derated = result.derating.get(joint.name)
        bound = shares.get(joint.name)
        check = candidate.checks[candidate.binding]
        rule = f"{CHECK_LABELS[candidate.binding]} " + (
            utilization_text(check.utilization, True) if check.ok
            else f"[red]{utilization_text(check.utilization, False)}✗[/red]")
        rows.append((
            escape(joint.name), escape(candidate.unit.id) + ("*" if candidate.flags else ""),
            rule, f"{lim.velocity:.3g} {_SOURCES[lim.velocity_source]}",
            f"{lim.torque:.3g}" + (f" ({derated:.0%})" if derated else ""),
            "-" if bound is None else f"{_SHORT_LIMITS[bound[0]]} {percent(bound[1])}",
            life_text(candidate.life_hours, "")))
        styles.append(None if check.ok else "bold")
    return FittedTable(title, columns, tuple(rows), tuple(styles),
                       tuple(_fastest_notes(result)))


def _fastest_notes(result: FastestResult) -> list[str]:
    motion = result.motion
    moving = result.cycle_time - float(np.sum(motion.dwells))
    notes = [f"Moving {moving:.3f} s, dwells {float(np.sum(motion.dwells)):.3f} s, "
             f"{len(result.trajectory.t):,} samples every {result.trajectory.dt * 1e3:g} ms."]
    if result.reason is None:
        notes.append(f"Every rule holds on the time-optimal run under the limits on single "
                     f"samples ({result.optimum:.3f} s): no shorter cycle passes, to the grid's "
                     f"resolution ({result.grid_per_waypoint} TOPPRA gridpoints per waypoint).")
    else:
        joint, rule = result.reason
        how = [f"{name}'s repeated-peak limit derated to {value:.0%}"
               for name, value in result.derating.items()]
        if result.slowdown > 1.0 + 1e-9:
            how.append(f"the moves slowed x{result.slowdown:.4f}")
        notes.append(f"The time-optimal run under the limits on single samples takes "
                     f"{result.optimum:.3f} s; {joint}'s {rule} rule fails there, so "
                     f"{' and '.join(how)} (the shortest cycle found that passes).")
    stops = [str(i) for i in range(len(motion.waypoints)) if motion.dwells[i] > 0.0]
    path = ("the TOPPRA planner's path" if motion.planner == "toppra" else
            "a clamped cubic spline through the waypoints, knots at each segment's time at "
            "the motion's velocity limits")
    notes.append(f"Path: {path}; it stops only where the motion dwells"
                 f"{' (waypoint ' + ', '.join(stops) + ')' if stops else ''}, and keeps "
                 "the dwells." + (" Ruckig's jerk limits do not apply: TOPPRA runs at a "
                                  "piecewise-constant path acceleration."
                                  if motion.jerk_limit is not None else ""))
    notes.append("rule: the rule with the highest utilization on the result (* catalog "
                 "stand-in). speed limit [rad/s, m/s for a prismatic joint]: the lowest of the "
                 "motion file's, the robot file's and the unit's (maximum input speed / ratio). "
                 "torque limit [N m]: the unit's repeated peak (derated: the fraction kept). "
                 "binds longest: the joint's limit that is the closest to its bound of all for "
                 "the longest share of the moving time.")
    notes.append("Assumptions: " + "; ".join(f"{k}: {v}" for k, v in
                                              assumptions(result.check).items()))
    notes += case_notes(result.robot, result.trajectory)
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.check.joints
               for c in joint.candidates for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    notes += list(result.warnings)
    return notes


def binding_table(result: FastestResult) -> FittedTable:
    """The limit closest to its bound, stretch by stretch along the moves."""
    columns = (Column("from s"), Column("to s"), Column("joint", "left"),
               Column("limit", "left"), Column("peak"),
               Column("waypoints", "left", group="waypoints"))
    rows = tuple((f"{b.start:.3f}", f"{b.end:.3f}", escape(b.joint), b.limit,
                  percent(b.utilization), f"{b.waypoints[0]} to {b.waypoints[1]}")
                 for b in result.binding)
    return FittedTable(
        "What binds along the moves", columns, rows,
        notes=("peak: the largest demand / limit over the stretch (torque against the limit "
               "before any derating). A stretch under 1 % of the moving time joins its "
               "neighbour.",))


def ratios_table(comparison: RatioComparison, joint: JointRatios) -> FittedTable:
    """Every unit on one joint: its shortest cycle, the other joints' units fixed.

    A limit or rule of the joint compared is named alone, another joint's with its name.
    On a narrow terminal what binds longest, then the notes, move below.
    """
    columns = (Column("unit", "left"), Column("cycle s"), Column("vs ▶"),
               Column("binds\nlongest", "left", group="binds"),
               Column("lengthened by\n/ note", "left", group="note"))

    def whose(name: str) -> str:
        return "" if name == joint.joint else f"{escape(name)} "

    reference = next((row.cycle_time for row in joint.rows if row.unit.id == joint.selected),
                     None)
    rows, styles = [], []
    for row in joint.rows:
        chosen = row.unit.id == joint.selected
        mark = "▶" if chosen else " "
        styles.append("bold" if chosen else None)
        if row.cycle_time is None:  # the note names the joint: the table's own goes without
            note = (row.note or "").replace(f"gravity on {joint.joint} > ", "gravity > ")
            note = note.removeprefix(f"{joint.joint} ")
            rows.append((mark + escape(row.unit.id), "[red]none[/red]", "", "-", escape(note)))
            continue
        change = "" if reference is None or chosen else \
            f"{(row.cycle_time / reference - 1.0) * 100:+.1f}%"
        binding = "-" if row.binding is None else \
            f"{whose(row.binding[0])}{_SHORT_LIMITS[row.binding[1]]}"
        lengthened = ""
        if row.lengthened_by is not None:
            how = [f"derated {row.derating:.0%}"] if row.derating is not None else []
            how += [f"x{row.slowdown:.4f}"] if row.slowdown > 1.0 + 1e-9 else []
            lengthened = (f"{whose(row.lengthened_by[0])}{escape(row.lengthened_by[1])}: "
                          + ", ".join(how))
        rows.append((mark + escape(row.unit.id), f"{row.cycle_time:.3f}", change, binding,
                     lengthened))
    others = ", ".join(f"{name} {unit.id}" for name, unit in comparison.units.items()
                       if name != joint.joint)
    note = ((f"Other joints: {others}. " if others else "")
            + f"▶ the unit `size` selects for {comparison.motion.path.name} as planned. none: "
            "the units cannot run the path at any speed. lengthened by: the rule that made the "
            "cycle longer than the time-optimal run under the limits on single samples, and "
            "how (derated: the repeated-peak limit held to that fraction; x: the moves slowed).")
    shown = len(columns) if any(row[-1] for row in rows) else -1  # no empty note column
    return FittedTable(f"Joint {joint.joint}: the shortest cycle with each unit",
                       columns[:shown], tuple(row[:shown] for row in rows), tuple(styles),
                       (note,))


def max_payload_text(result: MaxPayloadResult, robot: Robot, motion: Motion) -> Paragraphs:
    """The largest payload, where it sits, and which joint runs out of units there."""
    payload = result.payload
    where = (f"on '{result.frame}'"
             + ("" if payload.frame is not None else
                " (the tip of the longest chain of sized joints: no frame was given)")
             + f", centre of mass ({', '.join(f'{c:g}' for c in payload.com)}) m")
    inertia = np.asarray(payload.inertia)
    if inertia.any():
        where += (f", inertia about it {np.diag(inertia)[0]:.3g}, {np.diag(inertia)[1]:.3g}, "
                  f"{np.diag(inertia)[2]:.3g} kg m² per kg (diagonal)")
    head = f"{robot.path.name} running {motion.path.name} ({motion.planner})"
    if result.mass is None:
        return Paragraphs((f"{head}: no payload mass, not even none, leaves every joint a "
                           f"feasible unit ({where}).",))
    if not math.isfinite(result.mass):
        return Paragraphs((f"{head}: no rule depends on the payload mass {where}: no limit.",))
    lines = [f"{head}: the largest payload is {result.mass:.4g} kg {where}."]
    lines.append(f"{result.joint} runs out of units there: {result.unit.id if result.unit else '-'}"
                 f" reaches its {result.rule} limit. Torque is affine in the payload mass on a "
                 "fixed trajectory, so each rule's limit is solved exactly; the inertia about the "
                 "centre of mass grows with the mass.")
    if len(result.ranges) > 1 or result.ranges[0][0] > 0.0:
        spans = ", ".join(f"{lo:.4g} to {hi:.4g} kg" for lo, hi in result.ranges)
        lines.append(f"Every joint has a unit only from {spans}.")
    lines.append(f"The selection at {result.mass:.4g} kg:")
    return Paragraphs(tuple(lines))
