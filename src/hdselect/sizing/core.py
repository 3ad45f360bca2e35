"""Size every joint of a robot from what it does: the product's main job, and its one core.

`size_tasks` takes a robot's tasks (one or more planned trajectories, each with its
own payload and mounting, and a share of the time) and chooses a gearhead per joint
from the tip to the base, each chosen unit's mass (and motor mass) carried by the
joints nearer the base. Where motors are given it chooses a gearhead and a motor
together. `size_trajectory` is one task; `size_problem` solves a resolved
`hdselect.sizing.problem.Problem`, and `size` is `resolve` + `size_problem`.

The selection (`select_units`) reads its torques from a `TorqueModel`: batched
inverse dynamics here, a study's basis in `hdselect.study.group`. Every front end
(the command line, studies, co-design, Python) goes through it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS
from hdselect.catalog.units import Unit
from hdselect.motion.events import Carried
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import torque_floor
from hdselect.robot.model import Robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import (
    OptionValues,
    check_bearing_options,
    check_trajectory,
    checked_motors,
    loaded_units,
    units_as_catalog,
)
from hdselect.sizing.joint import JointCycle, size_joint, task_checks
from hdselect.sizing.options import Options, fixed_choice
from hdselect.sizing.precision import Precision
from hdselect.sizing.problem import Catalog, Problem, plan_tasks, resolve
from hdselect.sizing.result import JointSizing, Motors, SizingResult
from hdselect.sizing.slowdown import with_slowdowns
from hdselect.sizing.stiffening import stiffened
from hdselect.sizing.tasks import Task, check_shares, pooled
from hdselect.sizing.torques import DirectTorques, TorqueModel

if TYPE_CHECKING:
    from typing_extensions import Unpack

GRAVITY_LOADED = 1e-3
"""Gravity torque above which a joint is gravity-loaded (backdriving warning) [N m]."""
GUESS_SAMPLES = 200
"""Samples per task on which the carried masses are first guessed (a coarse selection)."""


def size(
    robot: Robot | str | Path | None,
    motion: Motion | Mix | str | Path,
    *,
    catalog: Catalog | None = (),
    payload: Payload | None = None,
    mounting: Mounting | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
    motors: Motors | None = None,
    options: Options | None = None,
    units: Sequence[Unit] | None = None,
    **values: Unpack[OptionValues],
) -> SizingResult:
    """Choose a gearhead for every joint of a robot from its motion: resolve, plan, size.

    `hdselect.sizing.problem.resolve`, then `size_problem`.

    Args:
        robot: Robot file or loaded robot; None takes the motion file's ``robot``.
        motion: Motion file or loaded motion; or a mix file (``[[task]]`` tables) or a
            loaded `Mix`: every task planned with its own payload and mounting and
            sized as one duty (`size_tasks`).
        catalog: Extra catalog files (the built-in PSA-G catalog is always loaded; a mix
            file's ``[sizing] catalog`` too), or the units already loaded.
        payload: Payload, overriding the motion file's (not for a mix: its tasks give theirs).
        mounting: Mounting, overriding the motion file's (a mix's: every task's).
        joints: Joints to size (default: the motion file's ``[sizing] joints``, else every
            revolute joint that is not a mimic follower).
        exclude: Joints not to size; they still move and load the others (default: the
            motion file's ``[sizing] exclude``).
        motors: Candidate motors per joint name, replacing the motion file's ``[motor]``;
            None takes the motion file's (for the joints sized).
        options: The assumptions as a whole (the files' are not read); not with `values`.
        units: Deprecated: the loaded catalog, now given as `catalog`.
        **values: Fields of `hdselect.sizing.options.Options` (``stop_time``, ``efficiency``,
            ``rotor_inertia``, ``motor_mass``, ``mass_coupling``, ``prefer``,
            ``life_hours``, ``life_basis``, ``threads``); what is not given comes from
            the motion file, else the defaults.

    Returns:
        The result for every sized joint.

    Raises:
        InputError: A file or argument is invalid, or two arguments contradict.
        PlanningError: The motion cannot be planned.
    """
    if units is not None:
        catalog = units_as_catalog(units, catalog, "size")
    return size_problem(resolve(robot, motion, catalog=catalog, payload=payload,
                                mounting=mounting, joints=joints, exclude=exclude,
                                motors=motors, options=options, **values))


def size_problem(problem: Problem, *, slowdowns: bool = True) -> SizingResult:
    """Solve a resolved problem: plan its tasks if they are not, and size them (`size_tasks`).

    Args:
        problem: The problem (`hdselect.sizing.problem.resolve`).
        slowdowns: For a joint no unit fits, find the time scales at which each would.

    Returns:
        The result for every sized joint; its ``mix`` the problem's mix, if any.

    Raises:
        InputError: As `size_tasks`.
        PlanningError: A motion cannot be planned.
    """
    expect_type(slowdowns, (bool,), "slowdowns", "True or False")
    expect_type(problem, (Problem,), "problem", "a Problem (hdselect.sizing.problem.resolve)")
    problem = problem if problem.planned else plan_tasks(problem)
    result = size_tasks(problem.tasks, problem.units, problem.options, motors=problem.motors,
                        idle=problem.idle, slowdowns=slowdowns)
    return replace(result, mix=problem.mix) if problem.mix is not None else result


def size_trajectory(robot: Robot, trajectory: Trajectory, catalog: Sequence[Unit] | None = None,
                    options: Options | None = None, *, motors: Motors | None = None,
                    units: Sequence[Unit] | None = None,
                    carried: Carried | None = None) -> SizingResult:
    """Choose a gearhead (or a gearhead and a motor) for every sized joint along a trajectory.

    One task: `size_tasks` of this trajectory alone.

    Args:
        robot: The robot (payload and mounting applied).
        trajectory: The trajectory, with the robot's joints.
        catalog: The loaded units to choose from (default: the built-in catalog).
        options: The assumptions (default `Options()`); its ``prefer`` None means
            ``"mass"`` where motors are given, else ``"size"``.
        motors: Candidate motors per sized joint; a joint not named has no motor data.
        units: Deprecated: the loaded catalog, now given as `catalog`.
        carried: The parts payload events move along the trajectory (`Task.carried`);
            None: the robot carries what it holds the whole cycle.

    Returns:
        The result for every sized joint (its ``motion`` is None); its options hold the
        selection order used.

    Raises:
        InputError: An argument is of the wrong type, the trajectory's joints are not the
            robot's or its arrays are malformed, the catalog is empty, the robot has no
            rotary joint to size, the motors name a joint that is not sized or give none
            for one, or motors and the options' rotor inertia or motor mass are both given.
    """
    expect_type(robot, (Robot,), "robot", "a Robot")
    expect_type(trajectory, (Trajectory,), "trajectory", "a Trajectory (hdselect.plan)")
    if units is not None:
        catalog = units_as_catalog(units, catalog, "size_trajectory")
    _check_carried(carried, trajectory)
    return size_tasks((Task(robot, trajectory, carried=carried),), catalog, options,
                      motors=motors)


def size_tasks(tasks: Sequence[Task], catalog: Sequence[Unit] | None = None,
               options: Options | None = None, *, motors: Motors | None = None,
               idle: float = 0.0, slowdowns: bool = True,
               units: Sequence[Unit] | None = None) -> SizingResult:
    """Choose a gearhead (or a pair) for every sized joint for everything a robot does.

    Per joint and unit, the rules of one sample (repeated peak, static, speed,
    momentary) take the worst over every task, and the averaged ones (mean torque,
    mean speed, life, motor RMS) pool every task's samples weighted by how often
    its cycle runs (`hdselect.sizing.tasks`). Sizing goes from the tip to the base,
    so each joint is sized with exactly the units chosen further out; the carried
    masses are first guessed from a coarse selection on a few hundred samples per
    task, so that the full trajectories usually take one pair of batched passes.

    Args:
        tasks: The robot's tasks: the same robot file and sized joints, each with its own
            payload and mounting; shares summing to 1.
        catalog: The loaded units to choose from (default: the built-in catalog).
        options: The assumptions (default `Options()`).
        motors: Candidate motors per sized joint.
        idle: The fraction of the time no task runs [-]: the shares and it sum to 1. A
            pause, it counts only where a series' rules take the mean speed over the
            whole cycle, pauses included.
        slowdowns: For a joint no unit fits, find the time scales at which each would;
            False leaves them out (the verdict and the figures are the same).
        units: Deprecated: the loaded catalog, now given as `catalog`.

    Returns:
        The result for every sized joint; its robot, trajectory and motion are the first
        counted task's, its `tasks` every task given. With several tasks counted, each
        joint's `per_task` holds its unit checked against each task alone.

    Raises:
        InputError: An argument is of the wrong type or inconsistent (see
            `size_trajectory`), the tasks are not of one robot, or the shares are not
            fractions summing to 1.
    """
    tasks = _tasks_argument(tasks, idle)
    if units is not None:
        catalog = units_as_catalog(units, catalog, "size_tasks")
    units = loaded_units(catalog)
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    expect_type(slowdowns, (bool,), "slowdowns", "True or False")
    robot = tasks[0].robot
    if not robot.sized_joints:
        raise InputError("the robot has no rotary joint to size (prismatic joints take no "
                         "gearhead)", path=robot.path, field="joints")
    options = options if options is not None else Options()
    motors = checked_motors(robot, motors, options)
    if options.prefer is None:
        options = replace(options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors
                          else DEFAULT_PREFER)
    check_bearing_options(robot, units, options)
    per_joint = {name: units for name in robot.sized_joints}
    guess: dict[str, float] = {}
    coarse_model: DirectTorques | None = None
    if options.mass_coupling:
        coarse = [decimated_task(task) for task in tasks]
        coarse_samples = pooled(coarse, idle)
        coarse_model = DirectTorques(coarse_samples.tasks, coarse_samples, options.stop_time,
                                     threads=options.threads,
                                     wrenches=any(unit.bearing is not None for unit in units))
        _, guess = select_units(coarse_model, per_joint, options, motors, detail=False,
                                slowdowns=False, per_task=False)
    samples = pooled(tasks, idle)
    model = DirectTorques(samples.tasks, samples, options.stop_time, threads=options.threads,
                          guess=guess, wrenches=options.bearing_loads)
    joints, masses = select_units(model, per_joint, options, motors, slowdowns=slowdowns)
    found = stiffened(model, per_joint, joints, masses, options, motors, select=select_units,
                      coarse=coarse_model, slowdowns=slowdowns)
    joints, masses, precision = found.joints, found.masses, found.precision
    first = samples.tasks[0]
    return SizingResult(first.robot, first.trajectory, tuple(joints), options, units,
                        first.motion, motors=motors, loads=model.loads(masses),
                        tasks=tuple(tasks), idle=float(idle), precision=precision)


def select_units(model: TorqueModel, units: Mapping[str, tuple[Unit, ...]], options: Options,
                 motors: Motors, *, detail: bool = True, slowdowns: bool = True,
                 per_task: bool = True) -> tuple[list[JointSizing], dict[str, float]]:
    """The one selection: every sized joint from the tip to the base, masses carried.

    Args:
        model: Where the torques come from.
        units: The candidate units of every sized joint.
        options: The assumptions, ``prefer`` resolved.
        motors: Candidate motors per sized joint (checked).
        detail: Keep every candidate checked (reports); False keeps the selected one.
        slowdowns: For a joint no unit fits, find the time scales at which each would.
        per_task: Where several tasks count, check each joint's unit against each task
            alone (`JointSizing.per_task`).

    Returns:
        The sized joints in the robot's order, with their carried masses, gravity figures
        and load inertias; and the mass each joint's unit (or, where none fits, its
        strongest candidate) and motor add [kg], by joint (empty without mass coupling).
    """
    robot = model.robot
    masses: dict[str, float] = {}
    found: dict[str, JointSizing] = {}
    floor = torque_floor(robot)
    for name in reversed(robot.sized_joints):  # a parent's index is below its children's
        tau, stop = (np.where(np.abs(x) < floor[robot.joint_index(name)], 0.0, x)
                     for x in model.torques(name, masses))  # noise counts as zero
        # the load inertia before the selection (the inertia-ratio and natural-frequency
        # rules): M_jj depends only on the bodies beyond the joint, whose units are chosen
        inertial = name in motors or options.joint_value("min_natural_frequency",
                                                         name) is not None
        inertia = model.load_inertia(name, masses) if inertial else None
        cycle = JointCycle(model.samples, robot.joint_index(name), tau, stop,
                           model.wrench(name, masses), options.bearing_offset.get(name, 0.0))
        joint = size_joint(name, cycle, units[name], options, motors=motors.get(name, ()),
                           detail=detail, load_inertia=inertia)
        if per_task and len(model.samples.tasks) > 1:
            inertias = model.task_inertias(name, masses) if inertial else None
            joint = replace(joint, per_task=task_checks(cycle, joint.selected or joint.strongest,
                                                        options, inertias, name=name))
        found[name] = joint
        if options.mass_coupling:
            masses[name] = added_mass(joint, options)
    masses = {name: masses[name] for name in robot.sized_joints if name in masses}
    gravity = model.gravity(masses)
    joints = []
    for name in robot.sized_joints:
        worst = float(gravity[robot.joint_index(name)])
        joints.append(replace(found[name], carried_mass=robot.carried_mass(name, masses),
                              gravity_loaded=worst > GRAVITY_LOADED, max_gravity_torque=worst))
    if slowdowns and any(joint.selected is None for joint in joints):
        joints = with_slowdowns(model, joints, units, options, motors, masses)
    return joints, masses


def check_units(robot: Robot, trajectory: Trajectory, units: Mapping[str, Unit],
                options: Options | None = None, *,
                motors: Mapping[str, Motor] | None = None,
                carried: Carried | None = None) -> SizingResult:
    """Check given units, one per sized joint, along a planned trajectory: no selection.

    Each joint's only candidate is its unit (paired with its motor, where one is
    given), `selected` when it passes every rule. With mass coupling, each unit's mass
    (and its motor's, else the options' motor mass) is carried by the joints nearer the
    base, as `size_trajectory` carries the units it chooses.

    Args:
        robot: The robot (payload and mounting applied).
        trajectory: The trajectory, with the robot's joints.
        units: The unit of every sized joint, by joint name.
        options: The assumptions (default `Options()`).
        motors: A fixed motor behind the unit of some sized joints, by joint name; its
            rotor inertia and mass replace the options' and its rules are checked.
        carried: The parts payload events move along the trajectory (`Task.carried`: the
            robot carries each between its events); None: the robot carries what it holds.

    Returns:
        The result for every sized joint (its ``motion`` is None, its ``units`` the
        distinct units given).

    Raises:
        InputError: An argument is of the wrong type, the trajectory's arrays are
            malformed, a sized joint has no unit, or a name is not a sized joint.
    """
    expect_type(robot, (Robot,), "robot", "a Robot")
    expect_type(trajectory, (Trajectory,), "trajectory", "a Trajectory (hdselect.plan)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    if not isinstance(units, Mapping):
        raise InputError(f"expected a mapping of joint names to catalog units, got "
                         f"{type(units).__name__}", field="units")
    for unit in units.values():
        expect_type(unit, (Unit,), "units", "catalog units (hdselect.load_catalog)")
    if trajectory.joint_names != robot.joint_names:
        raise InputError(f"the trajectory has joints {', '.join(trajectory.joint_names)}; the "
                         f"robot has {', '.join(robot.joint_names)}", field="trajectory")
    check_trajectory(trajectory)
    _check_carried(carried, trajectory)
    for name in units:
        if name not in robot.sized_joints:
            raise InputError(f"'{name}' is not a sized joint; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field="units")
    missing = [name for name in robot.sized_joints if name not in units]
    if missing:
        raise InputError(f"no unit given for {', '.join(missing)}", field="units")
    options = options if options is not None else Options()
    check_bearing_options(robot, units.values(), options)
    fixed = checked_motors(robot, motors, options) if motors else {}
    for name, given in fixed.items():
        if len(given) != 1:
            raise InputError(f"expected one motor to check, got {len(given)}",
                             field=f"motors.{name}")
    resolved, masses = fixed_choice(options, units, fixed, robot.sized_joints)
    task = Task(robot, trajectory, carried=carried)
    samples = pooled((task,))
    model = DirectTorques((task,), samples, options.stop_time, threads=options.threads,
                          guess=masses, wrenches=options.bearing_loads)
    joints, masses = select_units(model, {name: (units[name],) for name in robot.sized_joints},
                                  resolved, fixed, slowdowns=False)
    distinct = tuple(dict.fromkeys(units[name] for name in robot.sized_joints))
    return SizingResult(robot, trajectory, tuple(joints), options if not fixed else resolved,
                        distinct, motors=fixed, loads=model.loads(masses),
                        precision=precision_of(model, joints, masses, options))


def _check_carried(carried: object, trajectory: Trajectory) -> None:
    """Refuse a `carried` that is not a `Carried` of the trajectory's samples.

    Raises:
        InputError: It is neither None nor a `Carried`, or has another sample count.
    """
    expect_type(carried, (Carried, type(None)), "carried", "a Carried (Task.carried) or None")
    if isinstance(carried, Carried) and len(carried.mask) != len(trajectory.t):
        raise InputError(f"the carried parts are given for {len(carried.mask)} samples; the "
                         f"trajectory has {len(trajectory.t)}", field="carried")


def precision_of(model: TorqueModel, joints: Sequence[JointSizing], masses: Mapping[str, float],
               options: Options) -> Precision | None:
    """The stiffness figures of given units, the whole-arm targets judged (none raised)."""
    return stiffened(model, {}, list(joints), dict(masses), options, {}, select=None).precision


def _tasks_argument(tasks: object, idle: float = 0.0) -> tuple[Task, ...]:
    """The tasks checked: one robot file and sized joints, trajectories of its joints.

    Raises:
        InputError: They are not `Task` records of one robot, or their shares are wrong.
    """
    if isinstance(tasks, str | bytes | Path) or not isinstance(tasks, Sequence) or not tasks:
        raise InputError("expected one or more hdselect.sizing.tasks.Task", field="tasks")
    for task in tasks:
        expect_type(task, (Task,), "tasks", "hdselect.sizing.tasks.Task records")
    first = tasks[0].robot
    for i, task in enumerate(tasks):
        field = f"tasks[{i}]"
        expect_type(task.robot, (Robot,), f"{field}.robot", "a Robot")
        expect_type(task.trajectory, (Trajectory,), f"{field}.trajectory",
                    "a Trajectory (hdselect.plan)")
        if (task.robot.path != first.path or task.robot.sized_joints != first.sized_joints
                or task.robot.joint_names != first.joint_names):
            raise InputError("every task must run the same robot file with the same sized "
                             f"joints; {task.label} differs from {tasks[0].label}", field=field)
        if task.trajectory.joint_names != task.robot.joint_names:
            raise InputError(f"the trajectory has joints {', '.join(task.trajectory.joint_names)}"
                             f"; the robot has {', '.join(task.robot.joint_names)}",
                             field="trajectory" if len(tasks) == 1 else f"{field}.trajectory")
        check_trajectory(task.trajectory)
    check_shares([task.share for task in tasks], field="tasks.share", idle=idle)
    return tuple(tasks)


def decimated(traj: Trajectory, samples: int = GUESS_SAMPLES) -> Trajectory:
    """Every k-th sample of a trajectory (about `samples`), each standing for k periods."""
    step = max(1, len(traj.t) // samples)
    spread = traj.qdd_uncertainty
    return replace(traj, dt=traj.dt * step, t=traj.t[::step], q=traj.q[::step],
                   qd=traj.qd[::step], qdd=traj.qdd[::step],
                   qdd_uncertainty=None if spread is None else spread[::step])


def decimated_task(task: Task, samples: int = GUESS_SAMPLES) -> Task:
    """The task on its trajectory's `decimated` samples, its payload events at the same ones."""
    thin = decimated(task.trajectory, samples)
    step = round(thin.dt / task.trajectory.dt)  # the k of every k-th sample
    carried = None if task.carried is None else task.carried.sampled(slice(None, None, step))
    return replace(task, trajectory=thin, carried=carried)


def added_mass(joint: JointSizing, options: Options) -> float:
    """The mass a joint's unit (or, where none fits, its strongest candidate) and motor add [kg].

    The options' motor mass stands for a motor where the pair has none.
    """
    chosen = joint.selected or joint.strongest
    return chosen.unit.mass + (chosen.motor_unit.mass if chosen.motor_unit is not None
                               else options.motor_mass)
