"""Command line: a thin layer over the public API; it formats, it does not compute."""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import traceback
import warnings
from collections.abc import Sequence

from hdselect import __version__
from hdselect.base.errors import HdselectError
from hdselect.base.outputs import check_output_path
from hdselect.base.session import HeldLog, Terminated, handle_sigterm, tolerate_encoding
from hdselect.cli.catalog import run_catalog, run_duty
from hdselect.cli.codesign import run_fastest, run_max_payload
from hdselect.cli.envelope import envelope_arguments, run_envelope
from hdselect.cli.inputs import (
    catalog_argument,
    json_argument,
    margin_argument,
    robot_motion_arguments,
    sizing_arguments,
    xacro_argument,
)
from hdselect.cli.output import EXIT_BAD_INPUT, EXIT_BUG, EXIT_INTERRUPTED, EXIT_OK, EXIT_TERMINATED
from hdselect.cli.plan import run_plan
from hdselect.cli.robot import run_init, run_joints
from hdselect.cli.size import run_compare, run_size
from hdselect.cli.study import run_study

logger = logging.getLogger("hdselect")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``hdselect`` command.

    Returns:
        Exit status: 0 success, 1 no gearhead fits, 2 bad input (one line on standard
        error, no output), 3 some case of a study failed, 70 a bug in hdselect (one
        line; ``-v`` shows the traceback), 130 interrupted (Ctrl-C), 143 terminated
        (SIGTERM).
    """
    previous = handle_sigterm()
    held = HeldLog(logger)
    kept = _Kept()
    try:
        tolerate_encoding()
        parser = _parser()
        argv = list(sys.argv[1:] if argv is None else argv)
        args = parser.parse_args(argv)
        args.command_line = ["hdselect", *argv]
        args.kept, args.held = kept, held
        held.start(verbose=args.verbose)
        # Python's and numpy's warnings too are held: a refusal stays one line (the
        # filters in force still apply; only where they print changes)
        with warnings.catch_warnings(record=True) as caught:
            status = int(args.run(args))
        held.publish()
        for text in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught):
            _say(f"warning: {_one_line(text)}")
        return status
    except HdselectError as err:
        _say(f"error: {_one_line(str(err))}")
        return EXIT_BAD_INPUT
    except MemoryError:
        _say("error: out of memory; use a larger dt, a shorter cycle or a lower --max-samples")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        _say(f"interrupted; {kept.text()}")
        return EXIT_INTERRUPTED
    except Terminated:
        _say(f"terminated; {kept.text()}")
        return EXIT_TERMINATED
    except BrokenPipeError:
        # The reader went away (e.g. `| head`): not an error of ours.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except Exception as err:  # a bug: say so in one line, with the way to the traceback
        if held.verbose:
            traceback.print_exc()
        _say(f"internal error (a bug in hdselect, not in your input): {type(err).__name__}: "
             f"{_one_line(str(err))}; no output was written; run again with -v for the "
             "traceback")
        return EXIT_BUG
    finally:
        held.stop()
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


class _Kept:
    """What an interrupted command leaves behind: nothing, except a study's finished cases."""

    def __init__(self) -> None:
        self.note: str | None = None

    def text(self) -> str:
        return self.note or "no output was written"


def _say(message: str) -> None:
    print(f"hdselect: {message}", file=sys.stderr)


def _one_line(text: str) -> str:
    return " ".join(text.split())


_OUTPUTS = ("json", "report", "bom", "out", "plot", "waypoints", "line_errors")
"""Options naming an output: an empty one is refused in the words of every output's check
(`hdselect.base.outputs.check_output_path`)."""


class _Parser(argparse.ArgumentParser):
    """Command-line errors as one line, like every other error, with exit status 2."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def parse_known_args(self, args=None, namespace=None):  # type: ignore[override]
        """Parse, then refuse an empty value of any option or argument.

        An empty value never means "not given" (``--velocity ''`` fell back to a default).
        """
        parsed, extra = super().parse_known_args(args, namespace)
        for action in self._actions:
            if action.nargs == 0 or isinstance(action, argparse._SubParsersAction):
                continue
            value = getattr(parsed, action.dest, None)
            if any(isinstance(item, str) and not item.strip()
                   for item in (value if isinstance(value, list) else [value])):
                name = max(action.option_strings, key=len, default=action.metavar
                           or action.dest)
                if action.dest in _OUTPUTS:  # an output's own words
                    check_output_path("", name, directory=action.dest == "report")
                self.error(f"argument {name}: expected a value, got an empty string")
        return parsed, extra


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="hdselect",
        description="Size Harmonic Drive PSA-G gearheads for robot joints.")
    parser.add_argument("--version", action="version", version=f"hdselect {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="print progress notes")
    verbose = _Parser(add_help=False)  # -v after the command too
    verbose.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                         help="print progress notes")
    commands = parser.add_subparsers(title="commands", required=True, metavar="COMMAND",
                                     parser_class=_Parser)

    catalog = commands.add_parser("catalog", parents=[verbose],
                                  help="list the gearhead catalog")
    catalog_argument(catalog)
    catalog.add_argument("--units", choices=("si", "imperial"), default="si",
                         help="unit system of the table (default: si)")
    catalog.add_argument("--json", action="store_true", help="print JSON instead of a table")
    catalog.set_defaults(run=run_catalog)

    duty = commands.add_parser(
        "duty", parents=[verbose], help="size from a torque-speed profile (catalog method)")
    duty.add_argument("profile", help="duty-cycle profile (TOML)")
    catalog_argument(duty)
    margin_argument(duty)
    json_argument(duty)
    duty.set_defaults(run=run_duty)

    plan = commands.add_parser(
        "plan", parents=[verbose], help="plan a motion and write its torques (CSV)")
    robot_motion_arguments(plan, sizes=False)
    plan.add_argument("--out", metavar="FILE", required=True,
                      help="CSV: t, then q_, qd_, qdd_, tau_ per joint (SI)")
    plan.add_argument("--plot", metavar="PNG", help="speed and torque profiles per joint")
    plan.add_argument("--waypoints", metavar="FILE",
                      help="CSV of the joint path as solved: every waypoint and line sample "
                           "(tool poses solved for the mounting), with the tool's pose error")
    plan.add_argument("--line-errors", metavar="FILE",
                      help="CSV of every planned sample on a straight line: the tool's distance "
                           "and angle from the line")
    plan.set_defaults(run=run_plan)

    size = commands.add_parser(
        "size", parents=[verbose], help="choose a gearhead for every joint of a robot")
    robot_motion_arguments(size)
    sizing_arguments(size)
    json_argument(size)
    size.add_argument("--report", metavar="DIR",
                      help="write an HTML report with figures into DIR ('-': the page alone, "
                           "to stdout)")
    size.add_argument("--bom", metavar="CSV",
                      help="write the parts list: per joint the gearhead and motor, ratio, "
                           "masses, binding rule and margin, then the totals ('-': to stdout)")
    size.set_defaults(run=run_size)

    compare = commands.add_parser(
        "compare", parents=[verbose], help="every unit against every joint, side by side")
    robot_motion_arguments(compare)
    sizing_arguments(compare)
    compare.add_argument("--joint", action="append", metavar="NAME",
                         help="show only this joint (repeatable)")
    json_argument(compare)
    compare.add_argument("--report", metavar="DIR",
                         help="write an HTML report of the joints shown into DIR ('-': the "
                              "page alone, to stdout)")
    compare.add_argument("--bom", metavar="CSV",
                         help="write the parts list of the selection, every joint (as size "
                              "--bom; '-': to stdout)")
    compare.set_defaults(run=run_compare)

    fastest = commands.add_parser(
        "fastest", parents=[verbose],
        help="the shortest cycle of the motion's path that the gearheads allow")
    robot_motion_arguments(fastest)
    sizing_arguments(fastest)
    fastest.add_argument("--units", action="append", metavar="JOINT=UNIT", default=[],
                         help="the unit of a joint, as `hdselect catalog` names it (repeatable; "
                              "default: the unit `size` selects)")
    fastest.add_argument("--compare-ratios", action="store_true",
                         help="the shortest cycle with every catalog unit on each joint, the "
                              "others fixed")
    fastest.add_argument("--joint", action="append", metavar="NAME",
                         help="with --compare-ratios: compare this joint only (repeatable)")
    fastest.add_argument("--out", metavar="FILE",
                         help="CSV of the fastest trajectory: t, then q_, qd_, qdd_, tau_ per "
                              "sized joint (SI)")
    fastest.add_argument("--plot", metavar="PNG",
                         help="speed and torque per joint; with --compare-ratios, cycle time "
                              "against unit")
    json_argument(fastest)
    fastest.set_defaults(run=run_fastest)

    payload = commands.add_parser(
        "max-payload", parents=[verbose],
        help="the largest payload with a feasible unit on every joint")
    robot_motion_arguments(payload, mass=False)
    payload.add_argument("--task", action="append", metavar="NAME",
                         help="with a mix file: scale this task's payload (repeatable; default: "
                              "every task that carries one)")
    sizing_arguments(payload)
    payload.add_argument("--units", action="append", metavar="JOINT=UNIT", default=[],
                         help="a fixed unit for a joint, as `hdselect catalog` names it "
                              "(repeatable; give every sized joint one; default: the unit "
                              "`size` selects at each payload)")
    json_argument(payload)
    payload.set_defaults(run=run_max_payload)

    spec = commands.add_parser(
        "envelope", parents=[verbose],
        help="a gearhead for every joint that holds for any motion within a spec")
    envelope_arguments(spec)
    spec.set_defaults(run=run_envelope)

    joints = commands.add_parser("joints", parents=[verbose],
                                  help="list a robot's joints in the order lists use")
    joints.add_argument("robot", metavar="ROBOT", help="robot file, URDF, xacro or MJCF")
    xacro_argument(joints)
    json_argument(joints)
    joints.set_defaults(run=run_joints)

    init = commands.add_parser("init", parents=[verbose],
                                help="write a starter motion file for a robot")
    init.add_argument("robot", metavar="ROBOT", help="robot file, URDF, xacro or MJCF")
    xacro_argument(init)
    init.add_argument("--out", metavar="FILE",
                      help="the motion file to write (default or '-': print it); an existing "
                           "file is never overwritten")
    init.add_argument("--tool-poses", action="store_true",
                      help="write the waypoints as tool poses in the world (solved for the "
                           "mounting by inverse kinematics), not as joint positions")
    init.set_defaults(run=run_init)

    study = commands.add_parser("study", parents=[verbose],
                                help="run every case of a design study (TOML)")
    study.add_argument("study", metavar="STUDY", help="study file (TOML)")
    study.add_argument("--out", metavar="CSV", required=True,
                       help="rows, one per case and joint, appended as cases complete; a JSON "
                            "Lines record of each case is kept beside it (same name, .jsonl); "
                            "cases already there are skipped")
    study.add_argument("--workers", type=int, metavar="N",
                       help="worker processes (default: the cores here; 0: in this process); "
                            "with --scheduler local, Dask workers")
    study.add_argument("--scheduler", metavar="ADDRESS",
                       help="'local': a Dask LocalCluster on this machine; tcp://HOST:PORT: a "
                            "running Dask scheduler (needs pip install 'hdselect[dask]')")
    study.add_argument("--no-grouping", action="store_true",
                       help="size every case on its own, not from its group's shared basis")
    study.add_argument("--retry-failed", action="store_true",
                       help="run again the cases recorded as failed")
    study.add_argument("--plot", metavar="PNG",
                       help="draw the unit selected and its life per joint against the first "
                            "varied parameters")
    study.set_defaults(run=run_study)
    return parser
