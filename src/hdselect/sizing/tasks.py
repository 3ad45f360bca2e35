"""The tasks a robot is sized for, and the samples every rule is judged on.

A robot is sized for everything it does: one or more tasks, each a planned
trajectory with its own robot state (payload, mounting) and a share of the
operating time. The rules of one sample (repeated peak, static, speed, momentary)
take the worst over every sample of every task; the averaged rules (mean torque,
mean speed, life, motor RMS) pool the samples, each standing for its own duration
times how often its task's cycle runs (share / cycle time). So a task with share 0
counts in no rule, and one task alone is judged exactly as its trajectory is.

The shares may leave part of the time idle (a mix given in cycles per hour): idle
time is a pause that no sample stands for. It counts only where a series' rules
divide the mean speed by the whole cycle, pauses included (`Samples.idle`); every
other rule is over the time the robot works.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.bounds import SHARE_TOLERANCE, check_shares
from hdselect.catalog.rules import at_rest
from hdselect.motion.events import Carried, carried
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload

__all__ = ["SHARE_TOLERANCE", "Samples", "Task", "alone", "by_state", "check_shares", "cycle_of",
           "every_part", "holding", "merged", "over_states", "pooled", "task_of", "task_rows"]


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
        carried: Which parts its payload events move each sample carries (`by_state`);
            None where the motion has no events (the robot carries everything).
    """

    robot: Robot
    trajectory: Trajectory
    share: float = 1.0
    motion: Motion | None = None
    name: str = ""
    carried: Carried | None = None

    @property
    def label(self) -> str:
        """The task's name, else its motion file's name, else "task"."""
        if self.name:
            return self.name
        return self.motion.path.name if self.motion is not None else "task"


def task_of(robot: Robot, trajectory: Trajectory, motion: Motion | None, share: float = 1.0,
            name: str = "") -> Task:
    """A task with its motion's payload events (`hdselect.motion.events.carried`).

    The robot carries its payload the whole cycle unless an event names ``"payload"``: then
    that payload (the file's, or the one given over it) is the part the events move.

    Args:
        robot: The robot as it runs the motion (its payload and whole-cycle parts applied).
        trajectory: The motion's planned trajectory.
        motion: The motion it was planned from (None: a task without events).
        share: Fraction of the operating time [-].
        name: What reports call the task.

    Raises:
        InputError: The planner does not say when the arm reaches an event's waypoint.
    """
    moved = carried(motion, trajectory) if motion is not None else None
    if moved is not None and any(part.name == "payload" for part in moved.parts):
        if robot.payload is not None:
            moved = moved.with_part(replace(robot.payload, name="payload"))
        robot = robot.with_payload(None)
    return Task(robot, trajectory, share, motion, name, moved)


def every_part(robot: Robot, motion: Motion, parts: Sequence[Payload] = ()) -> Robot:
    """The robot carrying every part the motion's events move: their worst state.

    What a planner's torque limits (TOPPRA's) are taken on: conservative for every state.

    Args:
        robot: The robot as the motion runs it (its payload on, as the file gives it).
        motion: The motion (its events and parts).
        parts: The parts as a task moves them (its `Carried.parts`), over the file's.
    """
    given = {part.name: part for part in parts}
    moved = sorted({event.part for event in motion.events})
    return holding(robot, [given.get(name, motion.parts[name]) for name in moved])


def holding(robot: Robot, parts: Sequence[Payload]) -> Robot:
    """`robot` carrying `parts` besides its own.

    A part named "payload" (the ``[payload]`` an event moves) only where the robot carries
    no payload already.
    """
    extra = tuple(part for part in parts
                  if not (part.name == "payload" and robot.payload is not None))
    return robot.with_parts((*robot.parts, *extra)) if extra else robot


def by_state(task: Task, robot: Robot) -> tuple[tuple[Robot, np.ndarray | slice], ...]:
    """`robot` carrying each state's parts, and the task's sample rows in that state.

    Every computation over a task's samples (torques, wrenches, gravity torques, M_jj)
    evaluates each state's rows with that state's robot and puts them back in sample
    order, exactly as a mix of one task per state would.

    Args:
        task: The task.
        robot: Its robot as evaluated (the units' masses carried, `carrying`).

    Returns:
        ``((robot, slice(None)),)`` without events; else per carried state, in the order
        of its first sample, the robot with that state's parts added to its own and the
        rows (sorted indices).
    """
    if task.carried is None:
        return ((robot, slice(None)),)
    parts = task.carried.parts
    return tuple((robot.with_parts((*robot.parts, *(parts[i] for i in state))) if state
                  else robot, rows) for state, rows in task.carried.states())


def over_states(task: Task, robot: Robot,
                compute: Callable[[Robot, np.ndarray | slice], tuple[np.ndarray, ...]],
                rows: np.ndarray | None = None, axis: int = 0) -> tuple[np.ndarray, ...]:
    """Arrays over a task's samples, each carried state's samples with its own robot.

    Args:
        task: The task.
        robot: Its robot as evaluated (the units' masses carried, `carrying`).
        compute: The arrays of a robot at some of the task's samples (sample indices, or
            a slice), the samples along `axis` of each.
        rows: The samples wanted (sorted indices); None: every sample.
        axis: The samples' axis in `compute`'s arrays.

    Returns:
        `compute`'s arrays over `rows` in sample order, each state's rows evaluated with
        its robot (`by_state`); without events ``compute(robot, rows)`` itself.
    """
    if task.carried is None:
        return compute(robot, slice(None) if rows is None else rows)
    wanted = np.arange(len(task.trajectory.t)) if rows is None else rows
    out: list[np.ndarray] = []
    for state_robot, own in by_state(task, robot):
        where = np.isin(wanted, own) if isinstance(own, np.ndarray) else np.ones(len(wanted), bool)
        if not where.any():
            continue
        arrays = compute(state_robot, wanted[where])
        if not out:
            out = [np.empty((*a.shape[:axis], len(wanted), *a.shape[axis + 1:]), a.dtype)
                   for a in arrays]
        for full, part in zip(out, arrays, strict=True):
            np.moveaxis(full, axis, 0)[where] = np.moveaxis(part, axis, 0)
    return tuple(out)


def carrying(task: Task, masses: Mapping[str, float], sized: Sequence[str]) -> Robot:
    """The task's robot with each sized joint's unit mass [kg] carried, in joint order."""
    ordered = {name: masses[name] for name in sized if name in masses}
    return task.robot.with_gearheads(ordered) if ordered else task.robot


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
        idle: Time the robot stands idle, in the samples' time [s]: the idle share of
            the time over the first task's rate; 0 when the shares fill the time.
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
    idle: float = 0.0

    def __len__(self) -> int:
        return len(self.t)


def pooled(tasks: Sequence[Task], idle: float = 0.0) -> Samples:
    """The samples of every task with a share above 0, weighted by how often each runs.

    Args:
        tasks: The robot's tasks; every trajectory has the same joints.
        idle: The fraction of the time no task runs [-] (the shares and it sum to 1).

    Returns:
        The pooled samples. One task (or one with a share above 0) gives its own
        trajectory's samples, with its scalar dt and no weights.
    """
    counted = tuple(task for task in tasks if task.share > 0.0)
    own = []
    for task in counted:
        traj = task.trajectory
        index = np.zeros(len(traj.t), dtype=np.intp)
        index.setflags(write=False)
        own.append(Samples(traj.t, traj.dt, None, traj.qd, traj.qdd, _rest(traj), index,
                           (task,), traj.duration))
    return merged(own, idle)


def merged(parts: Sequence[Samples], idle: float = 0.0) -> Samples:
    """Several tasks' own samples pooled, each task weighted by how often its cycle runs.

    Task k (the only task of ``parts[k]``, with its share) runs share_k / cycle_k cycles
    per unit time, cycle_k the time its whole trajectory's samples stand for
    (`cycle_of`); its samples' durations are scaled by that rate over the first task's.

    Args:
        parts: Each counted task's samples (`Samples` of one task, its share above 0).
        idle: The fraction of the time no task runs [-].

    Returns:
        The pooled samples; one part as it is (with its idle time).
    """
    first = parts[0].tasks[0]
    reference = first.share / cycle_of(first.trajectory)
    pause = idle / reference if idle > 0.0 else 0.0
    if len(parts) == 1:
        return replace(parts[0], idle=pause) if pause else parts[0]
    rates = [part.tasks[0].share / cycle_of(part.tasks[0].trajectory) / reference
             for part in parts]
    dt = np.concatenate([np.broadcast_to(part.dt, len(part)) * rate
                         for part, rate in zip(parts, rates, strict=True)])
    return Samples(
        frozen(np.concatenate([part.t for part in parts])), frozen(dt),
        frozen(dt / first.trajectory.dt),
        frozen(np.concatenate([part.qd for part in parts])),
        frozen(np.concatenate([part.qdd for part in parts])),
        _locked(np.concatenate([part.rest for part in parts])),
        _locked(np.concatenate([np.full(len(part), k, dtype=np.intp)
                                for k, part in enumerate(parts)])),
        tuple(part.tasks[0] for part in parts), first.trajectory.duration, pause)


def alone(samples: Samples, k: int) -> Samples:
    """The samples of counted task k alone, as if the robot did nothing else.

    Its samples keep their lengths relative to each other (so every rule reads them
    as it reads the task's own trajectory); no idle time. The arrays are views.

    Args:
        samples: Pooled samples.
        k: Index into ``samples.tasks``.
    """
    if len(samples.tasks) == 1:
        return replace(samples, idle=0.0) if samples.idle else samples
    rows = task_rows(samples, k)
    task = samples.tasks[k]
    dt = samples.dt[rows] if isinstance(samples.dt, np.ndarray) else samples.dt
    weight = None if samples.weight is None else samples.weight[rows]
    if weight is not None and np.all(weight == weight[0]):
        weight, dt = None, task.trajectory.dt  # one trajectory's equal samples
    return Samples(samples.t[rows], dt, weight, samples.qd[rows], samples.qdd[rows],
                   samples.rest[rows], np.zeros(rows.stop - rows.start, dtype=np.intp),
                   (task,), task.trajectory.duration)


def task_rows(samples: Samples, k: int) -> slice:
    """Where counted task k's samples lie in the pooled samples (they are in task order)."""
    start, stop = np.searchsorted(samples.task, (k, k + 1))
    return slice(int(start), int(stop))


def cycle_of(traj: Trajectory) -> float:
    """The time one cycle's samples stand for [s]: n dt (the cycle time and one period)."""
    return len(traj.t) * traj.dt


def _locked(array: np.ndarray) -> np.ndarray:
    """`array` made read-only, its dtype kept (bool, index)."""
    array.setflags(write=False)
    return array


def _rest(traj: Trajectory) -> np.ndarray:
    """Where each joint is held still along one trajectory, shape (n, dof)."""
    rest = np.empty(traj.qd.shape, dtype=bool)
    for j in range(traj.qd.shape[1]):
        rest[:, j] = at_rest(traj.qd[:, j], traj.qdd[:, j])
    rest.setflags(write=False)
    return rest
