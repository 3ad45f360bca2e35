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
    from hdselect.motion.planning import plan
    from hdselect.report.case_tables import plan_text
    from hdselect.report.export import write_trajectory_csv
    from hdselect.robot.dynamics import inverse_dynamics

    for flag, given in (("--joints", args.joints), ("--exclude", args.exclude)):
        if given is not None and args.plot is None:
            raise InputError("only with --plot (it chooses the joints plotted; the CSV has "
                             "every joint)", field=flag)
    robot, motion = robot_and_motion(args)
    max_samples = max_samples_of(args)
    with Outputs(input_files(robot, motion)) as outputs:
        out = outputs.file(args.out, "--out")
        figure = outputs.file(args.plot, "--plot") if args.plot is not None else None
        trajectory = plan(robot, motion, max_samples=max_samples)
        tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
        write_trajectory_csv(out, trajectory, tau, robot.joint_names)
        if figure is not None:
            from hdselect.report.figures import write_profiles_png

            write_profiles_png(figure, trajectory, tau, robot.sized_joints,
                               title=f"{robot.path.name} running {motion.path.name}")
        text = "" if to_stdout(args) else rendered(plan_text(robot, motion, trajectory))
        outputs.commit()
    sys.stdout.write(text)
    say_written([(args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(robot.joint_names)} "
                             "(SI)"),
                  (args.plot, "speed and torque of each joint over the cycle")], args)
    return EXIT_OK
