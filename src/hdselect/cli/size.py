"""``hdselect size`` and ``hdselect compare``: a gearhead for every joint."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from hdselect.cli.inputs import SHOWN_LOGGERS, sizing_problem
from hdselect.cli.output import (
    EXIT_NO_FIT,
    EXIT_OK,
    rendered,
    report_and_json,
    reserve_parts,
    reserved_outputs,
    say_written,
    to_stdout,
    write_parts,
    write_report_and_json,
)


def run_size(args: argparse.Namespace) -> int:
    """``hdselect size``: a gearhead for every joint."""
    from hdselect.report.size_tables import report_tables

    problem = sizing_problem(args)
    with reserved_outputs(args, problem.robot, problem.source) as (outputs, json_file, report):
        bom = reserve_parts(outputs, args)
        result = _sized(problem, args)
        write_report_and_json(args, result, json_file, report)
        write_parts(bom, result)
        table = "" if to_stdout(args) else rendered(*report_tables(result))
        outputs.commit()
    args.held.shown(SHOWN_LOGGERS)  # the table, the JSON and the report list them
    sys.stdout.write(table)
    say_written(report_and_json(args), args)
    return EXIT_OK if result.feasible and result.targets_met else EXIT_NO_FIT


def run_compare(args: argparse.Namespace) -> int:
    """``hdselect compare``: every unit against every joint."""
    from dataclasses import replace

    from hdselect.report.precision_tables import verdict_lines
    from hdselect.report.size_tables import compare_table
    from hdselect.report.tables import Paragraphs
    from hdselect.sizing.arguments import not_sized

    problem = sizing_problem(args)
    for name in args.joint or []:
        if name not in problem.robot.sized_joints:
            raise not_sized(problem.robot, name, "--joint")
    with reserved_outputs(args, problem.robot, problem.source) as (outputs, json_file, report):
        bom = reserve_parts(outputs, args)
        result = _sized(problem, args)
        shown = replace(result, joints=tuple(joint for joint in result.joints
                                             if not args.joint or joint.name in args.joint))
        write_report_and_json(args, shown, json_file, report)
        write_parts(bom, result)
        tables: list[Any] = []
        for joint in shown.joints:
            tables += [""] if tables else []
            tables.append(compare_table(result, joint))
        if result.precision is not None and result.precision.targets:
            tables += ["", Paragraphs(tuple(verdict_lines(result.precision)))]
        text = "" if to_stdout(args) else rendered(*tables)
        outputs.commit()
    sys.stdout.write(text)
    say_written(report_and_json(args), args)
    return EXIT_OK if result.feasible and result.targets_met else EXIT_NO_FIT


def _sized(problem: Any, args: argparse.Namespace) -> Any:
    """The sizing, with the diagnosis of every joint no unit fits (its next steps checked).

    Each next step's command is this command line with one option set.
    """
    from hdselect.codesign.maxpayload import duty_bounds
    from hdselect.sizing.core import size_problem
    from hdselect.sizing.diagnosis import with_diagnoses

    return with_diagnoses(size_problem(problem), payload_bounds=duty_bounds,
                          command=args.command_line)
