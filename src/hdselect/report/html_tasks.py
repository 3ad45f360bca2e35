"""The HTML size report's task section: a duty's tasks and what each sets (none for one task).

The same content as the terminal's (`hdselect.report.task_tables`): every task's
motion, share, cycle, payload and mounting; per joint, which task sets each rule of its
unit (or ``pooled``); and the unit against each task alone beside the duty.
"""

from __future__ import annotations

from hdselect.catalog.rules import CHECK_LABELS
from hdselect.report.html_tables import esc, table
from hdselect.report.task_tables import (
    POOLED_NOTE,
    alone_rows,
    rule_rows,
    spread_notes,
    task_rows,
)
from hdselect.report.terminal import percent
from hdselect.sizing.result import SizingResult


def task_section(result: SizingResult) -> str:
    """The section, or nothing for a result of one task."""
    if len(result.tasks) < 2:
        return ""
    rows = [[esc(cell) for cell in row] for row in task_rows(result)]
    idle = (f"<p>Idle {percent(result.idle)} of the time: a pause, counted only where a "
            "series' rules take the mean speed over the whole cycle, pauses included.</p>"
            if result.idle > 0.0 else "")
    parts = [table(["task", "motion", "share", "cycle [s]", "cycles per hour", "payload",
                     "mounting"], rows, left=2, text=[5, 6]), idle]
    if any(joint.per_task for joint in result.joints):
        parts += [_rules(result), _alone(result)]
    name = result.mix.path.name if result.mix is not None else "the tasks"
    return (f"<section id=tasks><h2>Tasks: {esc(name)}, one duty</h2><p>The units above are "
            "chosen for every task together. " + esc(POOLED_NOTE) + ".</p>"
            + "".join(parts) + "</section>")


def duty_line(result: SizingResult) -> str:
    """The duty in a line, for the page's head: each task's cycle and share."""
    tasks = ", ".join(f"{task.label} (cycle {task.trajectory.duration:.3f} s, "
                      f"{percent(task.share)} of the time)" for task in result.tasks)
    idle = f", idle {percent(result.idle)}" if result.idle > 0.0 else ""
    return f"One duty of {len(result.tasks)} tasks: {tasks}{idle}"


def _rules(result: SizingResult) -> str:
    names, rows = rule_rows(result)
    cells = [[esc(text) if ok else f"<td class=fail>{esc(text)} ✗</td>" for text, ok in row]
             for row in rows]
    return ("<h3>Which task sets each rule</h3>"
            + table(["joint", "unit", *(CHECK_LABELS[name] for name in names)], cells, left=2))


def _alone(result: SizingResult) -> str:
    header = ["joint", "unit", "duty: binding", "duty: L50 h"]
    for task in result.counted:
        header += [f"{task.label}: binding", f"{task.label}: L50 h"]
    rows = [[esc(text) for text, _ in row] for row in alone_rows(result)]
    notes = "".join(f"<li>{esc(note)}</li>" for note in spread_notes(result))
    return ("<h3>Each joint's unit against each task alone</h3><p>As if the robot did nothing "
            "else: the rules of single samples reach the duty's in the task that sets them; "
            "the life alone differs from the duty's, which pools the tasks.</p>"
            + table(header, rows, left=2) + (f"<ul>{notes}</ul>" if notes else ""))
