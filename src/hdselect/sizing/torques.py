"""Where the sizing core's torques come from: the seam between the core and the dynamics.

The core chooses a unit per joint from the tip to the base, and asks for each
joint's torques with the masses of the units chosen further out. A `TorqueModel`
answers: `DirectTorques` by batched inverse dynamics of every task's trajectory
(a single sizing, a mix of tasks), a study's basis by linear combination
(`hdselect.study.group`). Both feed the same selection, so every rule lives once.

Masses are keyed by the joint whose unit they are: the unit (and its motor) is
bolted to the link before that joint, so it loads exactly the joints that move
that link (`hdselect.Robot.with_gearheads`).

A task with payload events (`hdselect.motion.events`) is evaluated state by state: the
samples of each set of carried parts with the robot carrying them, put back in sample
order (`hdselect.sizing.tasks.over_states`); a task without events takes the one pass
it always did.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import partial
from typing import Protocol

import numpy as np

from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import (
    cycle_torques,
    distinct_states,
    gravity_torques,
    joint_inertias,
    torque_spread,
)
from hdselect.robot.model import Robot
from hdselect.robot.wrenches import axis_wrenches, distinct_axis_wrenches
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.loads import JointLoad, joint_loads, merged_loads
from hdselect.sizing.tasks import Samples, Task, by_state, carrying, over_states

GRAVITY_SAMPLES = 400
"""Poses per task, evenly spread over its cycle, at which the gravity torque (the
backdriving warning) and a joint's load inertia M_jj are evaluated."""


class TorqueModel(Protocol):
    """The torques of a robot's tasks for any masses carried at its joints.

    Attributes:
        robot: The robot of the first task: its joints, tree and sized joints.
        samples: The pooled samples the torques are given on.
    """

    robot: Robot
    samples: Samples

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along the samples [N m], each (n,).

        `masses` [kg] gives at least every unit further out than `joint`.
        """

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along the samples, or None.

        In the joint's axis frame about its origin (rows as
        `hdselect.robot.wrenches.axis_wrenches`) [N, N m]; None where the model computes
        no wrenches.
        """

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each pose of the samples still, as `wrench` gives it, or None."""

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity part RNEA(q, 0, 0) and coasting part RNEA(q, qd, 0) [N m]."""

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over the gravity poses [N m], (dof,)."""

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over the gravity poses [kg m^2]."""

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj over each task's gravity poses [kg m^2], in task order."""

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint of the robot against its file's limits, with these masses."""


class DirectTorques:
    """Torques by batched inverse dynamics of every task, one full pass per change of masses.

    The pass of the last masses is kept: a joint whose units further out are those of
    the kept pass reads its column from it. With a good `guess` of the masses (the
    core's coarse first selection), every joint reads the same pass: two batched
    passes of inverse dynamics per task, the motion's and the emergency stop's, and
    with `wrenches` a third giving every sized joint's whole force and moment along
    the motion (`hdselect.robot.wrenches.axis_wrenches`): its output bearing's loads.
    """

    def __init__(self, tasks: Sequence[Task], samples: Samples, stop_time: float, *,
                 threads: int | None = None, guess: Mapping[str, float] | None = None,
                 wrenches: bool = True) -> None:
        """Prepare the model; nothing is computed until asked.

        Args:
            tasks: The tasks counted, in the samples' order.
            samples: Their pooled samples.
            stop_time: The emergency-stop time [s].
            threads: Threads for the batched passes; None chooses from the sample count.
            guess: Masses [kg] expected per joint, used where the core has not chosen yet.
            wrenches: Also compute the sized joints' wrenches along the motion.
        """
        self.tasks = tuple(tasks)
        self.robot = self.tasks[0].robot
        self.samples = samples
        self.stop_time = stop_time
        self.threads = threads
        self.guess = dict(guess or {})
        model = self.robot.model
        self._below = {name: {k for k in self.robot.sized_joints
                              if _moves(model, model.getJointId(name), model.getJointId(k))}
                       for name in self.robot.sized_joints}
        self._carriers = tuple(k for k in self.robot.sized_joints
                               if model.parents[model.getJointId(k)] > 0)
        self.wrenches = wrenches
        self._masses: dict[str, float] | None = None
        self._tau: np.ndarray | None = None
        self._stop: np.ndarray | None = None
        self._wrench: np.ndarray | None = None
        self._index: np.ndarray | None = None
        self._distinct = [distinct_states(task.trajectory.q, task.trajectory.qd,
                                          task.trajectory.qdd)
                          if wrenches and task.carried is None else None
                          for task in self.tasks]  # the same states at every pass

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along the samples [N m], each (n,)."""
        if self._masses is None or any(self._masses.get(k, 0.0) != masses.get(k, 0.0)
                                       for k in self._below[joint]):
            self._pass(masses)
        if self._tau is None or self._stop is None:
            raise RuntimeError("the torque pass did not run")
        j = self.robot.joint_index(joint)
        return np.array(self._tau[:, j]), np.array(self._stop[:, j])

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along the samples [N, N m]."""
        if not self.wrenches:
            return None
        if self._masses is None or any(self._masses.get(k, 0.0) != masses.get(k, 0.0)
                                       for k in self._below[joint]):
            self._pass(masses)
        if self._wrench is None:
            raise RuntimeError("the torque pass did not run")
        return SampledWrench(self._wrench[self.robot.sized_joints.index(joint)], self._index)

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each pose still [N, N m], (6, n): one pass per task."""
        if not self.wrenches:
            return None
        parts = [over_states(task, self._carrying(task, masses),
                             partial(_held, task.trajectory, joint, self.threads), axis=1)[0]
                 for task in self.tasks]
        return parts[0] if len(parts) == 1 else np.concatenate(parts, axis=1)

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity part RNEA(q, 0, 0) and coasting part RNEA(q, qd, 0) [N m]."""
        j = self.robot.joint_index(joint)
        parts = [over_states(task, self._carrying(task, masses), partial(
                     _split, task.trajectory, self.stop_time, j, self.threads))
                 for task in self.tasks]
        gravity = np.concatenate([p[0][:, 0] for p in parts])
        coast = np.concatenate([p[1][:, 0] for p in parts])
        return gravity, coast

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over the gravity poses [N m], (dof,)."""
        return np.max([np.abs(over_states(task, self._carrying(task, masses),
                                          partial(gravity_at, task.trajectory, self.threads),
                                          inertia_poses(task.trajectory))[0]).max(axis=0)
                       for task in self.tasks], axis=0)

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over the gravity poses [kg m^2]."""
        return max(self.task_inertias(joint, masses))

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj over each task's gravity poses [kg m^2], in task order."""
        return tuple(float(over_states(task, self._carrying(task, masses),
                                       partial(_inertias, task.trajectory, joint, self.threads),
                                       inertia_poses(task.trajectory))[0].max())
                     for task in self.tasks)

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint of the robot against its file's limits, with these masses."""
        if self._masses is None or any(self._masses.get(k, 0.0) != masses.get(k, 0.0)
                                       for k in self._carriers):
            self._pass(masses)
        if self._tau is None or self._masses is None:
            raise RuntimeError("the torque pass did not run")
        per_task, start = [], 0
        for task in self.tasks:
            traj, n = task.trajectory, len(task.trajectory.t)
            spread = None if traj.qdd_uncertainty is None else over_states(
                task, self._carrying(task, self._masses),
                partial(_spread, traj, self.threads))[0]
            per_task.append(joint_loads(task.robot, traj, self._tau[start:start + n], spread))
            start += n
        return merged_loads(per_task)

    def _pass(self, masses: Mapping[str, float]) -> None:
        """Both batched passes of every task with `masses`, the guess where none is given."""
        merged = {**self.guess, **masses}
        ordered = {name: merged[name] for name in self.robot.sized_joints if name in merged}
        self._masses = self._tau = self._stop = self._wrench = self._index = None  # go first
        robots = [self._carrying(task, ordered) for task in self.tasks]
        parts = [over_states(task, robot, partial(_cycle, task.trajectory, self.stop_time,
                                                  self.threads))
                 for robot, task in zip(robots, self.tasks, strict=True)]
        wrenches = [self._wrenches(robot, task, distinct)
                    for robot, task, distinct in zip(robots, self.tasks, self._distinct,
                                                     strict=True)
                    if self.wrenches]
        if len(parts) == 1:
            self._tau, self._stop = parts[0]
        else:
            self._tau = np.concatenate([p[0] for p in parts])
            self._stop = np.concatenate([p[1] for p in parts])
        if wrenches:
            self._wrench, self._index = _pooled(wrenches)
            self._wrench.setflags(write=False)
        self._masses = ordered

    def _carrying(self, task: Task, masses: Mapping[str, float]) -> Robot:
        """The task's robot with the units' masses, in the robot's joint order."""
        return carrying(task, masses, self.robot.sized_joints)

    def _wrenches(self, robot: Robot, task: Task, distinct: tuple[np.ndarray, np.ndarray] | None
                  ) -> tuple[np.ndarray, np.ndarray | None]:
        """The sized joints' distinct wrenches along a task and each sample's row among them."""
        traj, joints = task.trajectory, self.robot.sized_joints
        if task.carried is None:
            return distinct_axis_wrenches(robot, traj.q, traj.qd, traj.qdd, joints,
                                          threads=self.threads, distinct=distinct)
        found, index, start = [], np.empty(len(traj.t), dtype=np.intp), 0
        for state_robot, rows in by_state(task, robot):
            rows_found, own = distinct_axis_wrenches(
                state_robot, traj.q[rows], traj.qd[rows], traj.qdd[rows], joints,
                threads=self.threads)
            found.append(rows_found)
            index[rows] = start + (np.arange(rows_found.shape[2]) if own is None else own)
            start += rows_found.shape[2]
        return np.concatenate(found, axis=2), index


def _cycle(traj: Trajectory, stop_time: float, threads: int | None, robot: Robot,
           rows: np.ndarray | slice) -> tuple[np.ndarray, np.ndarray]:
    """The motion's and the emergency stop's torques at some samples [N m], each (m, dof)."""
    found = cycle_torques(robot, traj.q[rows], traj.qd[rows], traj.qdd[rows], stop_time,
                          threads=threads)
    return found.tau, found.stop


def _held(traj: Trajectory, joint: str, threads: int | None, robot: Robot,
          rows: np.ndarray | slice) -> tuple[np.ndarray]:
    """The wrench holding each pose at some samples still [N, N m], (6, m)."""
    q = traj.q[rows]
    still = np.zeros_like(q)
    return (axis_wrenches(robot, q, still, still, [joint], threads=threads)[0],)


def gravity_at(traj: Trajectory, threads: int | None, robot: Robot,
               rows: np.ndarray | slice) -> tuple[np.ndarray]:
    """The gravity torques RNEA(q, 0, 0) at some samples of a trajectory [N m], (m, dof).

    The form `hdselect.sizing.tasks.over_states` evaluates state by state.
    """
    return (gravity_torques(robot, traj.q[rows], threads=threads),)


def _inertias(traj: Trajectory, joint: str, threads: int | None, robot: Robot,
              rows: np.ndarray | slice) -> tuple[np.ndarray]:
    """A joint's M_jj at some samples [kg m^2], (m, 1)."""
    return (joint_inertias(robot, traj.q[rows], [joint], threads=threads),)


def _spread(traj: Trajectory, threads: int | None, robot: Robot,
            rows: np.ndarray | slice) -> tuple[np.ndarray]:
    """How far the torques at some samples may be off [N m], (m, dof) (a log's)."""
    if traj.qdd_uncertainty is None:
        raise RuntimeError("no acceleration uncertainty to spread")
    return (torque_spread(robot, traj.q[rows], traj.qdd_uncertainty[rows], threads=threads),)


def _split(traj: Trajectory, stop_time: float, joint: int, threads: int | None, robot: Robot,
           rows: np.ndarray | slice) -> tuple[np.ndarray, np.ndarray]:
    """One joint's gravity and coasting parts at some samples [N m], each (m, 1)."""
    found = cycle_torques(robot, traj.q[rows], traj.qd[rows], traj.qdd[rows], stop_time,
                          split=True, threads=threads, columns=[joint])
    if found.gravity is None or found.coasting is None:
        raise RuntimeError("cycle_torques(split=True) returned no gravity or coasting part")
    return found.gravity, found.coasting


def _pooled(parts: list[tuple[np.ndarray, np.ndarray | None]]
            ) -> tuple[np.ndarray, np.ndarray | None]:
    """Every task's distinct wrenches in one array, and each pooled sample's row among them."""
    if len(parts) == 1:
        return parts[0]
    rows = np.concatenate([wrench for wrench, _ in parts], axis=2)
    if all(index is None for _, index in parts):
        return rows, None
    index, start = [], 0
    for wrench, own in parts:
        count = wrench.shape[2]
        index.append(start + (np.arange(count) if own is None else own))
        start += count
    return rows, np.concatenate(index)


def _moves(model: object, joint_id: int, other_id: int) -> bool:
    """`other`'s unit (on the link before it) is moved by `joint`: other is further out."""
    parents = model.parents  # type: ignore[attr-defined]
    ancestor = parents[other_id]
    while ancestor > joint_id:
        ancestor = parents[ancestor]
    return bool(ancestor == joint_id)


def inertia_poses(trajectory: Trajectory) -> np.ndarray:
    """Indices of `GRAVITY_SAMPLES` poses evenly spread: the gravity torques' and M_jj's."""
    return np.unique(np.linspace(0, len(trajectory.t) - 1, GRAVITY_SAMPLES).astype(int))
