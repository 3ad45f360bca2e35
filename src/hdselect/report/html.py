"""The HTML report: one self-contained page to mail, print and check.

Everything is inside the page: the figures as base64 PNG, the styles, no script
and no external request. Utilization is coloured on one colour-blind-safe scale
that changes character at 100 %: blues that darken towards the limit, then
hatched oranges and browns, each failing cell also marked ✗ and classed ``fail``.
Where motors are given, every (gearhead, motor) pair is a candidate: the motor's
checks join the gearhead's in the heat maps and tables, and each joint shows its
motor's torque-speed plane.
"""

from __future__ import annotations

import base64
import re
from collections.abc import Mapping

from hdselect.catalog.rules import CHECK_LABELS, CHECKS, RPM_PER_RAD_S, Candidate, Check, rule
from hdselect.catalog.units import Flag
from hdselect.report.bearing_html import bearing_section
from hdselect.report.case_tables import case_notes
from hdselect.report.colours import ink, utilization_colour
from hdselect.report.html_summary import parts_section, summary
from hdselect.report.html_tables import STYLE, anchor, esc, number, slug, table
from hdselect.report.html_tasks import duty_line, task_section
from hdselect.report.precision_html import precision_section
from hdselect.report.provenance import Provenance
from hdselect.report.size_tables import diagnosis_lines, shortfall_text
from hdselect.report.task_tables import peak_carrying_note, task_of
from hdselect.report.terminal import (
    binding_words,
    life_text,
    ratio_text,
    selected_note,
    shown,
    utilization_text,
    verdict,
)
from hdselect.sizing.diagnosis import with_diagnoses
from hdselect.sizing.loads import JointLoad
from hdselect.sizing.records import MOTOR_MODEL_NOTE, assumptions, base_text
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import moved_parts

__all__ = ["number", "page", "slug"]


def page(result: SizingResult, figures: Mapping[str, bytes], origin: Provenance,
         motor_figures: Mapping[str, bytes] | None = None,
         bearing_figures: Mapping[str, bytes] | None = None,
         precision_figures: Mapping[str, bytes] | None = None) -> str:
    """The report page.

    Args:
        result: The sizing result.
        figures: PNG content of each joint's figure, by joint name.
        origin: Where the result came from.
        motor_figures: PNG content of each joint's motor torque-speed figure, by joint
            name, for the joints with motors.
        bearing_figures: PNG content of each joint's output-bearing figure, by joint name.
        precision_figures: PNG content of the precision section's figures, by name.

    Returns:
        The page, self-contained.
    """
    result = with_diagnoses(result)
    count = len(result.trajectory.t)
    sections = [_selection(result), task_section(result), parts_section(result),
                _warnings(result), _notes(result), _heat_maps(result), _loads(result),
                bearing_section(result, bearing_figures or {}),
                precision_section(result, precision_figures or {}),
                *(_joint_section(result, joint, figures.get(joint.name),
                                 (motor_figures or {}).get(joint.name))
                  for joint in result.joints),
                _assumptions(result), _provenance(origin)]
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>hdselect: {esc(result.title)}</title>
<style>{STYLE}</style></head><body>
<h1>{"Gearhead and motor" if result.motors else "Gearhead"} selection: {esc(result.title)}</h1>
<p>{esc(duty_line(result)) if len(result.tasks) > 1 else f"Cycle {result.cycle_time:.3f} s, "
     f"{count:,} sample{'s' if count != 1 else ''} every {result.trajectory.dt * 1e3:g} ms"}.
Made by hdselect {esc(origin.version)} on
{esc(origin.created)}; <a href="#provenance">how to re-run it</a>.
{esc(base_text(result.robot, moved_parts(result)) if len(result.tasks) < 2 else
     f"base: '{result.robot.root_link}' held fixed; each task's payload and mounting under "
     "Tasks")}.</p>
{summary(result, origin)}
{"".join(_folded(section) for section in sections if section)}
</body></html>
"""


def _folded(section: str) -> str:
    """A ``<section ...><h2>title</h2>...`` as a foldable, open ``<details>``.

    Its heading becomes the summary a reader clicks to fold it.
    """
    found = re.match(r"(<section([^>]*)>)<h2>(.*?)</h2>", section)
    if found is None:
        return section
    kind = re.search(r"class=(\w+)|id=(\w+)", found.group(2))
    of = "" if kind is None else f" data-of={kind.group(1) or kind.group(2)}"
    return (f"<details open{of}><summary><h2>{found.group(3)}</h2></summary>{found.group(1)}"
            f"{section[found.end():]}</details>")


def _unit_cell(candidate: Candidate) -> str:
    """The unit's id, with a * linked to its notes when a stand-in or correction is used."""
    if not candidate.flags:
        return esc(candidate.unit.id)
    return (f'{esc(candidate.unit.id)}<a href="#{anchor(candidate.unit.id)}" '
            f'title="depends on a catalog stand-in or correction">*</a>')


def _motor_cell(candidate: Candidate) -> str:
    """The paired motor's id, or ``-``."""
    return "-" if candidate.motor_unit is None else esc(candidate.motor_unit.id)


def _selection(result: SizingResult) -> str:
    motors = bool(result.motors)
    rows = []
    for joint in result.joints:
        c = joint.selected
        notes = []
        if joint.gravity_loaded:
            notes.append("gravity-loaded: fail-safe needed")
        if joint.load.max_speed == 0.0:
            notes.append("still")
        if c is None:
            cells = [esc(joint.name), "<td class='t fail'>none</td>",
                     *(["none"] if motors else []),
                     esc(shortfall_text(result, joint, words=True)),
                     *(["-", "-"] if motors else []), "-", "-", "-", "-", "-"]
            notes.append(f"no {'pair' if motors else 'unit'} fits: see below")
        else:
            if c.motor is None:
                raise RuntimeError(f"{c.unit.id} carries no motor demand")
            side = c.motor_binding
            binding = c.gearhead_binding if motors else c.binding
            cells = [f'<a href="#joint-{slug(joint.name)}">{esc(joint.name)}</a>', _unit_cell(c),
                     *([_motor_cell(c)] if motors else []),
                     esc(binding_words(c, binding) + task_of(result, joint, binding)),
                     *([("-" if side is None else esc(binding_words(c, side)
                                                      + task_of(result, joint, side))),
                        ratio_text(joint.inertia_ratio(c))] if motors else []),
                     esc(life_text(c.life_hours)), esc(life_text(c.l10_hours)),
                     f"{c.motor.peak_torque:.3g}", f"{c.motor.rms_torque:.3g}",
                     f"{c.motor.max_speed:,.0f}"]
        rows.append([*cells, f"{joint.carried_mass:.2f}",
                     f"<td class='t wrap'>{esc('; '.join(notes))}</td>"])
    header = ["joint", "unit", *(["motor", "gearhead binding", "motor binding",
                                  "load/rotor inertia"] if motors else ["binding rule"]),
              "L50 life", "L10 life", "motor peak [N m]", "motor rms [N m]", "motor max [rpm]",
              "carries [kg]", "notes"]
    slow = "".join(f"<p>{esc(line)}</p>" for joint in result.joints
                   for line in diagnosis_lines(result, joint))
    legend = ("<p>Gearhead binding: the gearhead's check closest to its limit (demand / limit); "
              "motor binding: the motor's (peak under its torque-speed curve, RMS against its "
              "rated torque, speed). load/rotor inertia = (M_jj / N&sup2; + J_in) / J_m, M_jj "
              "the joint's largest diagonal inertia over the cycle (payload and carried masses "
              "included): reported, not checked. carries: the gearheads' and motors' mass "
              "carried from joints further out. * the result depends on a catalog stand-in or "
              "correction: follow it to the note.</p>" if motors else
              "<p>Binding rule: the check closest to its limit (demand / limit). * the result "
              "depends on a catalog stand-in or correction: follow it to the note.</p>")
    # two tables, as the terminal splits them: why each unit, then what it lives and demands
    figures = ("L50 life", "L10 life", "motor peak [N m]", "motor rms [N m]", "motor max [rpm]")
    first = [k for k, h in enumerate(header) if h not in figures]
    second = [0, *(k for k, h in enumerate(header) if h in figures)]
    why = table([header[k] for k in first], [[row[k] for k in first] for row in rows],
                left=3 if motors else 2, text=[len(first) - 1, *([3, 4] if motors else [2])])
    demands = table([header[k] for k in second], [[row[k] for k in second] for row in rows])
    return (f"<section id=selection><h2>Selection</h2>{why}{demands}{slow}"
            f"{legend}</section>")


def _notes(result: SizingResult) -> str:
    flags: dict[str, dict[str, Flag]] = {}
    for joint in result.joints:
        for c in joint.candidates:
            for flag in c.flags:
                flags.setdefault(c.unit.id, {})[flag.code] = flag
    items = "".join(f'<li id="{anchor(unit)}"><b>{esc(unit)}</b>: '
                    + "; ".join(esc(f.note) for f in found.values()) + "</li>"
                    for unit, found in flags.items())
    case = "".join(f"<li>{esc(note)}</li>" for note in [*case_notes(
        result.robot, [task.trajectory for task in result.counted] or result.trajectory),
        *filter(None, [peak_carrying_note(result)])])
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    verb = "carry" if len(loaded) > 1 else "carries"
    gravity = (f"<p><b>Backdriving.</b> {esc(', '.join(loaded))} {verb} gravity. Harmonic Drive "
               "gearing backdrives when its input is free: where a falling load could injure, "
               "a fail-safe device on the output is needed.</p>" if loaded else "")
    return (f"<section id=notes><h2>Notes</h2>{f'<ul>{case}</ul>' if case else ''}"
            f"<h3>Catalog stand-ins and corrections</h3><ul>{items or '<li>none</li>'}</ul>"
            f"{gravity}</section>")


def _warnings(result: SizingResult) -> str:
    """What the robot file and the motion file raised, and the file's limits the cycle exceeds."""
    if not result.warnings:
        return ""
    items = "".join(f"<li>{esc(warning)}</li>" for warning in result.warnings)
    return f"<section id=warnings><h2>Warnings</h2><ul>{items}</ul></section>"


def _loads(result: SizingResult) -> str:
    """Every joint of the robot, sized or not, beside its robot file's limits."""
    if not result.loads:
        return ""
    angle = result.motion.angle_unit if result.motion is not None else "deg"
    rows = [[esc(load.name), esc(load.kind), "yes" if load.sized else "no",
             *_load_cells(load, angle)] for load in result.loads]
    notes = "".join(f"<li><b>{esc(load.name)}</b>: {esc(load.note)}</li>"
                    for load in result.loads if load.note)
    header = ["joint", "type", "sized", "peak torque or force", "file effort limit",
              "top speed", "file velocity limit", "travel"]
    return ("<section id=loads><h2>Every joint over the cycle</h2>"
            "<p>Peak torque (force, for a prismatic joint) with the gearheads"
            f"{' and motors' if result.motors else ''} carried, top "
            "speed and travel of every joint of the robot, beside the robot file's limits. ✗ "
            f"above the limit.</p>{table(header, rows, left=3, text=[7])}"
            f"{f'<ul>{notes}</ul>' if notes else ''}</section>")


def _load_cells(load: JointLoad, angle: str) -> list[str]:
    """Peak, effort limit, speed, velocity limit and travel of one joint, with units."""
    force, length, scale = load.units(angle)

    def value(figure: float | None, limit: float, unit: str, over: bool) -> str:
        if figure is None:
            return "-"
        text = esc(f"{number(figure)} {unit}")
        if not over:
            return text
        colour = utilization_colour(figure / limit)
        return (f"<td class=fail style='background-color:{colour};color:{ink(colour)}' "
                f"title='above the robot file&#x27;s limit'>{text} ✗</td>")

    def limit(figure: float, unit: str) -> str:
        return esc(f"{number(figure)} {unit}") if figure < float("inf") else "none"

    low, high = (x * scale for x in load.travel)
    return [value(load.peak, load.effort_limit, force, load.above_effort),
            limit(load.effort_limit, force),
            value(load.max_speed * scale, load.velocity_limit * scale, f"{length}/s",
                  load.above_velocity),
            limit(load.velocity_limit * scale, f"{length}/s"),
            esc(f"{number(low)} .. {number(high)} {length}")]


def _rules(result: SizingResult) -> list[str]:
    return [r for r in CHECKS if any(r in c.checks and shown(c.checks[r])
                                     for j in result.joints for c in j.candidates)]


def _heat_cell(check: Check | None, detail: bool, name: str, where: str) -> str:
    """One check's cell, coloured; `where` names its joint and unit as data attributes."""
    if check is not None and "not_rated" in check.detail:
        words = esc(str(check.detail["not_rated"]))
        return f"<td class='u na' data-check='{name}' {where}>{words}</td>"
    if check is None or check.value is None:
        return f"<td class='u na' data-check='{name}' {where}>-</td>"
    colour = utilization_colour(check.utilization)
    state = "ok" if check.ok else "fail"
    text = utilization_text(check.utilization, check.ok) + ("" if check.ok else " ✗")
    found = rule(name)
    if found.at_least:  # a life or a safety: required of reached
        figures = (f"needs {check.limit:,.0f} of {life_text(check.value)}" if found.life
                   else f"needs {check.limit:,.3g} of {check.value:.3g}")
    else:
        figures = f"{number(check.value)} / {number(check.limit)} {found.unit}"
    kind = check.detail.get("kind")
    if isinstance(kind, str) and name == "momentary":
        figures += f", {kind.replace('emergency ', '')}"
    small = f"<small>{esc(figures)}</small>" if detail else ""
    return (f"<td class='u {state}' data-check='{name}' {where} style='background-color:{colour};"
            f"color:{ink(colour)}' title='{esc(figures)}'>{esc(text)}{small}</td>")


def _where(joint: JointSizing, candidate: Candidate) -> str:
    motor = candidate.motor_unit
    return (f"data-joint='{esc(joint.name)}' data-unit='{esc(candidate.unit.id)}'"
            + ("" if motor is None else f" data-motor='{esc(motor.id)}'"))


def _colour_bar() -> str:
    return ("<div class=bar><span>utilization</span><div><div class=ramp><div class=hatch>"
            "</div></div><div class=ticks><span>0</span><span>50</span><span>100 %</span>"
            "<span>150</span><span>≥200</span></div></div><span>blue: within the limit, darker "
            "nearer it; hatched orange to brown and ✗: over it</span></div>")


def _heat_maps(result: SizingResult) -> str:
    rules = _rules(result)
    maps = []
    for joint in result.joints:
        rows = [[("▶ " if c is joint.selected else "") + esc(c.label),
                 *(_heat_cell(c.checks.get(r), False, r, _where(joint, c)) for r in rules)]
                for c in joint.candidates]
        header = [f'<a href="#joint-{slug(joint.name)}">{esc(joint.name)}</a>',
                  *(esc(CHECK_LABELS[r]) for r in rules)]
        maps.append(f"<div>{table(header, rows)}</div>")
    chosen = selected_note(next((j.selected for j in result.joints if j.selected), None),
                           "pair" if result.motors else "unit")
    pairs = (" class=pairs", "<p class=printnote>Printed without the maps: each joint's "
             "table below has every pair's checks, coloured the same way.</p>") \
        if result.motors else ("", "")
    return (f"<section id=heatmap{pairs[0]}><h2>Utilization of every candidate</h2>"
            f"{_colour_bar()}{pairs[1]}<div class=maps>{''.join(maps)}</div><p>{chosen} "
            "Utilization = demand / limit of each check (life: required over expected). "
            "mom. = momentary (T4), the worse of an emergency stop and a crash."
            + (" b. = the output bearing's checks (its life and static safety: required over "
               "reached)." if any(r.startswith("bearing_") for r in rules) else "")
            + (" Each row is a gearhead and motor pair: the gearhead's checks behind that motor "
               "(its rotor inertia in the motor torque and the crash), then m. = the motor's: "
               "peak under its torque-speed curve, RMS against its rated torque, speed."
               if result.motors else "") + "</p></section>")


def _joint_section(result: SizingResult, joint: JointSizing, png: bytes | None,
                   motor_png: bytes | None = None) -> str:
    rules = _rules(result)
    pairs = joint.name in result.motors
    rows, figures, classes = [], [], []
    for c in joint.candidates:
        if c.motor is None:
            raise RuntimeError(f"{c.unit.id} carries no motor demand")
        who = [_unit_cell(c), *([_motor_cell(c)] if pairs else [])]
        rows.append([*who,
                     *(_heat_cell(c.checks.get(r), True, r, _where(joint, c)) for r in rules),
                     f"<td class=t>{esc(verdict(c))}</td>"])
        figures.append([*who, *([ratio_text(joint.inertia_ratio(c))] if pairs else []),
                        esc(life_text(c.life_hours, "")), esc(life_text(c.l10_hours, "")),
                        f"{c.motor.peak_torque:.3g}", f"{c.motor.rms_torque:.3g}",
                        f"{c.motor.max_speed:,.0f}"])
        classes.append("chosen" if c is joint.selected else "")
    who_header = ["unit", *(["motor"] if pairs else [])]
    header = [*who_header, *(esc(CHECK_LABELS[r]) for r in rules), "result"]
    figure_header = [*who_header, *(["load/rotor inertia"] if pairs else []), "L50 h", "L10 h",
                     "motor peak [N m]", "motor rms [N m]", "motor max [rpm]"]
    load = joint.load
    mean = "n/a" if load.mean_torque is None else f"{load.mean_torque:.3g} N m"
    chosen = joint.selected
    inertia = ("" if joint.load_inertia is None else
               f", load inertia M_jj up to {number(joint.load_inertia)} kg m^2")
    text = (f"peak {load.peak_torque:.3g} N m while moving, mean torque {mean}, mean output "
               f"speed {load.mean_speed * RPM_PER_RAD_S:.3g} rpm, largest gravity torque "
               f"{number(joint.max_gravity_torque)} N m{inertia}, carries "
               f"{joint.carried_mass:.2f} kg of gearheads{' and motors' if result.motors else ''}"
               f". Selected: {chosen.label if chosen else 'none'}.")
    shown = chosen or joint.strongest
    limits = (shown.unit.id if chosen is not None
              else f"the strongest candidate, {shown.unit.id} (no unit holds this joint)")
    figure = ""
    if png is not None:
        figure = (f"<figure>{_img(png)} alt='speed and torque of {esc(joint.name)} over the "
                  f"cycle, with the limits of {esc(limits)}'><figcaption>Speed (output "
                  "and input) and output torque over the cycle. Grey bands: at rest, input "
                  "locked (static limit); elsewhere moving (repeated-peak limit).</figcaption>"
                  "</figure>")
    if motor_png is not None and shown.motor_unit is not None:
        figure += (f"<figure>{_img(motor_png)} alt='torque-speed plane of the motor "
                   f"{esc(shown.motor_unit.id)} of {esc(joint.name)}'><figcaption>The motor "
                   f"{esc(shown.motor_unit.id)} behind {esc(shown.unit.id)}: every sample of the "
                   "cycle as (input speed, motor torque) under its peak torque over speed, its "
                   "rated torque (the limit of the RMS torque) and its maximum speed; the RMS "
                   "point and the worst sample against the peak marked.</figcaption></figure>")
    shown = joint.selected or joint.strongest  # in print, the pairs that could be chosen
    kept = [c.feasible or c is shown or not pairs for c in joint.candidates]
    checks = table(header, rows, text=[len(header) - 1], left=2 if pairs else 1, classes=[
        " ".join(filter(None, (k, "" if keep else "out")))
        for k, keep in zip(classes, kept, strict=True)])
    demands = table(figure_header, figures, left=2 if pairs else 1, classes=[
        " ".join(filter(None, (k, "" if keep else "no")))
        for k, keep in zip(classes, kept, strict=True)])
    return (f"<section class=joint id='joint-{slug(joint.name)}'><h2>Joint "
            f"{esc(joint.name)}</h2><p>{esc(text)}</p>{checks}"
            "<p>Each check: utilization, then demand / limit. ✗ over the limit (or above "
            "what the design margin leaves)."
            + (" m. = the motor's checks; inertia = the load-to-rotor inertia ratio against "
               "the largest allowed. On paper, demand / limit is printed for the pairs that "
               "could be chosen." if pairs else "")
            + f"</p>{demands}<p>Life and what the motor must deliver behind each "
            + ("pair (printed: the feasible pairs); load/rotor inertia = (M_jj / N² + J_in) / "
               "J_m." if pairs else "unit.")
            + f"</p>{figure}</section>")


def _img(png: bytes) -> str:
    """The start of an ``img`` element embedding a PNG (the caller adds ``alt`` and ``>``)."""
    return f"<img src='data:image/png;base64,{base64.b64encode(png).decode('ascii')}'"


def _assumptions(result: SizingResult) -> str:
    given = {**assumptions(result),
             **({"motor rules": MOTOR_MODEL_NOTE} if result.motors else {})}
    items = "".join(f"<li><b>{esc(k)}</b>: {esc(v)}</li>" for k, v in given.items())
    return f"<section id=assumptions><h2>Assumptions</h2><ul>{items}</ul></section>"


def _provenance(origin: Provenance) -> str:
    import shlex

    if origin.command is None:
        run = ("<p>Made through the Python API: there is no command line. The case below is "
               "everything it was given.</p>")
    else:
        run = ("<p>Re-run it in the directory it ran in (the files' paths below are "
               "relative to it), with the files below (same hashes):</p>"
               f"<pre id=command>{esc(shlex.join(origin.command))}</pre>")
    software = ", ".join(f"{name} {version}" for name, version in origin.software)
    files = table(["role", "file", "bytes", "SHA-256"], [
        [esc(f.role), f"<code>{esc(f.path)}</code>", "-" if f.size is None else f"{f.size:,}",
         f"<code>{esc(f.sha256)}</code>"] for f in origin.files], left=1, text=[1])  # paths wrap
    settings = table(["what", "value"], [[esc(k), f"<td class='t wrap'>{esc(v)}</td>"]
                                          for k, v in origin.settings], left=2)
    limits = (f"<h3>Limits of the motion</h3>{table(*_escaped(origin.limits))}"
              if origin.limits[0] else "")
    waypoints = (f"<h3>Waypoints</h3>{table(*_escaped(origin.waypoints))}"
                 if origin.waypoints[0] else "")
    return (f"<section id=provenance><h2>Provenance</h2>{run}"
            f"<p>hdselect {esc(origin.version)}, made {esc(origin.created)}; {esc(software)}.</p>"
            f"<h3>Input files</h3>{files}<h3>The case as run</h3>{settings}{limits}{waypoints}"
            "</section>")


def _escaped(table: tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]):
    header, rows = table
    return [esc(h) for h in header], [[esc(c) for c in row] for row in rows]
