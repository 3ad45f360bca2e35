"""``hdselect plan``: a motion planned, its torques written."""

from __future__ import annotations

import argparse
import sys

from hdselect.base.errors import InputError
from hdselect.cli.inputs import input_files, max_samples_of, robot_and_motion
from hdselect.cli.output import EXIT_OK, rendered, say_written, to_stdout


def run_plan(args: argparse.Namespace) -> int:
    """``hdselect plan``: the trajectory and the torques along it, as CSV (and a plot)."""
    from hdselect.base.outputs import Outputs
    from hdselect.motion.mixfile import Mix
    from hdselect.motion.planning import plan_motion
    from hdselect.report.case_tables import plan_text
    from hdselect.report.export import (
        write_line_errors_csv,
        write_trajectory_csv,
        write_waypoints_csv,
    )
    from hdselect.robot.dynamics import inverse_dynamics

    for flag, given in (("--joints", args.joints), ("--exclude", args.exclude)):
        if given is not None and args.plot is None:
            raise InputError("only with --plot (it chooses the joints plotted; the CSV has "
                             "every joint)", field=flag)
    robot, motion = robot_and_motion(args)
    if isinstance(motion, Mix):
        raise InputError("plan takes one motion file; this is a mix: plan each of its "
                         f"motions ({', '.join(m.path.name for m in motion.motions)})",
                         path=motion.path, field="task")
    max_samples = max_samples_of(args)
    if args.line_errors and not motion.lines:
        raise InputError("the motion has no straight line (line = true) to measure",
                         field="--line-errors")
    if args.waypoints and not len(motion.waypoints):
        raise InputError("a logged trajectory (planner \"samples\") has no waypoints",
                         field="--waypoints")
    with Outputs(input_files(robot, motion)) as outputs:
        out = outputs.file(args.out, "--out")
        figure = outputs.file(args.plot, "--plot") if args.plot is not None else None
        solved = outputs.file(args.waypoints, "--waypoints") if args.waypoints else None
        deviations = outputs.file(args.line_errors, "--line-errors") if args.line_errors \
            else None
        planned = plan_motion(robot, motion, max_samples=max_samples)
        motion, trajectory = planned.motion, planned.trajectory
        tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
        write_trajectory_csv(out, trajectory, tau, robot.joint_names)
        if solved is not None:
            write_waypoints_csv(solved, motion)
        if deviations is not None:
            write_line_errors_csv(deviations, trajectory, planned.lines)
        if figure is not None:
            from hdselect.report.figures import write_profiles_png

            write_profiles_png(figure, trajectory, tau, robot.sized_joints,
                               title=f"{robot.path.name} running {motion.path.name}")
        text = "" if to_stdout(args) else rendered(plan_text(robot, motion, trajectory,
                                                             planned.lines))
        outputs.commit()
    sys.stdout.write(text)
    say_written([(args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(robot.joint_names)} "
                             "(SI)"),
                  (args.waypoints, "the joint path as solved: waypoints and line samples, "
                                   "with the tool's pose error at each (SI)"),
                  (args.line_errors, f"the tool's distance and angle from its straight line "
                                     f"at each of {sum(len(d.index) for d in planned.lines):,}"
                                     " planned samples on a line (SI)"),
                  (args.plot, "speed and torque of each joint over the cycle")], args)
    return EXIT_OK
