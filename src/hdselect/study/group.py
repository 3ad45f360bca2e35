"""Many sizing cases of one robot and one path from a few batched passes of inverse dynamics.

For a fixed robot, mounting and planned path, every joint torque is affine in the
payload mass (its inertia about its centre of mass stays as given) and in each
gearhead point mass the arm carries, and a uniform time scale s changes it exactly
(`hdselect.timescale`): with y = 1/s and T the stop time,

    tau  = sum_p theta_p (G_p + A_p y^2)
    stop = sum_p theta_p (G_p + V_p y^2 + E_p y / T)

where p runs over the reference robot (theta = 1), the payload (theta = mass - 1 kg)
and one gearhead point mass per joint that carries one (theta = its mass [kg]); G is
gravity RNEA(q, 0, 0), A = RNEA(q, qd, qdd) - G, V = RNEA(q, qd, 0) - G and
E = RNEA(q, qd, -qd) - RNEA(q, qd, 0), one stacked batched pass per parameter.
Every case of the group is then sized from these by linear combination, joint by
joint from the tip to the base, each joint with exactly the masses of the units
chosen further out: the answer `hdselect.size_trajectory` reaches by its fixed
point, from the same rules (`cycle_load`, `reflect`, `check_unit`, `select`).
Runs of identical samples (dwells) are kept once, weighted by their length.

Where a case gives motors, a joint with motors checks every (gearhead, motor) pair as
the core does (`reflect_motors`, `with_motor`): each motor's rotor inertia in the
motor torque and the crash, the motor's rules with its RMS torque weighted by the
runs, and the chosen pair's mass, gearhead and motor, in the carried point mass. The
joint's load inertia M_jj, linear in the same parameters, comes from one more set of
passes per parameter at the core's poses (`build_basis(..., inertias=True)`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    Candidate,
    CycleLoad,
    Momentary,
    at_rest,
    check_unit,
    cycle_load,
)
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, select
from hdselect.catalog.units import Unit
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.robot.dynamics import inverse_dynamics, joint_inertias
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import checked_motors
from hdselect.sizing.core import GRAVITY_LOADED, GRAVITY_SAMPLES  # the core's own choices
from hdselect.sizing.loads import joint_loads
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import Reflection, reflect, reflect_motors, weighted_demand
from hdselect.sizing.result import JointSizing, Motors, SizingResult
from hdselect.sizing.slowdown import fitting_time_scales
from hdselect.sizing.summary import Summary, summarize
from hdselect.sizing.timescale import ScalableCycle

REFERENCE_MASS = 1.0
"""Payload mass of the reference robot the group is planned and evaluated with [kg]."""


@dataclass(frozen=True, eq=False)
class Basis:
    """A robot and a planned path, with its torques split by parameter and by scaling.

    Attributes:
        robot: The reference robot: mounting applied, payload (if any) of `REFERENCE_MASS`.
        motion: The motion planned.
        trajectory: The trajectory at s = 1, every sample.
        payload: The payload at the reference mass, or None.
        rows: Index of each kept sample (the first of a run of identical ones), (n,).
        weight: Samples each kept row stands for [-], (n,).
        t: Time of each kept row at s = 1 [s], (n,).
        qd: Joint speeds of the kept rows at s = 1 [rad/s], (n, dof).
        qdd: Joint accelerations of the kept rows at s = 1 [rad/s^2], (n, dof).
        carriers: Sized joints whose gearhead some joint carries, one parameter each.
        gravity: G per joint and parameter [N m], shape (dof, P, n); parameter 0 is the
            reference robot, then the payload (if any), then one per carrier, per 1 kg.
        dynamic: A, the velocity and inertial part at s = 1 [N m], same shape.
        coasting: V, the velocity-product part at s = 1 [N m], same shape.
        stopping: E, an emergency stop's inertial part at s = 1 and a 1 s stop [N m].
        used: Per joint, the parameters that load it (the others add exactly zero).
        carried: carried[j, c] is 1 where sized joint j carries carrier c's gearhead.
        poses: The kept row of each pose at which gravity loading is judged.
        inertia: M_jj per sized joint and parameter at the same poses [kg m^2], shape
            (sized joints, P, poses), as `gravity`; None unless asked for (motors).
    """

    robot: Robot
    motion: Motion
    trajectory: Trajectory
    payload: Payload | None
    rows: np.ndarray
    weight: np.ndarray
    t: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    carriers: tuple[str, ...]
    gravity: np.ndarray
    dynamic: np.ndarray
    coasting: np.ndarray
    stopping: np.ndarray
    used: tuple[np.ndarray, ...]
    carried: np.ndarray
    poses: np.ndarray
    inertia: np.ndarray | None = None


def build_basis(robot: Robot, motion: Motion, payload: Payload | None, *,
                inertias: bool = False) -> Basis:
    """Plan the path once and run the batched passes of every parameter.

    Args:
        robot: The robot as the motion runs it, mounting applied, without a payload.
        motion: The motion; its plan must not depend on the payload (see `plan_depends_on_payload`).
        payload: The payload's shape (its mass is replaced by `REFERENCE_MASS`), or None.
        inertias: Also the sized joints' load inertia M_jj per parameter at the poses
            (what cases with motors need for their inertia ratio).

    Returns:
        The basis, 4 (2 + carriers) passes over the kept samples.
    """
    reference = robot.with_payload(None if payload is None
                                   else replace(payload, mass=REFERENCE_MASS))
    trajectory = plan(reference, motion)
    states = np.hstack([trajectory.q, trajectory.qd, trajectory.qdd])
    keep = np.ones(len(states), dtype=bool)
    keep[1:] = np.any(states[1:] != states[:-1], axis=1)
    rows = np.flatnonzero(keep)
    weight = np.diff(np.append(rows, len(states))).astype(float)
    model = robot.model
    carriers = tuple(name for name in robot.sized_joints
                     if model.parents[model.getJointId(name)] > 0)
    variants = [reference]
    if payload is not None:
        variants.append(reference.with_payload(replace(payload, mass=REFERENCE_MASS + 1.0)))
    variants += [reference.with_gearheads({name: 1.0}) for name in carriers]
    parts = np.stack([_parts(variant, trajectory, rows) for variant in variants])
    parts[1:] -= parts[0]  # each parameter's own contribution per unit of it
    gravity, dynamic, coasting, stopping = (np.ascontiguousarray(parts[:, k].transpose(2, 0, 1))
                                            for k in range(4))
    carried = np.array([[reference.with_gearheads({c: 1.0}).carried_mass(name) for c in carriers]
                        for name in robot.sized_joints]).reshape(len(robot.sized_joints), -1)
    run = np.cumsum(keep) - 1
    at = np.unique(np.linspace(0, len(states) - 1, GRAVITY_SAMPLES).astype(int))
    poses = run[at]
    loads = np.abs(parts).max(axis=(1, 2)) > 0.0  # (P, dof)
    used = tuple(_read_only(np.flatnonzero(loads[:, j])) for j in range(robot.dof))
    inertia = None
    if inertias:  # M(q) is linear in the inertial parameters, as the torques are
        m = np.stack([joint_inertias(variant, trajectory.q[at], robot.sized_joints, threads=1)
                      for variant in variants])  # (P, poses, sized)
        m[1:] -= m[0]
        inertia = frozen(np.ascontiguousarray(m.transpose(2, 0, 1)))
    return Basis(reference, motion, trajectory, payload, rows, weight, frozen(trajectory.t[rows]),
                 frozen(trajectory.qd[rows]), frozen(trajectory.qdd[rows]), carriers,
                 frozen(gravity), frozen(dynamic), frozen(coasting), frozen(stopping), used,
                 frozen(carried), _read_only(poses), inertia)


def plan_depends_on_payload(motion: Motion) -> bool:
    """TOPPRA under joint torque limits plans with the payload's dynamics: no common path."""
    return motion.planner == "toppra" and motion.torque_limit is not None


def _parts(robot: Robot, traj: Trajectory, rows: np.ndarray) -> np.ndarray:
    """G, A, V, E of one robot on the kept rows [N m], shape (4, n, dof): one stacked pass."""
    q, qd, qdd = traj.q[rows], traj.qd[rows], traj.qdd[rows]
    still = np.zeros_like(qd)
    tau = inverse_dynamics(robot, np.vstack([q, q, q, q]), np.vstack([still, qd, qd, qd]),
                           np.vstack([still, still, qdd, -qd]), threads=1)
    gravity, coast, full, stop = tau.reshape(4, len(rows), -1)
    return np.stack([gravity, full - gravity, coast - gravity, stop - coast])


def size_case(basis: Basis, mass: float | None, time_scale: float, units: Sequence[Unit],
              options: Options, motors: Motors | None = None) -> Summary:
    """One case of the group, sized as `hdselect.size_trajectory` sizes it.

    Args:
        basis: The group's basis (with `Basis.inertia` where motors are given).
        mass: Payload mass [kg] (None exactly when the basis has no payload).
        time_scale: The path run s times slower [-].
        units: The candidate units.
        options: The assumptions; ``prefer`` None is resolved as the core resolves it.
        motors: Candidate motors per sized joint, as `hdselect.size_trajectory` takes them.

    Returns:
        The case's summary; its robot and motion are the basis's files.

    Raises:
        InputError: The motors are not valid for this robot and these options (as the
            core says).
    """
    units = tuple(units)
    motors = checked_motors(basis.robot, motors, options)
    if options.prefer is None:
        options = replace(options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors
                          else DEFAULT_PREFER)
    assert options.prefer is not None
    if motors and basis.inertia is None:
        raise ValueError("a case with motors needs a basis built with inertias=True")
    traj, y = basis.trajectory, 1.0 / time_scale
    theta = np.zeros(basis.gravity.shape[1])
    theta[0] = 1.0
    if basis.payload is not None:
        assert mass is not None
        theta[1] = mass - REFERENCE_MASS
    first = len(theta) - len(basis.carriers)
    t, dt = basis.t * time_scale, traj.dt * time_scale * basis.weight
    qd, qdd = basis.qd * y, basis.qdd * y**2
    limits = _Limits.of(units, options)
    sized = basis.robot.sized_joints
    found: dict[str, JointSizing] = {}
    for name in reversed(sized):  # tip to base: a parent's index is below its children's
        j = basis.robot.joint_index(name)
        used = basis.used[j]
        weights = theta[used]
        gravity = weights @ basis.gravity[j, used]
        tau = gravity + (weights @ basis.dynamic[j, used]) * y**2
        coast = gravity + (weights @ basis.coasting[j, used]) * y**2
        stop = coast + (weights @ basis.stopping[j, used]) * (y / options.stop_time)
        pairs = motors.get(name, ())
        if pairs:
            assert basis.inertia is not None  # M_jj: only the units beyond j, all chosen
            inertia = float((theta @ basis.inertia[sized.index(name)]).max())
            joint = _size_pairs(name, t, dt, basis.weight, qd[:, j], qdd[:, j], tau, stop,
                                units, pairs, options, inertia)
        else:
            joint = _size_joint(name, t, dt, basis.weight, qd[:, j], qdd[:, j], tau, stop,
                                units, limits, options)
        if joint.selected is None:
            joint = _with_scales(joint, t, dt, traj.duration * time_scale, qd[:, j], qdd[:, j],
                                 tau, stop, gravity, coast, units, options, pairs,
                                 joint.load_inertia)
        found[name] = joint
        if options.mass_coupling and name in basis.carriers:
            chosen = joint.selected or joint.strongest
            theta[first + basis.carriers.index(name)] = chosen.unit.mass + (
                options.motor_mass if chosen.motor_unit is None else chosen.motor_unit.mass)
    masses = theta[first:]
    at_poses = np.abs(np.einsum("p,dpn->nd", theta, basis.gravity[:, :, basis.poses]))
    joints = []
    for i, name in enumerate(sized):
        j = basis.robot.joint_index(name)
        carried = 0.0
        for c in range(len(basis.carriers)):
            if basis.carried[i, c] and masses[c] > 0.0:
                carried += float(masses[c])
        worst = float(at_poses[:, j].max())
        joints.append(replace(found[name], carried_mass=carried,
                              gravity_loaded=worst > GRAVITY_LOADED, max_gravity_torque=worst))
    # every joint's torque with the masses chosen, on the kept rows (a run of identical
    # states has one torque): the peaks, speeds and travel the core's `joint_loads` finds
    tau = np.einsum("p,dpn->nd", theta, basis.gravity + basis.dynamic * y**2)
    kept = replace(traj, dt=traj.dt * time_scale, duration=traj.duration * time_scale, t=t,
                   q=traj.q[basis.rows], qd=qd, qdd=qdd)
    # only the cycle time and the sample count of the trajectory go into the summary
    timing = replace(traj, dt=traj.dt * time_scale, duration=traj.duration * time_scale)
    summary = summarize(SizingResult(basis.robot, timing, tuple(joints), options, units,
                                     basis.motion, motors=motors,
                                     loads=joint_loads(basis.robot, kept, tau)))
    # the basis's robot carries the reference payload; the case carries its own mass
    return replace(summary, payload_mass=0.0 if mass is None else float(mass))


@dataclass(frozen=True)
class _Limits:
    """The units' figures the rules on single numbers read, as arrays in catalog order."""

    ratio: np.ndarray
    crash_gain: np.ndarray
    repeated: np.ndarray
    momentary: np.ndarray
    static: np.ndarray
    max_speed: np.ndarray
    strongest: int

    @classmethod
    def of(cls, units: tuple[Unit, ...], options: Options) -> _Limits:
        ratio = np.array([unit.ratio for unit in units], dtype=float)
        inertia = np.array([unit.input_inertia for unit in units]) + options.rotor_inertia
        strongest = max(range(len(units)), key=lambda k: (
            units[k].repeated_torque, units[k].momentary_torque, units[k].rated_torque))
        return cls(ratio, inertia * ratio**2 / options.stop_time,
                   np.array([unit.repeated_torque for unit in units]),
                   np.array([unit.momentary_torque for unit in units]),
                   np.array([unit.static_torque for unit in units]),
                   np.array([unit.max_input_speed for unit in units]), strongest)


def _size_joint(name: str, t: np.ndarray, dt: np.ndarray, weight: np.ndarray, qd: np.ndarray,
                qdd: np.ndarray, tau: np.ndarray, stop: np.ndarray, units: tuple[Unit, ...],
                limits: _Limits, options: Options) -> JointSizing:
    """Select a unit for one joint on the kept rows, each weighted by its run length.

    The rules on single figures (peak, input speed, momentary, static) are first
    applied to every unit at once, with `check_unit`'s own expressions; `check_unit`
    then judges the units that pass them (for ``prefer = "size"`` the smallest size
    first, up to the first size that fits), and `reflect` the one selected, or the
    strongest when none fits: the figures `summarize` reports.
    """
    load = cycle_load(tau, qd, dt, at_rest(qd, qdd))
    speed = np.abs(qd)
    stopping = np.abs(stop)
    i_stop = int(stopping.argmax())
    crash = np.multiply.outer(limits.crash_gain, speed)
    crash += np.abs(tau)
    i_crash = crash.argmax(axis=1)
    worst_crash = crash[np.arange(len(units)), i_crash]
    momentary = np.maximum(stopping[i_stop], worst_crash)
    most = 1.0 - options.margin  # `holds`, on every unit at once
    passes = ((load.peak_torque / limits.repeated <= most)
              & (load.max_speed * RPM_PER_RAD_S * limits.ratio / limits.max_speed <= most)
              & (momentary / limits.momentary <= most))
    if load.static_torque is not None:
        passes &= load.static_torque / limits.static <= most
    survivors = [k for k in range(len(units)) if passes[k]]
    assert options.prefer is not None  # resolved by size_case
    motor_order = options.prefer.startswith("motor")
    if motor_order:
        checked = [_candidate(load, r, qd, weight, options)
                   for r in _reflect([units[k] for k in survivors], t, tau, qd, qdd, stop,
                                     options)]
    else:
        checked = []
        for size in sorted({units[k].size for k in survivors}):
            for k in survivors:
                if units[k].size == size or options.prefer != "size":
                    if options.prefer == "size" or size == min(units[s].size
                                                               for s in survivors):
                        checked.append(check_unit(
                            load, units[k], momentary=_event(k, i_stop, i_crash, stopping,
                                                             crash, speed, t, options),
                            life_hours=options.life_hours, life_basis=options.life_basis,
                            margin=options.margin))
            if options.prefer != "size" or any(c.feasible for c in checked):
                break
    selected = select(checked, options.prefer, inertia_target=options.inertia_target)
    if selected is None or not motor_order:
        unit = units[limits.strongest] if selected is None else selected.unit
        (reflection,) = _reflect([unit], t, tau, qd, qdd, stop, options)
        chosen = _candidate(load, reflection, qd, weight, options)
        selected = None if selected is None else chosen
    else:
        chosen = selected
    return JointSizing(name, load, (chosen,), selected, 0.0, False, 0.0, tau, stop)


def _size_pairs(name: str, t: np.ndarray, dt: np.ndarray, weight: np.ndarray, qd: np.ndarray,
                qdd: np.ndarray, tau: np.ndarray, stop: np.ndarray, units: tuple[Unit, ...],
                motors: Sequence[Motor], options: Options, load_inertia: float) -> JointSizing:
    """Every (gearhead, motor) pair against one joint on the kept rows, as the core checks them.

    The core's own steps (`reflect_motors`, `check_unit`, `with_motor`, `select`), the
    motor demand's RMS figures weighted by each row's run length (`weighted_demand`).
    """
    assert options.prefer is not None  # resolved by size_case
    load = cycle_load(tau, qd, dt, at_rest(qd, qdd))
    behind = reflect_motors(units, [m.rotor_inertia for m in motors], t, tau, qd, qdd, stop,
                            stop_time=options.stop_time, efficiency=options.efficiency)
    speed = np.abs(qd) * RPM_PER_RAD_S
    pairs, torque = [], {}
    for u, unit in enumerate(units):
        for m, motor in enumerate(motors):
            r = behind[m][u]
            demand = weighted_demand(r.motor, r.motor_torque, qd, unit.ratio, weight)
            gearhead = check_unit(load, unit, momentary=r.momentary,
                                  life_hours=options.life_hours, life_basis=options.life_basis,
                                  motor=demand, margin=options.margin)
            pair = with_motor(gearhead, motor, r.motor_torque, speed * unit.ratio,
                              load_inertia=load_inertia,
                              max_inertia_ratio=options.max_inertia_ratio)
            pairs.append(pair)
            torque[id(pair)] = r.motor_torque
    selected = select(pairs, options.prefer, inertia_target=options.inertia_target)
    joint = JointSizing(name, load, tuple(pairs), selected, 0.0, False, 0.0, tau, stop,
                        load_inertia=load_inertia)
    return replace(joint, motor_torque=frozen(torque[id(selected or joint.strongest)]))


def _event(k: int, i_stop: int, i_crash: np.ndarray, stopping: np.ndarray, crash: np.ndarray,
           speed: np.ndarray, t: np.ndarray, options: Options) -> Momentary:
    """Unit k's worst momentary event, as `reflect` reports it."""
    i = int(i_crash[k])
    if stopping[i_stop] >= crash[k, i]:
        return Momentary(float(stopping[i_stop]), "emergency stop", float(speed[i_stop]),
                         options.stop_time, float(t[i_stop]))
    return Momentary(float(crash[k, i]), "crash", float(speed[i]), options.stop_time,
                     float(t[i]))


def _reflect(units: list[Unit], t: np.ndarray, tau: np.ndarray, qd: np.ndarray,
             qdd: np.ndarray, stop: np.ndarray, options: Options) -> list[Reflection]:
    return reflect(units, t, tau, qd, qdd, stop, stop_time=options.stop_time,
                   efficiency=options.efficiency, rotor_inertia=options.rotor_inertia)


def _candidate(load: CycleLoad, reflection: Reflection, qd: np.ndarray, weight: np.ndarray,
               options: Options) -> Candidate:
    """`check_unit` with the motor demand, its RMS figures weighted by the rows' run lengths."""
    demand = weighted_demand(reflection.motor, reflection.motor_torque, qd,
                             reflection.unit.ratio, weight)
    return check_unit(load, reflection.unit, momentary=reflection.momentary,
                      life_hours=options.life_hours, life_basis=options.life_basis,
                      motor=demand, margin=options.margin)


def _with_scales(joint: JointSizing, t: np.ndarray, dt: np.ndarray, duration: float,
                 qd: np.ndarray, qdd: np.ndarray, tau: np.ndarray, stop: np.ndarray,
                 gravity: np.ndarray, coast: np.ndarray, units: tuple[Unit, ...],
                 options: Options, motors: Sequence[Motor] = (),
                 load_inertia: float | None = None) -> JointSizing:
    """The time scales at which each unit (or pair) would fit a joint none fits, as in the core."""
    cycle = ScalableCycle.split(t, dt, duration, qd, qdd, at_rest(qd, qdd), torque=tau,
                                stop_torque=stop, gravity=gravity, coast=coast,
                                stop_time=options.stop_time)
    slowdown, scales = fitting_time_scales(cycle, units, options, motors=motors,
                                           load_inertia=load_inertia)
    return replace(joint, slowdown=slowdown, scales=scales)


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array
