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

from hdselect import __version__
from hdselect.bounds import DEFAULT_MAX_SAMPLES
from hdselect.errors import HdselectError, InputError
from hdselect.session import HeldLog, Terminated, handle_sigterm, tolerate_encoding

logger = logging.getLogger("hdselect")


EXIT_OK, EXIT_NO_FIT, EXIT_BAD_INPUT, EXIT_BUG = 0, 1, 2, 3
"""Exit statuses: every joint has a unit; some joint has none; bad input; a bug in hdselect.
Interrupted runs exit 130 (Ctrl-C) or 143 (SIGTERM)."""


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``hdselect`` command.

    Returns:
        Exit status: 0 success, 1 no gearhead fits, 2 bad input (one line on standard
        error, no output), 3 a bug in hdselect (one line; ``-v`` shows the traceback),
        130 interrupted (Ctrl-C), 143 terminated (SIGTERM).
    """
    previous = handle_sigterm()
    held = HeldLog(logger)
    try:
        tolerate_encoding()
        parser = _parser()
        args = parser.parse_args(argv)
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
        _say("interrupted; no output was written")
        return 130
    except Terminated:
        _say("terminated; no output was written")
        return 143
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
    commands = parser.add_subparsers(title="commands", required=True, metavar="COMMAND",
                                     parser_class=_Parser)

    catalog = commands.add_parser("catalog", help="list the gearhead catalog")
    _catalog_option(catalog)
    catalog.add_argument("--units", choices=("si", "imperial"), default="si",
                         help="unit system of the table (default: si)")
    catalog.add_argument("--json", action="store_true", help="print JSON instead of a table")
    catalog.set_defaults(run=run_catalog)

    duty = commands.add_parser("duty", help="size from a torque-speed profile (catalog method)")
    duty.add_argument("profile", help="duty-cycle profile (TOML)")
    _catalog_option(duty)
    _json_option(duty)
    duty.set_defaults(run=run_duty)

    plan = commands.add_parser("plan", help="plan a motion and write its torques (CSV)")
    _robot_motion(plan)
    plan.add_argument("--out", metavar="FILE", required=True,
                      help="CSV: t, then q_, qd_, qdd_, tau_ per sized joint (SI)")
    plan.add_argument("--plot", metavar="PNG", help="speed and torque profiles per joint")
    plan.set_defaults(run=run_plan)

    size = commands.add_parser("size", help="choose a gearhead for every joint of a robot")
    _robot_motion(size)
    _sizing_options(size)
    _json_option(size)
    size.add_argument("--report", metavar="DIR",
                      help="write an HTML report with figures into DIR")
    size.set_defaults(run=run_size)

    compare = commands.add_parser("compare", help="every unit against every joint, side by side")
    _robot_motion(compare)
    _sizing_options(compare)
    compare.add_argument("--joint", action="append", metavar="NAME",
                         help="show only this joint (repeatable)")
    compare.set_defaults(run=run_compare)
    return parser


def _catalog_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog file (TOML; repeatable)")


def _json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", metavar="FILE",
                        help="also write JSON to FILE ('-': to stdout, instead of the table)")


def _robot_motion(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("robot", nargs="?", metavar="ROBOT",
                        help="robot file, URDF or MJCF (default: the motion file's `robot`)")
    parser.add_argument("motion", metavar="MOTION", help="motion file (TOML)")
    parser.add_argument("--payload", type=float, metavar="KG",
                        help="payload mass [kg]; the motion file's payload keeps its centre of "
                             "mass, inertia and frame")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="payload centre of mass in its frame [m] (changes the motion "
                             "file's payload, or the one --payload gives)")
    parser.add_argument("--payload-frame", metavar="LINK",
                        help="link carrying the payload (default: the motion file's, else the "
                             "last link)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")
    parser.add_argument("--max-samples", type=int, metavar="N",
                        default=DEFAULT_MAX_SAMPLES,
                        help="refuse a trajectory of more samples than this, before allocating "
                             f"it (default {DEFAULT_MAX_SAMPLES:,}: an 8-hour log at 1 kHz)")


def _sizing_options(parser: argparse.ArgumentParser) -> None:
    from hdselect.motion import LIFE_BASES
    from hdselect.options import Options
    from hdselect.select import PREFERENCES

    defaults = Options()
    _catalog_option(parser)
    parser.add_argument("--stop-time", type=float, metavar="S",
                        help="emergency-stop and crash time [s] (default: the motion file's "
                             f"[safety] stop_time, else {defaults.stop_time:g})")
    parser.add_argument("--efficiency", type=float,
                        help=f"gear efficiency where a unit has no table (default "
                             f"{defaults.efficiency:g})")
    parser.add_argument("--motor-inertia", type=float, metavar="KG_M2",
                        help="motor rotor inertia [kg m^2] (default 0)")
    parser.add_argument("--motor-mass", type=float, metavar="KG",
                        help="motor mass carried with each gearhead [kg] (default 0)")
    parser.add_argument("--no-mass-coupling", action="store_true",
                        help="do not carry chosen units' masses on the joints nearer the base")
    parser.add_argument("--prefer", choices=tuple(PREFERENCES),
                        help="; ".join(f"{k}: {v[0]}" for k, v in PREFERENCES.items())
                        + f" (default {defaults.prefer})")
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
    return 0 if result.selected is not None else 1


def run_plan(args: argparse.Namespace) -> int:
    """``hdselect plan``: the trajectory and the torques along it, as CSV (and a plot)."""
    from hdselect.dynamics import inverse_dynamics
    from hdselect.export import write_trajectory_csv
    from hdselect.outputs import Outputs
    from hdselect.planning import plan

    robot, motion = _load_case(args)
    max_samples = _max_samples(args)
    with Outputs(_inputs(robot, motion)) as outputs:
        out = outputs.file(args.out, "--out")
        figure = outputs.file(args.plot, "--plot") if args.plot else None
        trajectory = plan(robot, motion, max_samples=max_samples)
        tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
        joints = robot.sized_joints
        write_trajectory_csv(out, trajectory, tau, joints)
        if figure is not None:
            from hdselect.figures import write_profiles_png

            write_profiles_png(figure, trajectory, tau, joints,
                               title=f"{robot.path.name} running {motion.path.name}")
        outputs.commit()
    logger.info("wrote %d samples to %s", len(trajectory.t), args.out)
    return 0


def run_size(args: argparse.Namespace) -> int:
    """``hdselect size``: a gearhead for every joint."""
    from hdselect.export import size_json, write_json
    from hdselect.outputs import Outputs
    from hdselect.report import size_table

    robot, motion, units, options = _prepare(args)
    with Outputs([*_inputs(robot, motion), *args.catalog]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        report = None
        if args.report == "-":
            report = outputs.file("-", "--report")
        elif args.report:
            report = outputs.directory(args.report, "--report")
        result = _sized(robot, motion, units, options)
        if report is not None:
            from hdselect.figures import report_page, write_report

            if args.report == "-":
                report.write_text(report_page(result), encoding="utf-8")
            else:
                write_report(report, result)
        if json_file is not None:
            write_json(json_file, size_json(result))
        table = _rendered(size_table(result)) if "-" not in (args.json, args.report) else ""
        outputs.commit()
    sys.stdout.write(table)
    return 0 if result.feasible else 1


def run_compare(args: argparse.Namespace) -> int:
    """``hdselect compare``: every unit against every joint."""
    from hdselect.report import compare_table, console

    robot, motion, units, options = _prepare(args)
    for name in args.joint or []:
        if name not in robot.sized_joints:
            raise InputError(f"unknown joint '{name}'; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field="--joint")
    result = _sized(robot, motion, units, options)
    out = console()
    for joint in result.joints:
        if not args.joint or joint.name in args.joint:
            out.print(compare_table(result, joint))
    return 0 if result.feasible else 1


_PAYLOAD_FLAGS = {"payload.mass": "--payload", "payload.com": "--payload-com",
                  "payload.frame": "--payload-frame"}


def _load_case(args: argparse.Namespace):
    """The robot and the motion, with the command line's payload and mounting applied.

    ``--payload KG`` changes the mass of the motion file's payload and keeps its centre
    of mass, inertia and frame; ``--payload-com`` and ``--payload-frame`` change those of
    the file's payload (or of the one ``--payload`` makes) and are refused when there is
    none.
    """
    from hdselect.motion import load_motion, robot_file_of, robot_for_motion
    from hdselect.robot import Payload, load_robot

    robot = load_robot(args.robot if args.robot is not None else robot_file_of(args.motion))
    motion = load_motion(args.motion, robot)
    base = motion.payload
    given = [flag for flag, value in (("--payload", args.payload),
                                      ("--payload-com", args.payload_com),
                                      ("--payload-frame", args.payload_frame))
             if value is not None]
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
    try:
        robot = robot_for_motion(robot, motion, payload=payload, mounting=args.mounting)
    except InputError as err:
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
    """The robot, the motion, the catalog and the validated options of ``size``/``compare``."""
    from hdselect.catalog import load_catalog
    from hdselect.options import options_for

    robot, motion = _load_case(args)
    try:
        options = options_for(
            motion, stop_time=args.stop_time, efficiency=args.efficiency,
            rotor_inertia=args.motor_inertia, motor_mass=args.motor_mass,
            mass_coupling=not args.no_mass_coupling, prefer=args.prefer,
            life_hours=args.life_hours, life_basis=args.life_basis,
            max_samples=args.max_samples)
    except InputError as err:
        raise InputError(err.reason, field=_OPTION_FLAGS.get(str(err.field), err.field)) from err
    return robot, motion, load_catalog(args.catalog), options


def _sized(robot, motion, units, options):
    """Plan and size through the public core, as `hdselect.size` does."""
    from dataclasses import replace

    from hdselect.planning import plan
    from hdselect.sizing import size_trajectory

    trajectory = plan(robot, motion, max_samples=options.max_samples)
    return replace(size_trajectory(robot, trajectory, units, options), motion=motion)


def _rendered(table) -> str:
    """A table as the terminal would show it, rendered before any output is committed."""
    from hdselect.report import console

    out = console()
    with out.capture() as captured:
        out.print(table)
    return captured.get()


def _inputs(robot, motion) -> list[Path]:
    """The files a robot and a motion were read from."""
    files = [motion.path, robot.path]
    return files + ([motion.samples.path] if motion.samples is not None else [])


if __name__ == "__main__":
    sys.exit(main())
