"""The report's first page, one page on screen and on paper, and its parts list.

What a design review reads first: the robot, the motion (each task's cycle, payload
and share of the time), the mounting, the selection per joint (unit, motor, the rule
closest to its limit, an output bearing's among them, and the margin left, life), the
masses added, the warnings that change a decision (an output bearing the source does
not rate among them) and the assumptions in one short list.
"""

from __future__ import annotations

from hdselect.catalog.rules import CHECK_NAMES, Candidate
from hdselect.motion.motionfile import Motion
from hdselect.report.html_tables import esc, number, slug, table
from hdselect.report.parts import STIFFNESS_COLUMNS, Part, parts
from hdselect.report.precision_tables import precision_warnings
from hdselect.report.provenance import Provenance
from hdselect.report.size_tables import diagnosis_lines, shortfall_text
from hdselect.report.task_tables import mounting_text, task_of
from hdselect.report.terminal import binding_words, life_text, ratio_text
from hdselect.robot.model import Robot
from hdselect.sizing.precision_records import STIFFNESS_NOT_RATED
from hdselect.sizing.records import inertia_limit_text, margin_text
from hdselect.sizing.result import SizingResult


def summary(result: SizingResult, origin: Provenance) -> str:
    """The review summary: one page, the selection and what it rests on."""
    settings = dict(origin.settings)
    robot = result.robot
    mountings = {mounting_text(task.robot) for task in result.tasks}
    mounting = (settings.get("mounting", "-") if len(result.tasks) < 2 else
                mountings.pop() if len(mountings) == 1 else "each task's own (under Motion)")
    facts = [("robot", f"{robot.path.name}: {len(robot.sized_joints)} joints sized of "
                       f"{robot.dof}; base '{robot.root_link}' held fixed"),
             ("mounting", mounting)]
    fact_rows = "".join(f"<tr><th class=t>{esc(k)}</th><td class=t>{esc(v)}</td></tr>"
                        for k, v in facts)
    verdict_text = ("Every joint has a unit." if result.feasible else
                    "Some joints have no unit: see the warnings.")
    return (f"<section id=summary class=summary><h2>Review summary</h2>"
            f"<p class=verdict>{esc(verdict_text)}</p>"
            f"<div class=fit><table>{fact_rows}</table></div>"
            f"<h3>Motion</h3>{_tasks(result)}"
            f"<h3>Selection</h3>{_selection(result)}{_totals(result)}"
            f"<h3>Warnings that change a decision</h3>{_warnings(result)}"
            f"<h3>Assumptions</h3>{_assumptions(result)}</section>")


def _tasks(result: SizingResult) -> str:
    """Each task of the duty: its motion, cycle, payload and share of the operating time.

    A mix whose tasks are mounted differently gets each task's mounting too, and a mix
    in cycles per hour its idle time.
    """
    alone = result.motion if len(result.tasks) == 1 else None  # the motion size planned
    rows = [_task_row(task.name, task.motion or alone, task.trajectory.duration, task.robot,
                      task.share) for task in result.tasks]
    if not rows:  # a result not made from tasks: its own trajectory, the whole time
        rows.append(_task_row("", result.motion, result.cycle_time, result.robot, 1.0))
    header = ["task", "cycle", "payload", "share of the time"]
    if len({mounting_text(task.robot) for task in result.tasks}) > 1:
        header.append("mounting")
        for row, task in zip(rows, result.tasks, strict=True):
            row.append(esc(mounting_text(task.robot)))
    if result.idle > 0.0:
        rows.append(["idle (no task runs)", "-", "-", f"{result.idle * 100:.3g} %",
                     *(["-"] if len(header) > 4 else [])])
    return table(header, rows, left=1, text=[2, 4])


def _task_row(label: str, motion: Motion | None, cycle: float, robot: Robot,
              share: float) -> list[str]:
    name = label or (motion.path.name if motion is not None else "a given trajectory")
    planner = f" ({motion.planner})" if motion is not None else ""
    payload = robot.payload
    carried = "none" if payload is None else f"{payload.mass:g} kg on {robot.payload_frame}"
    return [esc(name + planner), f"{cycle:.3f} s", esc(carried), f"{share * 100:g} %"]


def _selection(result: SizingResult) -> str:
    motors = bool(result.motors)
    life = "L10" if result.options.life_basis == "L10" else "L50"
    rows = []
    for joint in result.joints:
        c = joint.selected
        name = f'<a href="#joint-{slug(joint.name)}">{esc(joint.name)}</a>'
        if c is None:
            rows.append([name, "<td class='t fail'>none fits</td>",
                         *(["-"] if motors else []),
                         esc(shortfall_text(result, joint, words=True)),
                         "-", "-", *(["-"] if motors else [])])
            continue
        binding = c.gearhead_binding if motors else c.binding
        words = binding_words(c, binding) + task_of(result, joint, binding)
        if motors and c.motor_binding is not None:
            words += ("; motor: " + binding_words(c, c.motor_binding)
                      + task_of(result, joint, c.motor_binding))
        if c.binding not in (binding, c.motor_binding):  # the pair's inertia ratio
            words += "; " + binding_words(c, c.binding) + task_of(result, joint, c.binding)
        rows.append([name, esc(c.unit.id), *([esc(_motor(c))] if motors else []), esc(words),
                     f"{(1.0 - c.checks[c.binding].utilization) * 100:.0f} %",
                     esc(life_text(c.l10_hours if life == "L10" else c.life_hours)).replace(
                         " h", "&nbsp;h"),
                     *([esc(ratio_text(joint.inertia_ratio(c)))] if motors else [])])
    header = ["joint", "unit", *(["motor"] if motors else []), "closest to its limit",
              "margin left", f"{life} life", *(["load/rotor inertia"] if motors else [])]
    return table(header, rows, left=3 if motors else 2, text=[3 if motors else 2])


def _motor(candidate: Candidate) -> str:
    return "-" if candidate.motor_unit is None else candidate.motor_unit.id


def _totals(result: SizingResult) -> str:
    total = parts(result)[-1]
    gearheads, motors = total.gearhead_mass_kg or 0.0, total.motor_mass_kg or 0.0
    what = "motors" if result.motors else "assumed motor mass"
    motor_text = (f", {what} {motors:.2f} kg, together {gearheads + motors:.2f} kg"
                  if motors > 0.0 else "; no motor mass given")
    return (f"<p><b>Mass added to the arm:</b> gearheads {gearheads:.2f} kg{motor_text} "
            '(the <a href="#parts">parts list</a> has each part).</p>')


def _warnings(result: SizingResult) -> str:
    items = []
    for joint in result.joints:
        lines = diagnosis_lines(result, joint)
        if lines:
            items.append(f"<b>{esc(joint.name)}</b>: " + " ".join(
                esc(line.removeprefix(f"{joint.name}: ").rstrip(".") + ".") for line in lines))
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    if loaded:
        items.append(f"<b>Backdriving</b>: {esc(', '.join(loaded))} carry gravity and "
                     "backdrive when the input is free: a fail-safe brake on the output is "
                     "needed where a falling load could injure.")
    items += [esc(warning) for warning in result.warnings]
    stand_ins = sorted({c.unit.id for joint in result.joints for c in [joint.selected]
                        if c is not None and any(f.kind == "fallback" for f in c.flags)})
    if stand_ins:
        items.append(f"{esc(', '.join(stand_ins))}: chosen on catalog stand-ins for values "
                     'the catalog does not rate (<a href="#notes">notes</a>).')
    unrated = sorted({c.unit.id for joint in result.joints for c in [joint.selected]
                      if c is not None and joint.bearing is not None and c.unit.bearing is None})
    if unrated:
        items.append(f"{esc(', '.join(unrated))}: output bearing not rated by the source: its "
                     'loads are reported (<a href="#bearing">output bearings</a>), not checked.')
    items += [esc(line) for line in precision_warnings(result)]
    thin = [joint for joint in result.joints if joint.selected is not None
            and 1.0 - joint.selected.checks[joint.selected.binding].utilization < 0.1]
    if thin:
        items.append("Less than 10 % margin left: " + ", ".join(
            f"{esc(j.name)} ({esc(CHECK_NAMES.get(j.selected.binding, j.selected.binding))})"
            for j in thin if j.selected is not None) + ".")
    return f"<ul class=warn>{''.join(f'<li>{i}</li>' for i in items) or '<li>none</li>'}</ul>"


def _assumptions(result: SizingResult) -> str:
    options = result.options
    life = ("none required" if options.life_hours is None
            else f"{options.life_hours:,.0f} h required ({options.life_basis})")
    items = [("design margin", margin_text(options.margin)),
             ("selection", str(options.prefer)
              + (f", target ratio {options.inertia_target:g}" if options.prefer == "inertia"
                 else "")),
             ("life", life),
             ("efficiency", f"{options.efficiency:.2f} where a unit has no table"),
             ("stop time", f"{options.stop_time:g} s (emergency stop and crash)")]
    if result.motors:
        items.append(("largest inertia ratio", inertia_limit_text(result)))
    elif options.rotor_inertia == 0.0 and options.motor_mass == 0.0:
        items.append(("motor", "none given: rotor inertia and mass not included"))
    items.append(("mass coupling", "on" if options.mass_coupling else "off"))
    return ("<ul>" + "".join(f"<li><b>{esc(k)}</b>: {esc(v)}</li>" for k, v in items)
            + '</ul><p>All assumptions: <a href="#assumptions">below</a>.</p>')


def parts_section(result: SizingResult) -> str:
    """The parts list (as ``--bom`` writes it): per joint the parts, their masses, why."""
    rows, listed = [], parts(result)
    for part in listed:
        def kg(value: float | None) -> str:
            return "-" if value is None else f"{value:.2f}"
        rows.append([esc(part.joint), esc(part.gearhead or "-"),
                     "-" if part.ratio is None else f"{part.ratio:g}", kg(part.gearhead_mass_kg),
                     esc(part.motor or "-"), kg(part.motor_mass_kg), kg(part.mass_kg),
                     esc(part.binding_rule or "-"),
                     "-" if part.margin_left is None else f"{part.margin_left * 100:.0f} %",
                     esc(part.status)])
    header = ["joint", "gearhead", "ratio", "gearhead [kg]", "motor", "motor [kg]",
              "together [kg]", "closest to its limit", "margin left", "status"]
    return (f"<section id=parts><h2>Parts list</h2>{table(header, rows, left=2, text=[4, 7, 9])}"
            f"{_stiffness(listed)}"
            "<p>As <code>--bom FILE.csv</code> writes it (full precision, lives and ratios "
            "too). Motor mass without motor data: the assumed one (--motor-mass). Stiffness: "
            "the catalog's torsional stiffness of each unit (the twist rises at K1 up to T1, "
            "at K2 up to T2, at K3 above), its hysteresis loss and lost motion, and its output "
            "bearing's moment stiffness K_B; - where the source gives no such figure.</p>"
            "</section>")


def _stiffness(listed: list[Part]) -> str:
    """Each chosen unit's stiffness, as the catalog gives it; one row per joint with a unit."""
    rows = []
    for part in listed[:-1]:
        if part.gearhead is None:
            continue
        cells = ["-" if value is None else number(value)
                 for value in (getattr(part, column) for column, _, _ in STIFFNESS_COLUMNS)]
        if part.stiffness == STIFFNESS_NOT_RATED:  # its K1: the twist is not computed
            cells[0] = f"<td class='t wrap'>{esc(STIFFNESS_NOT_RATED)}</td>"
        rows.append([esc(part.joint), esc(part.gearhead), *cells])
    if not rows:
        return ""
    return table(["joint", "gearhead", *(esc(header).replace("N m", "N&nbsp;m")
                                         for _, header, _ in STIFFNESS_COLUMNS)],
                 rows, left=2)
