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
    args = parser.parse_args(argv)
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

    fastest = commands.add_parser(
        "fastest", help="the shortest cycle of the motion's path that the gearheads allow")
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
        "max-payload", help="the largest payload with a feasible unit on every joint")
    _robot_motion(payload, mass=False)
    _sizing_options(payload)
    _json_option(payload)
    payload.set_defaults(run=run_max_payload)
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
                        help="link carrying the payload (default: the last link)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")


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
    joints = robot.sized_joints
    if args.plot:
        from hdselect.figures import write_profiles_png

        write_profiles_png(args.plot, trajectory, tau, joints,
                           title=f"{robot.path.name} running {motion.path.name}")
    write_trajectory_csv(args.out, trajectory, tau, joints)
    logger.info("wrote %d samples to %s", len(trajectory.t), args.out)
    return 0


def run_size(args: argparse.Namespace) -> int:
    """``hdselect size``: a gearhead for every joint."""
    from hdselect.export import size_json, write_json
    from hdselect.report import console, size_table

    result = _size(args)
    if args.report:
        from hdselect.figures import write_report

        write_report(args.report, result)
    if args.json:
        write_json(args.json, size_json(result))
    if args.json != "-":
        console().print(size_table(result))
    return 0 if result.feasible else 1


def run_compare(args: argparse.Namespace) -> int:
    """``hdselect compare``: every unit against every joint."""
    from hdselect.report import compare_table, console

    result = _size(args)
    names = [joint.name for joint in result.joints]
    for name in args.joint or []:
        if name not in names:
            raise InputError(f"unknown joint '{name}'; sized joints are: {', '.join(names)}",
                             field="--joint")
    out = console()
    for joint in result.joints:
        if not args.joint or joint.name in args.joint:
            out.print(compare_table(result, joint))
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
            for joint in comparison.joints:
                out.print(ratios_table(comparison, joint))
        else:
            out.print(fastest_table(result))
            out.print(binding_table(result))
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

            out.print(size_table(replace(result.selection, motion=motion)))
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
    return load_case(args.motion, args.robot, payload=payload, mounting=args.mounting)


def _size(args: argparse.Namespace):
    """Load, plan and size through the public core, as `hdselect.size` does."""
    from dataclasses import replace

    from hdselect.catalog import load_catalog
    from hdselect.planning import plan
    from hdselect.sizing import size_trajectory

    robot, motion = _load_case(args)
    options = _options(args, motion)
    _keep_inputs([getattr(args, "json", None)], [*_inputs(robot, motion), *args.catalog])
    if getattr(args, "report", None):
        _keep_inputs([Path(args.report) / "index.html"], _inputs(robot, motion))
    units = load_catalog(args.catalog)
    result = size_trajectory(robot, plan(robot, motion), units, options)
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
    return files + ([motion.samples.path] if motion.samples is not None else [])


def _keep_inputs(outputs: Sequence[str | Path | None], inputs: Sequence[str | Path]) -> None:
    """Refuse to write an output over a file the user gave as input."""
    given = {Path(file).resolve() for file in inputs}
    for output in outputs:
        if output is not None and str(output) != "-" and Path(output).resolve() in given:
            raise InputError("is an input file; choose another output path", path=output)


if __name__ == "__main__":
    sys.exit(main())
