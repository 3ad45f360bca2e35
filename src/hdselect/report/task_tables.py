"""The size report's task section in the terminal: a duty's tasks and what each task sets.

Every result is a duty of tasks (a motion file: one task). The selection table
(`hdselect.report.size_tables.size_table`) gives the units for the whole duty; for a
duty of several tasks (a mix) these tables follow it and say which task sets each
rule of each joint's unit (a rule of single samples: the worst task; mean torque,
average speed, life and motor RMS: every task pooled), and how the unit fares against
each task alone. A duty of one task has no task section.
"""

from __future__ import annotations

from rich.markup import escape

from hdselect.catalog.rules import CHECK_LABELS, CHECKS
from hdselect.report.tables import Column, FittedTable
from hdselect.report.terminal import life_text, percent, utilization_text
from hdselect.robot.model import Robot
from hdselect.robot.mounting import mounting_name
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import carrying_at, counted_at, peak_sample
from hdselect.sizing.tasks import cycle_of

POOLED_NOTE = ("pooled: mean torque, average speed, life and motor RMS pool every task's "
               "samples, each weighted by how often its cycle runs (share / cycle time); "
               "peak, speed, momentary (an emergency stop from every instant of every task, "
               "and the crash), static and the inertia ratio (the largest load inertia of "
               "any task) are the worst task's")
"""How the rules combine the tasks, for notes."""


def task_of(result: SizingResult, joint: JointSizing, rule: str) -> str:
    """The task that sets a rule, in brackets, for a duty of several tasks; else nothing.

    Plain text: the caller escapes it for its output.
    """
    who = result.set_by(joint, rule)
    return "" if who is None else f" ({who})"


def peak_carrying_note(result: SizingResult) -> str:
    """Where some task has payload events: each joint's peak sample and what it carried.

    E.g. ``peak: shoulder worst at t = 4.21 s, with part; elbow worst at t = 0.5 s,
    without part``: the parts its task's events move (what every sample carries is in the
    title line), nothing more for a task without events; empty where no task has events.
    """
    if all(task.carried is None for task in result.counted):
        return ""
    several = len(result.counted) > 1
    words = []
    for joint in result.joints:
        sample = peak_sample(result, joint)
        if sample is None:
            continue
        task, row = counted_at(result, sample)
        held = carrying_at(result, sample)
        parts = ", ".join(("with " if part.name in held else "without ") + part.name
                          for part in (() if task.carried is None else task.carried.parts))
        where = f" of {task.label}" if several else ""
        words.append(f"{joint.name} worst at t = {task.trajectory.t[row]:.3g} s{where}"
                     + (f", {parts}" if parts else ""))
    return "peak: " + "; ".join(words) if words else ""


def payload_text(robot: Robot) -> str:
    """A task's payload in a few words: mass, centre of mass and frame."""
    payload = robot.payload
    if payload is None:
        return "none"
    com = ", ".join(f"{c:g}" for c in payload.com)
    return f"{payload.mass:g} kg at ({com}) m on {robot.payload_frame}"


def mounting_text(robot: Robot) -> str:
    """A task's mounting: its name, else its base pose, else its gravity vector [m/s^2]."""
    if robot.base_pose is not None:
        return mounting_name(robot.base_pose).removeprefix("the ").removesuffix(" mounting")
    return "g = (" + ", ".join(f"{g:.3g}" for g in robot.gravity) + ") m/s^2"


def task_rows(result: SizingResult) -> list[list[str]]:
    """One row per task in plain text, as both reports show it.

    Its label, motion, share, cycle [s], cycles per hour, payload and mounting.
    """
    return [[task.label, "-" if task.motion is None else task.motion.path.name,
             percent(task.share), f"{task.trajectory.duration:.3f}",
             f"{task.share * 3600.0 / cycle_of(task.trajectory):,.1f}",
             payload_text(task.robot), mounting_text(task.robot)] for task in result.tasks]


def tasks_table(result: SizingResult) -> FittedTable:
    """One row per task: its motion, share, cycle, cycles per hour, payload and mounting.

    On a narrow terminal the payload and mounting move below.
    """
    columns = (Column("task", "left"), Column("motion", "left"), Column("share"),
               Column("cycle s"), Column("cycles/h"), Column("payload", "left", group="robot"),
               Column("mounting", "left", group="robot"))
    rows = [tuple(escape(cell) for cell in row) for row in task_rows(result)]
    notes = []
    if result.idle > 0.0:
        notes.append(f"idle {percent(result.idle)} of the time: a pause, counted only where a "
                     "series' rules take the mean speed over the whole cycle, pauses included "
                     "(never in the motor's RMS, which is over the time the robot works)")
    unused = [task.label for task in result.tasks if task.share == 0.0]
    if unused:
        notes.append(f"share 0: {', '.join(unused)} {'counts' if len(unused) == 1 else 'count'} "
                     "in no rule")
    notes.append("cycles/h: share x 3600 s / the time a cycle's samples stand for (the cycle "
                 "and one sample period)")
    title = (f"{result.mix.path.name}: {len(result.tasks)} tasks of one robot, sized as one duty"
             if result.mix is not None else f"{len(result.tasks)} tasks, sized as one duty")
    return FittedTable(title, columns, tuple(rows), notes=tuple(notes))


Cell = tuple[str, bool]
"""A table cell in plain text, and False where it shows a failing rule (to be marked)."""


def rule_rows(result: SizingResult) -> tuple[list[str], list[list[Cell]]]:
    """Which task sets each rule of each joint's unit: what both mix tables show.

    Returns:
        The rules some joint's unit gives a value, and per joint its name, its unit's
        label and, in the rules' order, each rule's utilization and the task that sets
        it ("" where none does, or "pooled"); "-" where the unit gives the rule no value.
    """
    chosen = {joint.name: joint.selected or joint.strongest for joint in result.joints}
    names = [name for name in CHECKS
             if any(name in c.checks and c.checks[name].value is not None
                    for c in chosen.values())]
    rows = []
    for joint in result.joints:
        candidate = chosen[joint.name]
        cells: list[Cell] = [(joint.name, True), (candidate.label, True)]
        for name in names:
            check = candidate.checks.get(name)
            if check is None or check.value is None:
                cells.append(("-", True))
                continue
            who = result.set_by(joint, name) or ""
            cells.append((f"{utilization_text(check.utilization, check.ok)} {who}", check.ok))
        rows.append(cells)
    return names, rows


def alone_rows(result: SizingResult) -> list[list[Cell]]:
    """Per joint, its unit against the duty and then each counted task alone.

    Its name, its unit's label, then for the duty and each task the binding rule with
    its utilization, and the L50 life [h].
    """
    rows = []
    for joint in result.joints:
        candidate = joint.selected or joint.strongest
        cells: list[Cell] = [(joint.name, True), (candidate.label, True)]
        for each in (candidate, *joint.per_task):
            check = each.checks[each.binding]
            cells += [(f"{CHECK_LABELS.get(each.binding, each.binding)} "
                       f"{utilization_text(check.utilization, check.ok)}", check.ok),
                      (life_text(each.life_hours, ""), True)]
        rows.append(cells)
    return rows


def _marked(row: list[Cell]) -> tuple[str, ...]:
    """A row for the terminal: each cell escaped, a failing one in red with a ✗."""
    return tuple(escape(text) if ok else f"[red]{escape(text)}✗[/red]" for text, ok in row)


def rules_table(result: SizingResult) -> FittedTable:
    """Per joint, each rule of its unit: utilization and the task that sets it (or pooled).

    A rule has a column when some joint's unit gives it a value.
    """
    names, rows = rule_rows(result)
    columns = (Column("joint", "left"), Column("unit", "left"),
               *(Column(CHECK_LABELS[name], "left", group=name) for name in names))
    return FittedTable("Which task sets each rule (the unit's utilization, and the task that "
                       "reaches it)", columns, tuple(_marked(row) for row in rows),
                       notes=(POOLED_NOTE,))


def per_task_table(result: SizingResult) -> FittedTable:
    """Per joint, its unit against the pooled duty and against each task alone.

    Each cell: the binding rule with its utilization, and the L50 life the unit would
    have if the robot did only that task. On a narrow terminal each task's columns
    move below together.
    """
    labels = [task.label for task in result.counted]
    columns = [Column("joint", "left"), Column("unit", "left"),
               Column("duty\nbinding", "left"), Column("duty\nL50 h")]
    for label in labels:
        columns += [Column(f"{escape(label)}\nbinding", "left", group=label),
                    Column(f"{escape(label)}\nL50 h", group=label)]
    return FittedTable("Each joint's unit against the duty and against each task alone "
                       "(as if the robot did nothing else)", tuple(columns),
                       tuple(_marked(row) for row in alone_rows(result)),
                       notes=spread_notes(result))


def spread_notes(result: SizingResult) -> tuple[str, ...]:
    """Where the duty's life differs from the spreadsheet shortcuts, joint by joint.

    The share-weighted mean of the lives alone, and the shortest of them, beside the
    duty's L50 life, for each joint whose lives are all finite (and the duty's under
    1e7 h). The weights are the tasks' shares of the operating time (summing to 1, the
    idle time of a day in cycles per hour left out), so the mean lies between the
    shortest and the longest life alone.
    """
    notes = []
    operating = sum(task.share for task in result.counted)
    shares = [task.share / operating for task in result.counted]
    for joint in result.joints:
        duty = (joint.selected or joint.strongest).life_hours
        lives = [c.life_hours for c in joint.per_task]
        if duty is None or any(life is None for life in lives) or duty > 1e7:
            continue
        weighted = sum(s * life for s, life in zip(shares, lives, strict=True)  # type: ignore
                       if life is not None)
        low = min(life for life in lives if life is not None)
        notes.append(f"{joint.name}: duty L50 {duty:,.0f} h; the share-weighted mean of the "
                     f"lives alone ({weighted:,.0f} h) is {weighted / duty - 1.0:+.0%}, the "
                     f"shortest ({low:,.0f} h) {low / duty - 1.0:+.0%}")
    if notes:
        notes.insert(0, "the duty's life pools the tasks' mean torque and speed; "
                        "combining the lives alone is not the same:")
    return tuple(notes)


def task_tables(result: SizingResult) -> list[object]:
    """The task section after the selection: tasks, rules by task, each task alone.

    Nothing for a duty of one task.
    """
    if not any(joint.per_task for joint in result.joints) and len(result.tasks) < 2:
        return []
    items: list[object] = ["", tasks_table(result)]
    if any(joint.per_task for joint in result.joints):
        items += ["", rules_table(result), "", per_task_table(result)]
    return items

