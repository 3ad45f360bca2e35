"""``hdselect envelope``: a unit per joint for any motion within a spec."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from hdselect.base.errors import InputError
from hdselect.cli.arguments import base_argument, json_argument
from hdselect.cli.inputs import (
    MOTOR_ORDERS,
    catalog_of,
    flag_options,
    joint_names,
    sizing_options_of,
    timeout_of,
)
from hdselect.cli.output import EXIT_NO_FIT, EXIT_OK, rendered, say_written, to_stdout
from hdselect.cli.placement import mounting_flag

_ANGLE = {"deg": math.pi / 180.0, "rad": 1.0}
_SPEC_SUFFIXES = (".toml",)
_AS_DUTY = "give it as --duty FILE: the cycle the mean torque and life are judged on"


def envelope_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``hdselect envelope``."""
    from hdselect.catalog.select import DEFAULT_PREFER, PREFERENCES
    from hdselect.cli.arguments import (
        option_help,
        scheduler_arguments,
        sizing_arguments,
        xacro_argument,
    )
    from hdselect.motion.option_specs import OPTIONS

    parser.add_argument("target", metavar="ROBOT",
                        help="robot file (URDF, xacro, MJCF), or an envelope file (TOML) that "
                             "names its robot")
    parser.add_argument("spec", nargs="?", metavar="SPEC",
                        help="envelope file (TOML): [limits], payload, mounting, [duty] ...")
    for kind, unit, default in (
            ("velocity", "/s", "default: the envelope file's, else the robot file's"),
            ("acceleration", "/s^2", "default: the envelope file's; no other"),
            ("jerk", "/s^3", "of the default duty's moves only (refused beside --duty or "
                             "a [duty] motion); "
                             "default: the envelope file's, else acceleration / 0.05 s")):
        parser.add_argument(
            f"--{kind}", action="append", metavar="V|JOINT=V",
            help=f"{kind} limit [deg{unit}, or rad with --angle-unit rad; m{unit} for a "
                 "prismatic joint]: one number for every joint, or JOINT=V (repeatable, "
                 f"comma-separated); {default}")
    xacro_argument(parser)
    parser.add_argument("--angle-unit", choices=tuple(_ANGLE), default="deg",
                        help="unit of the angles in --velocity, --acceleration, --jerk, --base "
                             "(default: deg)")
    parser.add_argument("--payload", type=float, metavar="KG",
                        help="payload mass [kg]; the file's payload keeps its centre of mass, "
                             "inertia and frame")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="payload centre of mass in its frame [m]")
    parser.add_argument("--payload-frame", metavar="LINK", help="link carrying the payload")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the file's")
    base_argument(parser, "--angle-unit's")
    parser.add_argument("--joints", metavar="A,B", action="append", help="size only these")
    parser.add_argument("--exclude", metavar="A,B", action="append",
                        help="do not size these joints; they still move and load the others")
    parser.add_argument("--duty", metavar="MOTION",
                        help="motion file whose cycle the mean torque and life are judged on, "
                             "or a mix file: its tasks pooled by share, as size pools them "
                             "(default: the file's [duty], else random moves at the limits)")
    parser.add_argument("--moves", type=int, metavar="N",
                        help="moves of the default duty (default: 20); refused beside --duty "
                             "or a [duty] motion")
    parser.add_argument("--seed", type=int, metavar="N",
                        help="seed of the default duty's random poses (default: 0); refused "
                             "beside --duty or a [duty] motion")
    parser.add_argument("--starts", type=int, metavar="N",
                        help="quasi-random starts of the search's first round, a power of 2 "
                             "from 64 to 65536 (default 4096; later rounds take 4N, 16N)")
    parser.add_argument("--max-samples", type=int, metavar="N", default=None,
                        help="refuse a duty of more samples than this")
    sizing_arguments(parser)
    for action in parser._actions:  # the shared flags, as the envelope reads them
        option = next((o for o in OPTIONS if o.dest == action.dest), None)
        if action.dest == "motor_catalog" or (option is not None and option.pairs is True):
            action.help = argparse.SUPPRESS  # the envelope chooses no motors yet: refused
        elif option is not None and "envelope" in option.files:
            action.help = option_help(option.name, "envelope", then=("the duty",))
        if action.dest == "prefer":  # no motors: the orders of gearheads alone
            action.choices = tuple(k for k in PREFERENCES if k not in MOTOR_ORDERS)
            action.help = "; ".join(f"{k}: {PREFERENCES[k][0]}" for k in action.choices) + (
                f" (default: {DEFAULT_PREFER})")
    json_argument(parser)
    parser.add_argument("--report", metavar="DIR",
                        help="write an HTML page of the envelope into DIR, the duty's own "
                             "sizing report beside it in DIR/duty ('-': the page alone, to "
                             "stdout)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="compute the search's states in N worker processes (with "
                             "--scheduler, Dask workers); default: this process, every core")
    scheduler_arguments(parser)


def run_envelope(args: argparse.Namespace) -> int:
    """``hdselect envelope``: the unit per joint for any motion within a spec."""
    from hdselect.base.outputs import Outputs
    from hdselect.envelope.records import envelope_json
    from hdselect.envelope.run import envelope
    from hdselect.envelope.search import SearchSettings
    from hdselect.report.envelope_tables import envelope_table, limits_table, states_text
    from hdselect.report.export import write_json

    for flag, value in (("--motor-catalog", args.motor_catalog),
                        ("--max-inertia-ratio", args.max_inertia_ratio),
                        ("--inertia-target", args.inertia_target)):
        if value is not None:
            raise InputError("envelope does not choose motors yet; size a motion with "
                             "`hdselect size --motor-catalog`", field=flag)
    mounting = mounting_flag(args, args.angle_unit)
    robot, spec = _robot_and_spec(args)
    options = sizing_options_of(args, None)
    try:
        settings = SearchSettings(**({} if args.starts is None else {"starts": args.starts}))
    except InputError as err:
        raise _flagged(err) from err
    inputs = [p for p in (robot.path, spec, args.duty, *args.catalog) if p is not None]
    with Outputs(inputs) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json else None
        report = None
        if args.report == "-":
            report = outputs.file("-", "--report")
        elif args.report:
            report = outputs.directory(args.report, "--report")
        try:
            result = envelope(
                robot, spec, velocity=_limits(args, "velocity", robot),
                acceleration=_limits(args, "acceleration", robot),
                jerk=_limits(args, "jerk", robot), payload=_payload(args, robot, spec),
                mounting=mounting, joints=joint_names(args.joints, "--joints"),
                exclude=joint_names(args.exclude, "--exclude"), duty=args.duty, moves=args.moves,
                seed=args.seed, catalog=catalog_of(args), settings=settings,
                workers=args.workers, scheduler=args.scheduler, timeout=timeout_of(args),
                **{name: getattr(options, name) for name, value in flag_options(args).items()
                   if value is not None})
        except InputError as err:
            raise _flagged(err) from err
        if json_file is not None:
            write_json(json_file, envelope_json(result))
        if report is not None:
            _write_report(args, result, report)
        text = "" if to_stdout(args) else rendered(envelope_table(result), "",
                                                      limits_table(result), "",
                                                      states_text(result),
                                                      *_precision(result))
        outputs.commit()
    sys.stdout.write(text)
    page = args.report if args.report in (None, "-") else str(Path(args.report) / "index.html")
    say_written([(page, "the envelope, with the duty's own report in duty/"
                  if args.report != "-" else None), (args.json, None)], args)
    return EXIT_OK if result.feasible else EXIT_NO_FIT


def _precision(result) -> list[object]:
    """The duty's precision section, said to be the duty's (the worst states have no cycle)."""
    from hdselect.report.precision_tables import precision_tables
    from hdselect.report.tables import Paragraphs

    section = precision_tables(result.sizing)
    if result.sizing.precision is None or not any(j.rated for j in result.sizing.precision.joints):
        return section
    return [*section, Paragraphs(("The precision figures above are the duty's, along its "
                                  "samples; the worst states of the spec are judged by the "
                                  "per-joint targets' rules (the table above the spec), not "
                                  "drawn here.",))]


def _write_report(args: argparse.Namespace, result, report: Path) -> None:
    """The HTML page (``--report -``) or the report directory, into its staged place."""
    from hdselect.report.envelope_html import envelope_page, write_envelope_report
    from hdselect.report.provenance import provenance

    if args.report == "-":
        report.write_text(envelope_page(result, provenance(result.sizing, args.command_line),
                                        duty_report=False), encoding="utf-8")
    else:
        write_envelope_report(report, result, command=args.command_line)


def _flagged(err: InputError) -> InputError:
    """An error of a Python argument renamed to the flag that gave it."""
    field = str(err.field or "")
    if err.path is None and field.startswith(("payload.com", "payload.frame")):
        return InputError(err.reason, field="--" + field.split("[")[0].replace(".", "-"))
    for kind in ("velocity", "acceleration", "jerk", "payload", "mounting", "joints", "exclude",
                 "duty", "moves", "seed", "starts", "workers", "scheduler", "timeout",
                 "max_tool_deflection", "min_arm_frequency"):
        if err.path is None and (field == kind or field.startswith(f"{kind}.")):
            return InputError(err.reason, field=f"--{kind.replace('_', '-')}")
    return err


def _robot_and_spec(args: argparse.Namespace):
    """The robot file loaded and the envelope file, from ROBOT [SPEC]."""
    from hdselect.cli.inputs import ROBOT_FILE, file_wanted, robot_file_loaded
    from hdselect.envelope.specfile import envelope_robot_file

    target = Path(args.target)
    spec_kinds, duty = ("an envelope file", "a TOML file"), {"a motion file": _AS_DUTY}
    if args.spec is not None:
        file_wanted(args, args.spec, "an envelope file (TOML)", spec_kinds, duty)
        return robot_file_loaded(args, target), Path(args.spec)
    if target.suffix.lower() in _SPEC_SUFFIXES:
        file_wanted(args, target, f"{ROBOT_FILE} or an envelope file (TOML)", spec_kinds, duty)
        return robot_file_loaded(args, envelope_robot_file(target)), target
    return robot_file_loaded(args, target), None


def _limits(args: argparse.Namespace, kind: str, robot) -> dict[str, float] | None:
    """A limit flag as joint name -> SI value (a bare number: every joint)."""
    from hdselect.base.bounds import MOTION_LIMITS

    given = getattr(args, kind)
    if not given:
        return None
    flag = f"--{kind}"
    angle = _ANGLE[args.angle_unit]
    power = {"velocity": "/s", "acceleration": "/s^2", "jerk": "/s^3"}[kind]
    out: dict[str, float] = {}
    named: dict[str, float] = {}
    for text in given:
        if not text.replace(",", "").strip():
            raise InputError(f"expected a number or JOINT=NUMBER, got {text!r}", field=flag)
    for item in (part.strip() for text in given for part in text.split(",") if part.strip()):
        name, sep, number = item.rpartition("=")
        try:
            value = float(number)
        except ValueError:
            raise InputError(f"expected a number or JOINT=NUMBER, got {item!r}",
                             field=flag) from None
        if sep:
            j = robot.joint_index(name.strip(), field=flag)
            scale = angle if robot.revolute[j] else 1.0
            unit = (args.angle_unit if robot.revolute[j] else "m") + power
            MOTION_LIMITS[kind].check(value, field=flag, scale=scale, unit=unit)
            named[name.strip()] = value * scale
        else:
            for j, joint in enumerate(robot.joint_names):
                scale = angle if robot.revolute[j] else 1.0
                unit = (args.angle_unit if robot.revolute[j] else "m") + power
                MOTION_LIMITS[kind].check(value, field=flag, scale=scale, unit=unit)
                out[joint] = value * scale
    return {**out, **named}


def _payload(args: argparse.Namespace, robot, spec: Path | None):
    """The payload the flags give (changing the envelope file's, else the duty's), or None."""
    from hdselect.envelope.specfile import load_envelope_file
    from hdselect.robot.payload import Payload

    given = [flag for flag, value in (("--payload", args.payload),
                                      ("--payload-com", args.payload_com),
                                      ("--payload-frame", args.payload_frame))
             if value is not None]
    if not given:
        return None
    file = load_envelope_file(spec, robot) if spec is not None else None
    base = file.payload if file is not None else None
    duty = args.duty if args.duty is not None else (file.duty if file is not None else None)
    if base is None and duty is not None:  # the duty's payload, as `size --payload` changes it
        from hdselect.envelope.dutycycle import task_payloads
        from hdselect.motion.mixfile import is_mix_file, load_mix
        from hdselect.motion.motionfile import load_motion

        if is_mix_file(duty):  # the payload its counted tasks share, if they do
            carried = {repr(payload): payload for payload in task_payloads(load_mix(duty, robot))}
            base = next(iter(carried.values())) if len(carried) == 1 else None
        else:
            base = load_motion(duty, robot).payload
    if base is None and args.payload is None:
        raise InputError(f"no payload for {given[0]} to change; give its mass with --payload KG",
                         field=given[0])
    try:
        return Payload(
            float(args.payload) if args.payload is not None else base.mass,  # type: ignore[union-attr]
            tuple(args.payload_com) if args.payload_com is not None
            else (base.com if base is not None else (0.0, 0.0, 0.0)),
            base.inertia if base is not None else ((0.0,) * 3,) * 3,
            args.payload_frame if args.payload_frame is not None
            else (base.frame if base is not None else None))
    except InputError as err:
        flag = {"payload.mass": "--payload", "payload.com": "--payload-com",
                "payload.frame": "--payload-frame"}
        raise InputError(err.reason, field=next((f for k, f in flag.items()
                                                 if str(err.field).startswith(k)),
                                                err.field)) from err

