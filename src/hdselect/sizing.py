"""Size every joint of a robot from its motion: the product's main job.

Plan the motion, compute the torques along it and along an emergency stop
from every instant, then choose a gearhead per joint from the tip to the base,
each chosen unit's mass (and motor mass) carried by the joints nearer the base.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from hdselect.arrays import frozen
from hdselect.catalog import Unit, load_catalog
from hdselect.coupling import carried_mass, with_gearheads
from hdselect.dynamics import inverse_dynamics
from hdselect.errors import InputError
from hdselect.motion import Motion, load_motion
from hdselect.plan import Trajectory, plan
from hdselect.reflect import DEFAULT_EFFICIENCY, reflect
from hdselect.robot import Payload, Robot
from hdselect.rules import Candidate, CycleLoad, check_unit, cycle_load
from hdselect.select import select
from hdselect.slowdown import Slowdown, find_slowdown

DEFAULT_STOP_TIME = 0.1
"""Time in which an emergency stop or a crash brings the arm to rest [s]."""
REST_FRACTION = 1e-3
"""A joint is at rest (input held) where both its speed and its acceleration are below
this fraction of their largest values in the cycle [-]."""
GRAVITY_LOADED = 1e-3
"""Gravity torque above which a joint is gravity-loaded (backdriving warning) [N m]."""
_GRAVITY_SAMPLES = 400
"""Poses at which the gravity torque is evaluated for the backdriving warning."""
_GUESS_SAMPLES = 200
"""Samples on which the carried masses are first guessed."""


@dataclass(frozen=True)
class Options:
    """Assumptions of a sizing run, stated in every report.

    Attributes:
        stop_time: Emergency-stop and crash time [s].
        efficiency: Gear efficiency where a unit has no table [-].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].
        motor_mass: Motor mass carried with each gearhead [kg].
        mass_coupling: Whether chosen units' masses load the joints nearer the base.
        prefer: Selection order (see `hdselect.select.PREFERENCES`).
        life_hours: Required L50 life [h], if any.
    """

    stop_time: float = DEFAULT_STOP_TIME
    efficiency: float = DEFAULT_EFFICIENCY
    rotor_inertia: float = 0.0
    motor_mass: float = 0.0
    mass_coupling: bool = True
    prefer: str = "size"
    life_hours: float | None = None


@dataclass(frozen=True, eq=False)
class JointSizing:
    """One joint: every unit checked, the selection and why.

    Attributes:
        name: Joint name.
        load: Output-side summary of the cycle (with carried masses).
        candidates: One per catalog unit.
        selected: The chosen unit, or None when none fits.
        carried_mass: Gearhead and motor mass this joint carries from joints
            further out [kg].
        gravity_loaded: Gravity loads this joint somewhere in the cycle: a
            fail-safe device is needed where a falling load could injure.
        max_gravity_torque: Largest gravity torque over the cycle's poses [N m].
        torque: Output torque along the cycle [N m], shape (n,).
        stop_torque: Output torque of an emergency stop from each instant [N m], (n,).
        slowdown: For a joint with no feasible unit, the slow-down that would fit.
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

    @property
    def strongest(self) -> Candidate:
        """The candidate with the highest repeated-peak limit."""
        return max(self.candidates, key=lambda c: (c.unit.repeated_torque,
                                                   c.unit.momentary_torque, c.unit.rated_torque))


@dataclass(frozen=True, eq=False)
class SizingResult:
    """Everything `hdselect size` prints, as values.

    Attributes:
        robot: The robot.
        motion: The motion.
        trajectory: The planned trajectory.
        joints: One result per sized joint, in the robot's joint order.
        options: The assumptions used.
        units: The catalog.
    """

    robot: Robot
    motion: Motion
    trajectory: Trajectory
    joints: tuple[JointSizing, ...]
    options: Options
    units: tuple[Unit, ...]

    @property
    def feasible(self) -> bool:
        """Every joint has a unit."""
        return all(joint.selected is not None for joint in self.joints)

    @property
    def cycle_time(self) -> float:
        """Cycle time [s]."""
        return self.trajectory.duration


def size(
    robot: Robot | str | Path | None,
    motion: Motion | str | Path,
    *,
    catalog: tuple[str | Path, ...] | list[str | Path] = (),
    units: tuple[Unit, ...] | None = None,
    stop_time: float | None = None,
    efficiency: float = DEFAULT_EFFICIENCY,
    rotor_inertia: float = 0.0,
    motor_mass: float = 0.0,
    mass_coupling: bool = True,
    prefer: str = "size",
    life_hours: float | None = None,
    payload: Payload | None = None,
    mounting: str | list[float] | None = None,
    joints: list[str] | None = None,
) -> SizingResult:
    """Choose a gearhead for every joint of a robot from its motion.

    Args:
        robot: Robot file or loaded robot; None takes the motion file's ``robot``.
        motion: Motion file or loaded motion.
        catalog: Extra catalog files (the built-in PSA-G catalog is always loaded).
        units: The catalog already loaded (overrides `catalog`).
        stop_time: Emergency-stop and crash time [s]; default the motion file's
            ``[safety] stop_time``, else `DEFAULT_STOP_TIME`.
        efficiency: Gear efficiency where a unit has no table [-].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].
        motor_mass: Motor mass carried with each gearhead [kg].
        mass_coupling: Carry each chosen unit's mass on the joints nearer the base.
        prefer: Selection order, a key of `hdselect.select.PREFERENCES`.
        life_hours: Required L50 life [h]; default the motion file's requirement.
        payload: Payload, overriding the motion file's.
        mounting: Mounting, overriding the motion file's.
        joints: Joints to size (default every revolute joint).

    Returns:
        The result for every sized joint.

    Raises:
        InputError: A file or option is invalid.
        PlanningError: The motion cannot be planned.
    """
    if not isinstance(motion, Motion):
        motion = load_motion(motion, robot, payload=payload, mounting=mounting, joints=joints)
    options = Options(
        stop_time=_positive(stop_time if stop_time is not None else
                            motion.stop_time or DEFAULT_STOP_TIME, "--stop-time"),
        efficiency=_fraction(efficiency),
        rotor_inertia=_non_negative(rotor_inertia, "--motor-inertia"),
        motor_mass=_non_negative(motor_mass, "--motor-mass"),
        mass_coupling=mass_coupling,
        prefer=prefer,
        life_hours=life_hours if life_hours is not None else motion.life_hours,
    )
    if units is None:
        units = load_catalog(catalog)
    select((), options.prefer)  # validates the order before the work
    trajectory = plan(motion)
    results = _size_trajectory(motion.robot, trajectory, units, options)
    return SizingResult(motion.robot, motion, trajectory, results, options, units)


def _size_trajectory(robot: Robot, traj: Trajectory, units: tuple[Unit, ...],
                     options: Options) -> tuple[JointSizing, ...]:
    """Size every joint, carrying the chosen units' masses when coupling is on.

    Joint j's torque depends only on the units chosen further out, so sizing
    from the tip to the base is one pass. It is found here as a fixed point:
    size every joint with the masses of a guess in the model, put the chosen
    units' masses in, and repeat until the choice no longer changes. At that
    point each joint was sized with exactly the units chosen beyond it, which is
    the tip-to-base answer (each round settles at least one more joint from the
    tip). The guess comes from two rounds on a coarse subset of the samples, so
    the full trajectory usually takes one round: two batched passes of inverse
    dynamics, the motion's and the emergency stop's.
    """
    masses: dict[str, float] = {}
    if options.mass_coupling:
        coarse = _decimated(traj, max(1, len(traj.t) // _GUESS_SAMPLES))
        for _ in range(2):
            masses = _unit_masses(_size_joints(with_gearheads(robot, masses), coarse, units,
                                               options), options)
    for _ in range(robot.dof + 1):
        carrying = with_gearheads(robot, masses)
        joints = _size_joints(carrying, traj, units, options)
        chosen = _unit_masses(joints, options)
        if not options.mass_coupling or chosen == masses:
            break
        masses = chosen
    else:  # each round settles at least one more joint from the tip
        raise AssertionError("the tip-to-base sizing did not settle")
    gravity_at = np.unique(np.linspace(0, len(traj.t) - 1, _GRAVITY_SAMPLES).astype(int))
    still = np.zeros((len(gravity_at), robot.dof))
    gravity = np.abs(inverse_dynamics(carrying, traj.q[gravity_at], still, still))
    joints = [replace(joint, carried_mass=carried_mass(robot, masses, joint.name),
                      gravity_loaded=bool(gravity[:, j].max() > GRAVITY_LOADED),
                      max_gravity_torque=float(gravity[:, j].max()))
              for joint in joints for j in [robot.joint_index(joint.name)]]
    if any(joint.selected is None for joint in joints):
        joints = _with_slowdowns(carrying, traj, joints, units, options)
    return tuple(joints)


def _unit_masses(joints: list[JointSizing], options: Options) -> dict[str, float]:
    """Mass each joint's unit (or, where none fits, the strongest) and motor add [kg]."""
    return {joint.name: (joint.selected or joint.strongest).unit.mass + options.motor_mass
            for joint in joints}


def _size_joints(robot: Robot, traj: Trajectory, units: tuple[Unit, ...],
                 options: Options) -> list[JointSizing]:
    """Every sized joint against every unit, for the masses in the robot's model."""
    tau = inverse_dynamics(robot, traj.q, traj.qd, traj.qdd)
    stop_tau = inverse_dynamics(robot, traj.q, traj.qd, -traj.qd / options.stop_time)
    joints = []
    for name in robot.sized_joints:
        j = robot.joint_index(name)
        joints.append(_size_joint(name, traj, traj.qd[:, j], traj.qdd[:, j], tau[:, j],
                                  stop_tau[:, j], units, options))
    return joints


def _decimated(traj: Trajectory, step: int) -> Trajectory:
    """Every `step`-th sample of a trajectory, each standing for `step` periods."""
    return replace(traj, dt=traj.dt * step, t=traj.t[::step], q=traj.q[::step],
                   qd=traj.qd[::step], qdd=traj.qdd[::step])


def _size_joint(name: str, traj: Trajectory, qd: np.ndarray, qdd: np.ndarray, tau: np.ndarray,
                stop_tau: np.ndarray, units: tuple[Unit, ...], options: Options) -> JointSizing:
    """Check every unit against one joint's torques and select one."""
    load = cycle_load(tau, qd, traj.dt, _at_rest(qd, qdd))
    reflections = reflect(units, traj.t, tau, qd, qdd, stop_tau, stop_time=options.stop_time,
                          efficiency=options.efficiency, rotor_inertia=options.rotor_inertia)
    candidates = [check_unit(load, r.unit, momentary=r.momentary, life_hours=options.life_hours,
                             motor=r.motor) for r in reflections]
    return JointSizing(name, load, tuple(candidates), select(candidates, options.prefer),
                       0.0, False, 0.0, frozen(tau), frozen(stop_tau))


def _at_rest(qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Samples where the joint is held still: speed and acceleration both negligible."""
    speed, acceleration = np.abs(qd), np.abs(qdd)
    return ((speed <= REST_FRACTION * speed.max())
            & (acceleration <= REST_FRACTION * acceleration.max()))


def _with_slowdowns(robot: Robot, traj: Trajectory, joints: list[JointSizing],
                    units: tuple[Unit, ...], options: Options) -> list[JointSizing]:
    """Attach to each joint without a unit the smallest slow-down that would fit.

    `robot` carries the chosen units' masses. The gravity and coasting (gravity
    plus velocity terms) torques split the motion's torques by how they scale.
    """
    still = np.zeros_like(traj.qd)
    gravity = inverse_dynamics(robot, traj.q, still, still)
    coasting = inverse_dynamics(robot, traj.q, traj.qd, still)
    out = []
    for joint in joints:
        if joint.selected is None:
            j = robot.joint_index(joint.name)
            qd, qdd = traj.qd[:, j], traj.qdd[:, j]
            joint = replace(joint, slowdown=find_slowdown(
                units, traj, qd, qdd, joint.torque, joint.stop_torque, gravity[:, j],
                coasting[:, j], _at_rest(qd, qdd), stop_time=options.stop_time,
                efficiency=options.efficiency, rotor_inertia=options.rotor_inertia,
                life_hours=options.life_hours))
        out.append(joint)
    return out


def _positive(value: float, field: str) -> float:
    if not np.isfinite(value) or value <= 0.0:
        raise InputError(f"must be a positive number of seconds, got {value:g}", field=field)
    return float(value)


def _non_negative(value: float, field: str) -> float:
    if not np.isfinite(value) or value < 0.0:
        raise InputError(f"must be zero or positive, got {value:g}", field=field)
    return float(value)


def _fraction(value: float) -> float:
    if not np.isfinite(value) or not 0.0 < value <= 1.0:
        raise InputError(f"must be in (0, 1], got {value:g}", field="--efficiency")
    return float(value)
