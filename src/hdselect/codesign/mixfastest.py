"""Co-design on a mix: the shortest cycle of each task that the duty's units allow.

1. Each task's path runs as fast as the units allow sample by sample: TOPPRA under its
   motion's and the units' limits (`hdselect.codesign.fastpath`), exactly as `fastest`
   runs one motion; these are the tasks' optima.
2. The rules over the whole duty (mean torque, life, average input speed) pool every
   task's samples at the mix's shares of the time (`hdselect.sizing.tasks`): where one
   fails at the optima, every task's moves are slowed by one smallest factor s (dwells
   keep their length), found with the exact time scaling of each task's cycle
   (`hdselect.sizing.timescale`); the rules of single samples hold at every s on the
   intersection of the tasks' exact intervals.
3. Each task is sampled on its motion's grid and the duty checked by the sizing core's
   own selection with the units fixed, slowed by any excess.

A slow-down by a common factor keeps every task's share of the time: each task runs
fewer cycles per hour. Derating a joint's torque limit (which `fastest` tries for one
motion) is not tried over a mix.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import Candidate, check_unit, cycle_load
from hdselect.catalog.select import DEFAULT_PREFER
from hdselect.catalog.units import Unit
from hdselect.codesign.cyclerules import (
    WRITTEN_MARGIN,
    _intersect,
    _scalable,
    first_passing,
)
from hdselect.codesign.fastest_cycle import no_unit_at_any_speed
from hdselect.codesign.fastpath import PathModel, cycle, kinematic_scales, solve
from hdselect.codesign.pathbounds import PathInfeasible, joint_limits
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.toppra import Profile
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import fixed_units
from hdselect.sizing.core import select_units, size_tasks
from hdselect.sizing.duty import mix_motors, mix_options, mix_tasks
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import reflect, weighted_demand
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task, pooled
from hdselect.sizing.timescale import S_MAX, ScalableCycle, exact_scales
from hdselect.sizing.torques import DirectTorques

_VERIFY_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class TaskFastest:
    """One task of a mix at its shortest cycle.

    Attributes:
        task: The task at its fastest: its robot, trajectory (sampled every ``motion.dt``),
            share, motion and name.
        planned: Its cycle as the motion file plans it [s].
        optimum: Its time-optimal cycle under the limits on single samples [s].
    """

    task: Task
    planned: float
    optimum: float

    @property
    def cycle_time(self) -> float:
        """Its shortest cycle over the duty, dwells included [s]."""
        return self.task.trajectory.duration


@dataclass(frozen=True, eq=False)
class MixFastestResult:
    """The shortest cycle of each task of a mix that a choice of units allows.

    Attributes:
        mix: The mix.
        units: The unit of every sized joint.
        options: The assumptions.
        tasks: Every counted task at its fastest, in the mix's order.
        slowdown: The common slow-down of every task's moves beyond its optimum [-]
            (1 when none was needed; TOPPRA's own overshoot correction not included).
        reason: The ``(joint, rule)`` of the pooled duty that set the slow-down, or None.
        check: Every rule of every joint's unit over the duty at the fastest cycles.
        idle: The fraction of the time no task runs [-].
    """

    mix: Mix
    units: Mapping[str, Unit]
    options: Options
    tasks: tuple[TaskFastest, ...]
    slowdown: float
    reason: tuple[str, str] | None
    check: SizingResult
    idle: float = 0.0

    @property
    def feasible(self) -> bool:
        """Every rule of every joint passes over the duty."""
        return self.check.feasible


@dataclass(frozen=True, eq=False)
class _Path:
    """One task's path at its optimum: what the slow-down search and the sampling need."""

    task: Task
    profiles: list[Profile | None]
    kinematic: list[float]
    cycles: Mapping[str, ScalableCycle]
    held: np.ndarray
    optimum: float
    planned: float

    @property
    def motion(self) -> Motion:
        """The task's motion."""
        assert self.task.motion is not None  # a mix's tasks have motions
        return self.task.motion


def mix_fastest(robot: Robot, mix: Mix, units: Mapping[str, Unit | str] | None = None,
                options: Options | None = None, *,
                catalog: Sequence[Unit] | None = None) -> MixFastestResult:
    """The shortest cycle of each task of a mix, every rule over the duty passing.

    Args:
        robot: The robot with the duty's sized joints (`hdselect.load_case` of the mix).
        mix: The mix; every task a motion with waypoints (no log).
        units: Unit (or unit id) per sized joint; joints not given get the unit `size`
            selects for the mix as planned.
        options: The assumptions (default: the mix's).
        catalog: Units to resolve ids and defaults from (default: the built-in catalog
            and the mix file's).

    Returns:
        Each task's shortest cycle, the common slow-down and the duty's check.

    Raises:
        InputError: A task is a log, motors are given, or a joint or unit id is unknown.
        PlanningError: A path cannot be run with these units at any speed, or TOPPRA fails.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(mix, (Mix,), "mix", "a Mix (hdselect.load_case of a mix file)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    for item in mix.tasks:
        if item.motion.planner == "samples":
            raise InputError("a logged trajectory ('samples') has no path to run faster; give "
                             "motions with waypoints", path=item.motion.path, field="planner")
    if mix_motors(robot, mix):
        raise InputError("fastest on a mix does not choose motors yet; the motors given "
                         "would be left out: remove [motor]", path=mix.path, field="motor")
    options = options if options is not None else mix_options(mix)
    catalog = tuple(catalog) if catalog is not None else load_catalog(list(mix.catalog))
    planned, idle = mix_tasks(robot, mix, joints=robot.sized_joints, exclude=(),
                              max_samples=options.max_samples)
    chosen = _units(robot, planned, idle, units, catalog, options)
    masses = ({name: unit.mass + options.motor_mass for name, unit in chosen.items()}
              if options.mass_coupling else {})
    paths = [_optimum(task, chosen, masses, options) for task in planned if task.share > 0.0]
    scale, reason = _smallest_scale(paths, chosen, options, idle, mix)
    check = None
    for _ in range(_VERIFY_ROUNDS):
        tasks = tuple(replace(path.task, trajectory=cycle(
            path.motion, path.profiles, [r * scale for r in path.kinematic],
            max_samples=options.max_samples)[0]) for path in paths)
        check = check_tasks(tasks, chosen, options, idle)
        excess = max((c.checks[rule].utilization for joint in check.joints
                      for c in joint.candidates for rule in c.checks if rule != "static"),
                     default=0.0) / (1.0 - options.margin)  # of the usable part of a limit
        if check.feasible and excess <= 1.0 - WRITTEN_MARGIN:
            break
        if any(not c.checks["static"].ok for joint in check.joints for c in joint.candidates):
            break  # a held load: no speed helps
        scale *= max(math.sqrt(excess), 1.0 + 10.0 * WRITTEN_MARGIN)
    assert check is not None
    fastest = tuple(TaskFastest(task, path.planned, path.optimum)
                    for task, path in zip(check.tasks, paths, strict=True))
    return MixFastestResult(mix, chosen, options, fastest, scale, reason,
                            replace(check, mix=mix), idle)


def _units(robot: Robot, tasks: Sequence[Task], idle: float,
           given: Mapping[str, Unit | str] | None, catalog: Sequence[Unit],
           options: Options) -> dict[str, Unit]:
    """The unit of every sized joint: those given, the duty's selection for the others."""
    chosen = fixed_units(given, catalog, robot)
    by_id = {unit.id: unit for unit in catalog}
    if all(name in chosen for name in robot.sized_joints):
        return {name: chosen[name] for name in robot.sized_joints}
    sizing = size_tasks(tasks, catalog, options, idle=idle)
    for joint in sizing.joints:
        pick = joint.selected.unit.id if joint.selected is not None else (
            joint.slowdown.unit if joint.slowdown is not None else None)
        if joint.name not in chosen:
            if pick is None:
                raise PathInfeasible(no_unit_at_any_speed(joint.name, "this mix"),
                                     joint=joint.name, limit="peak", gravity=True)
            chosen[joint.name] = by_id[pick]
    return {name: chosen[name] for name in robot.sized_joints}


def _optimum(task: Task, units: Mapping[str, Unit], masses: Mapping[str, float],
             options: Options) -> _Path:
    """One task's path run as fast as the limits on single samples allow (TOPPRA)."""
    robot, motion = task.robot, task.motion
    assert motion is not None  # a mix's tasks have motions
    model = PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
    limits = joint_limits(robot, motion, units, options, {})
    profiles = solve(model, limits, masses, stop_time=options.stop_time)
    kinematic = kinematic_scales(profiles, limits)
    trajectory, held = cycle(motion, profiles, kinematic, max_samples=options.max_samples)
    carrying = robot.with_gearheads(dict(masses)) if masses else robot
    cycles, held = _scalable(carrying, trajectory, held, units, options)
    return _Path(replace(task, trajectory=trajectory), profiles, kinematic, cycles, held,
                 trajectory.duration, task.trajectory.duration)


def pooled_check(paths: Sequence[_Path], name: str, unit: Unit, s: float, options: Options,
                 idle: float) -> Candidate:
    """Every rule of one joint's unit over the duty with every task's moves s times slower.

    Each task's dwells keep their length; its samples are weighted by how often its
    cycle runs at its share (share / cycle time at s), as `hdselect.sizing.tasks.pooled`
    weights them; the idle time is a pause.
    """
    parts = []
    for path in paths:
        at = path.cycles[name].at(s)
        dt = np.where(path.held, path.cycles[name].dt, at.dt)
        parts.append((at, dt, path.task.share / float(dt.sum())))
    reference = parts[0][2]
    dt = np.concatenate([step * rate / reference for _, step, rate in parts])

    def joined(field: str) -> np.ndarray:
        return np.concatenate([getattr(at, field) for at, _, _ in parts])

    torque, qd, stop = joined("torque"), joined("qd"), joined("stop_torque")
    load = cycle_load(torque, qd, dt, joined("at_rest"), idle=idle / reference)
    (reflection,) = reflect([unit], joined("t"), torque, qd, joined("qdd"), stop,
                            stop_time=options.stop_time, efficiency=options.efficiency,
                            rotor_inertia=options.rotor_inertia, rest=joined("at_rest"))
    demand = weighted_demand(reflection.motor, reflection.motor_torque, qd, unit.ratio, dt)
    return check_unit(load, unit, momentary=reflection.momentary, motor=demand,
                      life_hours=options.life_hours, life_basis=options.life_basis,
                      margin=options.margin)


def _smallest_scale(paths: Sequence[_Path], units: Mapping[str, Unit], options: Options,
                    idle: float, mix: Mix) -> tuple[float, tuple[str, str] | None]:
    """The smallest common s >= 1 [-] at which every rule over the duty passes, and why.

    As `hdselect.codesign.cyclerules.smallest_scale` for one motion: the rules of single
    samples exactly (every task's intervals intersected), the pooled rules by the same
    stepped and bisected search (`hdselect.codesign.cyclerules.first_passing`).
    """
    feasible: list[tuple[float, float]] = [(1.0, S_MAX)]
    for name, unit in units.items():
        for path in paths:
            feasible = _intersect(feasible, list(exact_scales(
                path.cycles[name], unit, rotor_inertia=options.rotor_inertia,
                margin=options.margin)))
        if not feasible:
            raise _hopeless(mix, name, "peak", unit)

    def fails(s: float) -> tuple[str, str] | None:
        worst: tuple[float, str, str] | None = None
        for name, unit in units.items():
            candidate = pooled_check(paths, name, unit, s, options, idle)
            if not candidate.feasible:
                rule = candidate.binding
                if worst is None or candidate.checks[rule].utilization > worst[0]:
                    worst = (candidate.checks[rule].utilization, name, rule)
        return None if worst is None else (worst[1], worst[2])

    found = first_passing(feasible, lambda s: fails(s) is None, fails)
    if found is not None:
        return found
    name, rule = fails(S_MAX) or (next(iter(units)), "mean")
    raise _hopeless(mix, name, rule, units[name])


def _hopeless(mix: Mix, joint: str, rule: str, unit: Unit) -> PathInfeasible:
    return PathInfeasible(f"{mix.path}: joint '{joint}' fails its {rule} rule over the duty "
                          f"with {unit.id} at every speed (from as fast as the limits allow "
                          f"to {S_MAX:g} times slower)", joint=joint, limit=rule,
                          gravity=rule in ("static", "peak", "momentary"))


def check_tasks(tasks: Sequence[Task], units: Mapping[str, Unit], options: Options,
                idle: float = 0.0) -> SizingResult:
    """Given units, one per sized joint, checked over a duty: no selection.

    As `hdselect.sizing.core.check_units` for one trajectory: each joint's only
    candidate is its unit; with mass coupling each unit's mass is carried.
    """
    robot = tasks[0].robot
    resolved = options if options.prefer is not None else replace(options,
                                                                    prefer=DEFAULT_PREFER)
    masses = ({name: units[name].mass + options.motor_mass for name in robot.sized_joints}
              if options.mass_coupling else {})
    samples = pooled(tasks, idle)
    model = DirectTorques(samples.tasks, samples, options.stop_time, threads=options.threads,
                          guess=masses)
    joints, masses = select_units(model, {name: (units[name],) for name in robot.sized_joints},
                                  resolved, {}, slowdowns=False)
    first = samples.tasks[0]
    distinct = tuple(dict.fromkeys(units[name] for name in robot.sized_joints))
    return SizingResult(first.robot, first.trajectory, tuple(joints), options, distinct,
                        first.motion, loads=model.loads(masses), tasks=tuple(tasks), idle=idle)
