"""Terminal tables of co-design.

The fastest cycle, what binds it, ratios compared, the largest payload.
"""

from __future__ import annotations

import math

import numpy as np
from rich.markup import escape

from hdselect.catalog.rules import CHECK_LABELS
from hdselect.codesign.fastest_cycle import FastestResult, JointRatios, RatioComparison
from hdselect.codesign.maxpayload import MaxPayloadResult
from hdselect.motion.motionfile import ANGLE_UNITS, Motion
from hdselect.report.case_tables import case_notes
from hdselect.report.size_tables import size_table
from hdselect.report.tables import Column, FittedTable, Paragraphs
from hdselect.report.task_tables import task_tables
from hdselect.report.terminal import life_text, percent, utilization_text
from hdselect.robot.model import Robot
from hdselect.sizing.records import assumptions, base_text


def short(unit: str) -> str:
    """PSA-14-100 -> 14-100: a series prefix common to a catalog adds nothing in a pivot."""
    return unit.split("-", 1)[1] if unit.startswith("PSA-") else unit


_SOURCES = {"motion": "motion", "robot": "robot", "unit": "unit"}


_SHORT_LIMITS = {"velocity (motion file)": "speed", "velocity (robot file)": "speed",
                 "max input speed": "speed", "acceleration": "accel.", "torque": "torque",
                 "emergency stop": "e-stop", "crash": "crash"}


def fastest_tables(result: FastestResult) -> list[FittedTable | str]:
    """What ``fastest`` prints: a mix's tasks, then every joint and what binds it.

    A motion is a duty of one task: it has no table of tasks.
    """
    tasks: list[FittedTable | str] = ([] if result.mix is None
                                      else [fastest_tasks_table(result), ""])
    return [*tasks, fastest_table(result), "", binding_table(result)]


def fastest_table(result: FastestResult) -> FittedTable:
    """One row per sized joint: its unit, the limits it ran under, what bound it, its rules.

    Speeds are in the motion file's angle unit per second (the sized joints are rotary);
    a mix's limits are the lowest over its tasks, its binding over the duty's moving time.

    On a narrow terminal the limits, then what binds longest, then the life move below;
    the joint, its unit and its highest rule stay.
    """
    robot, alone = result.robot, result.tasks[0] if len(result.tasks) == 1 else None
    angle = _angle_unit(result)
    per_rad = 1.0 / ANGLE_UNITS[angle]  # speeds in the files' angle unit
    if alone is not None:
        motion = alone.motion
        pieces = 1 + int(np.count_nonzero(motion.dwells[1:-1] > 0.0))
        title = (f"{motion.path.name} on {robot.path.name}: fastest cycle "
                 f"{result.cycle_time:.3f} s ({len(motion.waypoints)} waypoints, {pieces} "
                 f"piece{'s' if pieces > 1 else ''})\n{base_text(alone.task.robot)}")
    else:
        name = result.mix.path.name if result.mix is not None else "the duty"
        title = (f"{name} on {robot.path.name}: fastest cycle {result.cycle_time:.3f} s (its "
                 f"{len(result.tasks)} tasks' weighted by their shares)")
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
        lim = min((item.limits[joint.name] for item in result.tasks),
                  key=lambda each: each.velocity)
        torque = min(item.limits[joint.name].torque for item in result.tasks)
        derated = result.derating.get(joint.name)
        bound = shares.get(joint.name)
        check = candidate.checks[candidate.binding]
        rule = f"{CHECK_LABELS[candidate.binding]} " + (
            utilization_text(check.utilization, True) if check.ok
            else f"[red]{utilization_text(check.utilization, False)}✗[/red]")
        rows.append((
            escape(joint.name), escape(candidate.unit.id) + ("*" if candidate.flags else ""),
            rule, f"{lim.velocity * per_rad:.3g} {_SOURCES[lim.velocity_source]}",
            f"{torque:.3g}" + (f" ({derated:.0%})" if derated else ""),
            "-" if bound is None else f"{_SHORT_LIMITS[bound[0]]} {percent(bound[1])}",
            life_text(candidate.life_hours, "")))
        styles.append(None if check.ok else "bold")
    return FittedTable(title, columns, tuple(rows), tuple(styles),
                       tuple(_fastest_notes(result, angle)))


def _angle_unit(result: FastestResult) -> str:
    """The tasks' motion files' angle unit, where they agree; else degrees."""
    units = {item.motion.angle_unit for item in result.tasks}
    return units.pop() if len(units) == 1 else "deg"


def _fastest_notes(result: FastestResult, angle: str) -> list[str]:
    alone = result.tasks[0] if len(result.tasks) == 1 else None
    if alone is not None:
        motion = alone.motion
        notes = [f"Moving {result.cycle_time - alone.dwell_time:.3f} s, dwells "
                 f"{alone.dwell_time:.3f} s, {len(result.trajectory.t):,} samples every "
                 f"{result.trajectory.dt * 1e3:g} ms."]
        weighted = ""
    else:
        notes = ["; ".join(f"{item.task.label}: moving {item.cycle_time - item.dwell_time:.3f}"
                           f" s, dwells {item.dwell_time:.3f} s" for item in result.tasks)
                 + "."]
        weighted = ", the tasks' weighted by their shares"
    if result.reason is None:
        notes.append(f"Every rule holds on the time-optimal run under the limits on single "
                     f"samples ({result.optimum:.3f} s{weighted}): no shorter cycle passes, to "
                     f"the grid's resolution ({result.grid_per_waypoint} TOPPRA gridpoints per "
                     "waypoint).")
    else:
        joint, rule = result.reason
        how = [f"{name}'s repeated-peak limit derated to {value:.0%}"
               for name, value in result.derating.items()]
        if result.slowdown > 1.0 + 1e-9:
            how.append(f"the moves slowed x{result.slowdown:.4f}")
        notes.append(f"The time-optimal run under the limits on single samples takes "
                     f"{result.optimum:.3f} s{weighted}; {joint}'s {rule} rule fails there, so "
                     f"{' and '.join(how)} (the shortest cycle found that passes).")
    if alone is not None:
        stops = [str(i) for i in range(len(motion.waypoints)) if motion.dwells[i] > 0.0]
        path = ("the TOPPRA planner's path" if motion.planner == "toppra" else
                "a clamped cubic spline through the waypoints, knots at each segment's time at "
                "the motion's velocity limits")
        notes.append(f"Path: {path}; it stops only where the motion dwells"
                     f"{' (waypoint ' + ', '.join(stops) + ')' if stops else ''}, and keeps "
                     "the dwells." + (" Ruckig's jerk limits do not apply: TOPPRA runs at a "
                                      "piecewise-constant path acceleration."
                                      if motion.jerk_limit is not None else ""))
    lowest = "" if alone is not None else " (a mix: the lowest over its tasks)"
    by_twist = any(limit.torque_by == "torsion" for item in result.tasks
                   for limit in item.limits.values())
    notes.append("rule: the rule with the highest utilization on the result (* catalog "
                 f"stand-in). speed limit [{angle}/s, the motion file's angle "
                 "unit]: the lowest of the "
                 "motion file's, the robot file's and the unit's (maximum input speed / ratio)"
                 f"{lowest}. torque limit [N m]: the unit's repeated peak"
                 + (", or where a torsion target is tighter, the torque at which the unit "
                    "twists by it" if by_twist else "")
                 + " (derated: the fraction kept). binds longest: the joint's limit that is "
                 "the closest to its bound of all for the longest share of the moving time"
                 + ("." if alone is not None else " (of the duty: each task's as often as "
                    "it runs)."))
    notes.append("Assumptions: " + "; ".join(f"{k}: {v}" for k, v in
                                              assumptions(result.check).items()))
    notes += case_notes(result.robot, [item.task.trajectory for item in result.tasks]
                        if alone is None else result.trajectory)
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.check.joints
               for c in joint.candidates for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    notes += list(result.notes) + list(result.warnings)
    return notes


def binding_table(result: FastestResult) -> FittedTable:
    """The limit closest to its bound, stretch by stretch along the moves (each task's)."""
    named = len(result.tasks) > 1
    columns = ((Column("task", "left"),) if named else ()) + (
        Column("from s"), Column("to s"), Column("joint", "left"),
        Column("limit", "left"), Column("peak"),
        Column("waypoints", "left", group="waypoints"))
    rows = tuple(((escape(b.task),) if named else ()) + (
        f"{b.start:.3f}", f"{b.end:.3f}", escape(b.joint), b.limit,
        percent(b.utilization), f"{b.waypoints[0]} to {b.waypoints[1]}")
        for b in result.binding)
    return FittedTable(
        "What binds along the moves", columns, rows,
        notes=("peak: the largest demand / limit over the stretch (torque against the limit "
               "before any derating). A stretch under 1 % of the moving time joins its "
               "neighbour." + (" from s, to s: in the task's own cycle." if named else ""),))


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
            + f"▶ the unit `size` selects for {_planned_name(comparison)} as planned. none: "
            "the units cannot run the path at any speed. lengthened by: the rule that made the "
            "cycle longer than the time-optimal run under the limits on single samples, and "
            "how (derated: the repeated-peak limit held to that fraction; x: the moves slowed).")
    note += "".join(f" {line}." for line in comparison.base.notes)
    shown = len(columns) if any(row[-1] for row in rows) else -1  # no empty note column
    return FittedTable(f"Joint {joint.joint}: the shortest cycle with each unit",
                       columns[:shown], tuple(row[:shown] for row in rows), tuple(styles),
                       (note,))


def _planned_name(comparison: RatioComparison) -> str:
    """The file `size` sized: the motion's, or the mix's (whose rows are share-weighted)."""
    if comparison.mix is None:
        return comparison.motion.path.name
    return (f"{comparison.mix.path.name} (cycle s: the tasks' cycles weighted by their "
            "shares)")


def max_payload_tables(result: MaxPayloadResult, robot: Robot) -> list[object]:
    """What ``max-payload`` prints: the answer, then the selection there (a mix's tasks too).

    Args:
        result: The largest payload.
        robot: The robot as the command read it.
    """
    text = max_payload_text(result, robot, result.tasks[0].motion)
    if result.selection is None and result.unloaded is not None:
        return [text, "", size_table(result.unloaded), *task_tables(result.unloaded)]
    if result.selection is None:
        return [text]
    return [text, "", size_table(result.selection), *task_tables(result.selection)]


def max_payload_text(result: MaxPayloadResult, robot: Robot,
                     motion: Motion | None = None) -> Paragraphs:
    """The largest payload, where it sits, and which joint runs out of units there.

    One motion's answer is a mass on its payload's shape; a mix's (`motion` None) one
    factor on its tasks' payloads as given, mass and inertia alike.
    """
    x = result.mass
    one = motion if result.mix is None else None  # a mix's tasks name their motions
    if one is not None:
        payload = result.payload
        where = (f"on '{result.frame}'"
                 + ("" if payload.frame is not None else
                    " (the tip of the longest chain of joints not excluded: no frame was given)")
                 + f", centre of mass ({', '.join(f'{c:g}' for c in payload.com)}) m")
        inertia = np.asarray(payload.inertia)
        if inertia.any():
            diagonal = np.diag(inertia)
            where += (f", inertia about it {diagonal[0]:.3g}, {diagonal[1]:.3g}, "
                      f"{diagonal[2]:.3g} kg m² per kg (diagonal)")
        head = f"{robot.path.name} running {one.path.name} ({one.planner})"
        nothing = f"no payload mass, not even none, leaves every joint a feasible unit ({where})."
        unlimited = f"no rule depends on the payload mass {where}: no limit."
    else:
        name = result.mix.path.name if result.mix is not None else "the mix"
        given = ", ".join((f"{task}'s part '{item.name}'" if item.name else task)
                          + f" {item.mass:g} kg" for task, item in result.payloads.items())
        head = (f"{robot.path.name} running {name}: the payloads of "
                f"{', '.join(result.scaled)} (as given: {given}) scaled by one factor, mass "
                "and inertia alike")
        nothing = "no factor, not even 0, leaves every joint a feasible unit."
        unlimited = "no rule depends on them: no limit."
    if x is None or not math.isfinite(x):
        found = [] if result.unloaded is None else [
            joint.name for joint in result.unloaded.joints if joint.selected is None]
        return Paragraphs((f"{head}: {nothing if x is None else unlimited}",
                           *([f"Even without the payload no unit fits {', '.join(found)}; the "
                              "selection without it:"] if found else [])))
    if one is not None:
        what = (f"part '{result.payload.name}' (the one its payload events move: carried "
                "between them)" if result.payload.name else "payload")
        answer, at, kg, of = f"the largest {what} is {x:.4g} kg {where}.", f"{x:.4g} kg", " kg", ""
        how = (". Torque is affine in the payload mass on a fixed trajectory, so each rule's "
               "limit is solved exactly; the inertia about the centre of mass grows with the "
               "mass.")
    else:
        masses = ", ".join(f"{task} {mass:.4g} kg" for task, mass in result.masses().items())
        answer, at, kg, of = (f"the largest factor is {x:.4g}: {masses}.",
                              f"a factor of {x:.4g}", "", "for factors ")
        how = (" over the duty (rules of single samples: the worst task; mean torque and life: "
               "every task pooled at its share). Torque is affine in the factor on fixed "
               "trajectories, so each rule's limit is solved exactly.")
    lines = [f"{head}: {answer}",
             f"{result.joint} runs out of units there: {result.unit.id if result.unit else '-'}"
             f" reaches its {result.rule} limit{how}"]
    if len(result.ranges) > 1 or result.ranges[0][0] > 0.0:
        spans = ", ".join(f"{lo:.4g} to {hi:.4g}{kg}" for lo, hi in result.ranges)
        lines.append(f"Every joint has a unit only {of}from {spans}.")
    lines.append(f"The selection at {at}:")
    return Paragraphs(tuple(lines))


def fastest_tasks_table(result: FastestResult) -> FittedTable:
    """Each task of a mix: its planned cycle, its optimum and its shortest over the duty."""
    columns = (Column("task", "left"), Column("share"), Column("planned s"),
               Column("optimum s"), Column("fastest s"), Column("cycles/h"))
    rows = tuple((escape(item.task.label), percent(item.task.share),
                  "-" if item.planned is None else f"{item.planned:.3f}",
                  f"{item.optimum:.3f}", f"{item.cycle_time:.3f}",
                  f"{item.task.share * 3600.0 / item.cycle_time:,.1f}")
                 for item in result.tasks)
    units = ", ".join(f"{name} {result.units[name].id}"
                      + (f" + {result.motors[name].id}" if name in result.motors else "")
                      for name in result.robot.sized_joints)
    if result.reason is None:
        why = ("every task at its optimum: the rules over the duty pass there (the limits on "
               "single samples, TOPPRA's, bound each task)")
    else:
        why = (f"every task's moves {result.slowdown:.4f}x slower than its optimum, dwells "
               f"kept: {result.reason[0]}'s {result.reason[1]} rule over the duty (pooled at "
               "the shares) fails faster")
    notes = (f"units: {units}", why,
             "optimum: TOPPRA under the motion's and the units' limits on single samples; "
             "the shares of the time are held, so a faster cycle runs more often")
    name = result.mix.path.name if result.mix is not None else "the duty"
    return FittedTable(f"{name}: the shortest cycle of each task with these units",
                       columns, rows, notes=notes)
