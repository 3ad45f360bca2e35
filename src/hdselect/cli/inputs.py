"""A command's inputs: what the options several commands share give.

The robot and the motion with the flags applied, the validated sizing options and
the motors, each flag named in the message when it is bad.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path

from hdselect.base.errors import InputError
from hdselect.base.scheduler import DEFAULT_TIMEOUT, timeout_seconds
from hdselect.cli.placement import mounting_flag, mounting_option, one_mounting, source_angle_unit
from hdselect.motion.option_specs import OPTION, OPTIONS

SHOWN_LOGGERS = ("hdselect.robot.reading", "hdselect.motion.motionfile",
                 "hdselect.motion.planning.solve",
                 "hdselect.motion.planning", "hdselect.motion.planning.crossings")
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


ROBOT_FILE = "a robot file (URDF, xacro or MJCF)"
"""What a command's ROBOT is, for messages."""
_READ_BY = {"a motion file": "hdselect size FILE sizes it", "a mix file": "hdselect size FILE "
            "sizes it", "an envelope file": "hdselect envelope FILE reads it",
            "a study file": "hdselect study FILE runs it", "a duty profile": "hdselect duty "
            "FILE reads it", "a catalog file": "give it as --catalog FILE",
            "a motor file": "give it as --motor-catalog FILE"}
"""Where each kind of hdselect TOML file goes, said when it is given in the wrong place."""


def file_wanted(args: argparse.Namespace, file: str | Path, wants: str,
                accepted: tuple[str, ...] = (), read_by: Mapping[str, str] | None = None,
                field: str | None = None) -> None:
    """Refuse a TOML file of another kind where the command wants `wants`, saying what it is.

    Args:
        args: The command's arguments (``args.command`` names it).
        file: The file given.
        wants: What the command wants there, e.g. `ROBOT_FILE`.
        accepted: The kinds of TOML file taken there (`hdselect.base.tomlfile.toml_kind`).
        read_by: Where a kind of file goes instead, where this command says it otherwise
            (FILE stands for the file).
        field: The option that gave the file, when not a positional argument.

    Raises:
        InputError: `file` is a TOML file of another kind: one line naming the file, its
            kind, what the command wants and where the file goes.
    """
    from hdselect.base.inputfiles import read_input
    from hdselect.base.tomlfile import read_toml, toml_kind

    kind = toml_kind(read_input(Path(file)))
    if kind is None or kind in accepted:
        return
    said = f"{file} is {kind}" + ("" if kind == "a TOML file" else " (TOML)")
    hints = []
    motion = getattr(args, "motion", None)
    robot = read_toml(file).get("robot")
    goes = {**_READ_BY, **(read_by or {})}
    if file == getattr(args, "robot", None) and motion is not None and \
            toml_kind(read_input(Path(motion))) is None:
        hints.append("the order is ROBOT, then MOTION")
    elif wants == ROBOT_FILE and isinstance(robot, str):
        hints.append(f"the robot it names is {os.path.normpath(Path(file).parent / robot)}")
    elif kind in goes:
        hints.append(goes[kind].replace("FILE", str(file)))
    raise InputError(f"{said}; {args.command} wants {wants} here"
                     + (f" ({'; '.join(hints)})" if hints else ""), field=field)


_TOML_OPTIONS = (("catalog", "--catalog", "a catalog file"),
                 ("motor_catalog", "--motor-catalog", "a motor file"),
                 ("study", None, "a study file"), ("profile", None, "a duty profile"))
"""The TOML files options and arguments name: attribute, option (None: positional), kind."""


def toml_files_wanted(args: argparse.Namespace) -> None:
    """Refuse a catalog, motor, study or duty file that is another kind of hdselect file.

    A file of no known kind is left to its reader, whose message names the key at fault.

    Raises:
        InputError: As `file_wanted`, naming the option.
    """
    from hdselect.base.inputfiles import is_input_file

    for attribute, flag, kind in _TOML_OPTIONS:
        given = getattr(args, attribute, None)
        for file in given if isinstance(given, list) else [given] if given else []:
            if is_input_file(Path(file)):  # a missing file is the command's to refuse
                file_wanted(args, file, f"{kind} (TOML)", (kind, "a TOML file"), field=flag)


def robot_of(args: argparse.Namespace, named: Path | None = None):
    """The robot ROBOT names (else `named`, else the motion file's), with ``--xacro-arg``."""
    return robot_file_loaded(args, args.robot if args.robot is not None else named)


def robot_file_loaded(args: argparse.Namespace, file: str | Path | None):
    """The robot `file` (None: the one ``args.motion`` names), expanded with ``--xacro-arg``.

    Raises:
        InputError: As the robot's reading does; an argument refused is named where it
            came from (``--xacro-arg`` or the motion file's ``xacro_args``).
    """
    from hdselect.motion.robot_named import load_expanded, load_motion_robot
    from hdselect.robot.xacrofile import xacro_arguments

    given = xacro_arguments(args.xacro_arg, "--xacro-arg") if args.xacro_arg else {}
    if file is not None:
        file_wanted(args, file, ROBOT_FILE)
        return load_expanded(Path(file), ((None, "--xacro-arg", given),))
    return load_motion_robot(args.motion, given, given_as="--xacro-arg")


def _other_robot(args: argparse.Namespace, err: InputError) -> InputError:
    """`err` (about a joint), saying so where the motion file names another robot than ROBOT."""
    from hdselect.base.tomlfile import read_toml

    named = read_toml(args.motion).get("robot") if args.robot is not None else None
    if not isinstance(named, str) or "joint" not in err.reason:
        return err
    named = os.path.normpath(Path(args.motion).parent / named)
    if Path(named).resolve() == Path(args.robot).resolve():
        return err
    return InputError(f"{err.reason} (the motion file is written for {named}, not for the "
                      f"ROBOT given, {args.robot})", path=err.path, field=err.field)


def robot_and_motion(args: argparse.Namespace):
    """The robot and the motion (or mix), with the command line's payload, mounting and joints.

    ``--payload KG`` changes the mass of the motion file's payload and keeps its centre
    of mass, inertia and frame; ``--payload-com`` and ``--payload-frame`` change those of
    the file's payload (or of the one ``--payload`` makes) and are refused when there is
    none. A payload without a frame goes on the robot's default payload frame. A mix
    file's tasks carry their own payloads; ``--mounting`` goes on every task.
    """
    from hdselect.motion.loading import load_case, robot_for_motion
    from hdselect.motion.mixfile import is_mix_file, load_mix, mix_robot_file
    from hdselect.motion.motionfile import load_motion
    from hdselect.motion.planning.hints import allowing_flips
    from hdselect.motion.planning.solve import solve_motion

    file_wanted(args, args.motion, "a motion file or a mix file (TOML)",
                ("a motion file", "a mix file", "a TOML file"))
    one_mounting(args)
    mix = is_mix_file(args.motion)
    if mix:
        for flag in ("payload", "payload_com", "payload_frame"):
            if getattr(args, flag, None) is not None:
                raise InputError("a mix's tasks carry their own payloads: give each task's "
                                 "`payload` in the mix file",
                                 field="--" + flag.replace("_", "-"))
    robot = robot_of(args, mix_robot_file(args.motion) if mix else None)
    if mix:
        mixed = allowing_flips(load_mix(args.motion, robot), getattr(args, "allow_flip", False))
        joints, exclude = _joint_flags(args)
        mounting = mounting_flag(args, source_angle_unit(mixed))
        with _flags_named(args, joints, exclude, None):
            return load_case(mixed, robot, mounting=mounting, joints=joints, exclude=exclude)
    try:
        motion = load_motion(args.motion, robot)
    except InputError as err:
        raise _other_robot(args, err) from err
    motion = allowing_flips(motion, getattr(args, "allow_flip", False))
    payload = _payload_of(args, motion)
    joints, exclude = _joint_flags(args)
    mounting = mounting_flag(args, motion.angle_unit)
    with _flags_named(args, joints, exclude, payload, motion.path):
        robot = robot_for_motion(robot, motion, payload=payload, mounting=mounting,
                                 joints=joints, exclude=exclude)
    return robot, solve_motion(robot, motion)  # its messages name the motion file's fields


def _joint_flags(args: argparse.Namespace) -> tuple[list[str] | None, list[str] | None]:
    """The joints of ``--joints`` and ``--exclude`` (None: not given)."""
    return joint_names(args.joints, "--joints"), joint_names(args.exclude, "--exclude")


@contextmanager
def _flags_named(args: argparse.Namespace, joints: list[str] | None,
                 exclude: list[str] | None, payload, path: Path | None = None):
    """Name the flag behind an error of the robot's set-up, where a flag gave the value."""
    try:
        yield
    except InputError as err:
        given = {"joints": joints, "exclude": exclude}
        if err.field in given and given[str(err.field)] is not None:
            raise InputError(err.reason, field=f"--{err.field}") from err
        if err.field == "payload.frame" and args.payload_frame is not None:
            raise InputError(err.reason, field="--payload-frame") from err
        if err.field == "payload.frame" and payload is not None:
            raise InputError(err.reason, path=path, field="payload.frame") from err
        if str(err.field).startswith("mounting") and mounting_option(args) is not None:
            raise InputError(err.reason, field=mounting_option(args)) from err
        raise


def _payload_of(args: argparse.Namespace, motion):
    """The payload the flags make of the motion file's, or None where no flag is given.

    Raises:
        InputError: A flag changes a payload the file does not give, or is invalid.
    """
    from hdselect.robot.payload import Payload

    base = motion.payload
    given = [flag for flag, value in (("--payload", args.payload),
                                      ("--payload-com", args.payload_com),
                                      ("--payload-frame", args.payload_frame))
             if value is not None] if hasattr(args, "payload") else []  # max-payload: its own
    if not given:
        return None
    if base is None and args.payload is None:
        raise InputError(f"the motion file gives no payload for {given[0]} to change; give "
                         "its mass with --payload KG", path=motion.path, field=given[0])
    mass = float(args.payload) if args.payload is not None else base.mass
    try:
        return Payload(
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


def unit_pairs(pairs: Sequence[str]) -> dict[str, str]:
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


def flagged(err: InputError, args: argparse.Namespace) -> InputError:
    """An error of the library with the command line's option as its field."""
    field = str(err.field)
    flag = {"units": "--units", "joint": "--joint", "joints": "--joint"}.get(field)
    if field.startswith("motors") and args.motor_catalog:
        flag = "--motor-catalog"
    return InputError(err.reason, path=err.path, field=flag or err.field)


def timeout_of(args: argparse.Namespace) -> float:
    """The ``--timeout`` given, else the default [s]; refused without ``--scheduler``."""
    if args.timeout is None:
        return DEFAULT_TIMEOUT
    if args.scheduler is None:
        raise InputError("bounds connecting to a Dask scheduler: give --scheduler too",
                         field="--timeout")
    return timeout_seconds(args.timeout, "--timeout")


def max_samples_of(args: argparse.Namespace) -> int:
    """The --max-samples flag, checked."""
    from hdselect.base.bounds import check_max_samples

    return check_max_samples(args.max_samples, field="--max-samples")


def catalog_of(args: argparse.Namespace):
    """The units of ``--catalog`` (and the built-in PSA-G), of ``--series`` where given."""
    from hdselect.catalog.builtin import of_series
    from hdselect.catalog.catalogfile import load_catalog

    return of_series(load_catalog(args.catalog), args.series, field="--series")


def series_of(args: argparse.Namespace, problem):
    """The problem with its units restricted to ``--series`` (where given)."""
    from dataclasses import replace

    from hdselect.catalog.builtin import of_series

    if not getattr(args, "series", None):
        return problem
    return replace(problem, units=of_series(problem.units, args.series, field="--series"))


def sizing_problem(args: argparse.Namespace, *, plan: bool = False):
    """The resolved problem of the flags (`hdselect.sizing.problem.Problem`), unplanned.

    Everything is read and checked before any planning: the robot and the motion (or
    mix) with the flags applied, the motors, the options and the catalog.
    """
    from hdselect.sizing.arguments import check_joint_options
    from hdselect.sizing.problem import problem_of

    robot, motion = robot_and_motion(args)
    motors = motors_of(args, robot, motion)
    options = sizing_options_of(args, motion)
    problem = problem_of(robot, motion, catalog=args.catalog, motors=motors, options=options,
                         plan=plan, mounting=mounting_flag(args, source_angle_unit(motion)))
    try:
        check_joint_options(problem.robot, options)
    except InputError as err:  # a joint a flag names: the flag's words
        option = OPTION.get(str(err.field).split(".")[0])
        if err.path is None and option is not None and option.flag is not None \
                and getattr(args, str(option.dest), None) is not None:
            raise InputError(err.reason, field=option.flag) from err
        raise
    return series_of(args, problem)


def sizing_case(args: argparse.Namespace):
    """The robot, the motion (or mix), the catalog, the options and the motors, unplanned."""
    problem = sizing_problem(args)
    return problem.robot, problem.source, problem.units, problem.options, problem.motors


def motors_of(args: argparse.Namespace, robot, motion) -> dict:
    """The candidate motors per sized joint: ``--motor-catalog``'s, else the motion file's.

    Raises:
        InputError: ``--motor-inertia`` or ``--motor-mass`` is given beside the motors.
    """
    from hdselect.catalog.motors import load_motors
    from hdselect.sizing.problem import file_motors

    if args.motor_catalog:
        catalog = load_motors(args.motor_catalog)
        motors = {name: catalog for name in robot.sized_joints}
    else:
        motors = file_motors(robot, motion)
    refuse_pair_flags(args, bool(motors))
    if motors:
        for flag in ("--motor-inertia", "--motor-mass"):
            if getattr(args, flag[2:].replace("-", "_"), None) is not None:
                given = ("--motor-catalog" if args.motor_catalog
                         else f"[motor] of {motion.path.name}")
                raise InputError(f"the motors come from {given}, with their own rotor inertia "
                                 "and mass; drop this option", field=flag)
    return motors


MOTOR_ORDERS = tuple(order for order in OPTION["prefer"].choices
                     if OPTION["prefer"].needs_motors(order))
"""The selection orders (``--prefer``) that rank gearhead and motor pairs by the motor."""


def refuse_pair_flags(args: argparse.Namespace, motors: bool) -> None:
    """Refuse the flags that would act on nothing: each acts on gearhead and motor pairs.

    An option that acts only with another's value (``--inertia-target``: ``--prefer
    inertia``) is refused without it; one that acts on pairs (`Option.pairs`: the motor
    orders of ``--prefer``, ``--max-inertia-ratio``, ``--inertia-target``) only where
    motors are given. A command takes the flags it offers (``plan``: neither).

    Raises:
        InputError: One is given where it cannot act; the message names both flags.
    """
    given = flag_options(args)
    for name, value in given.items():
        requires = OPTION[name].requires
        if value is not None and requires is not None and given.get(requires[0]) != requires[1]:
            other = f"{OPTION[requires[0]].flag} {requires[1]}"
            raise InputError(f"{OPTION[name].help}: without {other} it acts on nothing; give "
                             "both, or neither", field=OPTION[name].flag)
    if motors:
        return
    for name, value in sorted(given.items(), key=lambda item: OPTION[item[0]].kind == "choice"):
        option = OPTION[name]  # a flag that acts on pairs named before an order of them
        if option.needs_motors(value):
            what = f"'{value}' {option.noun}s" if option.kind == "choice" else "judges"
            raise InputError(f"{what} gearhead and motor pairs, and no motor is given: give "
                             "--motor-catalog (or a [motor] table in the motion file)",
                             field=option.flag)


def sizing_options_of(args: argparse.Namespace, motion):
    """The validated options of the sizing flags, the motion file's where a flag is absent.

    A command takes the flags it offers (``plan``: the few its torques depend on); a
    switch's flag gives the value opposite its default.

    For a mix: the mix file's, else what its motions agree on (`source_options`).
    """
    from hdselect.sizing.problem import source_options

    given = flag_options(args)
    try:
        return source_options(motion, **given)
    except InputError as err:
        if err.path is not None:
            raise
        flag = OPTION[str(err.field)].flag if str(err.field) in OPTION else None
        raise InputError(err.reason, field=flag or err.field) from err


def flag_options(args: argparse.Namespace) -> dict[str, object]:
    """The options whose flags the command offers, by name: None where a flag is not given.

    A switch's flag given is the value opposite the option's default; a value in the
    flag's unit (arcmin, mm) or an application class is in SI (`Option.from_flag`).

    Raises:
        InputError: A value that is no number (or class) or out of range, naming the flag.
    """
    given: dict[str, object] = {}
    for option in OPTIONS:
        if option.dest is not None and hasattr(args, option.dest):
            value = getattr(args, option.dest)
            if option.kind == "switch":
                value = (not option.default) if value else None
            given[option.name] = option.from_flag(value)
    return given


def input_files(robot, motion) -> list[Path]:
    """The files a robot and a motion (or mix) were read from (logs and motor files included)."""
    from hdselect.sizing.problem import source_files

    return source_files(robot, motion)
