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

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from functools import partial

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.codesign.bindings import bindings
from hdselect.codesign.choice import Duty, choose, duty_of, refuse_arm_targets
from hdselect.codesign.fastest_result import (
    FastestResult,
    JointRatios,
    RatioComparison,
    RatioRow,
    TaskFastest,
)
from hdselect.codesign.fastpath import PathModel, cycle
from hdselect.codesign.pathbounds import PathInfeasible, joint_limits
from hdselect.codesign.trials import (
    EVENTS_NOTE,
    UNTIMED_NOTE,
    derated,
    retimed,
    run_trial,
    verified,
)
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, check_within_limits
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import not_sized
from hdselect.sizing.options import Options
from hdselect.sizing.problem import Problem
from hdselect.sizing.result import Motors
from hdselect.sizing.tasks import Task, every_part

OPTIMAL_WITHIN = 1e-3
"""A cycle at most this fraction longer than the optimum counts as the optimum: the
slow-down that corrects TOPPRA's overshoot between gridpoints is of this order [-]."""
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
    refuse_arm_targets(options, "the shortest cycle")
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
    refuse_arm_targets(options, "the shortest cycle")
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
    return RatioComparison(base.robot, chosen, options, tuple(out), base, duty.mix)


def _models(duty: Duty, options: Options) -> tuple[PathModel, ...]:
    """Each counted task's path, its dynamics batched once."""
    held = [() if task.carried is None else task.carried.parts for task in duty.planned] or [()]
    return tuple(PathModel.build(every_part(robot, motion, parts), motion, robot.sized_joints,
                                 threads=options.threads)  # the path bound carries every part
                 for robot, motion, parts in zip(duty.robots, duty.motions, held, strict=True))


def _fastest(models: Sequence[PathModel], units: Mapping[str, Unit], options: Options,
             motors: Mapping[str, Motor], duty: Duty) -> FastestResult:
    """Steps 1 to 3 of the module's method for one choice of units (and motors)."""
    motors = dict(motors)
    masses = ({name: unit.mass + (motors[name].mass if name in motors else options.motor_mass)
               for name, unit in units.items()} if options.mass_coupling else {})
    carrying = [each.robot.with_gearheads(masses) for each in models]
    on = _on_legs(duty)
    first = run_trial(models, carrying, duty.shares, units, masses, {}, options, motors,
                      duty.idle, duty.where, tasks=on)
    best = first
    if first.whole_cycle_failing and len(models) == 1:  # a duty keeps its shares: slowed
        best = derated(models, carrying, units, masses, first, options, motors, tasks=on)
    planned = duty.planned or None
    if planned is None and duty.motions[0].events:  # checked with its events: as a task
        leg = best.legs[0]
        sampled, _ = cycle(leg.model.motion, leg.profiles, leg.kinematic,
                           max_samples=options.max_samples)
        planned = (Task(duty.robots[0], sampled, 1.0, duty.motions[0]),)
    trajectory, _, check, scale, helds = verified(units, best, options, motors, planned,
                                                  duty.where)
    trajectories = tuple(task.trajectory for task in check.tasks) if duty.planned else (
        trajectory,)
    for each, run in zip(models, trajectories, strict=True):
        check_within_limits(each.robot, each.motion, run, what="fastest")  # as plan does
    reason = None
    if any(run.duration > leg.optimum * (1.0 + OPTIMAL_WITHIN)
           for run, leg in zip(trajectories, first.legs, strict=True)):
        reason = first.reason if best is not first else best.reason
    tasks = duty.planned or planned or (
        Task(models[0].robot, trajectories[0], 1.0, models[0].motion),)
    checked = tuple(task.trajectory for task in check.tasks) if duty.planned else (
        check.trajectory,)
    timed, start = [], 0
    for task, run, sampled, model, leg, run_leg, held in zip(
            tasks, trajectories, checked, models, first.legs, best.legs, helds, strict=True):
        names = model.robot.joint_names
        limits = joint_limits(model.robot, model.motion, units, options, best.derating,
                              motors=motors)
        plain = joint_limits(model.robot, model.motion, units, options, motors=motors)
        span = slice(start, start + len(sampled.t))
        start = span.stop
        binding = bindings(model, run_leg, scale, sampled, check.joints, held, plain, span,
                           task.label if len(models) > 1 else "")
        timed.append(TaskFastest(retimed(task, run),
                                 task.trajectory.duration if duty.planned else None,
                                 leg.optimum, dict(zip(names, limits, strict=True)), binding))
    if duty.mix is not None:
        check = replace(check, mix=duty.mix)
    return FastestResult(
        robot=duty.robots[0] if duty.mix is None else duty.robot, units=dict(units),
        options=options, check=check, slowdown=scale, derating=dict(best.derating),
        reason=reason, grid_per_waypoint=models[0].grid_per_waypoint, motors=motors,
        tasks=tuple(timed), idle=duty.idle, mix=duty.mix, notes=_event_notes(duty, timed))


def _on_legs(duty: Duty) -> tuple[Callable[[Trajectory], Task], ...]:
    """Each counted task on a sampled trajectory of its path, its events on its times.

    Empty where no task has payload events (the legs' robots are the tasks' own).
    """
    if not any(motion.events for motion in duty.motions):
        return ()
    if duty.planned:
        return tuple(partial(retimed, task) for task in duty.planned)
    robot, motion = duty.robots[0], duty.motions[0]
    return (lambda run: retimed(Task(robot, run, 1.0, motion), run),)


def _event_notes(duty: Duty, timed: Sequence[TaskFastest]) -> tuple[str, ...]:
    """The notes on payload events: how the path and the check carry the parts."""
    if not any(motion.events for motion in duty.motions):
        return ()
    untimed = any(item.task.motion is not None and item.task.motion.events
                  and item.task.carried is None for item in timed)
    return (EVENTS_NOTE, *((UNTIMED_NOTE,) if untimed else ()))


def _row(unit: Unit, result: FastestResult) -> RatioRow:
    shares = result.binding_shares()
    derating = min(result.derating.values()) if result.derating else None
    note = None
    if result.reason is not None:
        how = [f"derated {derating:.0%}"] if derating is not None else []
        if result.slowdown > 1.0 + 1e-9:
            how.append(f"x{result.slowdown:.4f}")
        note = f"{result.reason[0]} {result.reason[1]}: {', '.join(how)}"
    return RatioRow(unit, result.cycle_time, result.optimum, False, note,
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
