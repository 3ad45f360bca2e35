"""Size every joint of a robot from its motion: the product's main job, and its one core.

`size_trajectory` takes a robot and a planned trajectory and chooses a gearhead
per joint from the tip to the base, each chosen unit's mass (and motor mass)
carried by the joints nearer the base. Where motors are given, it chooses a
gearhead and a motor together: every (gearhead, motor) pair is checked, and the
pair's mass is carried. `size` is load + plan + `size_trajectory`. Every front end
(the command line, studies, co-design, Python) goes through it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from hdselect.base.arrays import frozen, readonly
from hdselect.base.bounds import expect_type, files_argument
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import RPM_PER_RAD_S, at_rest, check_unit, cycle_load
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, select
from hdselect.catalog.units import Unit
from hdselect.motion.case import load_case, robot_for_motion
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.robot.dynamics import CycleTorques, cycle_torques, gravity_torques, joint_inertias
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import check_trajectory, checked_motors, units_argument
from hdselect.sizing.loads import joint_loads
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.reflect import reflect, reflect_motors
from hdselect.sizing.result import JointSizing, Motors, SizingResult
from hdselect.sizing.slowdown import with_slowdowns

GRAVITY_LOADED = 1e-3
"""Gravity torque above which a joint is gravity-loaded (backdriving warning) [N m]."""


GRAVITY_SAMPLES = 400
"""Poses at which the gravity torque is evaluated for the backdriving warning."""


_GUESS_SAMPLES = 200
"""Samples on which the carried masses are first guessed."""


INERTIA_POSES = GRAVITY_SAMPLES
"""Poses, evenly spread over the cycle, at which a joint's load inertia M_jj is evaluated."""


def size(
    robot: Robot | str | Path | None,
    motion: Motion | str | Path,
    *,
    catalog: Sequence[str | Path] = (),
    units: Sequence[Unit] | None = None,
    payload: Payload | None = None,
    mounting: str | Sequence[float] | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
    motors: Motors | None = None,
    **options: object,
) -> SizingResult:
    """Choose a gearhead for every joint of a robot from its motion: load, plan, size.

    Args:
        robot: Robot file or loaded robot; None takes the motion file's ``robot``.
        motion: Motion file or loaded motion.
        catalog: Extra catalog files (the built-in PSA-G catalog is always loaded).
        units: The catalog already loaded (instead of `catalog`).
        payload: Payload, overriding the motion file's.
        mounting: Mounting, overriding the motion file's.
        joints: Joints to size (default: the motion file's ``[sizing] joints``, else every
            revolute joint that is not a mimic follower).
        exclude: Joints not to size; they still move and load the others (default: the
            motion file's ``[sizing] exclude``).
        motors: Candidate motors per joint name, replacing the motion file's ``[motor]``;
            None takes the motion file's (for the joints sized).
        **options: Fields of `hdselect.sizing.options.Options` (``stop_time``, ``efficiency``,
            ``rotor_inertia``, ``motor_mass``, ``mass_coupling``, ``prefer``,
            ``life_hours``, ``life_basis``, ``threads``); what is not given comes from
            the motion file, else the defaults.

    Returns:
        The result for every sized joint.

    Raises:
        InputError: A file or argument is invalid, or two arguments contradict.
        PlanningError: The motion cannot be planned.
    """
    catalog = files_argument(catalog, "catalog")
    if units is not None and catalog:
        raise InputError("give either catalog files or loaded units, not both", field="units")
    if units is not None:
        units = units_argument(units)
    expect_type(robot, (Robot, str, Path, type(None)), "robot", "a Robot, a robot file or None")
    expect_type(motion, (Motion, str, Path), "motion", "a Motion or a motion file")
    expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    if isinstance(motion, Motion):
        if not isinstance(robot, Robot):
            file = robot if robot is not None else motion.robot_file
            if file is None:
                raise InputError("no robot given, and the motion file names none",
                                 path=motion.path, field="robot")
            robot = load_robot(file, xacro_args=motion.xacro_args if robot is None else None)
        robot = robot_for_motion(robot, motion, payload=payload, mounting=mounting,
                                 joints=joints, exclude=exclude)
    else:
        robot, motion = load_case(motion, robot, payload=payload, mounting=mounting,
                                  joints=joints, exclude=exclude)
    resolved = options_for(motion, **options)
    units = tuple(units) if units is not None else load_catalog(catalog)
    if motors is None:
        motors = motion_motors(robot, motion)
    trajectory = plan(robot, motion, max_samples=resolved.max_samples)
    return replace(size_trajectory(robot, trajectory, units, resolved, motors=motors),
                   motion=motion)


def motion_motors(robot: Robot, motion: Motion) -> dict[str, tuple[Motor, ...]]:
    """The motion file's candidate motors for the robot's sized joints (empty if none).

    Args:
        robot: The robot as sized (its sized joints choose which of the file's apply).
        motion: The motion, with its ``[motor]`` tables read.

    Returns:
        Joint name -> its candidate motors, for every sized joint the file gives motors.

    Raises:
        InputError: A ``[motor.JOINT]`` block names a joint that is not sized.
    """
    if motion.motors is None:
        return {}
    for name in motion.motor_joints:
        if name not in robot.sized_joints:
            raise InputError(f"joint '{name}' is not sized (excluded, or a mimic follower), so "
                             "its motor cannot apply; remove the block or size the joint",
                             path=motion.path, field=f"motor.{name}")
    return {name: motion.motors[name] for name in robot.sized_joints if name in motion.motors}


def size_trajectory(robot: Robot, trajectory: Trajectory, units: Sequence[Unit],
                    options: Options | None = None, *,
                    motors: Motors | None = None) -> SizingResult:
    """Choose a gearhead (or a gearhead and a motor) for every sized joint along a trajectory.

    Joint j's torque depends only on the units chosen further out, so sizing
    from the tip to the base is one pass. It is found here as a fixed point:
    size every joint with the masses of a guess in the model, put the chosen
    units' masses in, and repeat until the choice no longer changes. At that
    point each joint was sized with exactly the units chosen beyond it, which is
    the tip-to-base answer (each round settles at least one more joint from the
    tip). The guess comes from two rounds on a coarse subset of the samples, so
    the full trajectory usually takes one round: two batched passes of inverse
    dynamics, the motion's and the emergency stop's.

    Where a joint has candidate motors, every (gearhead, motor) pair is checked: the
    gearhead's rules with this motor's rotor inertia in the motor torque and the crash,
    and the motor's rules (`hdselect.catalog.rules.check_motor`). The selected pair's mass,
    gearhead and motor, is carried by the joints nearer the base.

    Args:
        robot: The robot (payload and mounting applied).
        trajectory: The trajectory, with the robot's joints.
        units: The catalog.
        options: The assumptions (default `Options()`); its ``prefer`` None means
            ``"mass"`` where motors are given, else ``"size"``.
        motors: Candidate motors per sized joint; a joint not named has no motor data.

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
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    if trajectory.joint_names != robot.joint_names:
        raise InputError(f"the trajectory has joints {', '.join(trajectory.joint_names)}; the "
                         f"robot has {', '.join(robot.joint_names)}", field="trajectory")
    check_trajectory(trajectory)
    units = units_argument(units)
    if not units:
        raise InputError("no gearhead to choose from", field="units")
    if not robot.sized_joints:
        raise InputError("the robot has no rotary joint to size (prismatic joints take no "
                         "gearhead)", path=robot.path, field="joints")
    options = options if options is not None else Options()
    motors = checked_motors(robot, motors, options)
    if options.prefer is None:
        options = replace(options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors
                          else DEFAULT_PREFER)
    masses: dict[str, float] = {}
    if options.mass_coupling:
        coarse = _decimated(trajectory, max(1, len(trajectory.t) // _GUESS_SAMPLES))
        for _ in range(2):
            masses = _unit_masses(_size_joints(robot.with_gearheads(masses), coarse, units,
                                               options, motors)[0], options)
    joints: list[JointSizing] = []
    torques: CycleTorques | None = None
    for _ in range(robot.dof + 1):
        carrying = robot.with_gearheads(masses)
        joints, torques = [], None  # let the last round's torques go before computing the next
        joints, torques = _size_joints(carrying, trajectory, units, options, motors)
        chosen = _unit_masses(joints, options)
        if not options.mass_coupling or chosen == masses:
            break
        masses = chosen
    else:  # each round settles at least one more joint from the tip
        raise AssertionError("the tip-to-base sizing did not settle")
    joints = _with_gravity(carrying, trajectory, joints, options)
    if motors:
        poses = np.unique(np.linspace(0, len(trajectory.t) - 1,
                                      GRAVITY_SAMPLES).astype(int))
        with_motors = [name for name in robot.sized_joints if name in motors]
        inertia = joint_inertias(carrying, trajectory.q[poses], with_motors,
                                 threads=options.threads).max(axis=0)
        by_name = dict(zip(with_motors, inertia, strict=True))
        joints = [replace(joint, load_inertia=float(by_name[joint.name]))
                  if joint.name in by_name else joint for joint in joints]
    if any(joint.selected is None for joint in joints):
        joints = with_slowdowns(carrying, trajectory, joints, units, options, motors)
    assert torques is not None
    return SizingResult(robot, trajectory, tuple(joints), options, units, motors=motors,
                        loads=joint_loads(robot, trajectory, torques.tau))


def check_units(robot: Robot, trajectory: Trajectory, units: Mapping[str, Unit],
                options: Options | None = None) -> SizingResult:
    """Check given units, one per sized joint, along a planned trajectory: no selection.

    Each joint's only candidate is its unit, `selected` when it passes every rule.
    With mass coupling, each unit's mass (and the motor mass) is carried by the
    joints nearer the base, as `size_trajectory` carries the units it chooses.

    Args:
        robot: The robot (payload and mounting applied).
        trajectory: The trajectory, with the robot's joints.
        units: The unit of every sized joint, by joint name.
        options: The assumptions (default `Options()`).

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
    for name in units:
        if name not in robot.sized_joints:
            raise InputError(f"'{name}' is not a sized joint; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field="units")
    missing = [name for name in robot.sized_joints if name not in units]
    if missing:
        raise InputError(f"no unit given for {', '.join(missing)}", field="units")
    options = options if options is not None else Options()
    masses = ({name: unit.mass + options.motor_mass for name, unit in units.items()}
              if options.mass_coupling else {})
    carrying = robot.with_gearheads(masses)
    torques = cycle_torques(carrying, trajectory.q, trajectory.qd, trajectory.qdd,
                            options.stop_time, threads=options.threads)
    joints = []
    for name in robot.sized_joints:
        j = robot.joint_index(name)
        joints.append(_size_joint(name, trajectory, trajectory.qd[:, j], trajectory.qdd[:, j],
                                  torques.tau[:, j], torques.stop[:, j], (units[name],),
                                  options))
    distinct = tuple(dict.fromkeys(units[name] for name in robot.sized_joints))
    return SizingResult(robot, trajectory, tuple(_with_gravity(carrying, trajectory, joints,
                                                               options)), options, distinct,
                        loads=joint_loads(robot, trajectory, torques.tau))


def _with_gravity(carrying: Robot, trajectory: Trajectory, joints: list[JointSizing],
                  options: Options) -> list[JointSizing]:
    """The joints with their carried mass and whether gravity loads them (from ~400 poses)."""
    poses = np.unique(np.linspace(0, len(trajectory.t) - 1, GRAVITY_SAMPLES).astype(int))
    gravity = np.abs(gravity_torques(carrying, trajectory.q[poses], threads=options.threads))
    return [replace(joint, carried_mass=carrying.carried_mass(joint.name),
                    gravity_loaded=bool(gravity[:, j].max() > GRAVITY_LOADED),
                    max_gravity_torque=float(gravity[:, j].max()))
            for joint in joints for j in [carrying.joint_index(joint.name)]]


def _unit_masses(joints: list[JointSizing], options: Options) -> dict[str, float]:
    """Mass each joint's unit (or, where none fits, the strongest) and motor add [kg]."""
    masses = {}
    for joint in joints:
        chosen = joint.selected or joint.strongest
        motor = chosen.motor_unit
        masses[joint.name] = chosen.unit.mass + (motor.mass if motor is not None
                                                 else options.motor_mass)
    return masses


def _size_joints(robot: Robot, traj: Trajectory, units: tuple[Unit, ...],
                 options: Options, motors: Motors | None = None,
                 ) -> tuple[list[JointSizing], CycleTorques]:
    """Every sized joint against every unit (or pair), for the masses in the robot's model."""
    torques = cycle_torques(robot, traj.q, traj.qd, traj.qdd, options.stop_time,
                            threads=options.threads)
    joints = []
    for name in robot.sized_joints:
        j = robot.joint_index(name)
        joints.append(_size_joint(name, traj, traj.qd[:, j], traj.qdd[:, j], torques.tau[:, j],
                                  torques.stop[:, j], units, options,
                                  motors=tuple(motors.get(name, ())) if motors else ()))
    return joints, torques


def _decimated(traj: Trajectory, step: int) -> Trajectory:
    """Every `step`-th sample of a trajectory, each standing for `step` periods."""
    return replace(traj, dt=traj.dt * step, t=traj.t[::step], q=traj.q[::step],
                   qd=traj.qd[::step], qdd=traj.qdd[::step])


def _size_joint(name: str, traj: Trajectory, qd: np.ndarray, qdd: np.ndarray, tau: np.ndarray,
                stop_tau: np.ndarray, units: tuple[Unit, ...], options: Options, *,
                motors: tuple[Motor, ...] = ()) -> JointSizing:
    """Check every unit (every pair with `motors`) against one joint's torques; select one."""
    load = cycle_load(tau, qd, traj.dt, at_rest(qd, qdd))
    prefer = options.prefer or (DEFAULT_PREFER_WITH_MOTORS if motors else DEFAULT_PREFER)
    if not motors:
        reflections = reflect(units, traj.t, tau, qd, qdd, stop_tau,
                              stop_time=options.stop_time, efficiency=options.efficiency,
                              rotor_inertia=options.rotor_inertia)
        candidates = [check_unit(load, r.unit, momentary=r.momentary,
                                 life_hours=options.life_hours, life_basis=options.life_basis,
                                 motor=r.motor) for r in reflections]
        return JointSizing(name, load, tuple(candidates), select(candidates, prefer),
                           0.0, False, 0.0, readonly(tau), readonly(stop_tau))
    behind = reflect_motors(units, [m.rotor_inertia for m in motors], traj.t, tau, qd, qdd,
                            stop_tau, stop_time=options.stop_time, efficiency=options.efficiency)
    speed = np.abs(qd) * RPM_PER_RAD_S
    pairs, reflection = [], {}
    for u, unit in enumerate(units):
        for m, motor in enumerate(motors):
            r = behind[m][u]
            gearhead = check_unit(load, unit, momentary=r.momentary,
                                  life_hours=options.life_hours, life_basis=options.life_basis,
                                  motor=r.motor)
            pair = with_motor(gearhead, motor, r.motor_torque, speed * unit.ratio)
            pairs.append(pair)
            reflection[id(pair)] = r
    selected = select(pairs, prefer)
    joint = JointSizing(name, load, tuple(pairs), selected, 0.0, False, 0.0, readonly(tau),
                        readonly(stop_tau))
    shown = selected or joint.strongest
    return replace(joint, motor_torque=frozen(reflection[id(shown)].motor_torque))
