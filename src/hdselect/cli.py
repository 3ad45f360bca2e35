"""Command line: a thin layer over the public API; it formats, it does not compute."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from hdselect import __version__
from hdselect.errors import HdselectError, InputError

logger = logging.getLogger("hdselect")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``hdselect`` command.

    Returns:
        Exit status: 0 success, 1 no gearhead fits, 2 bad input.
    """
    parser = _parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(argv)
    args.command_line = ["hdselect", *argv]
    logging.basicConfig(format="hdselect: %(levelname)s: %(message)s",
                        level=logging.INFO if args.verbose else logging.WARNING)
    try:
        return int(args.run(args))
    except HdselectError as err:
        print(f"hdselect: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        # The reader went away (e.g. `| head`): not an error of ours.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


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
                      help="write an HTML report with figures into DIR")
    size.set_defaults(run=run_size)

    compare = commands.add_parser(
        "compare", parents=[verbose], help="every unit against every joint, side by side")
    _robot_motion(compare)
    _sizing_options(compare)
    compare.add_argument("--joint", action="append", metavar="NAME",
                         help="show only this joint (repeatable)")
    _json_option(compare)
    compare.add_argument("--report", metavar="DIR",
                         help="write an HTML report of the joints shown into DIR")
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
                      help="the motion file to write (default: print it); never overwritten")
    init.set_defaults(run=run_init)

    study = commands.add_parser("study", parents=[verbose],
                                help="run every case of a design study (TOML)")
    study.add_argument("study", metavar="STUDY", help="study file (TOML)")
    study.add_argument("--out", metavar="CSV", required=True,
                       help="rows, one per case and joint; a JSON Lines record of each case "
                            "is kept beside it (same name, .jsonl); cases already there are "
                            "skipped")
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
                            help="payload mass, overriding the motion file's [kg]")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        default=None if not mass else (0.0, 0.0, 0.0),
                        help="payload centre of mass in its frame [m]")
    parser.add_argument("--payload-frame", metavar="LINK",
                        help="link carrying the payload (default: the tip of the longest chain "
                             "of sized joints)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")
    parser.add_argument("--joints", metavar="A,B", action="append",
                        help="size only these joints (comma-separated; overrides the motion "
                             "file's [sizing] joints)")
    parser.add_argument("--exclude", metavar="A,B", action="append",
                        help="do not size these joints; they still move and load the others "
                             "(overrides the motion file's [sizing] exclude)")


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
                 "life_basis": "--life-basis"}
"""The command-line option of each field of `hdselect.options.Options`."""


def run_catalog(args: argparse.Namespace) -> int:
    """``hdselect catalog``: print the catalog."""
    from hdselect.catalog import load_catalog
    from hdselect.export import catalog_json, write_json
    from hdselect.report import catalog_table, console

    units = load_catalog(args.catalog)
    if args.json:
        write_json("-", catalog_json(units))
    else:
        console().print(catalog_table(units, imperial=args.units == "imperial"))
    return 0


def run_duty(args: argparse.Namespace) -> int:
    """``hdselect duty``: the catalog's torque-speed method for one joint."""
    from hdselect.catalog import load_catalog
    from hdselect.duty import load_duty, size_duty
    from hdselect.export import duty_json, write_json
    from hdselect.report import console, duty_table

    units = load_catalog(args.catalog)
    _keep_inputs([args.json], [args.profile, *args.catalog])
    result = size_duty(load_duty(args.profile), units)
    if args.json:
        write_json(args.json, duty_json(result))
    if args.json != "-":
        console().print(duty_table(result))
    return 0 if result.selected is not None else 1


def run_plan(args: argparse.Namespace) -> int:
    """``hdselect plan``: the trajectory and the torques along it, as CSV (and a plot)."""
    from hdselect.dynamics import inverse_dynamics
    from hdselect.export import write_trajectory_csv
    from hdselect.planning import plan

    robot, motion = _load_case(args)
    _keep_inputs([args.out, args.plot], _inputs(robot, motion))
    trajectory = plan(robot, motion)
    tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
    from hdselect.report import console, plan_text
    from hdselect.tables import Paragraphs

    if args.plot:
        from hdselect.figures import write_profiles_png

        write_profiles_png(args.plot, trajectory, tau, robot.sized_joints,
                           title=f"{robot.path.name} running {motion.path.name}")
    write_trajectory_csv(args.out, trajectory, tau, robot.joint_names)
    out = console()
    out.print(plan_text(robot, motion, trajectory))
    written = [f"wrote {args.out}: t, then q_, qd_, qdd_, tau_ of "
               f"{', '.join(robot.joint_names)} (SI)"]
    if args.plot:
        written.append(f"wrote {args.plot}: speed and torque of each joint over the cycle")
    out.print(Paragraphs(tuple(written)))
    return 0


def run_size(args: argparse.Namespace) -> int:
    """``hdselect size``: a gearhead for every joint."""
    from hdselect.report import console, loads_table, size_table

    result = _size(args)
    _write_outputs(args, result)
    if args.json != "-":
        out = console()
        out.print(size_table(result))
        out.print()
        out.print(loads_table(result))
    _say_written(args)
    return 0 if result.feasible else 1


def run_compare(args: argparse.Namespace) -> int:
    """``hdselect compare``: every unit against every joint."""
    from dataclasses import replace

    from hdselect.report import compare_table, console

    result = _size(args)
    names = [joint.name for joint in result.joints]
    for name in args.joint or []:
        if name not in names:
            raise InputError(f"unknown joint '{name}'; sized joints are: {', '.join(names)}",
                             field="--joint")
    shown = replace(result, joints=tuple(joint for joint in result.joints
                                         if not args.joint or joint.name in args.joint))
    _write_outputs(args, shown)
    if args.json != "-":
        out = console()
        for i, joint in enumerate(shown.joints):
            if i:
                out.print()
            out.print(compare_table(result, joint))
    _say_written(args)
    return 0 if result.feasible else 1


def run_fastest(args: argparse.Namespace) -> int:
    """``hdselect fastest``: the shortest cycle the units allow, or every unit compared."""
    from hdselect.catalog import load_catalog
    from hdselect.codesign import compare_ratios, fastest
    from hdselect.export import fastest_json, ratios_json, write_json, write_trajectory_csv
    from hdselect.report import binding_table, console, fastest_table, ratios_table

    if args.joint and not args.compare_ratios:
        raise InputError("only with --compare-ratios", field="--joint")
    robot, motion = _load_case(args)
    options = _options(args, motion)
    _keep_inputs([args.json, args.out, args.plot], [*_inputs(robot, motion), *args.catalog])
    units = load_catalog(args.catalog)
    given = _unit_pairs(args.units)
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
    if args.plot:
        from hdselect.figures import write_fastest_png, write_ratios_png

        if args.compare_ratios:
            write_ratios_png(args.plot, comparison)
        else:
            write_fastest_png(args.plot, result)
    if args.out:
        write_trajectory_csv(args.out, result.trajectory, _gear_torques(result),
                             result.robot.sized_joints)
    if args.json:
        write_json(args.json, ratios_json(comparison) if args.compare_ratios
                   else fastest_json(result))
    if args.json != "-":
        out = console()
        if args.compare_ratios:
            for i, joint in enumerate(comparison.joints):
                if i:
                    out.print()
                out.print(ratios_table(comparison, joint))
        else:
            out.print(fastest_table(result))
            out.print()
            out.print(binding_table(result))
    written = []
    if args.out:
        written.append(f"wrote {args.out}: t, then q_, qd_, qdd_, tau_ of "
                       f"{', '.join(result.robot.sized_joints)} (SI) along the fastest cycle")
    if args.plot:
        written.append(f"wrote {args.plot}: " + (
            "the shortest cycle against the unit on each joint compared" if args.compare_ratios
            else "speed and torque of each sized joint against its limits"))
    _say_files(args, written)
    return 0


def run_max_payload(args: argparse.Namespace) -> int:
    """``hdselect max-payload``: the largest payload mass with a unit on every joint."""
    from hdselect.catalog import load_catalog
    from hdselect.export import max_payload_json, write_json
    from hdselect.maxpayload import max_payload
    from hdselect.report import console, max_payload_text, size_table

    robot, motion = _load_case(args)
    options = _options(args, motion)
    _keep_inputs([args.json], [*_inputs(robot, motion), *args.catalog])
    units = load_catalog(args.catalog)
    try:
        result = max_payload(robot, motion, options, catalog=units, frame=args.payload_frame,
                             com=args.payload_com)
    except InputError as err:
        flag = {"payload.frame": "--payload-frame", "payload.com": "--payload-com"}.get(
            str(err.field))
        if flag is None or getattr(args, flag[2:].replace("-", "_")) is None:
            raise
        raise InputError(err.reason, field=flag) from err
    if args.json:
        write_json(args.json, max_payload_json(result, motion))
    if args.json != "-":
        out = console()
        out.print(max_payload_text(result, robot, motion))
        if result.selection is not None:
            from dataclasses import replace

            out.print()
            out.print(size_table(replace(result.selection, motion=motion)))
    _say_files(args, [])
    return 0 if result.mass is not None else 1


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
    from hdselect.report import console, joints_table
    from hdselect.robot import load_robot

    robot = load_robot(args.robot)
    _keep_inputs([args.json], [robot.path])
    infos = describe_joints(robot)
    if args.json:
        write_json(args.json, joints_json(robot, infos))
    if args.json != "-":
        console().print(joints_table(robot, infos))
    return 0


def run_init(args: argparse.Namespace) -> int:
    """``hdselect init``: a starter motion file that plans and sizes as written."""
    from hdselect.export import write_output
    from hdselect.robot import load_robot
    from hdselect.starter import starter_motion

    robot = load_robot(args.robot)
    out = Path(args.out) if args.out else None
    if out is not None and out.exists():
        raise InputError("exists; choose another path or remove it first", path=out)
    where = os.path.abspath(out.parent if out is not None else Path.cwd())
    target = os.path.abspath(robot.path)
    shared = os.path.commonpath([target, where])
    text = starter_motion(robot, str(target) if shared == os.sep
                          else os.path.relpath(target, where))
    if out is None:
        sys.stdout.write(text)
    else:
        from hdselect.report import console
        from hdselect.tables import Paragraphs

        write_output(out, lambda stream: stream.write(text))
        console().print(Paragraphs((f"wrote {out}; edit its waypoints, limits and payload, "
                                    f"then: hdselect size {out}",)))
    return 0


def _names(given: list[str] | None) -> list[str] | None:
    """Joint names from repeatable, comma-separated options."""
    if given is None:
        return None
    return [name.strip() for text in given for name in text.split(",") if name.strip()]


def _write_outputs(args: argparse.Namespace, result) -> None:
    """The report and the JSON a command was asked for; the report first, as it may fail."""
    from hdselect.export import size_json, write_json

    if args.report:
        from hdselect.figures import write_report

        write_report(args.report, result, command=args.command_line)
    if args.json:
        write_json(args.json, size_json(result))


def _say_written(args: argparse.Namespace) -> None:
    """Name the report and JSON written (`_say_files`)."""
    written = []
    if args.report:
        written.append(f"wrote {Path(args.report) / 'index.html'}: the report, figures "
                       "embedded (also as PNG files beside it)")
    _say_files(args, written)


def _say_files(args: argparse.Namespace, written: list[str]) -> None:
    """Name the files written and the JSON file; on standard error when stdout carries JSON."""
    from hdselect.tables import Paragraphs, console_for

    if args.json and args.json != "-":
        written = [*written, f"wrote {args.json}"]
    if written:
        console_for(sys.stderr if args.json == "-" else sys.stdout).print(
            Paragraphs(tuple(written)))


def run_study(args: argparse.Namespace) -> int:
    """``hdselect study``: every case of a study, in parallel, kept as it completes."""
    import time

    from hdselect.report import console, study_tables, study_value_table
    from hdselect.study.run import run_study as run
    from hdselect.study.spec import load_study
    from hdselect.study.store import journal_path, pivots, table, value_pivot
    from hdselect.tables import Paragraphs

    study = load_study(args.study)
    _keep_inputs([args.out, journal_path(args.out), args.plot], [args.study])
    started = time.perf_counter()
    with _progress(study.title) as progress:
        done = run(study, args.out, workers=args.workers, scheduler=args.scheduler,
                   grouping=not args.no_grouping, retry_failed=args.retry_failed,
                   progress=progress)
    out = console()
    methods = ", ".join(f"{count} {name}" for name, count in sorted(done.methods.items()))
    out.print(Paragraphs((f"{study.title}: {len(study.cases)} cases: {done.ran} run now"
                          + (f" ({methods})" if methods else "")
                          + f", {done.skipped} already done, {done.failed} failed",)))
    rows = table(study, done.records)
    if "size" in study.compute:
        tables, constant = pivots(study, done.records)
        for item in study_tables(tables, constant):
            out.print(Paragraphs((item,)) if isinstance(item, str) else item)
    for name, what, value in _STUDY_VALUES:
        pivot = value_pivot(study, done.records, name, value) if name in study.compute else None
        if pivot is not None:
            out.print(study_value_table(pivot, what))
    out.print(Paragraphs((f"rows: {args.out}; records: {journal_path(args.out)}",)))
    if args.plot and "size" in study.compute:
        from hdselect.figures import write_study_png

        joints = list(dict.fromkeys(row["joint"] for row in rows if row.get("joint")))
        first = study.varied[0] if study.varied else "case"
        second = study.varied[1] if len(study.varied) > 1 else None
        write_study_png(args.plot, study.title, [r for r in rows if r["compute"] == "size"],
                        first, second, joints)
    if done.ran:
        print(f"hdselect: {done.ran} cases in {time.perf_counter() - started:.1f} s on "
              f"{done.executor}", file=sys.stderr)
    return 3 if done.failed else 0


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
        self.bar = None

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


def _load_case(args: argparse.Namespace):
    from hdselect.motion import load_case
    from hdselect.robot import Payload

    payload = None
    if getattr(args, "payload", None) is not None:
        try:
            payload = Payload(args.payload, tuple(args.payload_com), frame=args.payload_frame)
        except InputError as err:
            flag = {"payload.mass": "--payload", "payload.com": "--payload-com"}
            raise InputError(err.reason, field=flag.get(str(err.field), err.field)) from err
    joints, exclude = _names(args.joints), _names(args.exclude)
    try:
        return load_case(args.motion, args.robot, payload=payload, mounting=args.mounting,
                         joints=joints, exclude=exclude)
    except InputError as err:
        given = {"joints": joints, "exclude": exclude}
        if err.field in given and given[str(err.field)] is not None:
            raise InputError(err.reason, field=f"--{err.field}") from err
        raise


def _size(args: argparse.Namespace):
    """Load, plan and size through the public core, as `hdselect.size` does."""
    from dataclasses import replace

    from hdselect.catalog import load_catalog
    from hdselect.motors import load_motors
    from hdselect.planning import plan
    from hdselect.sizing import motion_motors, size_trajectory

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
    _keep_inputs([getattr(args, "json", None)],
                 [*_inputs(robot, motion), *args.catalog,
                  *([args.motor_catalog] if args.motor_catalog else [])])
    if getattr(args, "report", None):
        _keep_inputs([Path(args.report) / "index.html"], _inputs(robot, motion))
    units = load_catalog(args.catalog)
    result = size_trajectory(robot, plan(robot, motion), units, options, motors=motors)
    return replace(result, motion=motion)


def _options(args: argparse.Namespace, motion):
    """The validated options of the sizing flags, the motion file's where a flag is absent."""
    from hdselect.options import options_for

    try:
        return options_for(
            motion, stop_time=args.stop_time, efficiency=args.efficiency,
            rotor_inertia=args.motor_inertia, motor_mass=args.motor_mass,
            mass_coupling=not args.no_mass_coupling, prefer=args.prefer,
            life_hours=args.life_hours, life_basis=args.life_basis)
    except InputError as err:
        raise InputError(err.reason, field=_OPTION_FLAGS.get(str(err.field), err.field)) from err


def _inputs(robot, motion) -> list[Path]:
    """The files a robot and a motion were read from."""
    files = [motion.path, robot.path]
    motors = {m.source for ms in (motion.motors or {}).values() for m in ms if m.source}
    return files + ([motion.samples.path] if motion.samples is not None else []) + sorted(motors)


def _keep_inputs(outputs: Sequence[str | Path | None], inputs: Sequence[str | Path]) -> None:
    """Refuse to write an output over a file the user gave as input."""
    given = {Path(file).resolve() for file in inputs}
    for output in outputs:
        if output is not None and str(output) != "-" and Path(output).resolve() in given:
            raise InputError("is an input file; choose another output path", path=output)


if __name__ == "__main__":
    sys.exit(main())
