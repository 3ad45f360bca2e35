"""``hdselect plan``: a motion planned, its torques written."""

from __future__ import annotations

import argparse
import sys

from hdselect.base.errors import InputError
from hdselect.cli.arguments import catalog_argument, motor_arguments, robot_motion_arguments
from hdselect.cli.inputs import (
    flagged,
    input_files,
    max_samples_of,
    motors_of,
    robot_and_motion,
    sizing_options_of,
    unit_pairs,
)
from hdselect.cli.output import (
    EXIT_OK,
    gear_torques,
    rendered,
    say_written,
    to_stdout,
    torques_note,
)

_UNIT_FLAGS = ("--catalog", "--motor-mass", "--no-mass-coupling")
"""Flags that only change the units' torques: refused without --units or --motor-catalog."""


def plan_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``hdselect plan``."""
    robot_motion_arguments(parser, sizes=False)
    parser.add_argument("--out", metavar="FILE", required=True,
                        help="CSV: t, then q_, qd_, qdd_, tau_ per joint (SI); tau_ is the "
                             "robot's own dynamics, without gearhead or motor masses, unless "
                             "--units or --motor-catalog is given")
    parser.add_argument("--plot", metavar="PNG", help="speed and torque profiles per joint")
    parser.add_argument("--waypoints", metavar="FILE",
                        help="CSV of the joint path as solved: every waypoint and line sample "
                             "(tool poses solved for the mounting), with the tool's pose error")
    parser.add_argument("--line-errors", metavar="FILE",
                        help="CSV of every planned sample on a straight line: the tool's "
                             "distance and angle from the line")
    units = parser.add_argument_group(
        "gearhead and motor masses",
        "With --units or --motor-catalog, tau_ is the output torque of every sized joint "
        "carrying the units' and motors' masses, as `size` computes it (unsized joints are "
        "left out of the CSV).")
    units.add_argument("--units", action="append", metavar="JOINT=UNIT",
                       help="the unit of a joint, as `hdselect catalog` names it (repeatable; "
                            "the other sized joints get the unit `size` selects)")
    catalog_argument(units, series=False)  # --units names the units
    motor_arguments(units)


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
    for flag, given in (("--joints", args.joints), ("--exclude", args.exclude)):
        if given is not None and args.plot is None:
            raise InputError("only with --plot (it chooses the joints plotted; the CSV has "
                             "every joint)", field=flag)
    carrying = bool(args.units or args.motor_catalog)
    for flag in _UNIT_FLAGS:
        if getattr(args, flag[2:].replace("-", "_")) not in (None, False, []) and not carrying:
            raise InputError("only with --units or --motor-catalog (it changes the units' "
                             "torques)", field=flag)
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
    units = _units_case(args, robot, motion) if carrying else None  # checked before the work
    with Outputs(input_files(robot, motion)) as outputs:
        out = outputs.file(args.out, "--out")
        figure = outputs.file(args.plot, "--plot") if args.plot is not None else None
        solved = outputs.file(args.waypoints, "--waypoints") if args.waypoints else None
        deviations = outputs.file(args.line_errors, "--line-errors") if args.line_errors \
            else None
        planned = plan_motion(robot, motion, max_samples=max_samples)
        motion, trajectory = planned.motion, planned.trajectory
        check = None if units is None else _checked_units(args, units, robot, motion,
                                                          trajectory)
        if check is None:
            tau = _torques(robot, motion, trajectory)
            write_trajectory_csv(out, trajectory, tau, robot.joint_names)
        else:
            tau = gear_torques(check)
            write_trajectory_csv(out, trajectory, tau, robot.sized_joints)
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
    columns = robot.joint_names if check is None else robot.sized_joints
    say_written([(args.out, f"t, then q_, qd_, qdd_, tau_ of {', '.join(columns)} (SI); "
                            + torques_note(check)),
                  (args.waypoints, "the joint path as solved: waypoints and line samples, "
                                   "with the tool's pose error at each (SI)"),
                  (args.line_errors, f"the tool's distance and angle from its straight line "
                                     f"at each of {sum(len(d.index) for d in planned.lines):,}"
                                     " planned samples on a line (SI)"),
                  (args.plot, "speed and torque of each joint over the cycle")], args)
    return EXIT_OK


def _units_case(args: argparse.Namespace, robot, motion):
    """The units given (``--units``) and the problem (catalog, options, motors), checked."""
    from hdselect.sizing.problem import problem_of

    given = unit_pairs(args.units or [])
    motors = motors_of(args, robot, motion)
    return given, problem_of(robot, motion, catalog=args.catalog, motors=motors,
                             options=sizing_options_of(args, motion), plan=False)


def _checked_units(args: argparse.Namespace, units, robot, motion, trajectory):
    """The units of ``--units`` and their motors checked along `trajectory`.

    The sized joints not given get the sizing's selection; the check's torques carry the
    units' and motors' masses as `size`'s do.
    """
    from hdselect.codesign.choice import resolve_case
    from hdselect.sizing.core import check_units
    from hdselect.sizing.tasks import task_of

    given, problem = units
    try:
        chosen, _, paired = resolve_case(robot, motion, given, problem.units, problem.options,
                                         selection=False, trajectory=trajectory,
                                         motors=problem.motors)
    except InputError as err:
        raise flagged(err, args) from err
    task = task_of(robot, trajectory, motion)  # the parts its payload events move
    return check_units(task.robot, trajectory, chosen, problem.options, motors=paired,
                       carried=task.carried)


def _torques(robot, motion, trajectory):
    """The robot's own joint torques along `trajectory` [N m], shape (n, dof).

    Each part its payload events move is carried between them
    (`hdselect.sizing.tasks.over_states`).
    """
    from hdselect.robot.dynamics import inverse_dynamics
    from hdselect.sizing.tasks import over_states, task_of

    task = task_of(robot, trajectory, motion)
    return over_states(task, task.robot, lambda state, rows: (inverse_dynamics(
        state, trajectory.q[rows], trajectory.qd[rows], trajectory.qdd[rows]),))[0]
