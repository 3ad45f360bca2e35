"""A command's inputs: the options several commands share, and what they give.

The robot and the motion with the flags applied, the validated sizing options and
the motors, each flag named in the message when it is bad.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError


def catalog_argument(parser: argparse.ArgumentParser) -> None:
    """--catalog: extra catalog files."""
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog file (TOML; repeatable)")


def json_argument(parser: argparse.ArgumentParser) -> None:
    """--json FILE."""
    parser.add_argument("--json", metavar="FILE",
                        help="also write JSON to FILE ('-': to stdout, instead of the table)")


def xacro_argument(parser: argparse.ArgumentParser) -> None:
    """--xacro-arg NAME:=VALUE (repeatable): a .xacro robot's arguments."""
    parser.add_argument("--xacro-arg", metavar="NAME:=VALUE", action="append",
                        dest="xacro_arg", help="an argument of a .xacro robot file "
                        "(repeatable; overrides the motion file's xacro_args)")


def robot_motion_arguments(parser: argparse.ArgumentParser, *, mass: bool = True,
                           sizes: bool = True) -> None:
    """ROBOT, MOTION and the flags that change the case: payload, mounting, joints, samples.

    Args:
        parser: The command's parser.
        mass: Offer --payload (max-payload finds the mass instead).
        sizes: The command sizes joints (plan only draws them).
    """
    parser.add_argument("robot", nargs="?", metavar="ROBOT",
                        help="robot file, URDF, xacro or MJCF (default: the motion file's "
                             "`robot`)")
    parser.add_argument("motion", metavar="MOTION", help="motion file (TOML)")
    xacro_argument(parser)
    if mass:
        parser.add_argument("--payload", type=float, metavar="KG",
                            help="payload mass [kg]; the motion file's payload keeps its centre "
                                 "of mass, inertia and frame")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="payload centre of mass in its frame [m] (changes the motion "
                             + ("file's payload, or the one --payload gives)" if mass else
                                "file's payload; without one, puts a point mass there)"))
    parser.add_argument("--payload-frame", metavar="LINK",
                        help="link carrying the payload (default: the motion file's, else the "
                             "tip of the longest chain of sized joints)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")
    doing = "size" if sizes else "plot"
    parser.add_argument("--joints", metavar="A,B", action="append",
                        help=f"{doing} only these joints (comma-separated; overrides the motion "
                             "file's [sizing] joints)" + ("" if sizes else "; the CSV has every "
                                                          "joint"))
    parser.add_argument("--exclude", metavar="A,B", action="append",
                        help=f"do not {doing} these joints; they still move and load the others "
                             "(overrides the motion file's [sizing] exclude)")
    parser.add_argument("--max-samples", type=int, metavar="N",
                        default=DEFAULT_MAX_SAMPLES,
                        help="refuse a trajectory of more samples than this, before allocating "
                             f"it (default {DEFAULT_MAX_SAMPLES:,}: an 8-hour log at 1 kHz)")


def sizing_arguments(parser: argparse.ArgumentParser) -> None:
    """The flags of the sizing assumptions (`hdselect.sizing.core.options.Options`)."""
    from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, PREFERENCES
    from hdselect.motion.motionfile import LIFE_BASES
    from hdselect.sizing.options import Options

    defaults = Options()
    catalog_argument(parser)
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
    margin_argument(parser)
    parser.add_argument("--max-inertia-ratio", type=float, metavar="R",
                        help="a gearhead and motor pair whose load-to-rotor inertia ratio is "
                             "above R is not feasible (default: the motor file's "
                             "max_inertia_ratio, else none)")
    parser.add_argument("--inertia-target", type=float, metavar="R",
                        help="the load-to-rotor inertia ratio --prefer inertia aims at "
                             f"(default {defaults.inertia_target:g})")


def margin_argument(parser: argparse.ArgumentParser) -> None:
    """--margin: the design margin every rule must keep."""
    parser.add_argument("--margin", type=float, metavar="M",
                        help="design margin: every rule must hold at (1 - M) of its limit, "
                             "e.g. 0.2 for 80 %% (default: the motion file's [requirements] "
                             "margin, else 0)")


_OPTION_FLAGS = {"stop_time": "--stop-time", "efficiency": "--efficiency",
                 "rotor_inertia": "--motor-inertia", "motor_mass": "--motor-mass",
                 "prefer": "--prefer", "life_hours": "--life-hours",
                 "life_basis": "--life-basis", "max_samples": "--max-samples",
                 "margin": "--margin", "max_inertia_ratio": "--max-inertia-ratio",
                 "inertia_target": "--inertia-target"}
"""The command-line option of each field of `hdselect.sizing.options.Options`."""


SHOWN_LOGGERS = ("hdselect.robot.reading", "hdselect.motion.motionfile", "hdselect.motion.solve")
"""Loggers whose warnings a sizing result carries (`SizingResult.warnings`)."""


_PAYLOAD_FLAGS = {"payload.mass": "--payload", "payload.com": "--payload-com",
                  "payload.frame": "--payload-frame"}


def joint_names(given: list[str] | None, flag: str) -> list[str] | None:
    """Joint names from a repeatable, comma-separated option (None: not given).

    Raises:
        InputError: An occurrence of the option names no joint (only commas): it is
            refused, never read as not given.
    """
    if given is None:
        return None
    for text in given:
        if not text.replace(",", "").strip():
            raise InputError(f"expected joint names, got {text!r}", field=flag)
    return [name.strip() for text in given for name in text.split(",") if name.strip()]


def robot_of(args: argparse.Namespace, named: Path | None = None):
    """The robot ROBOT names (else `named`, else the motion file's), with ``--xacro-arg``."""
    return robot_file_loaded(args, args.robot if args.robot is not None else named)


def robot_file_loaded(args: argparse.Namespace, file: str | Path | None):
    """The robot `file` (None: the one ``args.motion`` names), expanded with ``--xacro-arg``.

    Raises:
        InputError: As the robot's reading does; arguments given for a file that takes
            none are refused naming ``--xacro-arg``.
    """
    from hdselect.motion.robot_named import load_motion_robot
    from hdselect.robot.model import load_robot
    from hdselect.robot.xacrofile import xacro_arguments

    given = xacro_arguments(args.xacro_arg, "--xacro-arg") if args.xacro_arg else None
    try:
        if file is not None:
            return load_robot(file, xacro_args=given)
        return load_motion_robot(args.motion, given)
    except InputError as err:
        if err.field == "xacro_args" and given:  # given for a file that takes none
            raise InputError(err.reason, path=err.path, field="--xacro-arg") from err
        raise


def robot_and_motion(args: argparse.Namespace):
    """The robot and the motion, with the command line's payload, mounting and joints applied.

    ``--payload KG`` changes the mass of the motion file's payload and keeps its centre
    of mass, inertia and frame; ``--payload-com`` and ``--payload-frame`` change those of
    the file's payload (or of the one ``--payload`` makes) and are refused when there is
    none. A payload without a frame goes on the robot's default payload frame.
    """
    from hdselect.motion.case import robot_for_motion
    from hdselect.motion.mixfile import is_mix_file
    from hdselect.motion.motionfile import load_motion
    from hdselect.motion.solve import solve_motion
    from hdselect.robot.payload import Payload

    if is_mix_file(args.motion):
        return _robot_and_mix(args)
    robot = robot_of(args)
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
    joints = joint_names(args.joints, "--joints")
    exclude = joint_names(args.exclude, "--exclude")
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
    return robot, solve_motion(robot, motion)


def _robot_and_mix(args: argparse.Namespace):
    """The robot with the mix's sized joints, and the mix with ``--mounting`` on every task."""
    from hdselect.motion.case import robot_for_mix
    from hdselect.motion.mixfile import load_mix, mix_robot_file

    for flag in ("payload", "payload_com", "payload_frame"):
        if getattr(args, flag, None) is not None:
            raise InputError("a mix's tasks carry their own payloads: give each task's "
                             "`payload` in the mix file", field="--" + flag.replace("_", "-"))
    robot = robot_of(args, mix_robot_file(args.motion))
    mix = load_mix(args.motion, robot)
    if args.mounting is not None:
        try:
            robot.with_mounting(args.mounting)
        except InputError as err:
            raise InputError(err.reason, field="--mounting") from err
        mix = mix.with_mounting(args.mounting)
    joints = joint_names(args.joints, "--joints")
    exclude = joint_names(args.exclude, "--exclude")
    try:
        return robot_for_mix(robot, mix, joints=joints, exclude=exclude), mix
    except InputError as err:
        given = {"joints": joints, "exclude": exclude}
        if err.field in given and given[str(err.field)] is not None:
            raise InputError(err.reason, field=f"--{err.field}") from err
        raise


def max_samples_of(args: argparse.Namespace) -> int:
    """The --max-samples flag, checked."""
    from hdselect.base.bounds import check_max_samples

    return check_max_samples(args.max_samples, field="--max-samples")


def sizing_case(args: argparse.Namespace):
    """The robot, the motion, the catalog, the validated options and the motors."""
    from hdselect.catalog.catalogfile import load_catalog
    from hdselect.catalog.motors import load_motors
    from hdselect.motion.mixfile import Mix
    from hdselect.sizing.core import motion_motors
    from hdselect.sizing.duty import mix_motors

    robot, motion = robot_and_motion(args)
    if args.motor_catalog:
        catalog = load_motors(args.motor_catalog)
        motors = {name: catalog for name in robot.sized_joints}
    elif isinstance(motion, Mix):
        motors = mix_motors(robot, motion)
    else:
        motors = motion_motors(robot, motion)
    refuse_pair_flags(args, bool(motors))
    if motors:
        for value, flag in ((args.motor_inertia, "--motor-inertia"),
                            (args.motor_mass, "--motor-mass")):
            if value is not None:
                given = ("--motor-catalog" if args.motor_catalog
                         else f"[motor] of {motion.path.name}")
                raise InputError(f"the motors come from {given}, with their own rotor inertia "
                                 "and mass; drop this option", field=flag)
    options = sizing_options_of(args, motion)
    extra = list(motion.catalog) if isinstance(motion, Mix) else []
    return robot, motion, load_catalog([*extra, *args.catalog]), options, motors


MOTOR_ORDERS = ("motor-rms", "motor-peak", "inertia")
"""The selection orders (``--prefer``) that rank gearhead and motor pairs by the motor."""


def refuse_pair_flags(args: argparse.Namespace, motors: bool) -> None:
    """Refuse the flags that would act on nothing: each acts on gearhead and motor pairs.

    ``--inertia-target`` acts only with ``--prefer inertia``; that order, the motor
    orders and ``--max-inertia-ratio`` only where motors are given.

    Raises:
        InputError: One is given where it cannot act; the message names both flags.
    """
    if args.inertia_target is not None and args.prefer != "inertia":
        raise InputError("the ratio --prefer inertia aims at: without --prefer inertia it acts "
                         "on nothing; give both, or neither", field="--inertia-target")
    if motors:
        return
    for flag, given in (("--max-inertia-ratio", args.max_inertia_ratio is not None),
                        ("--inertia-target", args.inertia_target is not None),
                        ("--prefer", args.prefer in MOTOR_ORDERS)):
        if given:
            what = f"'{args.prefer}' orders" if flag == "--prefer" else "judges"
            raise InputError(f"{what} gearhead and motor pairs, and no motor is given: give "
                             "--motor-catalog (or a [motor] table in the motion file)",
                             field=flag)


def planned_and_sized(robot, motion, units, options, motors):
    """Plan and size through the public core, as `hdselect.size` does."""
    from dataclasses import replace

    from hdselect.motion.mixfile import Mix
    from hdselect.motion.planning import plan
    from hdselect.sizing.core import size_tasks, size_trajectory
    from hdselect.sizing.duty import mix_tasks

    if isinstance(motion, Mix):
        tasks, idle = mix_tasks(robot, motion, joints=robot.sized_joints, exclude=(),
                                max_samples=options.max_samples)
        return replace(size_tasks(tasks, units, options, motors=motors, idle=idle), mix=motion)
    trajectory = plan(robot, motion, max_samples=options.max_samples)
    return replace(size_trajectory(robot, trajectory, units, options, motors=motors),
                   motion=motion)


def sizing_options_of(args: argparse.Namespace, motion):
    """The validated options of the sizing flags, the motion file's where a flag is absent.

    For a mix: the mix file's, else what its motions agree on (`hdselect.sizing.duty`).
    """
    from hdselect.motion.mixfile import Mix
    from hdselect.sizing.duty import mix_options
    from hdselect.sizing.options import options_for

    given = {"stop_time": args.stop_time, "efficiency": args.efficiency,
             "rotor_inertia": args.motor_inertia, "motor_mass": args.motor_mass,
             "mass_coupling": not args.no_mass_coupling, "prefer": args.prefer,
             "life_hours": args.life_hours, "life_basis": args.life_basis,
             "max_samples": args.max_samples, "margin": args.margin,
             "max_inertia_ratio": args.max_inertia_ratio, "inertia_target": args.inertia_target}
    if isinstance(motion, Mix) and not args.no_mass_coupling:
        given["mass_coupling"] = None  # the mix file's, else on
    try:
        return (mix_options(motion, **given) if isinstance(motion, Mix)
                else options_for(motion, **given))
    except InputError as err:
        if err.path is not None:
            raise
        raise InputError(err.reason, field=_OPTION_FLAGS.get(str(err.field), err.field)) from err


def input_files(robot, motion) -> list[Path]:
    """The files a robot and a motion (or mix) were read from (logs and motor files included)."""
    from hdselect.motion.mixfile import Mix

    if isinstance(motion, Mix):
        files = [motion.path, *motion.catalog]
        for item in dict.fromkeys(motion.motions):
            files += [f for f in input_files(robot, item) if f not in files]
        mine = {m.source for ms in (motion.given.get("motors") or {}).values() for m in ms
                if m.source}
        return files + sorted(f for f in mine if f not in files)
    files = [motion.path, robot.path]
    motors = {m.source for ms in (motion.motors or {}).values() for m in ms if m.source}
    return files + ([motion.samples.path] if motion.samples is not None else []) + sorted(motors)
