"""``hdselect fastest`` and ``hdselect max-payload``: co-design."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from typing import Any

from hdselect.base.errors import InputError
from hdselect.cli.inputs import flagged, input_files, sizing_problem, unit_pairs
from hdselect.cli.output import (
    EXIT_NO_FIT,
    EXIT_OK,
    gear_torques,
    rendered,
    say_written,
    to_stdout,
    torques_note,
)


def run_fastest(args: argparse.Namespace) -> int:
    """``hdselect fastest``: the shortest cycle the units allow, or every unit compared."""
    from hdselect.base.outputs import Outputs
    from hdselect.codesign.choice import NoUnit, no_fit
    from hdselect.codesign.fastest_cycle import compare_ratios, fastest
    from hdselect.codesign.pathbounds import PathInfeasible
    from hdselect.codesign.records import fastest_json, ratios_json

    if args.joint and not args.compare_ratios:
        raise InputError("only with --compare-ratios", field="--joint")
    problem = sizing_problem(args)
    mix = problem.mix is not None  # several trajectories: no one CSV or figure of them
    for flag, value in (("--out", args.out), ("--plot", not args.compare_ratios and args.plot)):
        if mix and value:
            raise InputError("not for a mix yet: give one of its motion files", field=flag)
    given = unit_pairs(args.units)
    with Outputs(_inputs(args, problem.robot, problem.source)) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json is not None else None
        csv_file = outputs.file(args.out, "--out") if args.out is not None else None
        figure = outputs.file(args.plot, "--plot") if args.plot is not None else None
        try:
            if args.compare_ratios:
                comparison = compare_ratios(problem, units=given, joints=args.joint)
                result = comparison.base
            else:
                result = fastest(problem, units=given)
        except InputError as err:
            raise flagged(err, args) from err
        except (NoUnit, PathInfeasible) as err:  # the units' physics: a result
            if not no_fit(err):
                raise
            outputs.discard()  # no cycle: no CSV or figure
            return _no_fit(args, err, problem)
        if figure is not None:
            from hdselect.report.codesign_figures import write_fastest_png, write_ratios_png

            if args.compare_ratios:
                write_ratios_png(figure, comparison)
            else:
                write_fastest_png(figure, result)
        if csv_file is not None:
            from hdselect.report.export import write_trajectory_csv

            write_trajectory_csv(csv_file, result.trajectory, gear_torques(result.check),
                                 result.robot.sized_joints)
        if json_file is not None:
            from hdselect.report.export import write_json

            write_json(json_file, ratios_json(comparison) if args.compare_ratios
                       else fastest_json(result))
        text = "" if to_stdout(args) else rendered(*_fastest_tables(args, result, comparison
                                                                    if args.compare_ratios
                                                                    else None))
        outputs.commit()
    sys.stdout.write(text)
    say_written([
        (args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(result.robot.sized_joints)} "
                   f"(SI) along the fastest cycle; {torques_note(result.check)}"),
        (args.plot, "the shortest cycle against the unit on each joint compared"
         if args.compare_ratios else "speed and torque of each sized joint against its limits"),
        (args.json, None)], args)
    return EXIT_OK if result.feasible else EXIT_NO_FIT


def _no_fit(args: argparse.Namespace, err, problem) -> int:
    """``fastest`` where a joint has no unit that runs the path at any speed: a result.

    Why on standard output, and the JSON (`hdselect.codesign.records.no_fit_json`) if
    asked for; exit status 1.
    """
    from hdselect.base.outputs import Outputs
    from hdselect.codesign.choice import NoUnit
    from hdselect.codesign.records import no_fit_json
    from hdselect.report.export import write_json
    from hdselect.report.tables import Paragraphs

    source = problem.source
    with Outputs(_inputs(args, problem.robot, source)) as outputs:
        if args.json is not None:
            write_json(outputs.file(args.json, "--json"),
                       no_fit_json(err, str(problem.robot.path), source, args.command_line))
        lines = err.lines(args.command_line) if isinstance(err, NoUnit) else str(err).splitlines()
        text = "" if to_stdout(args) else rendered(Paragraphs(tuple(lines)))
        outputs.commit()
    sys.stdout.write(text)
    say_written([(args.json, None)], args)
    return EXIT_NO_FIT


def _fastest_tables(args: argparse.Namespace, result, comparison) -> list[Any]:
    """What ``fastest`` prints: the ratios compared, else the cycle (a mix's tasks first)."""
    from hdselect.report.codesign_tables import fastest_tables, ratios_table

    if comparison is None:
        return fastest_tables(result)
    tables: list[Any] = []
    for joint in comparison.joints:
        tables += [""] if tables else []
        tables.append(ratios_table(comparison, joint))
    return tables


def run_max_payload(args: argparse.Namespace) -> int:
    """``hdselect max-payload``: the largest payload with a unit on every joint."""
    from hdselect.base.outputs import Outputs
    from hdselect.codesign.maxpayload import max_payload
    from hdselect.codesign.records import max_payload_json
    from hdselect.report.codesign_tables import max_payload_tables
    from hdselect.report.export import write_json
    from hdselect.sizing.diagnosis import with_diagnoses

    problem = sizing_problem(args)
    robot, motion = problem.robot, problem.source
    given = unit_pairs(args.units)
    with Outputs(_inputs(args, robot, motion)) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json is not None else None
        try:
            result = max_payload(problem, frame=args.payload_frame, com=args.payload_com,
                                 units=given or None, tasks=args.task)
        except InputError as err:
            flag = {"payload.frame": "--payload-frame", "frame": "--payload-frame",
                    "payload.com": "--payload-com", "com": "--payload-com",
                    "task": "--task"}.get(_scaled_field(str(err.field)))
            if flag is None or getattr(args, flag[2:].replace("-", "_")) is None:
                raise flagged(err, args) from err
            raise InputError(err.reason, field=flag) from err
        if result.unloaded is not None:  # the next steps: this command, one option changed
            result = replace(result, unloaded=with_diagnoses(result.unloaded,
                                                             command=args.command_line))
        document = max_payload_json(result)
        items = max_payload_tables(result, robot)
        if json_file is not None:
            write_json(json_file, document)
        text = "" if to_stdout(args) else rendered(*items)
        outputs.commit()
    sys.stdout.write(text)
    say_written([(args.json, None)], args)
    return EXIT_OK if result.mass is not None else EXIT_NO_FIT


def _inputs(args: argparse.Namespace, robot, motion) -> list:
    """Every file the command reads: no output may replace one."""
    return [*input_files(robot, motion), *args.catalog,
            *([args.motor_catalog] if args.motor_catalog else [])]


def _scaled_field(field: str) -> str:
    """An error's field as the payload's, where it is a part's (``payloads.part.frame``).

    max-payload's --payload-frame and --payload-com place the part it scales.
    """
    field = field.split("[")[0]
    if field.startswith("payloads."):
        return "payload." + field.rsplit(".", 1)[-1]
    return field
