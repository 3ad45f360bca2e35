"""``hdselect joints`` and ``hdselect init``: a robot's joints, a starter motion."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from hdselect.cli.inputs import robot_of
from hdselect.cli.output import EXIT_OK, rendered, say_written


def run_joints(args: argparse.Namespace) -> int:
    """``hdselect joints``: every joint of a robot file, in the order lists use."""
    from hdselect.base.outputs import Outputs
    from hdselect.report.case_tables import joints_table
    from hdselect.report.export import joints_json, write_json
    from hdselect.robot.joints import describe_joints

    robot = robot_of(args)
    with Outputs([robot.path]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json is not None else None
        infos = describe_joints(robot)
        if json_file is not None:
            write_json(json_file, joints_json(robot, infos))
        text = "" if args.json == "-" else rendered(joints_table(robot, infos))
        outputs.commit()
    args.held.shown(("hdselect.robot.reading",))  # the table and the JSON list them
    sys.stdout.write(text)
    say_written([(args.json, None)], args)
    return EXIT_OK


def run_init(args: argparse.Namespace) -> int:
    """``hdselect init``: a starter motion file that plans and sizes as written."""
    from hdselect.base.outputs import Outputs
    from hdselect.motion.starter import starter_motion
    from hdselect.report.tables import Paragraphs

    robot = robot_of(args)
    out = None if args.out in (None, "-") else Path(args.out)

    def text() -> str:
        """The starter: its robot relative to --out's folder, absolute when printed."""
        target = os.path.abspath(robot.path)
        if out is None:
            return starter_motion(robot, target, tool_poses=args.tool_poses)
        where = os.path.abspath(out.parent)
        shared = os.path.commonpath([target, where])
        return starter_motion(robot, target if shared == os.sep
                              else os.path.relpath(target, where), tool_poses=args.tool_poses)

    if out is None:
        sys.stdout.write(text())
        return EXIT_OK
    with Outputs([robot.path]) as outputs:
        staging = outputs.file(args.out, "--out", exclusive=True)
        staging.write_text(text(), encoding="utf-8")
        note = rendered(Paragraphs((f"wrote {out}; edit its waypoints, limits and payload, "
                                     f"then: hdselect size {out}",)))
        outputs.commit()
    sys.stdout.write(note)
    return EXIT_OK
