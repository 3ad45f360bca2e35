"""Command line: a thin layer over the public API; it formats, it does not compute."""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hdselect import __version__
from hdselect.bounds import DEFAULT_MAX_SAMPLES
from hdselect.errors import HdselectError, InputError
from hdselect.session import HeldLog, Terminated, handle_sigterm, tolerate_encoding

logger = logging.getLogger("hdselect")


EXIT_OK, EXIT_NO_FIT, EXIT_BAD_INPUT, EXIT_CASES_FAILED, EXIT_BUG = 0, 1, 2, 3, 70
"""Exit statuses: success (every joint has a unit); some joint has none; bad input; some
case of a study failed (its row says why); a bug in hdselect (70, EX_SOFTWARE of
sysexits.h). Interrupted runs exit 130 (Ctrl-C) or 143 (SIGTERM)."""
EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143


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
        status = int(args.run(args))
        held.publish()
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


class _Parser(argparse.ArgumentParser):
    """Command-line errors as one line, like every other error, with exit status 2."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


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
    _catalog_option(catalog)
    catalog.add_argument("--units", choices=("si", "imperial"), default="si",
                         help="unit system of the table (default: si)")
    catalog.add_argument("--json", action="store_true", help="print JSON instead of a table")
    catalog.set_defaults(run=run_catalog)

    duty = commands.add_parser(
        "duty", parents=[verbose], help="size from a torque-speed profile (catalog method)")
    duty.add_argument("profile", help="duty-cycle profile (TOML)")
    _catalog_option(duty)
    _json_option(duty)
    duty.set_defaults(run=run_duty)

    plan = commands.add_parser(
        "plan", parents=[verbose], help="plan a motion and write its torques (CSV)")
    _robot_motion(plan)
    plan.add_argument("--out", metavar="FILE", required=True,
                      help="CSV: t, then q_, qd_, qdd_, tau_ per joint (SI)")
    plan.add_argument("--plot", metavar="PNG", help="speed and torque profiles per joint")
    plan.set_defaults(run=run_plan)

    size = commands.add_parser(
        "size", parents=[verbose], help="choose a gearhead for every joint of a robot")
    _robot_motion(size)
    _sizing_options(size)
    _json_option(size)
    size.add_argument("--report", metavar="DIR",
                      help="write an HTML report with figures into DIR ('-': the page alone, "
                           "to stdout)")
    size.set_defaults(run=run_size)

    compare = commands.add_parser(
        "compare", parents=[verbose], help="every unit against every joint, side by side")
    _robot_motion(compare)
    _sizing_options(compare)
    compare.add_argument("--joint", action="append", metavar="NAME",
                         help="show only this joint (repeatable)")
    _json_option(compare)
    compare.add_argument("--report", metavar="DIR",
                         help="write an HTML report of the joints shown into DIR ('-': the "
                              "page alone, to stdout)")
    compare.set_defaults(run=run_compare)

    fastest = commands.add_parser(
        "fastest", parents=[verbose],
        help="the shortest cycle of the motion's path that the gearheads allow")
    _robot_motion(fastest)
    _sizing_options(fastest)
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
    _json_option(fastest)
    fastest.set_defaults(run=run_fastest)

    payload = commands.add_parser(
        "max-payload", parents=[verbose],
        help="the largest payload with a feasible unit on every joint")
    _robot_motion(payload, mass=False)
    _sizing_options(payload)
    _json_option(payload)
    payload.set_defaults(run=run_max_payload)

    joints = commands.add_parser("joints", parents=[verbose],
                                  help="list a robot's joints in the order lists use")
    joints.add_argument("robot", metavar="ROBOT", help="robot file, URDF or MJCF")
    _json_option(joints)
    joints.set_defaults(run=run_joints)

    init = commands.add_parser("init", parents=[verbose],
                                help="write a starter motion file for a robot")
    init.add_argument("robot", metavar="ROBOT", help="robot file, URDF or MJCF")
    init.add_argument("--out", metavar="FILE",
                      help="the motion file to write (default or '-': print it); an existing "
                           "file is never overwritten")
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


def _catalog_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog file (TOML; repeatable)")


def _json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", metavar="FILE",
                        help="also write JSON to FILE ('-': to stdout, instead of the table)")


def _robot_motion(parser: argparse.ArgumentParser, *, mass: bool = True) -> None:
    parser.add_argument("robot", nargs="?", metavar="ROBOT",
                        help="robot file, URDF or MJCF (default: the motion file's `robot`)")
    parser.add_argument("motion", metavar="MOTION", help="motion file (TOML)")
    if mass:
        parser.add_argument("--payload", type=float, metavar="KG",
                            help="payload mass [kg]; the motion file's payload keeps its centre "
                                 "of mass, inertia and frame")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="payload centre of mass in its frame [m] (changes the motion "
                             "file's payload, or the one --payload gives)")
    parser.add_argument("--payload-frame", metavar="LINK",
                        help="link carrying the payload (default: the motion file's, else the "
                             "tip of the longest chain of sized joints)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")
    parser.add_argument("--joints", metavar="A,B", action="append",
                        help="size only these joints (comma-separated; overrides the motion "
                             "file's [sizing] joints)")
    parser.add_argument("--exclude", metavar="A,B", action="append",
                        help="do not size these joints; they still move and load the others "
                             "(overrides the motion file's [sizing] exclude)")
    parser.add_argument("--max-samples", type=int, metavar="N",
                        default=DEFAULT_MAX_SAMPLES,
                        help="refuse a trajectory of more samples than this, before allocating "
                             f"it (default {DEFAULT_MAX_SAMPLES:,}: an 8-hour log at 1 kHz)")


def _sizing_options(parser: argparse.ArgumentParser) -> None:
    from hdselect.motion import LIFE_BASES
    from hdselect.options import Options
    from hdselect.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, PREFERENCES

    defaults = Options()
    _catalog_option(parser)
    parser.add_argument("--stop-time", type=float, metavar="S",
                        help="emergency-stop and crash time [s] (default: the motion file's "
                             f"[safety] stop_time, else {defaults.stop_time:g})")
    parser.add_argument("--efficiency", type=float,
                        help=f"gear efficiency where a unit has no table (default "
                             f"{defaults.efficiency:g})")
    parser.add_argument("--motor-inertia", type=float, metavar="KG_M2",
                        help="motor rotor inertia [kg m^2] where no motor data is given "
                             "(default 0)")
    parser.add_argument("--motor-mass", type=float, metavar="KG",
                        help="motor mass carried with each gearhead [kg] where no motor data "
                             "is given (default 0)")
    parser.add_argument("--motor-catalog", metavar="FILE",
                        help="motor file (TOML): every sized joint chooses its motor from it, "
                             "with its gearhead (replaces the motion file's [motor])")
    parser.add_argument("--no-mass-coupling", action="store_true",
                        help="do not carry chosen units' masses on the joints nearer the base")
    parser.add_argument("--prefer", choices=tuple(PREFERENCES),
                        help="; ".join(f"{k}: {v[0]}" for k, v in PREFERENCES.items())
                        + f" (default: {DEFAULT_PREFER_WITH_MOTORS} where motors are given, "
                          f"else {DEFAULT_PREFER})")
    parser.add_argument("--life-hours", type=float, metavar="H",
                        help="required life [h] (default: the motion file's requirement)")
    parser.add_argument("--life-basis", choices=LIFE_BASES,
                        help="basis of the required life: L50, average life, or L10, 90 %% "
                             "survive it (default: the motion file's, else L50)")


_OPTION_FLAGS = {"stop_time": "--stop-time", "efficiency": "--efficiency",
                 "rotor_inertia": "--motor-inertia", "motor_mass": "--motor-mass",
                 "prefer": "--prefer", "life_hours": "--life-hours",
                 "life_basis": "--life-basis", "max_samples": "--max-samples"}
"""The command-line option of each field of `hdselect.options.Options`."""


def run_catalog(args: argparse.Namespace) -> int:
    """``hdselect catalog``: print the catalog."""
    from hdselect.catalog import load_catalog
    from hdselect.export import catalog_json, write_json
    from hdselect.report import catalog_table

    units = load_catalog(args.catalog)
    if args.json:
        write_json("-", catalog_json(units))
    else:
        sys.stdout.write(_rendered(catalog_table(units, imperial=args.units == "imperial")))
    return EXIT_OK


def run_duty(args: argparse.Namespace) -> int:
    """``hdselect duty``: the catalog's torque-speed method for one joint."""
    from hdselect.catalog import load_catalog
    from hdselect.duty import load_duty, size_duty
    from hdselect.export import duty_json, write_json
    from hdselect.outputs import Outputs
    from hdselect.report import duty_table

    units = load_catalog(args.catalog)
    cycle = load_duty(args.profile)
    with Outputs([args.profile, *args.catalog]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        result = size_duty(cycle, units)
        if json_file is not None:
            write_json(json_file, duty_json(result))
        table = _rendered(duty_table(result)) if args.json != "-" else ""
        outputs.commit()
    sys.stdout.write(table)
    _say_written([(args.json, None)], args)
    return EXIT_OK if result.selected is not None else EXIT_NO_FIT


def run_plan(args: argparse.Namespace) -> int:
    """``hdselect plan``: the trajectory and the torques along it, as CSV (and a plot)."""
    from hdselect.dynamics import inverse_dynamics
    from hdselect.export import write_trajectory_csv
    from hdselect.outputs import Outputs
    from hdselect.planning import plan
    from hdselect.report import plan_text

    robot, motion = _load_case(args)
    max_samples = _max_samples(args)
    with Outputs(_inputs(robot, motion)) as outputs:
        out = outputs.file(args.out, "--out")
        figure = outputs.file(args.plot, "--plot") if args.plot else None
        trajectory = plan(robot, motion, max_samples=max_samples)
        tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
        write_trajectory_csv(out, trajectory, tau, robot.joint_names)
        if figure is not None:
            from hdselect.figures import write_profiles_png

            write_profiles_png(figure, trajectory, tau, robot.sized_joints,
                               title=f"{robot.path.name} running {motion.path.name}")
        text = "" if _to_stdout(args) else _rendered(plan_text(robot, motion, trajectory))
        outputs.commit()
    sys.stdout.write(text)
    _say_written([(args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(robot.joint_names)} "
                             "(SI)"),
                  (args.plot, "speed and torque of each joint over the cycle")], args)
    return EXIT_OK


def run_size(args: argparse.Namespace) -> int:
    """``hdselect size``: a gearhead for every joint."""
    from hdselect.report import loads_table, size_table

    robot, motion, units, options, motors = _prepare(args)
    with _outputs(args, robot, motion) as (outputs, json_file, report):
        result = _sized(robot, motion, units, options, motors)
        _write_outputs(args, result, json_file, report)
        table = "" if _to_stdout(args) else _rendered(size_table(result), "",
                                                      loads_table(result))
        outputs.commit()
    args.held.shown(_SHOWN)  # the table, the JSON and the report list them
    sys.stdout.write(table)
    _say_written(_report_and_json(args), args)
    return EXIT_OK if result.feasible else EXIT_NO_FIT


def run_compare(args: argparse.Namespace) -> int:
    """``hdselect compare``: every unit against every joint."""
    from dataclasses import replace

    from hdselect.report import compare_table

    robot, motion, units, options, motors = _prepare(args)
    for name in args.joint or []:
        if name not in robot.sized_joints:
            raise InputError(f"unknown joint '{name}'; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field="--joint")
    with _outputs(args, robot, motion) as (outputs, json_file, report):
        result = _sized(robot, motion, units, options, motors)
        shown = replace(result, joints=tuple(joint for joint in result.joints
                                             if not args.joint or joint.name in args.joint))
        _write_outputs(args, shown, json_file, report)
        tables: list[Any] = []
        for joint in shown.joints:
            tables += [""] if tables else []
            tables.append(compare_table(result, joint))
        text = "" if _to_stdout(args) else _rendered(*tables)
        outputs.commit()
    sys.stdout.write(text)
    _say_written(_report_and_json(args), args)
    return EXIT_OK if result.feasible else EXIT_NO_FIT


def run_fastest(args: argparse.Namespace) -> int:
    """``hdselect fastest``: the shortest cycle the units allow, or every unit compared."""
    from hdselect.catalog import load_catalog
    from hdselect.codesign import compare_ratios, fastest
    from hdselect.export import fastest_json, ratios_json, write_json, write_trajectory_csv
    from hdselect.outputs import Outputs
    from hdselect.report import binding_table, fastest_table, ratios_table

    if args.joint and not args.compare_ratios:
        raise InputError("only with --compare-ratios", field="--joint")
    robot, motion = _load_case(args)
    options = _options(args, motion)
    units = load_catalog(args.catalog)
    given = _unit_pairs(args.units)
    with Outputs([*_inputs(robot, motion), *args.catalog]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        csv_file = outputs.file(args.out, "--out") if args.out else None
        figure = outputs.file(args.plot, "--plot") if args.plot else None
        try:
            if args.compare_ratios:
                comparison = compare_ratios(robot, motion, given, options, catalog=units,
                                            joints=args.joint)
                result = comparison.base
            else:
                result = fastest(robot, motion, given, options, catalog=units)
        except InputError as err:
            field = {"units": "--units", "joint": "--joint"}.get(str(err.field), err.field)
            raise InputError(err.reason, path=err.path, field=field) from err
        if figure is not None:
            from hdselect.figures import write_fastest_png, write_ratios_png

            if args.compare_ratios:
                write_ratios_png(figure, comparison)
            else:
                write_fastest_png(figure, result)
        if csv_file is not None:
            write_trajectory_csv(csv_file, result.trajectory, _gear_torques(result),
                                 result.robot.sized_joints)
        if json_file is not None:
            write_json(json_file, ratios_json(comparison) if args.compare_ratios
                       else fastest_json(result))
        tables: list[Any] = []
        if args.compare_ratios:
            for joint in comparison.joints:
                tables += [""] if tables else []
                tables.append(ratios_table(comparison, joint))
        else:
            tables = [fastest_table(result), "", binding_table(result)]
        text = "" if _to_stdout(args) else _rendered(*tables)
        outputs.commit()
    sys.stdout.write(text)
    _say_written([
        (args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(result.robot.sized_joints)} "
                   "(SI) along the fastest cycle"),
        (args.plot, "the shortest cycle against the unit on each joint compared"
         if args.compare_ratios else "speed and torque of each sized joint against its limits"),
        (args.json, None)], args)
    return EXIT_OK


def run_max_payload(args: argparse.Namespace) -> int:
    """``hdselect max-payload``: the largest payload mass with a unit on every joint."""
    from dataclasses import replace

    from hdselect.catalog import load_catalog
    from hdselect.export import max_payload_json, write_json
    from hdselect.maxpayload import max_payload
    from hdselect.outputs import Outputs
    from hdselect.report import max_payload_text, size_table

    robot, motion = _load_case(args)
    options = _options(args, motion)
    units = load_catalog(args.catalog)
    with Outputs([*_inputs(robot, motion), *args.catalog]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        try:
            result = max_payload(robot, motion, options, catalog=units,
                                 frame=args.payload_frame, com=args.payload_com)
        except InputError as err:
            flag = {"payload.frame": "--payload-frame", "payload.com": "--payload-com"}.get(
                str(err.field))
            if flag is None or getattr(args, flag[2:].replace("-", "_")) is None:
                raise
            raise InputError(err.reason, field=flag) from err
        if json_file is not None:
            write_json(json_file, max_payload_json(result, motion))
        items: list[Any] = [max_payload_text(result, robot, motion)]
        if result.selection is not None:
            items += ["", size_table(replace(result.selection, motion=motion))]
        text = "" if _to_stdout(args) else _rendered(*items)
        outputs.commit()
    sys.stdout.write(text)
    _say_written([(args.json, None)], args)
    return EXIT_OK if result.mass is not None else EXIT_NO_FIT


def _gear_torques(result):
    """The output torque of every joint (n, dof), as the gears carry it; 0 where unsized."""
    import numpy as np

    tau = np.zeros_like(result.trajectory.q)
    for joint in result.check.joints:
        tau[:, result.robot.joint_index(joint.name)] = joint.torque
    return tau


def _unit_pairs(pairs: Sequence[str]) -> dict[str, str]:
    """``JOINT=UNIT`` pairs as a dict; each joint once."""
    out: dict[str, str] = {}
    for pair in pairs:
        joint, sep, unit = pair.partition("=")
        if not sep or not joint.strip() or not unit.strip():
            raise InputError(f"expected JOINT=UNIT, got {pair!r}", field="--units")
        if joint.strip() in out:
            raise InputError(f"joint '{joint.strip()}' given twice", field="--units")
        out[joint.strip()] = unit.strip()
    return out


def run_joints(args: argparse.Namespace) -> int:
    """``hdselect joints``: every joint of a robot file, in the order lists use."""
    from hdselect.export import joints_json, write_json
    from hdselect.joints import describe_joints
    from hdselect.outputs import Outputs
    from hdselect.report import joints_table
    from hdselect.robot import load_robot

    robot = load_robot(args.robot)
    with Outputs([robot.path]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        infos = describe_joints(robot)
        if json_file is not None:
            write_json(json_file, joints_json(robot, infos))
        text = "" if args.json == "-" else _rendered(joints_table(robot, infos))
        outputs.commit()
    args.held.shown(("hdselect.robotfile",))  # the table and the JSON list them
    sys.stdout.write(text)
    _say_written([(args.json, None)], args)
    return EXIT_OK


def run_init(args: argparse.Namespace) -> int:
    """``hdselect init``: a starter motion file that plans and sizes as written."""
    from hdselect.outputs import Outputs
    from hdselect.robot import load_robot
    from hdselect.starter import starter_motion
    from hdselect.tables import Paragraphs

    robot = load_robot(args.robot)
    out = None if args.out in (None, "-") else Path(args.out)

    def text() -> str:
        where = os.path.abspath(out.parent if out is not None else Path.cwd())
        target = os.path.abspath(robot.path)
        shared = os.path.commonpath([target, where])
        return starter_motion(robot, str(target) if shared == os.sep
                              else os.path.relpath(target, where))

    if out is None:
        sys.stdout.write(text())
        return EXIT_OK
    with Outputs([robot.path]) as outputs:
        staging = outputs.file(out, "--out", exclusive=True)
        staging.write_text(text(), encoding="utf-8")
        note = _rendered(Paragraphs((f"wrote {out}; edit its waypoints, limits and payload, "
                                     f"then: hdselect size {out}",)))
        outputs.commit()
    sys.stdout.write(note)
    return EXIT_OK


def run_study(args: argparse.Namespace) -> int:
    """``hdselect study``: every case of a study, in parallel, kept as it completes.

    The CSV and its journal are appended to as cases complete (what makes a study
    resumable); the study file is read and both paths are checked before any case
    runs, and the plot is written with the other outputs' transaction at the end.
    """
    import time

    from hdselect.outputs import Outputs
    from hdselect.report import study_tables, study_value_table
    from hdselect.study.run import run_study as run
    from hdselect.study.spec import load_study
    from hdselect.study.store import Store, journal_path, pivots, table, value_pivot
    from hdselect.tables import Paragraphs

    study = load_study(args.study)
    store = Store(args.out, study)  # checks both paths before any case runs
    with Outputs([args.study, *store.paths]) as outputs:
        plot = outputs.file(args.plot, "--plot") if args.plot else None
        started = time.perf_counter()
        args.kept.note = (f"the cases done are kept in {args.out} and its journal "
                          f"{store.journal_path.name}; run the same command to resume")
        with _progress(study.title) as progress:
            done = run(study, store, workers=args.workers, scheduler=args.scheduler,
                       grouping=not args.no_grouping, retry_failed=args.retry_failed,
                       progress=progress)
        methods = ", ".join(f"{count} {name}" for name, count in sorted(done.methods.items()))
        items: list[Any] = [Paragraphs((
            f"{study.title}: {len(study.cases)} cases: {done.ran} run now"
            + (f" ({methods})" if methods else "")
            + f", {done.skipped} already done, {done.failed} failed",))]
        rows = table(study, done.records)
        if "size" in study.compute:
            tables, constant = pivots(study, done.records)
            items += [Paragraphs((item,)) if isinstance(item, str) else item
                      for item in study_tables(tables, constant)]
        for name, what, value in _STUDY_VALUES:
            pivot = (value_pivot(study, done.records, name, value) if name in study.compute
                     else None)
            if pivot is not None:
                items.append(study_value_table(pivot, what))
        csv_shown = store.csv_path if Path(args.out).is_symlink() else Path(args.out)
        journal_shown = (store.journal_path if Path(args.out).is_symlink()
                         else journal_path(args.out))
        items.append(Paragraphs((f"rows: {csv_shown}; records: {journal_shown}",)))
        if plot is not None and "size" in study.compute:
            from hdselect.figures import write_study_png

            joints = list(dict.fromkeys(row["joint"] for row in rows if row.get("joint")))
            first = study.varied[0] if study.varied else "case"
            second = study.varied[1] if len(study.varied) > 1 else None
            write_study_png(plot, study.title, [r for r in rows if r["compute"] == "size"],
                            first, second, joints)
        text = "" if args.plot == "-" else _rendered(*items)
        outputs.commit()
    sys.stdout.write(text)
    _say_written([(args.plot, "the unit selected and its life per joint")], args)
    if done.ran:
        print(f"hdselect: {done.ran} cases in {time.perf_counter() - started:.1f} s on "
              f"{done.executor}", file=sys.stderr)
    return EXIT_CASES_FAILED if done.failed else EXIT_OK


def _payload_cell(result: dict) -> str:
    if result["unlimited"]:
        return "no limit"
    mass = result["max_payload_kg"]
    return "none" if mass is None else f"{mass:.3g}"


_STUDY_VALUES = (("fastest", "fastest cycle s", lambda r: f"{r['cycle_time_s']:.3f}"),
                 ("max-payload", "largest payload kg", _payload_cell))
"""The number a study prints per case of a computation other than ``size``."""


class _progress:
    """A progress bar with ETA on a terminal (standard error); nothing when piped."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.bar: Any = None

    def __enter__(self):
        if not sys.stderr.isatty():
            return None
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        bar = self.bar = Progress(
            TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
            console=Console(stderr=True), transient=True)
        self.bar.start()
        task = self.bar.add_task(self.title, total=None)

        def update(done: int, total: int, record: dict) -> None:
            bar.update(task, completed=done, total=total)
        return update

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()


_SHOWN = ("hdselect.robotfile", "hdselect.motion")
"""Loggers whose warnings a sizing result carries (`SizingResult.warnings`)."""

_PAYLOAD_FLAGS = {"payload.mass": "--payload", "payload.com": "--payload-com",
                  "payload.frame": "--payload-frame"}


def _names(given: list[str] | None) -> list[str] | None:
    """Joint names from repeatable, comma-separated options."""
    if given is None:
        return None
    return [name.strip() for text in given for name in text.split(",") if name.strip()]


def _load_case(args: argparse.Namespace):
    """The robot and the motion, with the command line's payload, mounting and joints applied.

    ``--payload KG`` changes the mass of the motion file's payload and keeps its centre
    of mass, inertia and frame; ``--payload-com`` and ``--payload-frame`` change those of
    the file's payload (or of the one ``--payload`` makes) and are refused when there is
    none. A payload without a frame goes on the robot's default payload frame.
    """
    from hdselect.motion import load_motion, robot_file_named, robot_for_motion
    from hdselect.robot import Payload, load_robot

    robot = load_robot(args.robot if args.robot is not None else robot_file_named(args.motion))
    motion = load_motion(args.motion, robot)
    base = motion.payload
    given = [flag for flag, value in (("--payload", args.payload),
                                      ("--payload-com", args.payload_com),
                                      ("--payload-frame", args.payload_frame))
             if value is not None] if hasattr(args, "payload") else []  # max-payload: its own
    payload = None
    if given:
        if base is None and args.payload is None:
            raise InputError(f"the motion file gives no payload for {given[0]} to change; give "
                             "its mass with --payload KG", path=motion.path, field=given[0])
        if args.payload is not None:
            mass = float(args.payload)
        else:
            assert base is not None  # refused above
            mass = base.mass
        try:
            payload = Payload(
                mass,
                tuple(args.payload_com) if args.payload_com is not None
                else (base.com if base is not None else (0.0, 0.0, 0.0)),
                base.inertia if base is not None else ((0.0,) * 3,) * 3,
                args.payload_frame if args.payload_frame is not None
                else (base.frame if base is not None else None))
        except InputError as err:
            field = str(err.field)
            flag = next((f for k, f in _PAYLOAD_FLAGS.items() if field.startswith(k)), field)
            raise InputError(err.reason, field=flag) from err
    joints, exclude = _names(args.joints), _names(args.exclude)
    try:
        robot = robot_for_motion(robot, motion, payload=payload, mounting=args.mounting,
                                 joints=joints, exclude=exclude)
    except InputError as err:
        options = {"joints": joints, "exclude": exclude}
        if err.field in options and options[str(err.field)] is not None:
            raise InputError(err.reason, field=f"--{err.field}") from err
        if err.field == "payload.frame" and args.payload_frame is not None:
            raise InputError(err.reason, field="--payload-frame") from err
        if err.field == "payload.frame" and payload is not None:
            raise InputError(err.reason, path=motion.path, field="payload.frame") from err
        if str(err.field).startswith("mounting") and args.mounting is not None:
            raise InputError(err.reason, field="--mounting") from err
        raise
    return robot, motion


def _max_samples(args: argparse.Namespace) -> int:
    from hdselect.bounds import check_max_samples

    return check_max_samples(args.max_samples, field="--max-samples")


def _prepare(args: argparse.Namespace):
    """The robot, the motion, the catalog, the validated options and the motors."""
    from hdselect.catalog import load_catalog
    from hdselect.motors import load_motors
    from hdselect.sizing import motion_motors

    robot, motion = _load_case(args)
    if args.motor_catalog:
        catalog = load_motors(args.motor_catalog)
        motors = {name: catalog for name in robot.sized_joints}
    else:
        motors = motion_motors(robot, motion)
    if motors:
        for value, flag in ((args.motor_inertia, "--motor-inertia"),
                            (args.motor_mass, "--motor-mass")):
            if value is not None:
                given = ("--motor-catalog" if args.motor_catalog
                         else f"[motor] of {motion.path.name}")
                raise InputError(f"the motors come from {given}, with their own rotor inertia "
                                 "and mass; drop this option", field=flag)
    options = _options(args, motion)
    return robot, motion, load_catalog(args.catalog), options, motors


def _sized(robot, motion, units, options, motors):
    """Plan and size through the public core, as `hdselect.size` does."""
    from dataclasses import replace

    from hdselect.planning import plan
    from hdselect.sizing import size_trajectory

    trajectory = plan(robot, motion, max_samples=options.max_samples)
    return replace(size_trajectory(robot, trajectory, units, options, motors=motors),
                   motion=motion)


class _outputs:
    """The outputs of ``size`` and ``compare`` reserved: (Outputs, JSON file, report target).

    The report target is a staging directory, or a file for ``--report -`` (the page alone).
    """

    def __init__(self, args: argparse.Namespace, robot, motion) -> None:
        from hdselect.outputs import Outputs

        inputs = [*_inputs(robot, motion), *args.catalog,
                  *([args.motor_catalog] if args.motor_catalog else [])]
        self.outputs = Outputs(inputs)
        self.args = args

    def __enter__(self):
        args, outputs = self.args, self.outputs
        try:
            json_file = outputs.file(args.json, "--json") if args.json else None
            report = None
            if args.report == "-":
                report = outputs.file("-", "--report")
            elif args.report:
                report = outputs.directory(args.report, "--report")
        except BaseException:
            outputs.discard()
            raise
        return outputs, json_file, report

    def __exit__(self, *exc: object) -> None:
        self.outputs.discard()


def _write_outputs(args: argparse.Namespace, result, json_file: Path | None,
                   report: Path | None) -> None:
    """The report and the JSON a command was asked for, into their staged places."""
    from hdselect.export import size_json, write_json

    if report is not None:
        from hdselect.figures import report_files, report_page

        if args.report == "-":
            report.write_text(report_page(result, command=args.command_line),
                              encoding="utf-8")
        else:
            report_files(report, result, command=args.command_line)
    if json_file is not None:
        write_json(json_file, size_json(result))


def _to_stdout(args: argparse.Namespace) -> bool:
    """An output goes to standard output (``-``): then no table is printed there."""
    return "-" in (getattr(args, name, None) for name in ("json", "report", "out", "plot"))


def _report_and_json(args: argparse.Namespace) -> list[tuple[str | None, str | None]]:
    report = args.report if args.report in (None, "-") else str(Path(args.report) / "index.html")
    return [(report, "the report, figures embedded (also as PNG files beside it)"
             if args.report != "-" else None), (args.json, None)]


def _say_written(written: Sequence[tuple[str | None, str | None]],
                 args: argparse.Namespace) -> None:
    """Name the files written, on standard error when standard output carries an output."""
    from hdselect.tables import Paragraphs, console_for

    lines = [f"wrote {path}" + (f": {what}" if what else "") for path, what in written
             if path is not None and path != "-"]
    if lines:
        console_for(sys.stderr if _to_stdout(args) else sys.stdout).print(
            Paragraphs(tuple(lines)))


def _rendered(*items: Any) -> str:
    """Renderables as standard output would show them, rendered before any output is committed.

    Rendering first means a failure while formatting leaves no output behind.
    """
    import io

    from hdselect.tables import console_for

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


def _options(args: argparse.Namespace, motion):
    """The validated options of the sizing flags, the motion file's where a flag is absent."""
    from hdselect.options import options_for

    try:
        return options_for(
            motion, stop_time=args.stop_time, efficiency=args.efficiency,
            rotor_inertia=args.motor_inertia, motor_mass=args.motor_mass,
            mass_coupling=not args.no_mass_coupling, prefer=args.prefer,
            life_hours=args.life_hours, life_basis=args.life_basis,
            max_samples=args.max_samples)
    except InputError as err:
        raise InputError(err.reason, field=_OPTION_FLAGS.get(str(err.field), err.field)) from err


def _inputs(robot, motion) -> list[Path]:
    """The files a robot and a motion were read from (logs and motor files included)."""
    files = [motion.path, robot.path]
    motors = {m.source for ms in (motion.motors or {}).values() for m in ms if m.source}
    return files + ([motion.samples.path] if motion.samples is not None else []) + sorted(motors)


if __name__ == "__main__":
    sys.exit(main())
