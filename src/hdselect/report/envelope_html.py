"""The envelope's HTML page: the units for any motion within the spec, the worst states, the search.

One self-contained page (no script, no external request). In a report directory the
duty's own sizing report (`hdselect.report.report_files`) sits beside it in ``duty/``,
linked from the page.
"""

from __future__ import annotations

import html
import shlex
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from hdselect.base.errors import InputError
from hdselect.envelope.result import EnvelopeResult
from hdselect.report.envelope_tables import note_lines, shortfall_cell
from hdselect.report.provenance import Provenance, provenance
from hdselect.report.terminal import DEG_PER_RAD, life_text, utilization_text
from hdselect.sizing.records import base_text

esc = html.escape

_STYLE = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;max-width:1200px;
margin:1.5em auto;padding:0 1em;color:#1a1a1a;line-height:1.4}
h1{font-size:1.5em}h2{font-size:1.25em;margin-top:1.6em;border-bottom:1px solid #ccc}
.scroll{overflow-x:auto}table{border-collapse:collapse;margin:.4em 0;font-size:.9em}
td,th{border:1px solid #bbb;padding:2px 6px;text-align:right;white-space:nowrap}
th{background:#eee}td.t,th.t{text-align:left}td.fail{font-weight:bold;color:#7f3b08}
code,pre{font-family:ui-monospace,Menlo,Consolas,monospace;font-size:.85em}
pre{background:#f4f4f4;padding:.5em;white-space:pre-wrap;word-break:break-all}
"""


def envelope_page(result: EnvelopeResult, origin: Provenance, *, duty_report: bool) -> str:
    """The page.

    Args:
        result: The envelope.
        origin: Where it came from (the command, the software, the input files).
        duty_report: The duty's own report sits in ``duty/`` beside the page (link it).

    Returns:
        The page, self-contained.
    """
    verdict_text = ("Every joint has a unit that holds for any motion within the spec."
                    if result.feasible else "<strong>Some joints have no unit.</strong>")
    link = (' (<a href="duty/index.html">its own report</a>)' if duty_report else "")
    sections = [
        f"<h2>Units</h2>{_units(result)}",
        f"<h2>The spec</h2>{_spec(result)}",
        "<h2>Worst states</h2><p>Each state lists every joint in the robot's order (q deg, "
        "qd deg/s, qdd deg/s²; m for a prismatic joint). The stop decelerates at -qd / stop "
        f"time from its state.</p>{_states(result)}",
        f"<h2>Search</h2>{_search(result)}",
        "<h2>Notes</h2>" + "".join(f"<p>{esc(line)}</p>" for line in note_lines(result)),
        _origin(origin)]
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>hdselect envelope: {esc(result.robot.path.name)}</title>
<style>{_STYLE}</style></head><body>
<h1>Envelope: {esc(result.robot.path.name)}, any motion within the spec</h1>
<p>{verdict_text} Mean torque and life are judged on {esc(result.duty.phrase)}{link}.
Made by hdselect {esc(origin.version)} on {esc(origin.created)}.</p>
<p>{esc(base_text(result.robot))}</p>
{"".join(sections)}
</body></html>
"""


def write_envelope_report(directory: Path, result: EnvelopeResult, *,
                          command: Sequence[str] | None = None) -> None:
    """The page and the duty's own report into an existing (staging) directory.

    Raises:
        InputError: A file cannot be written.
    """
    from hdselect.report.report_files import report_files

    duty = directory / "duty"
    try:
        duty.mkdir()
        report_files(duty, result.duty_sizing, command=command)
        page = envelope_page(result, provenance(result.sizing, command), duty_report=True)
        (directory / "index.html").write_text(page, encoding="utf-8")
    except OSError as err:
        raise InputError(f"cannot write the report ({err.strerror})", path=directory,
                         field="--report") from err


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], left: int = 1) -> str:
    head = "".join(f"<th{' class=t' if i < left else ''}>{h}</th>" for i, h in enumerate(header))
    body = "".join("<tr>" + "".join(c if c.startswith("<td") else
                                    f"<td{' class=t' if i < left else ''}>{c}</td>"
                                    for i, c in enumerate(row)) + "</tr>" for row in rows)
    return f'<div class="scroll"><table><tr>{head}</tr>{body}</table></div>'


def _units(result: EnvelopeResult) -> str:
    rows = []
    for joint in result.joints:
        chosen = joint.selected
        torques = [f"{abs(joint.worst[f].torque):.4g}" for f in ("peak", "static", "stop")]
        duty = esc(joint.duty.unit.id) if joint.duty is not None else "none"
        if chosen is None:
            rows.append([esc(joint.name), '<td class="t fail">none</td>',
                         f'<td class="t fail">{esc(shortfall_cell(result, joint))}</td>',
                         *torques, "-", "yes" if joint.convergence.converged else "no", duty])
            continue
        check = chosen.checks[chosen.binding]
        rows.append([esc(joint.name), esc(chosen.unit.id),
                     f"{esc(chosen.binding)} {utilization_text(check.utilization, True)}",
                     *torques, life_text(chosen.life_hours),
                     "yes" if joint.convergence.converged else "no", duty])
    return _table(["joint", "unit", "binding", "peak [N m]", "static [N m]", "stop [N m]",
                   "L50 life", "converged", "duty alone"], rows, left=3)


def _spec(result: EnvelopeResult) -> str:
    box, spec = result.spec.box, result.spec
    rows = []
    for j, name in enumerate(box.joint_names):
        scale, unit = (DEG_PER_RAD, "deg") if result.robot.revolute[j] else (1.0, "m")
        rows.append([esc(name), f"{box.lower[j] * scale:.4g} .. {box.upper[j] * scale:.4g} {unit}",
                     f"{box.velocity[j] * scale:.4g} {unit}/s",
                     f"{box.acceleration[j] * scale:.4g} {unit}/s²",
                     f"{spec.jerk[j] * scale:.4g} {unit}/s³",
                     f"v: {spec.sources['velocity'][j]}, a: {spec.sources['acceleration'][j]}"])
    return _table(["joint", "range", "velocity", "acceleration", "duty's jerk", "from"], rows)


def _states(result: EnvelopeResult) -> str:
    scale = np.where(result.robot.revolute, DEG_PER_RAD, 1.0)
    rows = []
    for joint in result.joints:
        for state in (*joint.worst.values(), joint.gravity):
            rows.append([esc(joint.name), state.figure, f"{state.torque:.6g}", esc(state.source),
                         *(f"<code>{_vector(v * scale)}</code>" for v in
                           (state.q, state.qd, state.qdd))])
    return _table(["joint", "figure", "torque [N m]", "source", "q", "qd", "qdd"], rows,
                  left=2)


def _search(result: EnvelopeResult) -> str:
    rows = []
    for joint in result.joints:
        for kind, worst in joint.convergence.by_demand.items():
            history = "; ".join(f"{n:,}: {value:.6g}" for n, value in worst.by_starts)
            rows.append([esc(joint.name), kind, f"{worst.value:.6g}", history,
                         "yes" if worst.converged else '<td class="fail">no</td>'])
    settings = result.settings
    return (f"<p>{settings.starts:,} quasi-random starts (Sobol, seed {settings.seed}), then "
            f"four times more each round until two rounds agree within "
            f"{settings.tolerance:.1%}; the {settings.refine} best distinct starts of each round "
            f"refined by batched BFGS. {result.states:,} states evaluated in "
            f"{result.seconds:.1f} s ({esc(result.executor)}); carried masses "
            + ("settled" if result.settled else "<strong>did not settle</strong>")
            + f" after {result.rounds} full search{'es' if result.rounds > 1 else ''}.</p>"
            + _table(["joint", "demand", "worst [N m]", "worst by starts", "converged"], rows,
                     left=2))


def _origin(origin: Provenance) -> str:
    run = ("<p>Made through the Python API.</p>" if origin.command is None else
           "<p>Re-run it in the directory it ran in:</p>"
           f"<pre>{esc(shlex.join(origin.command))}</pre>")
    software = ", ".join(f"{name} {version}" for name, version in origin.software)
    return f"<h2 id=provenance>Provenance</h2>{run}<p>{esc(software)}</p>"


def _vector(values: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.4g}" if abs(v) >= 5e-5 else "0" for v in values) + ")"
