"""A command's outputs and exit status.

Files are reserved and committed together, tables rendered before anything is
written, and the files written are named.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hdselect.cli.inputs import input_files

EXIT_OK, EXIT_NO_FIT, EXIT_BAD_INPUT, EXIT_CASES_FAILED, EXIT_BUG = 0, 1, 2, 3, 70
"""Exit statuses: success (every joint has a unit); some joint has none; bad input; some
case of a study failed (its row says why); a bug in hdselect (70, EX_SOFTWARE of
sysexits.h). Interrupted runs exit 130 (Ctrl-C) or 143 (SIGTERM): `EXIT_INTERRUPTED`,
`EXIT_TERMINATED` of `hdselect.base.session`."""


class reserved_outputs:
    """The outputs of ``size`` and ``compare`` reserved: (Outputs, JSON file, report target).

    The report target is a staging directory, or a file for ``--report -`` (the page alone).
    """

    def __init__(self, args: argparse.Namespace, robot, motion) -> None:
        from hdselect.base.outputs import Outputs

        inputs = [*input_files(robot, motion), *args.catalog,
                  *([args.motor_catalog] if args.motor_catalog else [])]
        self.outputs = Outputs(inputs)
        self.args = args

    def __enter__(self):
        args, outputs = self.args, self.outputs
        try:
            json_file = outputs.file(args.json, "--json") if args.json is not None else None
            report = None
            if args.report == "-":
                report = outputs.file("-", "--report")
            elif args.report is not None:
                report = outputs.directory(args.report, "--report")
        except BaseException:
            outputs.discard()
            raise
        return outputs, json_file, report

    def __exit__(self, *exc: object) -> None:
        self.outputs.discard()


def write_report_and_json(args: argparse.Namespace, result, json_file: Path | None,
                   report: Path | None) -> None:
    """The report and the JSON a command was asked for, into their staged places."""
    from hdselect.report.export import write_json
    from hdselect.sizing.records import size_json

    if report is not None:
        from hdselect.report.report_files import report_files, report_page

        if args.report == "-":
            report.write_text(report_page(result, command=args.command_line),
                              encoding="utf-8")
        else:
            report_files(report, result, command=args.command_line)
    if json_file is not None:
        write_json(json_file, size_json(result))


def to_stdout(args: argparse.Namespace) -> bool:
    """An output goes to standard output (``-``): then no table is printed there."""
    return "-" in (getattr(args, name, None) for name in ("json", "report", "out", "plot",
                                                          "bom"))


def reserve_parts(outputs, args: argparse.Namespace) -> Path | None:
    """The staged place of the parts list (``--bom``), reserved before the work; or None."""
    return outputs.file(args.bom, "--bom") if getattr(args, "bom", None) else None


def write_parts(target: Path | None, result) -> None:
    """The parts list into its staged place, if one was reserved."""
    if target is not None:
        from hdselect.report.parts import parts_csv

        target.write_text(parts_csv(result), encoding="utf-8")


def report_and_json(args: argparse.Namespace) -> list[tuple[str | None, str | None]]:
    """The report's page and the JSON file, as `say_written` names them."""
    report = args.report if args.report in (None, "-") else str(Path(args.report) / "index.html")
    return [(report, "the report, figures embedded (also as PNG files beside it)"
             if args.report != "-" else None), (args.json, None),
            (getattr(args, "bom", None), "the parts list")]


def say_written(written: Sequence[tuple[str | None, str | None]],
                 args: argparse.Namespace) -> None:
    """Name the files written, on standard error when standard output carries an output."""
    from hdselect.report.tables import Paragraphs, console_for

    lines = [f"wrote {path}" + (f": {what}" if what else "") for path, what in written
             if path is not None and path != "-"]
    if lines:
        console_for(sys.stderr if to_stdout(args) else sys.stdout).print(
            Paragraphs(tuple(lines)))


def rendered(*items: Any) -> str:
    """Renderables as standard output would show them, rendered before any output is committed.

    Rendering first means a failure while formatting leaves no output behind.
    """
    import io

    from hdselect.report.tables import console_for

    real = console_for(sys.stdout)
    if sys.stdout.isatty():  # its width and colours, captured
        with real.capture() as captured:
            for item in items:
                real.print(item)
        return captured.get()
    buffer = io.StringIO()
    out = console_for(buffer)  # COLUMNS or 80, no colour, no trailing spaces
    for item in items:
        out.print(item)
    out.file.flush()
    return buffer.getvalue()



def gear_torques(check):
    """The output torque of every joint (n, dof) as the gears carry it; 0 where unsized.

    Args:
        check: A sizing result (`hdselect.check_units`): with mass coupling, its torques
            carry the units' and motors' masses [N m].
    """
    import numpy as np

    tau = np.zeros_like(check.trajectory.q)
    for joint in check.joints:
        tau[:, check.robot.joint_index(joint.name)] = joint.torque
    return tau


def torques_note(check) -> str:
    """What the ``tau_`` columns of a trajectory CSV carry, for the line naming the file.

    Args:
        check: The units checked along the trajectory (`hdselect.check_units`), or None:
            the robot's own inverse dynamics.
    """
    if check is None:
        return "tau_ without gearhead or motor masses (--units adds them)"
    if not check.options.mass_coupling:
        return "tau_ without gearhead or motor masses (--no-mass-coupling)"
    carried = ", ".join(
        f"{joint.name} {c.unit.id}" + (f" + {c.motor_unit.id}" if c.motor_unit else "")
        for joint, c in ((joint, joint.candidates[0]) for joint in check.joints))
    return f"tau_ carrying the masses of the units ({carried}), as size computes it"
