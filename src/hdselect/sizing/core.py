"""Size every joint of a robot from its motion: the product's main job, and its one core.

`size_trajectory` takes a robot and a planned trajectory and chooses a gearhead
per joint from the tip to the base, each chosen unit's mass (and motor mass)
carried by the joints nearer the base. Where motors are given, it chooses a
gearhead and a motor together: every (gearhead, motor) pair is checked, and the
pair's mass is carried. `size` is load + plan + `size_trajectory`. Every front end
(the command line, studies, co-design, Python) goes through it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from hdselect.base.arrays import frozen, readonly
from hdselect.base.bounds import expect_type, files_argument
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motor_rules import inertia_ratio, with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import RPM_PER_RAD_S, Candidate, CycleLoad, check_unit, cycle_load
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, select
from hdselect.catalog.units import Unit
from hdselect.motion.case import load_case, robot_for_motion
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.robot.dynamics import CycleTorques, cycle_torques, gravity_torques, joint_inertias
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.payload import Payload
from hdselect.sizing.loads import JointLoad, joint_loads
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.reflect import reflect, reflect_motors
from hdselect.sizing.timescale import JointScales, ScalableCycle, Slowdown, joint_scales

REST_FRACTION = 1e-3
"""A joint is at rest (input held) where both its speed and its acceleration are below
this fraction of their largest values in the cycle [-]."""
GRAVITY_LOADED = 1e-3
"""Gravity torque above which a joint is gravity-loaded (backdriving warning) [N m]."""
GRAVITY_SAMPLES = 400
"""Poses at which the gravity torque is evaluated for the backdriving warning."""
_GUESS_SAMPLES = 200
"""Samples on which the carried masses are first guessed."""
_INERTIA_POSES = GRAVITY_SAMPLES
"""Poses, evenly spread over the cycle, at which a joint's load inertia M_jj is evaluated."""

Motors = Mapping[str, Sequence[Motor]]
"""Candidate motors per joint name: the motors each joint's gearhead may be paired with."""


@dataclass(frozen=True, eq=False)
class JointSizing:
    """One joint: every unit (or every gearhead and motor pair) checked, the selection and why.

    Attributes:
        name: Joint name.
        load: Output-side summary of the cycle (with carried masses).
        candidates: One per catalog unit; where motors are given, one per (unit, motor)
            pair, unit by unit.
        selected: The chosen unit (or pair), or None when none fits.
        carried_mass: Gearhead and motor mass this joint carries from joints
            further out [kg].
        gravity_loaded: Gravity loads this joint somewhere in the cycle: a
            fail-safe device is needed where a falling load could injure.
        max_gravity_torque: Largest gravity torque over the cycle's poses [N m].
        torque: Output torque along the cycle [N m], shape (n,).
        stop_torque: Output torque of an emergency stop from each instant [N m], (n,).
        slowdown: For a joint with no feasible unit, the smallest slow-down that would
            fit (its factor rounded up to 0.001).
        scales: For a joint with no feasible unit, the time scales at which each unit
            would fit.
        load_inertia: Where motors are given, the joint's output-side inertia: the largest
            diagonal entry M_jj of the joint-space inertia matrix over the cycle's poses
            (`_INERTIA_POSES` of them), carried masses and payload included [kg m^2].
        motor_torque: Where motors are given, the motor torque of the selected pair (else
            of the strongest) per sample [N m], shape (n,).
    """

    name: str
    load: CycleLoad
    candidates: tuple[Candidate, ...]
    selected: Candidate | None
    carried_mass: float
    gravity_loaded: bool
    max_gravity_torque: float
    torque: np.ndarray
    stop_torque: np.ndarray
    slowdown: Slowdown | None = None
    scales: JointScales | None = None
    load_inertia: float | None = None
    motor_torque: np.ndarray | None = None

    @property
    def strongest(self) -> Candidate:
        """The candidate with the highest repeated-peak limit.

        With motors: behind the motor with the highest peak, then rated torque.
        """
        return max(self.candidates, key=lambda c: (
            c.unit.repeated_torque, c.unit.momentary_torque, c.unit.rated_torque,
            *((c.motor_unit.peak_torque, c.motor_unit.rated_torque)
              if c.motor_unit is not None else ())))

    def inertia_ratio(self, candidate: Candidate) -> float | None:
        """Load inertia at the motor shaft over the rotor inertia for one pair [-].

        (M_jj / N^2 + J_in) / J_m with M_jj the `load_inertia`; None without a motor, or
        for a motor without rotor inertia (`hdselect.catalog.rules.inertia_ratio`).
        """
        if self.load_inertia is None or candidate.motor_unit is None:
            return None
        return inertia_ratio(self.load_inertia, candidate.unit, candidate.motor_unit)


@dataclass(frozen=True, eq=False)
class SizingResult:
    """Everything `hdselect size` prints, as values.

    Attributes:
        robot: The robot as sized (payload and mounting applied, no gearhead masses).
        trajectory: The trajectory sized.
        joints: One result per sized joint, in the robot's joint order.
        options: The assumptions used.
        units: The catalog.
        motion: The motion the trajectory was planned from, when `size` planned it.
        motors: The candidate motors per joint; empty where no motor data was given
            (then `options` say which rotor inertia and motor mass were assumed).
        loads: Every joint of the robot, sized or not, followers included, in the
            model's order: what it does beside its file's limits.
    """

    robot: Robot
    trajectory: Trajectory
    joints: tuple[JointSizing, ...]
    options: Options
    units: tuple[Unit, ...]
    motion: Motion | None = None
    motors: Mapping[str, tuple[Motor, ...]] = field(default_factory=dict)
    loads: tuple[JointLoad, ...] = ()

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the robot file and the motion file raised, and limits the cycle exceeds.

        Each line starts with where it comes from: ``robot file:``, ``motion file:`` or
        ``cycle:``.
        """
        asked = self.motion.warnings if self.motion is not None else ()
        lines = [f"robot file: {note}" for note in self.robot.notes]
        lines += [f"motion file: {warning}" for warning in asked]
        for load in self.loads:
            if load.above_effort:
                lines.append(f"cycle: joint '{load.name}' peaks at {load.peak:.3g} "
                             f"{'N' if load.linear else 'N m'}, above the robot file's effort "
                             f"limit {load.effort_limit:.3g}")
            if load.above_velocity and not any(f"'{load.name}'" in w for w in asked):
                per_s = "m/s" if load.linear else "rad/s"
                lines.append(f"cycle: joint '{load.name}' moves at up to {load.max_speed:.3g} "
                             f"{per_s}, above the robot file's velocity limit "
                             f"{load.velocity_limit:.3g}")
        return tuple(lines)

    @property
    def feasible(self) -> bool:
        """Every joint has a unit."""
        return all(joint.selected is not None for joint in self.joints)

    @property
    def cycle_time(self) -> float:
        """Cycle time [s]."""
        return self.trajectory.duration

    @property
    def hold_only(self) -> bool:
        """No sized joint moves: a held pose, judged by the static and momentary checks only."""
        return all(joint.load.moving_time == 0.0 for joint in self.joints)

    @property
    def title(self) -> str:
        """What was sized, for headings: the robot file, the motion file and its planner."""
        if self.motion is None:
            return f"{self.robot.path.name} on a given trajectory"
        return f"{self.robot.path.name} running {self.motion.path.name} ({self.motion.planner})"


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
        units = _units_argument(units)
    expect_type(robot, (Robot, str, Path, type(None)), "robot", "a Robot, a robot file or None")
    expect_type(motion, (Motion, str, Path), "motion", "a Motion or a motion file")
    expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    if isinstance(motion, Motion):
        if not isinstance(robot, Robot):
            file = robot if robot is not None else motion.robot_file
            if file is None:
                raise InputError("no robot given, and the motion file names none",
                                 path=motion.path, field="robot")
            robot = load_robot(file)
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
    _check_trajectory(trajectory)
    units = _units_argument(units)
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
        joints = _with_slowdowns(carrying, trajectory, joints, units, options, motors)
    assert torques is not None
    return SizingResult(robot, trajectory, tuple(joints), options, units, motors=motors,
                        loads=joint_loads(robot, trajectory, torques.tau))


def checked_motors(robot: Robot, motors: Motors | None,
                   options: Options) -> dict[str, tuple[Motor, ...]]:
    """The candidate motors per sized joint, checked; empty when none are given.

    Args:
        robot: The robot as sized.
        motors: Candidate motors per joint name (a single `Motor` is one candidate).
        options: The assumptions: with motors, their rotor inertia and motor mass must
            not be given too.

    Returns:
        Joint name -> its candidate motors, in the order given.

    Raises:
        InputError: A joint is not sized, has no motor or a motor id twice, or the
            options give a rotor inertia or motor mass beside the motors.
    """
    if not motors:
        return {}
    if isinstance(motors, str | Path) or not isinstance(motors, Mapping):
        raise InputError("expected a mapping of joint name to candidate motors",
                         field="motors")
    checked: dict[str, tuple[Motor, ...]] = {}
    for name, given in motors.items():
        if name not in robot.sized_joints:
            raise InputError(f"'{name}' is not a sized joint; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field=f"motors.{name}")
        candidates = (given,) if isinstance(given, Motor) else tuple(given)
        if not candidates or not all(isinstance(m, Motor) for m in candidates):
            raise InputError("expected one or more hdselect.catalog.motors.Motor",
                             field=f"motors.{name}")
        ids = [m.id for m in candidates]
        for motor_id in ids:
            if ids.count(motor_id) > 1:
                raise InputError(f"motor id '{motor_id}' is given twice",
                                 field=f"motors.{name}")
        checked[name] = candidates
    if options.rotor_inertia > 0.0 or options.motor_mass > 0.0:
        raise InputError("motor data is given, so the rotor inertia and motor mass come from "
                         "the motors; drop rotor_inertia and motor_mass (--motor-inertia, "
                         "--motor-mass)", field="motors")
    return checked


def _units_argument(units: object) -> tuple[Unit, ...]:
    """The `units` argument as a tuple of units.

    Raises:
        InputError: It is not a sequence of `hdselect.catalog.units.Unit`.
    """
    if isinstance(units, str | bytes | Path) or not isinstance(units, Sequence):
        raise InputError(f"expected a sequence of catalog units, got {type(units).__name__}",
                         field="units")
    for unit in units:
        expect_type(unit, (Unit,), "units", "catalog units (hdselect.load_catalog)")
    return tuple(units)


def _check_trajectory(trajectory: Trajectory) -> None:
    """A trajectory's arrays agree in shape and hold finite numbers.

    Raises:
        InputError: They do not (the field names the array).
    """
    n, dof = len(trajectory.t), len(trajectory.joint_names)
    if not (isinstance(trajectory.dt, float | int) and math.isfinite(trajectory.dt)
            and trajectory.dt > 0.0):
        raise InputError(f"must be a positive time [s], got {trajectory.dt!r}",
                         field="trajectory.dt")
    for name, shape in (("t", (n,)), ("q", (n, dof)), ("qd", (n, dof)), ("qdd", (n, dof))):
        array = np.asarray(getattr(trajectory, name))
        if array.shape != shape or n == 0:
            raise InputError(f"expected shape {shape} with n >= 1, got {array.shape}",
                             field=f"trajectory.{name}")
        if not np.all(np.isfinite(array)):
            raise InputError("holds a number that is not finite", field=f"trajectory.{name}")


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
    _check_trajectory(trajectory)
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


def at_rest(qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Samples where a joint is held still: speed and acceleration both negligible.

    Args:
        qd: The joint's speed [rad/s], shape (n,).
        qdd: The joint's acceleration [rad/s^2], shape (n,).

    Returns:
        True where both are at most `REST_FRACTION` of their largest values.
    """
    speed, acceleration = np.abs(qd), np.abs(qdd)
    return ((speed <= REST_FRACTION * speed.max())
            & (acceleration <= REST_FRACTION * acceleration.max()))


def _with_slowdowns(robot: Robot, traj: Trajectory, joints: list[JointSizing],
                    units: tuple[Unit, ...], options: Options,
                    motors: Motors | None = None) -> list[JointSizing]:
    """Attach to each joint without a unit the time scales at which each unit would fit.

    `robot` carries the chosen units' masses. Two more batched passes (gravity, and
    gravity plus velocity terms) split the motion's torques by how they scale.
    """
    failing = [robot.joint_index(joint.name) for joint in joints if joint.selected is None]
    torques = cycle_torques(robot, traj.q, traj.qd, traj.qdd, options.stop_time, split=True,
                            threads=options.threads, columns=failing)
    assert torques.gravity is not None and torques.coasting is not None
    out = []
    for joint in joints:
        if joint.selected is None:
            j = robot.joint_index(joint.name)
            c = failing.index(j)
            qd, qdd = traj.qd[:, j], traj.qdd[:, j]
            cycle = ScalableCycle.split(
                traj.t, traj.dt, traj.duration, qd, qdd, at_rest(qd, qdd),
                torque=torques.tau[:, c], stop_torque=torques.stop[:, c],
                gravity=torques.gravity[:, c], coast=torques.coasting[:, c],
                stop_time=options.stop_time)
            slowdown, scales = fitting_time_scales(
                cycle, units, options,
                motors=tuple(motors.get(joint.name, ())) if motors else ())
            joint = replace(joint, slowdown=slowdown, scales=scales)
        out.append(joint)
    return out


def fitting_time_scales(cycle: ScalableCycle, units: Sequence[Unit], options: Options, *,
                        motors: Sequence[Motor] = ()) -> tuple[Slowdown, JointScales]:
    """For a joint no unit fits: every unit's feasible time scales and the smallest slow-down.

    Args:
        cycle: The joint's cycle split by how its torques scale.
        units: The catalog.
        options: The assumptions (efficiency, rotor inertia, life requirement).
        motors: The joint's candidate motors: then the scales are per (gearhead, motor)
            pair, each with its motor's rotor inertia and rules.

    Returns:
        The slow-down, its factor rounded to 0.001 (see `_rounded`), and the scales.
    """
    scales = joint_scales(cycle, units, efficiency=options.efficiency,
                          rotor_inertia=options.rotor_inertia,
                          check_options={"life_hours": options.life_hours,
                                         "life_basis": options.life_basis},
                          motors=tuple(motors))
    return _rounded(scales.slowdown(), scales, cycle.duration), scales


def _rounded(slowdown: Slowdown, scales: JointScales, duration: float) -> Slowdown:
    """The slow-down with its factor rounded to 0.001, away from the edge of what fits.

    The exact factor is the edge of the feasible range, where a re-planned motion
    sampled on its own grid can fail by the change over one sample. Rounding up (or
    down, for a speed-up) keeps inside the range whenever the range allows it.
    """
    if slowdown.factor is None or slowdown.unit is None:
        return slowdown
    exact = slowdown.factor
    rounded = (math.ceil(exact * 1000.0) if exact >= 1.0 else math.floor(exact * 1000.0)) / 1000.0
    if not any(lo <= rounded <= hi for lo, hi in scales.fits[slowdown.unit]):
        rounded = exact
    return replace(slowdown, factor=rounded, cycle_time=rounded * duration)
