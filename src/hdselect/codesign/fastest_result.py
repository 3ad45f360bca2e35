"""What co-design's `fastest` and `compare_ratios` return: per task, and over the duty.

A motion is a duty of one task: its `motion`, `trajectory` and `limits` are that task's;
a duty of several tasks has them per task (`TaskFastest`), and its cycle, optimum and
binding shares are the tasks' weighted by how often each runs.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.codesign.bindings import Binding, shares
from hdselect.codesign.pathbounds import JointLimits
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.sizing.options import Options
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task


@dataclass(frozen=True, eq=False)
class TaskFastest:
    """One task of a duty at its shortest cycle.

    Attributes:
        task: The task at its fastest: its robot, trajectory (sampled every ``motion.dt``),
            share, motion and name.
        planned: Its cycle as the motion file plans it [s]; None where it was not planned.
        optimum: Its time-optimal cycle under the limits on single samples [s].
        limits: What bounded each joint along its path, by joint name.
        binding: Which limit is closest to its bound along its moves, stretch by stretch.
    """

    task: Task
    planned: float | None
    optimum: float
    limits: Mapping[str, JointLimits] = field(default_factory=dict)
    binding: tuple[Binding, ...] = ()

    @property
    def cycle_time(self) -> float:
        """Its shortest cycle over the duty, dwells included [s]."""
        return self.task.trajectory.duration

    @property
    def motion(self) -> Motion:
        """The motion whose path it runs."""
        if self.task.motion is None:
            raise InputError("a co-design task runs a motion", field="motion")
        return self.task.motion

    @property
    def dwell_time(self) -> float:
        """The time of its dwells [s]."""
        return float(np.sum(self.motion.dwells))

    def binding_shares(self) -> list[tuple[str, str, float]]:
        """(joint, limit, share of its moving time) [-], longest first."""
        return shares(self.binding)


@dataclass(frozen=True, eq=False)
class FastestResult:
    """The shortest cycle of every task's path that a choice of units allows.

    A motion is a duty of one task: `motion`, `trajectory` and `limits` are that task's
    and a duty of several tasks has them per task only (`tasks`); `cycle_time` and
    `optimum` are the tasks' weighted by their shares, `binding` every task's stretches.

    Attributes:
        robot: The robot with the sized joints (one motion's: payload and mounting
            applied; no gearhead masses).
        units: The unit of every sized joint.
        options: The assumptions.
        check: Every rule of every joint's unit over the duty (`check_units` for one task).
        slowdown: The uniform slow-down of the moves beyond TOPPRA's own overshoot
            correction [-]; 1 when none was needed.
        derating: Fraction of its repeated-peak limit each derated joint was held to [-].
        reason: What made the cycle longer than `optimum` (by more than `OPTIMAL_WITHIN`):
            ``(joint, rule)``, or None.
        grid_per_waypoint: TOPPRA gridpoints per waypoint (every task's).
        motors: The motor behind the unit of each joint that has one (its peak torque,
            speed and rotor inertia bound the path; its rules are checked).
        tasks: Every counted task at its fastest, in the duty's order.
        idle: The fraction of the time no task runs [-].
        mix: The mix, or None for one motion.
        notes: What the run assumed of its inputs, one line each (payload events).
    """

    robot: Robot
    units: Mapping[str, Unit]
    options: Options
    check: SizingResult
    slowdown: float
    derating: Mapping[str, float]
    reason: tuple[str, str] | None
    grid_per_waypoint: int
    motors: Mapping[str, Motor] = field(default_factory=dict)
    tasks: tuple[TaskFastest, ...] = ()
    idle: float = 0.0
    mix: Mix | None = None
    notes: tuple[str, ...] = ()

    @property
    def alone(self) -> TaskFastest:
        """The one task of a motion (or of a mix of one).

        Raises:
            InputError: The duty has several tasks: each has its own (`tasks`).
        """
        if len(self.tasks) != 1:
            raise InputError(f"a duty of {len(self.tasks)} tasks has one per task: read "
                             "FastestResult.tasks", field="tasks")
        return self.tasks[0]

    @property
    def motion(self) -> Motion:
        """The motion whose path was run (one task's: `alone`)."""
        return self.alone.motion

    @property
    def trajectory(self) -> Trajectory:
        """The trajectory, sampled every ``motion.dt`` (one task's: `alone`)."""
        return self.alone.task.trajectory

    @property
    def limits(self) -> Mapping[str, JointLimits]:
        """What bounded each joint along the path, by joint name (one task's: `alone`)."""
        return self.alone.limits

    @property
    def binding(self) -> tuple[Binding, ...]:
        """Which limit is closest to its bound along the moves: every task's stretches."""
        return tuple(b for item in self.tasks for b in item.binding)

    @property
    def cycle_time(self) -> float:
        """The cycle time, dwells included [s]; the tasks' weighted by their shares."""
        return self.weighted([item.cycle_time for item in self.tasks])

    @property
    def optimum(self) -> float:
        """The time-optimal cycle under the rules on single samples [s].

        Before any slow-down or derating; the tasks' weighted by their shares.
        """
        return self.weighted([item.optimum for item in self.tasks])

    @property
    def mean_cycle_time(self) -> float:
        """The tasks' cycle times weighted by their shares [s] (`cycle_time`)."""
        return self.cycle_time

    @property
    def mean_optimum(self) -> float:
        """The tasks' optima weighted by their shares [s] (`optimum`)."""
        return self.optimum

    def weighted(self, values: Sequence[float]) -> float:
        """Per-task values weighted by the tasks' shares; one task's own [as given]."""
        if len(values) == 1:
            return values[0]
        return (sum(item.task.share * value for item, value in zip(self.tasks, values,
                                                                     strict=True))
                / sum(item.task.share for item in self.tasks))

    @property
    def feasible(self) -> bool:
        """Every rule of every joint passes on the trajectory."""
        return self.check.feasible

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the robot and motion files raised, and robot-file limits the cycle exceeds.

        As `hdselect.sizing.core.SizingResult.warnings`: each line starts with ``robot file:``,
        ``motion file:`` or ``cycle:``.
        """
        if self.mix is not None:
            return self.check.warnings
        return replace(self.check, motion=self.motion).warnings

    def binding_shares(self) -> list[tuple[str, str, float]]:
        """(joint, limit, share of the moving time) [-], longest first.

        Over a duty, a stretch counts for the time it takes in the duty: as often as its
        task runs (share / cycle time).
        """
        if len(self.tasks) == 1:
            return shares(self.binding)
        first = self.tasks[0]
        reference = first.task.share / first.cycle_time
        return shares(self.binding, {item.task.label: item.task.share / item.cycle_time
                                     / reference for item in self.tasks})


@dataclass(frozen=True)
class RatioRow:
    """One unit on one joint, the other joints' units fixed.

    Attributes:
        unit: The unit.
        cycle_time: The shortest cycle [s]; None when the units cannot run the path.
        optimum: The time-optimal cycle under the limits on single samples [s], or None.
        gravity: The units cannot run the path at any speed because a load that does not
            depend on the speed (gravity, held at rest or moving) is beyond a limit.
        note: Why there is no cycle, or what lengthened it beyond `optimum`, in a few words.
        binding: The limit that binds longest, ``(joint, limit)``, or None.
        lengthened_by: The ``(joint, rule)`` that lengthened the cycle, or None.
        derating: The fraction of its repeated-peak limit the derated joint kept [-].
        slowdown: The uniform slow-down of the moves [-].
    """

    unit: Unit
    cycle_time: float | None
    optimum: float | None
    gravity: bool
    note: str | None
    binding: tuple[str, str] | None
    lengthened_by: tuple[str, str] | None = None
    derating: float | None = None
    slowdown: float = 1.0


@dataclass(frozen=True)
class JointRatios:
    """Every catalog unit on one joint.

    Attributes:
        joint: The joint.
        selected: The unit `hdselect.size` picks for the motion as planned, or None.
        rows: One per unit, in catalog order.
    """

    joint: str
    selected: str | None
    rows: tuple[RatioRow, ...]


@dataclass(frozen=True, eq=False)
class RatioComparison:
    """The shortest cycle with each unit on each joint compared.

    Attributes:
        robot: The robot with the sized joints (one motion's: payload and mounting applied).
        units: The units the other joints keep.
        options: The assumptions.
        joints: One comparison per joint compared.
        base: The fastest cycle with `units` everywhere.
        mix: The mix whose tasks were run, or None for one motion (a mix's rows give
            the share-weighted mean of its tasks' cycles, `FastestResult.cycle_time`).
    """

    robot: Robot
    units: Mapping[str, Unit]
    options: Options
    joints: tuple[JointRatios, ...]
    base: FastestResult = field(repr=False)
    mix: Mix | None = None

    @property
    def motion(self) -> Motion:
        """The motion whose path was run (one task's: `FastestResult.alone`)."""
        return self.base.motion
