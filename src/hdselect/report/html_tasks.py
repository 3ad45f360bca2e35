"""The HTML size report's task section: a duty's tasks and what each sets (none for one task).

The same content as the terminal's (`hdselect.report.task_tables`): every task's
motion, share, cycle, payload and mounting; per joint, which task sets each rule of its
unit (or ``pooled``); and the unit against each task alone beside the duty.
"""

from __future__ import annotations

from hdselect.catalog.rules import CHECK_LABELS, Candidate
from hdselect.report.html_tables import esc, table
from hdselect.report.task_tables import (
    POOLED_NOTE,
    mounting_text,
    payload_text,
    rule_setters,
    spread_notes,
)
from hdselect.report.terminal import life_text, percent, utilization_text
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import cycle_of


def task_section(result: SizingResult) -> str:
    """The section, or nothing for a result of one task."""
    if len(result.tasks) < 2:
        return ""
    rows = [[esc(task.label), esc("-" if task.motion is None else task.motion.path.name),
             percent(task.share), f"{task.trajectory.duration:.3f}",
             f"{task.share * 3600.0 / cycle_of(task.trajectory):,.1f}",
             esc(payload_text(task.robot)), esc(mounting_text(task.robot))]
            for task in result.tasks]
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
    names, setters = rule_setters(result)
    rows = []
    for joint, label, found in setters:
        cells = [esc(joint), esc(label)]
        for setting in found:
            if setting is None:
                cells.append("-")
                continue
            check, who = setting
            text = f"{utilization_text(check.utilization, check.ok)} {who}"
            cells.append(esc(text) if check.ok else f"<td class=fail>{esc(text)} ✗</td>")
        rows.append(cells)
    return ("<h3>Which task sets each rule</h3>"
            + table(["joint", "unit", *(CHECK_LABELS[name] for name in names)], rows, left=2))


def _alone(result: SizingResult) -> str:
    labels = [task.label for task in result.counted]
    header = ["joint", "unit", "duty: binding", "duty: L50 h"]
    for label in labels:
        header += [f"{label}: binding", f"{label}: L50 h"]
    rows = []
    for joint in result.joints:
        candidate = joint.selected or joint.strongest
        cells = [esc(joint.name), esc(candidate.label), *_cells(candidate)]
        for alone in joint.per_task:
            cells += _cells(alone)
        rows.append(cells)
    notes = "".join(f"<li>{esc(note)}</li>" for note in spread_notes(result))
    return ("<h3>Each joint's unit against each task alone</h3><p>As if the robot did nothing "
            "else: the rules of single samples reach the duty's in the task that sets them; "
            "the life alone differs from the duty's, which pools the tasks.</p>"
            + table(header, rows, left=2) + (f"<ul>{notes}</ul>" if notes else ""))


def _cells(candidate: Candidate) -> list[str]:
    rule = candidate.binding
    check = candidate.checks[rule]
    return [esc(f"{CHECK_LABELS.get(rule, rule)} {utilization_text(check.utilization, check.ok)}"),
            esc(life_text(candidate.life_hours, ""))]

