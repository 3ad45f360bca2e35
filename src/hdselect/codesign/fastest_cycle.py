"""Co-design: the shortest cycle a choice of gearheads allows, and every ratio compared on it.

`fastest` runs every task's path as fast as the units allow (a motion is a duty of one
task; a mix's tasks keep their shares of the time), in three steps:

1. TOPPRA under every limit that holds sample by sample (`hdselect.codesign.fastpath`,
   `hdselect.codesign.pathbounds`): the motion's and the robot file's speeds, the units'
   maximum input speeds over their ratios, the motion's accelerations, the units'
   repeated-peak torques (through the dynamics, payload and carried gearheads
   included), the emergency stop and the crash. Any trajectory that passes the rules
   meets these, so this cycle, the `optimum`, is the shortest possible to the grid's
   resolution.
2. The rules over the whole cycle (mean torque, life, average input speed), every
   task's samples pooled at its share, are checked on it; where one fails, every task's
   moves are lengthened by the smallest common exact slow-down, or (one task) by
   derating the failing joints' torque limits, whichever is shorter
   (`hdselect.codesign.cyclerules`, `hdselect.codesign.trials`). A pure bang-bang move
   gives the same answer both ways (both run it at the mean-torque allowance); a move
   that cruises is faster derated.
3. Each trajectory is sampled on its motion's time grid and checked by the sizing's own
   selection with the units fixed (`hdselect.sizing.core.check_units` for one task),
   and slowed by any excess.

`compare_ratios` does this for every catalog unit on each joint, the others fixed,
sharing one path and its dynamics per task (a unit's mass changes the torque
coefficients linearly, so no unit needs new dynamics passes on the path).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.codesign.bindings import Binding, bindings
from hdselect.codesign.choice import Duty, choose, duty_of
from hdselect.codesign.fastpath import PathModel
from hdselect.codesign.pathbounds import JointLimits, PathInfeasible, joint_limits
from hdselect.codesign.trials import derated, run_trial, verified
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, check_within_limits
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import not_sized
from hdselect.sizing.options import Options
from hdselect.sizing.problem import Problem
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.tasks import Task

OPTIMAL_WITHIN = 1e-3
"""A cycle at most this fraction longer than the optimum counts as the optimum: the
slow-down that corrects TOPPRA's overshoot between gridpoints is of this order [-]."""
@dataclass(frozen=True, eq=False)
class TaskFastest:
    """One task of a duty at its shortest cycle.

    Attributes:
        task: The task at its fastest: its robot, trajectory (sampled every ``motion.dt``),
            share, motion and name.
        planned: Its cycle as the motion file plans it [s]; None where it was not planned.
        optimum: Its time-optimal cycle under the limits on single samples [s].
    """

    task: Task
    planned: float | None
    optimum: float

    @property
    def cycle_time(self) -> float:
        """Its shortest cycle over the duty, dwells included [s]."""
        return self.task.trajectory.duration


@dataclass(frozen=True, eq=False)
class FastestResult:
    """The shortest cycle of every task's path that a choice of units allows.

    A motion is a duty of one task; for a mix, `robot`, `motion`, `trajectory`,
    `limits`, `optimum` and `grid_per_waypoint` are its first counted task's, `check`
    is the duty's and `tasks` has every counted task.

    Attributes:
        robot: The robot (payload and mounting applied, no gearhead masses).
        motion: The motion whose path was run.
        units: The unit of every sized joint.
        options: The assumptions.
        trajectory: The trajectory, sampled every ``motion.dt``.
        check: Every rule of every joint's unit on that trajectory (`check_units`).
        limits: What bounded each joint along the path, by joint name.
        optimum: The time-optimal cycle under the limits on single samples, before any
            slow-down or derating [s].
        slowdown: The uniform slow-down of the moves beyond TOPPRA's own overshoot
            correction [-]; 1 when none was needed.
        derating: Fraction of its repeated-peak limit each derated joint was held to [-].
        reason: What made the cycle longer than `optimum` (by more than `OPTIMAL_WITHIN`):
            ``(joint, rule)``, or None.
        binding: Which limit is closest to its bound along the moves, stretch by stretch.
        grid_per_waypoint: TOPPRA gridpoints per waypoint.
        motors: The motor behind the unit of each joint that has one (its peak torque,
            speed and rotor inertia bound the path; its rules are checked).
        tasks: Every counted task at its fastest, in the duty's order.
        idle: The fraction of the time no task runs [-].
        mix: The mix, or None for one motion.
    """

    robot: Robot
    motion: Motion
    units: Mapping[str, Unit]
    options: Options
    trajectory: Trajectory
    check: SizingResult
    limits: Mapping[str, JointLimits]
    optimum: float
    slowdown: float
    derating: Mapping[str, float]
    reason: tuple[str, str] | None
    binding: tuple[Binding, ...]
    grid_per_waypoint: int
    motors: Mapping[str, Motor] = field(default_factory=dict)
    tasks: tuple[TaskFastest, ...] = ()
    idle: float = 0.0
    mix: Mix | None = None

    @property
    def cycle_time(self) -> float:
        """The cycle time, dwells included [s] (of the first task, for a mix)."""
        return self.trajectory.duration

    @property
    def mean_cycle_time(self) -> float:
        """The tasks' cycle times weighted by their shares [s]; one task's cycle time."""
        return self._share_mean([item.cycle_time for item in self.tasks], self.cycle_time)

    @property
    def mean_optimum(self) -> float:
        """The tasks' optima weighted by their shares [s]; one task's `optimum`."""
        return self._share_mean([item.optimum for item in self.tasks], self.optimum)

    def _share_mean(self, values: Sequence[float], alone: float) -> float:
        """The tasks' `values` weighted by their shares [s]; `alone` for one task."""
        if len(self.tasks) < 2:
            return alone
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
        return replace(self.check, motion=self.motion).warnings

    def binding_shares(self) -> list[tuple[str, str, float]]:
        """(joint, limit, share of the moving time) [-], longest first."""
        total: dict[tuple[str, str], float] = {}
        for b in self.binding:
            total[(b.joint, b.limit)] = total.get((b.joint, b.limit), 0.0) + b.end - b.start
        moving = sum(total.values()) or 1.0
        return sorted(((j, lim, t / moving) for (j, lim), t in total.items()),
                      key=lambda item: -item[2])


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
        robot: The robot (payload and mounting applied).
        motion: The motion whose path was run.
        units: The units the other joints keep.
        options: The assumptions.
        joints: One comparison per joint compared.
        base: The fastest cycle with `units` everywhere.
        mix: The mix whose tasks were run, or None for one motion (a mix's rows give
            the share-weighted mean of its tasks' cycles, `FastestResult.mean_cycle_time`).
    """

    robot: Robot
    motion: Motion
    units: Mapping[str, Unit]
    options: Options
    joints: tuple[JointRatios, ...]
    base: FastestResult = field(repr=False)
    mix: Mix | None = None


def fastest(robot: Robot | Problem, motion: Motion | Mix | None = None,
            units: Mapping[str, Unit | str] | None = None, options: Options | None = None, *,
            catalog: Sequence[Unit] | None = None,
            motors: Motors | None = None) -> FastestResult:
    """The shortest cycle of every task's path that the units allow, every rule passing.

    A motion is a duty of one task. For a mix, every task's moves are slowed by one
    common factor where the duty's pooled rules need it (dwells keep their length, the
    shares their value); a derating of a joint's torque limit is tried for one task only.

    Args:
        robot: The robot as the motion runs it (`hdselect.load_case`); or the resolved
            `Problem` (`hdselect.resolve`), alone: its motion or mix, catalog, options
            and motors.
        motion: A motion with waypoints (a Ruckig or TOPPRA motion, not a log), or a mix
            of such motions.
        units: Unit (or unit id) per sized joint; joints not given get the unit
            `hdselect.size` selects for the motion (or mix) as planned.
        options: The assumptions (default: `options_for(motion)`, or the mix's).
        catalog: Units to resolve ids and defaults from (default: the built-in catalog,
            and the mix file's).
        motors: Candidate motors per sized joint (a `Motor` is a fixed one); None takes
            the files' ``[motor]``. A joint with several gets the motor the sizing
            pairs with its unit. The motor's peak torque (through the ratio, with the
            reflected inertia (J_in + J_m) N qdd) and maximum speed bound the path, and
            its rules are checked on the result.

    Returns:
        The fastest trajectories, their check and what bounds them.

    Raises:
        InputError: A motion is a log, or a joint, unit id or motor is unknown or
            invalid.
        PlanningError: The path cannot be run with these units at any speed (the
            message names the joint, the limit and where), or TOPPRA fails.
    """
    duty, options, catalog, candidates = duty_of(robot, motion, options, catalog, motors,
                                                 units=units)
    chosen, _, paired = choose(duty.robot, duty, units, catalog, options, candidates,
                               selection=False)
    return _fastest(_models(duty, options), chosen, options, paired, duty)


def compare_ratios(robot: Robot | Problem, motion: Motion | Mix | None = None,
                   units: Mapping[str, Unit | str] | None = None,
                   options: Options | None = None, *, catalog: Sequence[Unit] | None = None,
                   joints: Sequence[str] | None = None,
                   motors: Motors | None = None) -> RatioComparison:
    """The shortest cycle with each catalog unit on each joint, the other joints' units fixed.

    Args:
        robot: The robot as the motion runs it; or the resolved `Problem`, alone.
        motion: A motion with waypoints, or a mix of such motions.
        units: Units the other joints keep (defaults as in `fastest`).
        options: The assumptions (default: `options_for(motion)`, or the mix's).
        catalog: The units compared (default: the built-in catalog, and the mix file's).
        joints: The joints compared (default: every sized joint).
        motors: Candidate motors per sized joint, as `fastest` takes them; each joint
            keeps its motor whatever unit it is compared with.

    Returns:
        One row per unit and joint.

    Raises:
        InputError: A motion is a log, or a joint or unit id is unknown.
        PlanningError: The units given cannot run the path at all.
    """
    duty, options, catalog, candidates = duty_of(robot, motion, options, catalog, motors,
                                                 units=units, joints=joints)
    chosen, selected, paired = choose(duty.robot, duty, units, catalog, options, candidates)
    names = list(duty.robot.sized_joints)
    if joints is not None and (isinstance(joints, str) or not isinstance(joints, Sequence)
                               or not all(isinstance(name, str) for name in joints)):
        raise InputError(f"expected a list of joint names, got {joints!r}", field="joints")
    for name in joints or ():
        if name not in names:
            raise not_sized(duty.robot, name, "joint")
    models = _models(duty, options)
    base = _fastest(models, chosen, options, paired, duty)
    out = []
    for name in joints or names:
        rows = []
        for unit in catalog:
            if unit is chosen[name]:
                rows.append(_row(unit, base))
                continue
            try:
                rows.append(_row(unit, _fastest(models, {**chosen, name: unit}, options,
                                                paired, duty)))
            except PathInfeasible as err:
                rows.append(RatioRow(unit, None, None, err.gravity, _short(err), None))
        out.append(JointRatios(name, selected.get(name), tuple(rows)))
    return RatioComparison(base.robot, base.motion, chosen, options, tuple(out), base,
                           duty.mix)


def _models(duty: Duty, options: Options) -> tuple[PathModel, ...]:
    """Each counted task's path, its dynamics batched once."""
    return tuple(PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
                 for robot, motion in zip(duty.robots, duty.motions, strict=True))


def _fastest(models: Sequence[PathModel], units: Mapping[str, Unit], options: Options,
             motors: Mapping[str, Motor], duty: Duty) -> FastestResult:
    """Steps 1 to 3 of the module's method for one choice of units (and motors)."""
    model = models[0]
    robot = model.robot
    motors = dict(motors)
    masses = ({name: unit.mass + (motors[name].mass if name in motors else options.motor_mass)
               for name, unit in units.items()} if options.mass_coupling else {})
    carrying = [each.robot.with_gearheads(masses) for each in models]
    first = run_trial(models, carrying, duty.shares, units, masses, {}, options, motors,
                      duty.idle, duty.where)
    best = first
    if first.whole_cycle_failing and len(models) == 1:  # a duty keeps its shares: slowed
        best = derated(models, carrying, units, masses, first, options, motors)
    trajectory, held, check, scale = verified(units, best, options, motors,
                                              duty.planned or None, duty.where)
    trajectories = tuple(task.trajectory for task in check.tasks) if duty.planned else (
        trajectory,)
    for each, run in zip(models, trajectories, strict=True):
        check_within_limits(each.robot, each.motion, run, what="fastest")  # as plan does
    reason = None
    if any(run.duration > leg.optimum * (1.0 + OPTIMAL_WITHIN)
           for run, leg in zip(trajectories, first.legs, strict=True)):
        reason = first.reason if best is not first else best.reason
    limits = joint_limits(robot, model.motion, units, options, best.derating, motors=motors)
    binding = bindings(model, best, scale, check, held, joint_limits(
        robot, model.motion, units, options, motors=motors)) if len(models) == 1 else ()
    tasks = duty.planned or (Task(robot, trajectories[0], 1.0, model.motion),)
    timed = tuple(TaskFastest(replace(task, trajectory=run),
                              task.trajectory.duration if duty.planned else None, leg.optimum)
                  for task, run, leg in zip(tasks, trajectories, first.legs, strict=True))
    if duty.mix is not None:
        check = replace(check, mix=duty.mix)
    return FastestResult(
        robot=robot, motion=model.motion, units=dict(units), options=options,
        trajectory=trajectory, check=check,
        limits=dict(zip(robot.joint_names, limits, strict=True)),
        optimum=first.legs[0].optimum, slowdown=scale, derating=dict(best.derating),
        reason=reason, binding=binding, grid_per_waypoint=model.grid_per_waypoint,
        motors=motors, tasks=timed, idle=duty.idle, mix=duty.mix)


def _row(unit: Unit, result: FastestResult) -> RatioRow:
    shares = result.binding_shares()
    derating = min(result.derating.values()) if result.derating else None
    note = None
    if result.reason is not None:
        how = [f"derated {derating:.0%}"] if derating is not None else []
        if result.slowdown > 1.0 + 1e-9:
            how.append(f"x{result.slowdown:.4f}")
        note = f"{result.reason[0]} {result.reason[1]}: {', '.join(how)}"
    return RatioRow(unit, result.mean_cycle_time, result.mean_optimum, False, note,
                    (shares[0][0], shares[0][1]) if shares else None, result.reason, derating,
                    result.slowdown)


def _short(err: PathInfeasible) -> str:
    """A few words for a table: who cannot do what."""
    if err.joint is None:
        return f"{err.limit} limits"
    if err.gravity:
        limit = "momentary" if err.limit == "emergency stop" else err.limit
        return f"gravity on {err.joint} > its {limit} limit"
    return f"{err.joint} {err.limit} fails at any speed"
