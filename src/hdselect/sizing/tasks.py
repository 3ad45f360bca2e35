"""The tasks a robot is sized for, and the samples every rule is judged on.

A robot is sized for everything it does: one or more tasks, each a planned
trajectory with its own robot state (payload, mounting) and a share of the
operating time. The rules of one sample (repeated peak, static, speed, momentary)
take the worst over every sample of every task; the averaged rules (mean torque,
mean speed, life, motor RMS) pool the samples, each standing for its own duration
times how often its task's cycle runs (share / cycle time). So a task with share 0
counts in no rule, and one task alone is judged exactly as its trajectory is.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.catalog.rules import at_rest
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot

SHARE_TOLERANCE = 1e-9
"""How far the shares of a robot's tasks may sum from 1 [-]."""


@dataclass(frozen=True, eq=False)
class Task:
    """One thing the robot does: a trajectory, the robot state it runs with, how often.

    Attributes:
        robot: The robot as it runs this task (payload and mounting applied; no gearhead
            masses: the sizing adds those).
        trajectory: The planned trajectory, with the robot's joints.
        share: Fraction of the operating time spent repeating this task [-].
        motion: The motion the trajectory was planned from, if any.
        name: What reports call the task (default: the motion file's name).
    """

    robot: Robot
    trajectory: Trajectory
    share: float = 1.0
    motion: Motion | None = None
    name: str = ""

    @property
    def label(self) -> str:
        """The task's name, else its motion file's name, else "task"."""
        if self.name:
            return self.name
        return self.motion.path.name if self.motion is not None else "task"


@dataclass(frozen=True, eq=False)
class Samples:
    """Every counted sample of every task, pooled in task order: what the rules are judged on.

    Attributes:
        t: Each sample's time within its own task's cycle [s], shape (n,).
        dt: What each sample stands for [s]: the trajectory's dt for one task (a float,
            exactly), else its dt times its task's rate relative to the first task's,
            shape (n,), so that sums over samples are sums over operating time. A task's
            rate is its share over the time its samples stand for (n dt, one cycle).
        weight: Relative weight of each sample in an RMS figure, shape (n,); None where
            every sample stands for the same time.
        qd: Joint speeds [rad/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2], shape (n, dof).
        rest: Where each joint is held still in its own task (`at_rest`), shape (n, dof).
        task: Index (into `tasks`) of each sample's task, shape (n,).
        tasks: The tasks counted (share above 0), in the order given.
        duration: The first task's cycle time [s] (the one a slow-down is stated for).
    """

    t: np.ndarray
    dt: np.ndarray | float
    weight: np.ndarray | None
    qd: np.ndarray
    qdd: np.ndarray
    rest: np.ndarray
    task: np.ndarray
    tasks: tuple[Task, ...]
    duration: float

    def __len__(self) -> int:
        return len(self.t)


def check_shares(shares: Sequence[float], *, field: str = "share") -> None:
    """Shares of operating time are non-negative, finite, not all zero, and sum to 1.

    Raises:
        InputError: They do not (the message gives the sum).
    """
    for i, share in enumerate(shares):
        if not (isinstance(share, float | int) and math.isfinite(share) and share >= 0.0):
            raise InputError(f"must be a fraction of time >= 0, got {share!r}",
                             field=f"{field}[{i}]")
    total = math.fsum(shares)
    if abs(total - 1.0) > SHARE_TOLERANCE:
        raise InputError(f"the shares sum to {total!r}; they must sum to 1", field=field)


def pooled(tasks: Sequence[Task]) -> Samples:
    """The samples of every task with a share above 0, weighted by how often each runs.

    Args:
        tasks: The robot's tasks; every trajectory has the same joints.

    Returns:
        The pooled samples. One task (or one with a share above 0) gives its own
        trajectory's samples, with its scalar dt and no weights.
    """
    counted = tuple(task for task in tasks if task.share > 0.0)
    first = counted[0]
    rests = [_rest(task.trajectory) for task in counted]
    if len(counted) == 1:
        traj = first.trajectory
        index = np.zeros(len(traj.t), dtype=np.intp)
        index.setflags(write=False)
        return Samples(traj.t, traj.dt, None, traj.qd, traj.qdd, rests[0], index, counted,
                       traj.duration)
    reference = first.share / _cycle(first.trajectory)
    rates = [task.share / _cycle(task.trajectory) / reference for task in counted]
    dt = np.concatenate([np.full(len(task.trajectory.t), task.trajectory.dt * rate)
                         for task, rate in zip(counted, rates, strict=True)])
    return Samples(
        frozen(np.concatenate([task.trajectory.t for task in counted])), frozen(dt),
        frozen(dt / first.trajectory.dt),
        frozen(np.concatenate([task.trajectory.qd for task in counted])),
        frozen(np.concatenate([task.trajectory.qdd for task in counted])),
        frozen(np.concatenate(rests)),
        frozen(np.concatenate([np.full(len(task.trajectory.t), k, dtype=np.intp)
                               for k, task in enumerate(counted)])),
        counted, first.trajectory.duration)


def _cycle(traj: Trajectory) -> float:
    """The time a trajectory's samples stand for, one cycle [s]: n dt."""
    return len(traj.t) * traj.dt


def _rest(traj: Trajectory) -> np.ndarray:
    """Where each joint is held still along one trajectory, shape (n, dof)."""
    rest = np.empty(traj.qd.shape, dtype=bool)
    for j in range(traj.qd.shape[1]):
        rest[:, j] = at_rest(traj.qd[:, j], traj.qdd[:, j])
    rest.setflags(write=False)
    return rest
