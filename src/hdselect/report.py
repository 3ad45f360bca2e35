"""Terminal tables of catalogs and results; they format, they do not compute."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable

import numpy as np
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
from hdselect.codesign import FastestResult, JointRatios, RatioComparison
from hdselect.duty import DutyResult
from hdselect.export import assumptions, mean_speed_note
from hdselect.maxpayload import MaxPayloadResult
from hdselect.motion import Motion
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
            f"{len(result.trajectory.t):,} samples")


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
    loaded = [joint.name for joint in result.joints if joint.gravity_loaded]
    if loaded:
        notes.append(f"gravity: {', '.join(loaded)} carry gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes


_SOURCES = {"motion": "motion", "robot": "URDF", "unit": "unit"}
_SHORT_LIMITS = {"velocity (motion file)": "speed", "velocity (URDF)": "speed",
                 "max input speed": "speed", "acceleration": "accel.", "torque": "torque",
                 "emergency stop": "e-stop", "crash": "crash"}


def fastest_table(result: FastestResult) -> Table:
    """One row per sized joint: its unit, the limits it ran under, what bound it, its rules."""
    robot, motion = result.robot, result.motion
    pieces = 1 + int(np.count_nonzero(motion.dwells[1:-1] > 0.0))
    table = Table(
        title=f"{motion.path.name} on {robot.path.name}: fastest cycle {result.cycle_time:.3f} s "
              f"({len(motion.waypoints)} waypoints, {pieces} piece{'s' if pieces > 1 else ''})",
        title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, collapse_padding=True)
    for header in ("joint", "unit", "speed\nlimit", "torque\nlimit", "binds\nlongest", "rule",
                   "L50 h"):
        table.add_column(header, no_wrap=True,
                         justify="right" if header in ("torque\nlimit", "L50 h") else "left")
    shares: dict[str, tuple[str, float]] = {}
    for name, limit, share in result.binding_shares():  # longest first
        shares.setdefault(name, (limit, share))
    for joint in result.check.joints:
        (candidate,) = joint.candidates
        lim = result.limits[joint.name]
        derated = result.derating.get(joint.name)
        torque = f"{lim.torque:.3g}" + (f" ({derated:.0%})" if derated else "")
        bound = shares.get(joint.name)
        check = candidate.checks[candidate.binding]
        table.add_row(
            joint.name, candidate.unit.id + ("*" if candidate.flags else ""),
            f"{lim.velocity:.3g} {_SOURCES[lim.velocity_source]}", torque,
            "-" if bound is None else f"{_SHORT_LIMITS[bound[0]]} {percent(bound[1])}",
            f"{CHECK_LABELS[candidate.binding]} {percent(check.utilization)}",
            life_text(candidate.life_hours, ""))
    table.caption = escape("\n".join(_fastest_notes(result)))
    table.caption_justify = "left"
    return table


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
    notes.append("speed limit [rad/s, m/s for a prismatic joint]: the lowest of the motion "
                 "file's, the URDF's and the unit's (maximum input speed / ratio). torque "
                 "limit [N m]: the unit's repeated peak (derated: the fraction kept). binds "
                 "longest: the joint's limit that is the closest to its bound of all for the "
                 "longest share of the moving time. rule: the rule with the highest "
                 "utilization on the result (* catalog stand-in).")
    notes.append("Assumptions: " + "; ".join(f"{k}: {v}" for k, v in
                                              assumptions(result.check).items()))
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.check.joints
               for c in joint.candidates for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    return notes


def binding_table(result: FastestResult) -> Table:
    """The limit closest to its bound, stretch by stretch along the moves."""
    table = Table(title="What binds along the moves", title_justify="left",
                  box=box.SIMPLE_HEAD, pad_edge=False)
    for header in ("from s", "to s", "waypoints", "joint", "limit", "peak"):
        table.add_column(header, no_wrap=True,
                         justify="right" if header in ("from s", "to s", "peak") else "left")
    for b in result.binding:
        table.add_row(f"{b.start:.3f}", f"{b.end:.3f}", f"{b.waypoints[0]} to {b.waypoints[1]}",
                      b.joint, b.limit, percent(b.utilization))
    table.caption = ("peak: the largest demand / limit over the stretch (torque against the "
                     "limit before any derating). A stretch under 1 % of the moving time "
                     "joins its neighbour.")
    table.caption_justify = "left"
    return table


def ratios_table(comparison: RatioComparison, joint: JointRatios) -> Table:
    """Every unit on one joint: its shortest cycle, the other joints' units fixed."""
    table = Table(title=f"Joint {joint.joint}: the shortest cycle with each unit",
                  title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False)
    for header in ("unit", "cycle s", "vs ▶", "binds longest", "lengthened by / note"):
        table.add_column(header, no_wrap=header != "lengthened by / note",
                         justify="right" if header in ("cycle s", "vs ▶") else "left")
    reference = next((row.cycle_time for row in joint.rows if row.unit.id == joint.selected),
                     None)
    for row in joint.rows:
        mark = "▶" if row.unit.id == joint.selected else " "
        if row.cycle_time is None:
            table.add_row(mark + row.unit.id, "[red]none[/red]", "", "", row.note or "")
            continue
        change = "" if reference is None or row.unit.id == joint.selected else \
            f"{(row.cycle_time / reference - 1.0) * 100:+.1f}%"
        binding = "-" if row.binding is None else \
            f"{row.binding[0]} {_SHORT_LIMITS[row.binding[1]]}"
        table.add_row(mark + row.unit.id, f"{row.cycle_time:.3f}", change, binding,
                      row.note or "")
    others = ", ".join(f"{name} {unit.id}" for name, unit in comparison.units.items()
                       if name != joint.joint)
    table.caption = escape(
        (f"Other joints: {others}. " if others else "")
        + f"▶ the unit `size` selects for {comparison.motion.path.name} as planned. none: "
        "the units cannot run the path at any speed. lengthened by: the rule that made the "
        "cycle longer than the time-optimal run under the limits on single samples, and "
        "how (derated: the repeated-peak limit held to that fraction; x: the moves slowed).")
    table.caption_justify = "left"
    return table


def max_payload_text(result: MaxPayloadResult, robot: Robot, motion: Motion) -> str:
    """The largest payload, where it sits, and which joint runs out of units there."""
    payload = result.payload
    where = (f"at {payload.frame or 'the last link'}, centre of mass "
             f"({', '.join(f'{c:g}' for c in payload.com)}) m")
    inertia = np.asarray(payload.inertia)
    if inertia.any():
        where += (f", inertia about it {np.diag(inertia)[0]:.3g}, {np.diag(inertia)[1]:.3g}, "
                  f"{np.diag(inertia)[2]:.3g} kg m² per kg (diagonal)")
    head = f"{robot.path.name} running {motion.path.name} ({motion.planner})"
    if result.mass is None:
        return (f"{head}: no payload mass, not even none, leaves every joint a feasible unit "
                f"({where}).")
    if not math.isfinite(result.mass):
        return f"{head}: no rule depends on the payload mass {where}: no limit."
    lines = [f"{head}: the largest payload is {result.mass:.4g} kg {where}."]
    lines.append(f"{result.joint} runs out of units there: {result.unit.id if result.unit else '-'}"
                 f" reaches its {result.rule} limit. Torque is affine in the payload mass on a "
                 "fixed trajectory, so each rule's limit is solved exactly; the inertia about the "
                 "centre of mass grows with the mass.")
    if len(result.ranges) > 1 or result.ranges[0][0] > 0.0:
        spans = ", ".join(f"{lo:.4g} to {hi:.4g} kg" for lo, hi in result.ranges)
        lines.append(f"Every joint has a unit only from {spans}.")
    lines.append(f"The selection at {result.mass:.4g} kg:")
    return escape("\n".join(lines))
