"""Terminal tables of a sizing: the selection per joint, every candidate, the loads."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

from rich.markup import escape

from hdselect.catalog.rules import (
    CHECK_LABELS,
    CHECKS,
    MOTOR_CHECKS,
    RPM_PER_RAD_S,
    Candidate,
    CycleLoad,
    MotorDemand,
)
from hdselect.catalog.units import MeanSpeed, Unit
from hdselect.report.bearing_tables import BEARING_COLUMNS, bearing_cells, bearing_notes, load_line
from hdselect.report.case_tables import case_notes, tool_pose_notes
from hdselect.report.precision_tables import precision_tables
from hdselect.report.tables import Column, FittedTable
from hdselect.report.task_tables import peak_carrying_note, task_of, task_tables
from hdselect.report.terminal import (
    life_text,
    ratio_text,
    selected_note,
    shown,
    utilization_cell,
    utilization_text,
    verdict,
)
from hdselect.sizing.diagnosis import diagnosis_of, with_diagnoses
from hdselect.sizing.loads import JointLoad
from hdselect.sizing.records import assumptions, base_text
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import moved_parts


def candidates_table(title: str, candidates: Iterable[Candidate], selected: Candidate | None,
                      *, extra: dict[str, Callable[[Candidate], str]],
                      notes: Iterable[str] = (), extra_group: str = "extra") -> FittedTable:
    """Every candidate's utilization per rule, its L50 life, `extra` columns and verdict.

    A rule has a column when some candidate has a value for it. On a narrow terminal
    the `extra` columns, then the life and the rules, move below; the unit and its
    verdict stay.
    """
    candidates = list(candidates)
    names = [name for name in CHECKS
             if any(name in c.checks and shown(c.checks[name]) for c in candidates)]
    columns = [Column("unit", "left"), *(Column(CHECK_LABELS[name], group=name) for name in names),
               Column("L50 h", group="life hours"),
               *(Column(header, group=extra_group) for header in extra),
               Column("result", "left")]
    failing = {name for name in names for c in candidates
               if name in c.checks and not c.checks[name].ok}
    rows, styles = [], []
    for c in candidates:
        chosen = c is selected
        cells = [("▶" if chosen else " ") + escape(c.unit.id)]
        cells += [utilization_cell(c.checks[name], pad=name in failing) if name in c.checks
                  else "-" + " " * (name in failing) for name in names]
        cells += [life_text(c.life_hours, ""), *(cell(c) for cell in extra.values()),
                  verdict(c)]
        rows.append(tuple(cells))
        styles.append("bold" if chosen else None)
    return FittedTable(title, tuple(columns), tuple(rows), tuple(styles), tuple(notes))


def load_text(load: CycleLoad, units: Iterable[Unit]) -> str:
    """The cycle in a line; the whole-cycle mean speed too where a unit's rules use it."""
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    text = (f"peak {load.peak_torque:.3g} N m, mean torque {mean}, mean output speed "
            f"{load.mean_speed * RPM_PER_RAD_S:.3g} rpm")
    if any(u.rules.mean_speed is MeanSpeed.WHOLE_CYCLE for u in units):
        text += f" moving, {load.cycle_mean_speed * RPM_PER_RAD_S:.3g} rpm over the whole cycle"
    return text


def size_table(result: SizingResult) -> FittedTable:
    """One row per joint: the unit chosen, why, its life and what the motor must do.

    On a narrow terminal the motor figures and the notes move into a second table;
    without a note on any joint there is no notes column. Where motors are given: the
    pair chosen and the binding rule on either side (`_pairs_table`).
    """
    result = with_diagnoses(result)
    if result.motors:
        return _pairs_table(result)
    columns = (Column("joint", "left"), Column("unit", "left"), Column("binding", "left"),
               Column("L50 life"), Column("motor\npeak N m", group="motor"),
               Column("motor\nrms N m", group="motor"), Column("motor\nmax rpm", group="motor"),
               *BEARING_COLUMNS, Column("notes", "left", group="notes"))
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        notes = ["gravity"] if joint.gravity_loaded else []
        if joint.load.max_speed == 0.0:
            notes.append("still")
        bearing = bearing_cells(joint, chosen or joint.strongest)
        if chosen is None:
            rows.append((escape(joint.name), "[red]none[/red]",
                         f"[red]{escape(shortfall_text(result, joint))}[/red]", "-", "-", "-",
                         "-", *bearing, ", ".join(notes)))
            continue
        motor = _motor(chosen)
        check = chosen.checks[chosen.binding]
        mark = "*" if chosen.flags else ""
        rows.append((
            escape(joint.name), escape(chosen.unit.id) + mark,
            f"{chosen.binding} {utilization_text(check.utilization, True)}"
            + escape(task_of(result, joint, chosen.binding)),
            life_text(chosen.life_hours),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            *bearing, ", ".join(notes)))
    return _fitted(result, columns, rows)


def _fitted(result: SizingResult, columns: tuple[Column, ...],
            rows: list[tuple[str, ...]]) -> FittedTable:
    """The size table: no empty notes column, no bearing columns where no loads were computed."""
    keep = [i for i, column in enumerate(columns)
            if not (column.group == "notes" and not any(row[i] for row in rows))
            and not (column.group == "bearing" and all(j.bearing is None for j in result.joints))]
    return FittedTable(_size_title(result), tuple(columns[i] for i in keep),
                       tuple(tuple(row[i] for i in keep) for row in rows),
                       notes=tuple(_size_notes(result)))


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
               *BEARING_COLUMNS, Column("notes", "left", group="notes"))
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        notes = _joint_notes(joint)
        bearing = bearing_cells(joint, chosen or joint.strongest)
        if chosen is None:
            rows.append((escape(joint.name), "[red]none[/red]", "[red]none[/red]",
                         f"[red]{escape(shortfall_text(result, joint))}[/red]", "-", "-", "-",
                         "-", "-", "-", *bearing, ", ".join(notes)))
            continue
        motor = _motor(chosen)
        side = chosen.motor_binding
        rows.append((
            escape(joint.name), escape(chosen.unit.id) + ("*" if chosen.flags else ""),
            "-" if chosen.motor_unit is None else escape(chosen.motor_unit.id),
            _binding_text(chosen, chosen.gearhead_binding)
            + escape(task_of(result, joint, chosen.gearhead_binding)),
            "-" if side is None else _binding_text(chosen, side).removeprefix("motor_")
            + escape(task_of(result, joint, side)),
            ratio_text(joint.inertia_ratio(chosen)), life_text(chosen.life_hours),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            *bearing, ", ".join(notes)))
    return _fitted(result, columns, rows)


def _binding_text(candidate: Candidate, name: str) -> str:
    """A rule's name and utilization, e.g. ``momentary 88%`` (never 100% when it passes)."""
    check = candidate.checks[name]
    return f"{name} {utilization_text(check.utilization, check.ok)}"


def compare_table(result: SizingResult, joint: JointSizing) -> FittedTable:
    """One row per unit for one joint: every rule's utilization, life and motor demand.

    Where the joint has motors, one row per (unit, motor) pair: the motor's rules appear
    among the rules, with the inertia ratio and the motor's torques (`_pairs_compare_table`).
    """
    result = with_diagnoses(result)
    if joint.name in result.motors:
        return _pairs_compare_table(result, joint)
    return candidates_table(
        f"Joint {joint.name}: {load_text(joint.load, result.units)}, carries "
        f"{joint.carried_mass:.2f} kg of gearheads{_bearing_title(joint)}", joint.candidates,
        joint.selected,
        extra={"motor\npeak N m": lambda c: f"{_motor(c).peak_torque:.3g}",
               "motor\nrms N m": lambda c: f"{_motor(c).rms_torque:.3g}",
               "motor\nmax rpm": lambda c: f"{_motor(c).max_speed:,.0f}"},
        notes=[f"{selected_note(joint.selected)} utilization = demand / limit, ✗ over the "
               "limit; mom. = momentary "
               "(T4): the worse of an emergency stop and a crash."
               + (" b. = the output bearing's checks (b.life: its L10 life, b.static: "
                  "the static safety C0 / P0; utilization = required / reached), - where the "
                  "unit's catalog does not rate the bearing."
                  if any(c.bearing is not None for c in joint.candidates) else ""),
               *diagnosis_lines(result, joint)])


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
            *(utilization_cell(c.checks[name], pad=name in failing) for name in MOTOR_CHECKS),
            ratio_text(joint.inertia_ratio(c)), life_text(c.life_hours, ""),
            f"{motor.peak_torque:.3g}", f"{motor.rms_torque:.3g}", f"{motor.max_speed:,.0f}",
            verdict(c)))
        styles.append("bold" if chosen else None)
    notes = (f"{selected_note(joint.selected, 'pair')} gearhead: its rule with the highest "
             "utilization behind this motor "
             "(the crash case carries the motor's rotor inertia), ✗ over the limit; m. = the "
             "motor's rules: peak under its torque-speed curve, RMS over the cycle against its "
             "rated torque, speed; load/rotor = (M_jj / N² + J_in) / J_m, M_jj the joint's "
             "largest over the cycle. --json gives every rule of every pair.",
             *diagnosis_lines(result, joint))
    return FittedTable(f"Joint {joint.name}: {load_text(joint.load, result.units)}, carries "
                       f"{joint.carried_mass:.2f} kg of gearheads and motors"
                       f"{_bearing_title(joint)}", columns, tuple(rows), tuple(styles), notes)


def _bearing_title(joint: JointSizing) -> str:
    """The joint's output-bearing loads for a compare table's heading, or nothing."""
    return "" if joint.bearing is None else f"; {load_line(joint.bearing)}"


def _motor(candidate: Candidate) -> MotorDemand:
    if candidate.motor is None:
        raise RuntimeError(f"{candidate.unit.id} carries no motor demand")
    return candidate.motor


def shortfall_text(result: SizingResult, joint: JointSizing, *, words: bool = False) -> str:
    """For a joint no unit fits: its headline shortfall, e.g. ``peak 87.3 > 20.3 N m``.

    The demand against the strongest candidate's limit in the rule's own unit
    (`hdselect.sizing.diagnosis`); a life only where nothing else falls short. `words`:
    ``no unit holds it: `` (or ``no pair``) before it.
    """
    found = diagnosis_of(result, joint.name)
    if found is None:
        raise RuntimeError(f"joint {joint.name} has no diagnosis (with_diagnoses first)")
    return found.summary() if words else found.headline.short()


def diagnosis_lines(result: SizingResult, joint: JointSizing) -> list[str]:
    """For a joint no unit fits: its diagnosis as sentences (none for a joint with a unit)."""
    found = diagnosis_of(result, joint.name)
    return [] if joint.selected is not None or found is None else found.lines()


def _size_title(result: SizingResult) -> str:
    if len(result.tasks) > 1:
        cycles = ", ".join(f"{task.label} {task.trajectory.duration:.3f} s"
                           for task in result.tasks)
        return (f"{result.title}, one duty: cycles {cycles}\nbase: '{result.robot.root_link}' "
                "held fixed; each task's share, payload and mounting below")
    count = len(result.trajectory.t)
    return (f"{result.title}: cycle {result.cycle_time:.3f} s, "
            f"{count:,} sample{'s' if count != 1 else ''}\n"
            + base_text(result.robot, moved_parts(result)))


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


def _size_notes(result: SizingResult) -> list[str]:
    notes = ["Assumptions: " + "; ".join(f"{k}: {v}" for k, v in assumptions(result).items())]
    notes += [peak] if (peak := peak_carrying_note(result)) else []
    poses = ([f"{task.label}: {note}" for task in result.counted
              for note in tool_pose_notes(task.motion)] if len(result.counted) > 1
             else tool_pose_notes(result.motion))
    notes += poses + case_notes(result.robot, [task.trajectory for task in result.counted]
                                if result.counted else result.trajectory)
    notes += bearing_notes(result)
    for joint in result.joints:
        notes += diagnosis_lines(result, joint)
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
        notes.append(f"gravity: {', '.join(loaded)} carr{'y' if len(loaded) > 1 else 'ies'} "
                     "gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes


def report_tables(result: SizingResult) -> list[object]:
    """The size report in the terminal: the selection, precision, the tasks, the joints' loads.

    One path for every duty: the task section (`task_tables`) is empty for one task, the
    precision section (`precision_tables`) without the precision figures.
    """
    result = with_diagnoses(result)
    return [size_table(result), *precision_tables(result), *task_tables(result), "",
            loads_table(result)]
