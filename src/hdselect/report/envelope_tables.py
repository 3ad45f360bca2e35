"""Terminal tables of an envelope: the unit per joint for any motion within the spec."""

from __future__ import annotations

import numpy as np
from rich.markup import escape

from hdselect.envelope.result import EnvelopeResult, JointEnvelope, WorstState
from hdselect.envelope.search import ABSOLUTE
from hdselect.envelope.torques import BEARING_NOTE, PARTS_NOTE
from hdselect.report.tables import Column, FittedTable, Paragraphs
from hdselect.report.terminal import DEG_PER_RAD, life_text, utilization_text, verdict
from hdselect.sizing.diagnosis import diagnosis_of
from hdselect.sizing.records import assumptions, base_text

_SOURCE_SHORT = {"given": "given", "file": "file", "robot file": "robot", "default": "default"}


def envelope_table(result: EnvelopeResult) -> FittedTable:
    """One row per joint: the unit for any motion within the spec, why, and the worst torques.

    Beside it, what the duty alone selects. On a narrow terminal the worst torques, the
    life and the duty's choice move into tables below; the joint, the unit and the
    binding rule stay.
    """
    columns = (Column("joint", "left"), Column("unit", "left"), Column("binding", "left"),
               Column("peak\nN m", group="worst"), Column("static\nN m", group="worst"),
               Column("stop\nN m", group="worst"), Column("L50 life", group="life"),
               Column("converged", "left", group="life"),
               Column("duty alone", "left", group="duty"))
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        torques = [f"{abs(joint.worst[f].torque):.3g}" for f in ("peak", "static", "stop")]
        duty = escape(joint.duty.unit.id) if joint.duty is not None else "none"
        settled = "yes" if joint.convergence.converged else "[red]no[/red]"
        if chosen is None:
            rows.append((escape(joint.name), "[red]none[/red]",
                         f"[red]{escape(shortfall_cell(result, joint))}[/red]", *torques, "-",
                         settled, duty))
            continue
        check = chosen.checks[chosen.binding]
        rows.append((escape(joint.name), escape(chosen.unit.id) + ("*" if chosen.flags else ""),
                     f"{chosen.binding} {utilization_text(check.utilization, True)}", *torques,
                     life_text(chosen.life_hours), settled, duty))
    title = (f"{result.robot.path.name}: the unit for any motion within the spec (q in the "
             "joint ranges, |qd| <= v, |qdd| <= a)\n" + base_text(result.robot)
             + f"\nmean torque and life on {result.duty.phrase}")
    return FittedTable(title, columns, tuple(rows), notes=tuple(note_lines(result)))


def shortfall_cell(result: EnvelopeResult, joint: JointEnvelope) -> str:
    """A joint without a unit: its diagnosis's headline, e.g. ``peak 45.2 > 20.3 N m``."""
    found = diagnosis_of(result.sizing, joint.name)
    return found.headline.short() if found is not None else verdict(joint.sizing.strongest)


def limits_table(result: EnvelopeResult) -> FittedTable:
    """The spec: each joint's range and limits, and where each limit came from."""
    box, spec = result.spec.box, result.spec
    columns = (Column("joint", "left"), Column("range", "left"), Column("velocity"),
               Column("acceleration"), Column("from", "left", group="from"))
    rows = []
    for j, name in enumerate(box.joint_names):
        rotary = result.robot.revolute[j]
        scale, unit = (DEG_PER_RAD, "deg") if rotary else (1.0, "m")
        span = (f"{box.lower[j] * scale:.4g} .. {box.upper[j] * scale:.4g} {unit}"
                + (" (a turn)" if box.periodic[j] else ""))
        sources = f"v {_SOURCE_SHORT[spec.sources['velocity'][j]]}, a " \
                  f"{_SOURCE_SHORT[spec.sources['acceleration'][j]]}"
        rows.append((escape(name), span, f"{box.velocity[j] * scale:.4g} {unit}/s",
                     f"{box.acceleration[j] * scale:.4g} {unit}/s^2", sources))
    return FittedTable("The spec: every state with q in these ranges, |qd| <= velocity, "
                       "|qdd| <= acceleration", columns, tuple(rows),
                       notes=("from: given (option or argument), file (the envelope file's "
                              "[limits]), robot (the robot file's velocity limit)",))


def states_text(result: EnvelopeResult) -> Paragraphs:
    """Each joint's worst states, to check with a motion through them (angles in degrees)."""
    lines = ["Worst states, each joint listed in the robot's order (q deg, qd deg/s, qdd "
             "deg/s^2; m for a prismatic joint); the stop decelerates at -qd / stop time from "
             "its state:"]
    revolute = np.array(result.robot.revolute)
    for joint in result.joints:
        for figure in ("peak", "static", "stop"):
            lines.append(_state_line(joint, joint.worst[figure], revolute))
    return Paragraphs(tuple(lines))


def _state_line(joint: JointEnvelope, state: WorstState, revolute: np.ndarray) -> str:
    scale = np.where(revolute, DEG_PER_RAD, 1.0)
    where = "" if state.source == "search" else f" ({state.source})"
    return (f"{joint.name} {state.figure} {state.torque:.4g} N m{where}: q = "
            f"{_vector(state.q * scale)}, qd = {_vector(state.qd * scale)}, qdd = "
            f"{_vector(state.qdd * scale)}")


def _vector(values: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.4g}" if abs(v) >= 5e-5 else "0" for v in values) + ")"


def note_lines(result: EnvelopeResult) -> list[str]:
    """What a reader must know under the units: the figures, the search, assumptions, flags."""
    settings = result.settings
    rounds = sorted({n for joint in result.joints for w in joint.convergence.by_demand.values()
                     for n, _ in w.by_starts})
    starts = " then ".join(f"{n:,}" for n in rounds[:2]) + (
        f" ({', '.join(f'{n:,}' for n in rounds[2:])} where those disagreed)"
        if len(rounds) > 2 else "")
    verdict_text = ("every worst value agrees within "
                    f"{settings.tolerance:.1%} (or {ABSOLUTE:g} N m) between the last two rounds"
                    if result.converged else "NOT CONVERGED: see below")
    notes = [f"peak: the largest |torque| while moving, at the worst vertex of the "
             f"acceleration box; static: the largest while the joint is held (speed and "
             f"acceleration 0) and the others move anywhere within the spec; stop: an emergency "
             f"stop within {result.sizing.options.stop_time:g} s from the worst state. The "
             f"crash (the unit's reflected inertia at full speed) is in the momentary rule.",
             f"search: {starts} quasi-random starts (Sobol, seed {settings.seed}), the "
             f"{settings.refine} best distinct of each round refined; {verdict_text}; carried "
             "masses " + (f"settled in {result.rounds} round{'s' if result.rounds > 1 else ''}"
                          if result.settled else "DID NOT SETTLE")
             + ". --json gives every state and count.",
             "duty alone: what `hdselect size` of the duty selects (the worst states left out)."]
    if any(joint.sizing.bearing is not None for joint in result.joints):
        notes.append(f"{BEARING_NOTE}. --json gives each joint's bearing loads.")
    if any(task.carried is not None for task in result.duty.tasks):
        notes.append(PARTS_NOTE + ".")
    notes += [f"{joint.name}: not converged: {joint.convergence.note}"
              for joint in result.joints if not joint.convergence.converged]
    notes += [line for joint in result.joints if joint.selected is None
              for found in [diagnosis_of(result.sizing, joint.name)] if found is not None
              for line in found.lines()]
    notes.append("Assumptions: " + "; ".join(f"{k}: {v}" for k, v in
                                             assumptions(result.sizing).items()))
    flagged = {(c.unit.id, flag.code): flag.note for joint in result.joints
               for c in [joint.selected] if c is not None for flag in c.flags}
    notes += [f"* {unit}: {note}" for (unit, _), note in sorted(flagged.items())]
    notes += list(result.sizing.warnings)
    loaded = [joint.name for joint in result.joints if joint.sizing.gravity_loaded]
    if loaded:
        notes.append(f"gravity: {', '.join(loaded)} carry gravity. Harmonic Drive gearing "
                     "backdrives when the input is free: where a falling load could injure, a "
                     "fail-safe device on the output is needed.")
    return notes
