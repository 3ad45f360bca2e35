"""Many sizing cases of one robot and one path from a few batched passes of inverse dynamics.

For a fixed robot, mounting and planned path, every joint torque is affine in the
payload mass (its inertia about its centre of mass stays as given) and in each
gearhead point mass the arm carries, and a uniform time scale s changes it exactly
(`hdselect.sizing.timescale`): with y = 1/s and T the stop time,

    tau  = sum_p theta_p (G_p + A_p y^2)
    stop = sum_p theta_p (G_p + V_p y^2 + E_p y / T)

where p runs over the reference robot (theta = 1), the payload (theta = mass - 1 kg)
and one gearhead point mass per joint that carries one (theta = its mass [kg]); G is
gravity RNEA(q, 0, 0), A = RNEA(q, qd, qdd) - G, V = RNEA(q, qd, 0) - G and
E = RNEA(q, qd, -qd) - RNEA(q, qd, 0), one stacked batched pass per parameter.
Every case of the group is then sized by the core's own selection
(`hdselect.sizing.core.select_units`, through `hdselect.study.pooled`: a motion is a
duty of one task, a mix one basis per task), which asks `BasisTorques` for each joint's
torques with the units chosen further out: a linear combination, not a pass of
inverse dynamics. The answer is the one `hdselect.size_trajectory` reaches.
Runs of identical samples (dwells) are kept once, weighted by their length.

Where a case gives motors or a natural frequency target, a joint's load inertia M_jj,
linear in the same parameters, comes from one more set of passes per parameter at the
core's poses (`build_basis(..., inertias=True)`).

With payload events (`hdselect.motion.events`) every pass evaluates each sample with the
parts it carries (`hdselect.sizing.tasks.over_states`): the torques stay affine in each
parameter, a part's term zero at the samples that do not carry it. The payload parameter
is then the part the events move (`build_basis(..., part=True)`), the ``[payload]`` carried
as given; runs of identical samples are split where the carried parts change.

The whole force and moment through each sized joint (its output bearing's loads) is
linear in the same parameters and scales the same way: w = sum_p theta_p (W_p + B_p
y^2), W the gravity wrench and B the rest along the motion, two more batched passes
per parameter (`hdselect.robot.wrenches.axis_wrenches`). So a grouped case reports
and checks the bearing loads as the core does.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.catalog.rules import (
    at_rest,
)
from hdselect.codesign.scaledpart import with_part
from hdselect.motion.events import Carried
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.robot.dynamics import inverse_dynamics, joint_inertias, torque_spread
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.robot.wrenches import axis_wrenches
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.loads import JointLoad, joint_loads
from hdselect.sizing.tasks import Samples, Task, over_states, task_of
from hdselect.sizing.torques import GRAVITY_SAMPLES

REFERENCE_MASS = 1.0
"""Payload mass of the reference robot the group is planned and evaluated with [kg]."""


@dataclass(frozen=True, eq=False)
class Basis:
    """A robot and a planned path, with its torques split by parameter and by scaling.

    Attributes:
        robot: The reference robot: mounting applied, payload (if any) of `REFERENCE_MASS`;
            the parts events move are not on it (`events`).
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
            (sized joints, P, poses), as `gravity`; None unless asked for (motors, a
            natural-frequency target).
        wrench_gravity: W, each sized joint's wrench at rest in its axis frame, rows 0-4
            of `axis_wrenches` [N, N m], shape (sized joints, P, 5 n): a parameter's row
            is its (5, n) wrench flattened, so a case's is one product with theta.
        wrench_dynamic: B, the rest of its wrench along the motion at s = 1 [N, N m],
            same shape.
        events: Which parts each sample of the trajectory carries (`hdselect.motion.events`;
            the scaled part at the reference mass), or None without payload events.
        part: The payload is the part the events move, else the ``[payload]``.
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
    wrench_gravity: np.ndarray | None = None
    wrench_dynamic: np.ndarray | None = None
    events: Carried | None = None
    part: bool = False


def build_basis(robot: Robot, motion: Motion, payload: Payload | None, *,
                inertias: bool = False, part: bool = False) -> Basis:
    """Plan the path once and run the batched passes of every parameter.

    Args:
        robot: The robot as the motion runs it, mounting applied, without a payload (with
            its ``[payload]`` where `part`).
        motion: The motion; its plan must not depend on the payload (see `plan_depends_on_payload`).
        payload: The payload's shape (its mass is replaced by `REFERENCE_MASS`), or None.
        inertias: Also the sized joints' load inertia M_jj per parameter at the poses
            (what cases with motors need for their inertia ratio, and a natural-frequency
            target for its J).
        part: `payload` is the part the motion's payload events move (`hdselect.codesign.
            scaledpart.moved_part`), carried between its events; else the ``[payload]``.

    Returns:
        The basis: 4 (2 + carriers) passes of the torques over the kept samples, and 2
        (2 + carriers) of the wrenches, each sample with the parts it carries.
    """
    trajectory = plan(robot if part else robot.with_payload(
        None if payload is None else replace(payload, mass=REFERENCE_MASS)), motion)
    reference = task_at(robot, trajectory, motion, payload, REFERENCE_MASS, part)
    states = np.hstack([trajectory.q, trajectory.qd, trajectory.qdd])
    keep = np.ones(len(states), dtype=bool)
    keep[1:] = np.any(states[1:] != states[:-1], axis=1)
    if reference.carried is not None:  # a run of one state carries one set of parts
        mask = reference.carried.mask
        keep[1:] |= np.any(mask[1:] != mask[:-1], axis=1)
    rows = np.flatnonzero(keep)
    weight = np.diff(np.append(rows, len(states))).astype(float)
    model = robot.model
    carriers = tuple(name for name in robot.sized_joints
                     if model.parents[model.getJointId(name)] > 0)
    variants = [reference]
    if payload is not None:
        variants.append(task_at(robot, trajectory, motion, payload, REFERENCE_MASS + 1.0, part))
    variants += [replace(reference, robot=reference.robot.with_gearheads({name: 1.0}))
                 for name in carriers]
    parts = np.stack([over_states(variant, variant.robot,
                                  lambda carrier, at: (_parts(carrier, trajectory, at),),
                                  rows, axis=1)[0] for variant in variants])
    parts[1:] -= parts[0]  # each parameter's own contribution per unit of it
    gravity, dynamic, coasting, stopping = (np.ascontiguousarray(parts[:, k].transpose(2, 0, 1))
                                            for k in range(4))
    carried = np.array([[reference.robot.with_gearheads({c: 1.0}).carried_mass(name)
                         for c in carriers]
                        for name in robot.sized_joints]).reshape(len(robot.sized_joints), -1)
    run = np.cumsum(keep) - 1
    at = np.unique(np.linspace(0, len(states) - 1, GRAVITY_SAMPLES).astype(int))
    poses = run[at]
    loads = np.abs(parts).max(axis=(1, 2)) > 0.0  # (P, dof)
    used = tuple(_read_only(np.flatnonzero(loads[:, j])) for j in range(robot.dof))
    inertia = None
    if inertias:  # M(q) is linear in the inertial parameters, as the torques are
        m = np.stack([over_states(variant, variant.robot,
                                  lambda carrier, poses: (joint_inertias(
                                      carrier, trajectory.q[poses], robot.sized_joints,
                                      threads=1),), at)[0]
                      for variant in variants])  # (P, poses, sized)
        m[1:] -= m[0]
        inertia = frozen(np.ascontiguousarray(m.transpose(2, 0, 1)))
    wrench = np.stack([over_states(variant, variant.robot,
                                   lambda carrier, at: (_wrench_parts(carrier, trajectory, at),),
                                   rows, axis=3)[0] for variant in variants])
    wrench[1:] -= wrench[0]  # (P, 2, sized, 5, n)
    wrench_gravity, wrench_dynamic = (
        frozen(wrench[:, k].transpose(1, 0, 2, 3).reshape(len(robot.sized_joints),
                                                           len(variants), -1))
        for k in range(2))
    return Basis(reference.robot, motion, trajectory, payload, rows, weight,
                 frozen(trajectory.t[rows]), frozen(trajectory.qd[rows]),
                 frozen(trajectory.qdd[rows]), carriers, frozen(gravity), frozen(dynamic),
                 frozen(coasting), frozen(stopping), used, frozen(carried), _read_only(poses),
                 inertia, wrench_gravity, wrench_dynamic, reference.carried, part)


def task_at(robot: Robot, trajectory: Trajectory, motion: Motion, payload: Payload | None,
            mass: float, part: bool = False) -> Task:
    """The motion's task carrying the payload (or the moved part) at `mass` [kg].

    Args:
        robot: The robot as `build_basis` takes it.
        trajectory: The motion's trajectory.
        motion: The motion (its payload events).
        payload: The payload's shape, or None (then nothing is scaled).
        mass: Its mass [kg]; its inertia about its centre of mass stays as given; 0
            takes it off.
        part: `payload` is the part the events move; else the ``[payload]``.
    """
    given = None if payload is None or mass <= 0.0 else replace(payload, mass=mass)
    if part:
        return with_part(task_of(robot, trajectory, motion), given)
    return task_of(robot.with_payload(given) if payload is not None else robot, trajectory,
                   motion)


def plan_depends_on_payload(motion: Motion) -> bool:
    """TOPPRA under joint torque limits plans with the payload's dynamics: no common path."""
    return motion.planner == "toppra" and motion.torque_limit is not None


def _parts(robot: Robot, traj: Trajectory, rows: np.ndarray | slice) -> np.ndarray:
    """G, A, V, E of one robot on the kept rows [N m], shape (4, n, dof): one stacked pass."""
    q, qd, qdd = traj.q[rows], traj.qd[rows], traj.qdd[rows]
    still = np.zeros_like(qd)
    tau = inverse_dynamics(robot, np.vstack([q, q, q, q]), np.vstack([still, qd, qd, qd]),
                           np.vstack([still, still, qdd, -qd]), threads=1)
    gravity, coast, full, stop = tau.reshape(4, len(q), -1)
    return np.stack([gravity, full - gravity, coast - gravity, stop - coast])


def _wrench_parts(robot: Robot, traj: Trajectory, rows: np.ndarray | slice) -> np.ndarray:
    """W and B of one robot's sized joints on the kept rows, shape (2, sized, 5, n)."""
    q, qd, qdd = traj.q[rows], traj.qd[rows], traj.qdd[rows]
    still = np.zeros_like(qd)
    wrench = axis_wrenches(robot, np.vstack([q, q]), np.vstack([still, qd]),
                           np.vstack([still, qdd]), robot.sized_joints, threads=1)[:, :5]
    gravity, full = wrench[:, :, :len(q)], wrench[:, :, len(q):]
    return np.stack([gravity, full - gravity])


class BasisTorques:
    """A case's torques as a linear combination of its group's basis: a `TorqueModel`.

    theta holds the parameters' weights (1 for the reference robot, the payload mass
    above the reference, each carried unit's mass); a time scale s multiplies the
    velocity and inertial parts by 1/s^2 and a stop's inertial part by 1/s.
    """

    def __init__(self, basis: Basis, mass: float | None, time_scale: float,
                 stop_time: float, *, wrenches: bool = True) -> None:
        """One case of the basis: its samples are the basis's kept rows.

        Args:
            basis: The group's basis.
            mass: Payload mass [kg] (None exactly when the basis has no payload).
            time_scale: The path run s times slower [-].
            stop_time: The emergency-stop time [s].
            wrenches: Give the sized joints' wrenches (the bearing loads).
        """
        self.basis = basis
        self.wrenches = wrenches
        self.stop_time = stop_time
        self.robot = basis.robot
        self.y = 1.0 / time_scale
        self._theta = np.zeros(basis.gravity.shape[1])
        self._theta[0] = 1.0
        if basis.payload is not None:
            if mass is None:
                raise RuntimeError("a basis with a payload needs the payload mass")
            self._theta[1] = mass - REFERENCE_MASS
        self._first = len(self._theta) - len(basis.carriers)
        traj = basis.trajectory
        qd, qdd = frozen(basis.qd * self.y), frozen(basis.qdd * self.y**2)
        rest = np.empty(qd.shape, dtype=bool)
        for j in range(qd.shape[1]):
            rest[:, j] = at_rest(qd[:, j], qdd[:, j])
        rest.setflags(write=False)
        timing = replace(traj, dt=traj.dt * time_scale, duration=traj.duration * time_scale)
        self.samples = Samples(frozen(basis.t * time_scale),
                               frozen(traj.dt * time_scale * basis.weight), basis.weight,
                               qd, qdd, rest, np.zeros(len(basis.rows), dtype=np.intp),
                               (Task(basis.robot, timing, motion=basis.motion),),
                               traj.duration * time_scale)

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along the kept rows [N m]."""
        j, used, weights = self._weights(joint, masses)
        gravity = weights @ self.basis.gravity[j, used]
        tau = gravity + (weights @ self.basis.dynamic[j, used]) * self.y**2
        coast = gravity + (weights @ self.basis.coasting[j, used]) * self.y**2
        stop = coast + (weights @ self.basis.stopping[j, used]) * (
            self.y / self.stop_time)
        return tau, stop

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along the kept rows [N, N m], (5, n)."""
        basis = self.basis
        if not self.wrenches or basis.wrench_gravity is None or basis.wrench_dynamic is None:
            return None
        s = self.robot.sized_joints.index(joint)
        theta = self._with(masses)  # a parameter that does not load the joint adds 0
        wrench = theta @ basis.wrench_gravity[s]
        wrench += (theta * self.y**2) @ basis.wrench_dynamic[s]
        return SampledWrench(wrench.reshape(5, -1))

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each kept row's pose still [N, N m], (5, n)."""
        basis = self.basis
        if not self.wrenches or basis.wrench_gravity is None:
            return None
        s = self.robot.sized_joints.index(joint)
        return (self._with(masses) @ basis.wrench_gravity[s]).reshape(5, -1)

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity and coasting parts along the kept rows [N m]."""
        j, used, weights = self._weights(joint, masses)
        gravity = weights @ self.basis.gravity[j, used]
        return gravity, gravity + (weights @ self.basis.coasting[j, used]) * self.y**2

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over the basis's poses [N m], (dof,)."""
        theta = self._with(masses)
        return np.abs(np.einsum("p,dpn->nd", theta,
                                self.basis.gravity[:, :, self.basis.poses])).max(axis=0)

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over the basis's poses [kg m^2]."""
        if self.basis.inertia is None:
            raise RuntimeError("the basis has no joint inertias")
        i = self.robot.sized_joints.index(joint)
        return float((self._with(masses) @ self.basis.inertia[i]).max())

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj of its one task [kg m^2]."""
        return (self.load_inertia(joint, masses),)

    def case_task(self) -> Task:
        """The case's task on the basis's trajectory at s = 1: its payload (or part) mass."""
        basis = self.basis
        mass = REFERENCE_MASS + float(self._theta[1]) if basis.payload is not None else 0.0
        robot = basis.robot if basis.part else basis.robot.with_payload(None)
        return task_at(robot, basis.trajectory, basis.motion, basis.payload, mass, basis.part)

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint on the kept rows (a run of identical states has one torque)."""
        basis = self.basis
        tau = np.einsum("p,dpn->nd", self._with(masses),
                        basis.gravity + basis.dynamic * self.y**2)
        kept = replace(basis.trajectory, t=self.samples.t, q=basis.trajectory.q[basis.rows],
                       qd=self.samples.qd, qdd=self.samples.qdd)
        spread = basis.trajectory.qdd_uncertainty
        if spread is None:
            return joint_loads(basis.robot, kept, tau)
        case = self.case_task()  # the case's own: its payload mass, its units' masses
        carried = {name: masses[name] for name in case.robot.sized_joints if name in masses}
        robot = case.robot.with_gearheads(carried) if carried else case.robot
        q = basis.trajectory.q
        return joint_loads(basis.robot, kept, tau, over_states(
            case, robot, lambda carrier, at: (torque_spread(carrier, q[at],
                                                            spread[at] * self.y**2),),
            basis.rows)[0])

    def _with(self, masses: Mapping[str, float]) -> np.ndarray:
        """The parameters' weights, the carried units' masses [kg] among them."""
        theta = self._theta.copy()
        for c, name in enumerate(self.basis.carriers):
            theta[self._first + c] = masses.get(name, 0.0)
        return theta

    def _weights(self, joint: str,
                 masses: Mapping[str, float]) -> tuple[int, np.ndarray, np.ndarray]:
        """The joint's column, the parameters that load it, and their weights."""
        j = self.robot.joint_index(joint)
        used = self.basis.used[j]
        return j, used, self._with(masses)[used]


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array
