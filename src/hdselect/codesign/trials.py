"""TOPPRA's runs of a duty's paths: one run per derating, the best derating, the verified cycle.

`run_trial` solves TOPPRA along every task's path under the units' limits (`fastpath`)
and finds the smallest common slow-down at which every rule passes
(`hdselect.codesign.cyclerules`). `derated` instead holds the failing joints to a
fraction of their repeated-peak limit (0.9, 0.8, ..., re-solved by TOPPRA, each with its
own smallest slow-down) and refines the best by golden section: the moves keep their
speed while the torque drops. `verified` samples the winner on each motion's grid and
checks it with the sizing's own selection (`check_tasks`, or
`hdselect.sizing.core.check_units` for one task), slowing it by the excess where a
sample lands on a peak the scaled model missed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import at_rest
from hdselect.catalog.units import Unit
from hdselect.codesign.cyclerules import (
    WRITTEN_MARGIN,
    Leg,
    after_solve,
    check_scaled,
    hopeless,
    smallest_scale,
)
from hdselect.codesign.fastpath import PathModel, cycle, kinematic_scales, slowdown_notes, solve
from hdselect.codesign.pathbounds import PathInfeasible, joint_limits
from hdselect.motion.events import carried
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import cycle_torques, joint_inertias
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import checked_motors
from hdselect.sizing.core import check_units, precision_of, select_units
from hdselect.sizing.options import Options, fixed_choice
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task, carrying, every_part, over_states, pooled, task_of
from hdselect.sizing.timescale import ScalableCycle
from hdselect.sizing.torques import DirectTorques

EVENTS_NOTE = ("payload events: the path is bounded with every part carried the whole cycle "
               "(conservative); the cycle found is checked with each part carried between "
               "its events")
"""What a fastest run of a motion with payload events says of them."""
UNTIMED_NOTE = ("payload events: the planner does not say when the arm reaches an event's "
                "waypoint, so the cycle found is checked with every part carried throughout")
"""Where an event's waypoint has no time on the re-planned cycle."""
DERATINGS = (0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3)
"""Fractions of the repeated-peak limit tried, until the cycle stops getting shorter."""
DERATING_RESOLUTION = 0.01
"""Width to which the best derating is refined [-]."""
_VERIFY_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class Trial:
    """TOPPRA's run of every task at one derating, and the smallest slow-down that passes.

    Attributes:
        derating: Fraction of its repeated-peak limit each derated joint keeps [-].
        legs: Every counted task's run, in the duty's order.
        scale: The smallest common slow-down of the moves at which every rule passes [-].
        reason: The (joint, rule) failing just below `scale`, or None.
        whole_cycle_failing: The joints whose whole-cycle rules fail at s = 1.
        idle: The fraction of the time no task runs [-].
    """

    derating: Mapping[str, float]
    legs: tuple[Leg, ...]
    scale: float
    reason: tuple[str, str] | None
    whole_cycle_failing: tuple[str, ...] = ()
    idle: float = 0.0

    @property
    def cycle_time(self) -> float:
        """One task's cycle at the slow-down [s] (a derating is tried for one task only)."""
        (leg,) = self.legs
        return leg.moving * self.scale + leg.dwell


def run_trial(models: Sequence[PathModel], carrying: Sequence[Robot], shares: Sequence[float],
              units: Mapping[str, Unit], masses: Mapping[str, float],
              derating: Mapping[str, float], options: Options,
              motors: Mapping[str, Motor] | None = None, idle: float = 0.0,
              where: str = "", tasks: Sequence[Callable[[Trajectory], Task]] = ()) -> Trial:
    """Solve TOPPRA for every task at one derating and find the smallest common slow-down.

    Args:
        models: Each counted task's path (its robot: payload and mounting applied).
        carrying: Each task's robot carrying the masses of `masses`.
        shares: Each task's share of the time [-].
        units: The unit of every sized joint.
        masses: The mass each joint's unit (and motor) adds [kg] (empty: none carried).
        derating: Fraction of its repeated-peak limit each derated joint keeps [-].
        options: The assumptions.
        motors: The motor behind the unit of some joints (its limits and rules apply).
        idle: The fraction of the time no task runs [-].
        where: The file the errors name (default: the first task's motion file).
        tasks: Each counted task on a sampled trajectory of its path, its payload events
            on the trajectory's times (`retimed`): the rules over the cycle carry each
            part between its events; empty: `carrying` throughout.

    Raises:
        PathInfeasible: No slow-down lets every rule pass.
    """
    motors = motors or {}
    legs = []
    after: dict[str, frozenset[str]] = {name: frozenset() for name in units}
    for i, (model, robot, share) in enumerate(zip(models, carrying, shares, strict=True)):
        motion = model.motion
        limits = joint_limits(model.robot, motion, units, options, derating, motors=motors)
        for name, lim in zip(model.robot.joint_names, limits, strict=True):
            if name in after:
                after[name] |= after_solve(lim)
        profiles = solve(model, limits, masses, stop_time=options.stop_time)
        kinematic = kinematic_scales(profiles, limits)
        trajectory, held = cycle(motion, profiles, kinematic, max_samples=options.max_samples)
        moving = sum(p.duration * r for p, r in zip(profiles, kinematic, strict=True)
                     if p is not None)
        task = tasks[i](trajectory) if tasks else None
        cycles, held, inertia = _scalable(robot, trajectory, held, units, options, task, masses)
        legs.append(Leg(model, share, profiles, kinematic, moving, trajectory.duration - moving,
                        cycles, held, slowdown_notes(motion.joint_names, profiles, limits),
                        inertia))
    where = where or str(models[0].motion.path)
    scale, reason = smallest_scale(legs, units, options, where, motors, idle)
    failing = {name for name in units
               if any(not c.ok for rule, c in check_scaled(legs, name, units[name], 1.0,
                                                           options, motors.get(name), idle
                                                           ).checks.items()
                      if rule in after[name])}
    return Trial(dict(derating), tuple(legs), scale, reason, tuple(sorted(failing)), idle)


def _scalable(robot: Robot, trajectory: Trajectory, held: np.ndarray,
              units: Mapping[str, Unit], options: Options, task: Task | None = None,
              masses: Mapping[str, float] | None = None
              ) -> tuple[dict[str, ScalableCycle], np.ndarray, dict[str, float]]:
    """Each sized joint's cycle split by how its torque scales with time (four passes).

    A dwell holds one pose at rest: it is kept as one sample that lasts the whole
    dwell, which every rule weighs alike (the motor's RMS torque, which assumes equal
    samples, is not a rule). Where `task` (on `trajectory`) has payload events, each
    carried state's samples are evaluated with its own robot, as the sizing does; else
    `robot` (every part carried) throughout. Time scaling keeps the states: the events
    sit at waypoints, and dwells keep their length.

    Returns:
        The cycles by joint, which of their samples are dwells, and the load inertia of
        each joint with a natural-frequency target (`Leg.inertia`).
    """
    keep = np.flatnonzero(~held | np.r_[True, ~held[:-1]])
    lasts = np.diff(np.r_[keep, len(held)]) * trajectory.dt
    qd, qdd = trajectory.qd[keep], trajectory.qdd[keep]
    dt = np.where(held[keep], lasts, trajectory.dt)

    def split(state: Robot, rows: np.ndarray | slice) -> tuple[np.ndarray, ...]:
        torques = cycle_torques(state, trajectory.q[rows], trajectory.qd[rows],
                                trajectory.qdd[rows], options.stop_time, split=True,
                                threads=options.threads)
        if torques.gravity is None or torques.coasting is None:
            raise RuntimeError("cycle_torques(split=True) returned no gravity or coasting part")
        return torques.tau, torques.stop, torques.gravity, torques.coasting
    tuned = [name for name in units
             if options.joint_value("min_natural_frequency", name) is not None]

    def inertias(state: Robot, rows: np.ndarray | slice) -> tuple[np.ndarray, ...]:
        return (joint_inertias(state, trajectory.q[rows], tuned, threads=options.threads),)
    if task is None or task.carried is None:
        tau, stop, gravity, coast = split(robot, keep)
        load = inertias(robot, keep)[0] if tuned else None
    else:
        states = carrying(task, masses or {}, task.robot.sized_joints)
        tau, stop, gravity, coast = over_states(task, states, split, keep)
        load = over_states(task, states, inertias, keep)[0] if tuned else None
    out = {}
    for name in units:
        j = robot.joint_index(name)
        out[name] = ScalableCycle.split(
            trajectory.t[keep], dt, trajectory.duration, qd[:, j], qdd[:, j],
            at_rest(qd[:, j], qdd[:, j]), torque=tau[:, j], stop_torque=stop[:, j],
            gravity=gravity[:, j], coast=coast[:, j], stop_time=options.stop_time)
    inertia = {} if load is None else dict(zip(tuned, map(float, load.max(axis=0)),
                                               strict=True))
    return out, held[keep], inertia


def derated(models: Sequence[PathModel], carrying: Sequence[Robot], units: Mapping[str, Unit],
            masses: Mapping[str, float], first: Trial, options: Options,
            motors: Mapping[str, Motor] | None = None,
            tasks: Sequence[Callable[[Trajectory], Task]] = ()) -> Trial:
    """The derating of the failing joints' torque limits that gives the shortest cycle.

    For one task (its cycle is what a derating shortens): `run_trial`'s arguments.
    """
    joints = first.whole_cycle_failing
    shares = [leg.share for leg in first.legs]

    def attempt(fraction: float) -> Trial | None:
        try:
            return run_trial(models, carrying, shares, units, masses,
                             dict.fromkeys(joints, fraction), options, motors, tasks=tasks)
        except PathInfeasible:
            return None
    tried: dict[float, Trial | None] = {1.0: first}
    best, previous = first, first.cycle_time
    for fraction in DERATINGS:
        found = tried[fraction] = attempt(fraction)
        if found is None or found.cycle_time > previous:
            break
        previous = found.cycle_time
        if found.cycle_time < best.cycle_time:
            best = found
    centre = max(best.derating.values(), default=1.0)
    lo, hi = max(centre - 0.1, 0.05), min(centre + 0.1, 1.0)
    golden = (math.sqrt(5.0) - 1.0) / 2.0

    def cycle_at(fraction: float) -> float:
        if fraction not in tried:
            tried[fraction] = attempt(fraction)
        found = tried[fraction]
        return math.inf if found is None else found.cycle_time

    x1, x2 = hi - golden * (hi - lo), lo + golden * (hi - lo)
    while hi - lo > DERATING_RESOLUTION:
        if cycle_at(x1) <= cycle_at(x2):
            hi, x2 = x2, x1
            x1 = hi - golden * (hi - lo)
        else:
            lo, x1 = x1, x2
            x2 = lo + golden * (hi - lo)
    for found in tried.values():
        if found is not None and found.cycle_time < best.cycle_time:
            best = found
    return best


_SPEED_FREE = ("static", "natural_frequency")
"""The rules no slow-down helps: a load held still, a joint's resonance."""


def timed(motion: Motion, trajectory: Trajectory) -> bool:
    """The trajectory says when the arm reaches every waypoint the motion's events are at."""
    reached = trajectory.waypoint_times
    return all(event.waypoint is None or (reached is not None
                                          and math.isfinite(reached[event.waypoint]))
               for event in motion.events)


def retimed(task: Task, trajectory: Trajectory) -> Task:
    """The task on a re-planned trajectory, its payload events put on the new times.

    Where the trajectory does not say when an event's waypoint is reached, every part is
    carried throughout (conservative: `UNTIMED_NOTE`).
    """
    motion = task.motion
    if motion is None or not motion.events:
        return replace(task, trajectory=trajectory)
    held = () if task.carried is None else task.carried.parts
    if not timed(motion, trajectory):
        return replace(task, robot=every_part(task.robot, motion, held), trajectory=trajectory,
                       carried=None)
    if task.carried is None:  # its robot as the file gives it: the events from the motion
        return task_of(task.robot, trajectory, motion, task.share, task.name)
    fresh = carried(motion, trajectory)
    for part in held:
        fresh = fresh.with_part(part) if fresh is not None else None
    return replace(task, trajectory=trajectory, carried=fresh)


def verified(units: Mapping[str, Unit], trial: Trial, options: Options,
             motors: Mapping[str, Motor] | None = None, tasks: Sequence[Task] | None = None,
             where: str = "") -> tuple[Trajectory, np.ndarray, SizingResult, float,
                                       tuple[np.ndarray, ...]]:
    """Every task's trajectory on its motion's grid and their check, slowed until all pass.

    Args:
        units: The unit of every sized joint.
        trial: The run whose profiles are sampled.
        options: The assumptions.
        motors: The motor behind the unit of some joints.
        tasks: The duty's counted tasks, checked together (`check_tasks`); None checks
            the one task's trajectory alone (`hdselect.sizing.core.check_units`).
        where: The file the errors name (default: the first task's motion file).

    Returns:
        The first task's trajectory, its dwell samples, the check (the tasks checked hold
        every task's trajectory), the slow-down [-] and every task's dwell samples.

    Raises:
        PathInfeasible: No slow-down the check confirms lets every rule pass.
    """
    scale = trial.scale
    passing = None
    for _ in range(_VERIFY_ROUNDS):
        runs = [cycle(leg.model.motion, leg.profiles, [r * scale for r in leg.kinematic],
                      max_samples=options.max_samples, notes=leg.notes) for leg in trial.legs]
        trajectories = tuple(trajectory for trajectory, _ in runs)
        held = runs[0][1]
        helds = tuple(dwells for _, dwells in runs)
        if tasks is None:
            check = check_units(trial.legs[0].model.robot, trajectories[0], units, options,
                                motors=motors)
        else:
            check = check_tasks([retimed(task, trajectory) for task, trajectory
                                 in zip(tasks, trajectories, strict=True)], units, options,
                                trial.idle, motors)
        candidates = [c for joint in check.joints for c in joint.candidates]
        excess = max((c.checks[rule].utilization for c in candidates for rule in c.checks
                      if rule not in _SPEED_FREE), default=0.0) / (1.0 - options.margin)
        if check.feasible:
            passing = passing or (trajectories[0], held, check, scale, helds)
            if excess <= 1.0 - WRITTEN_MARGIN:
                return trajectories[0], held, check, scale, helds
        if any(not c.checks[rule].ok for c in candidates for rule in _SPEED_FREE
               if rule in c.checks):
            break  # a held load, or a joint's resonance: no speed helps
        scale *= max(math.sqrt(excess), 1.0 + 10.0 * WRITTEN_MARGIN)
    if passing is not None:  # at its limit to within the margin, whatever the speed
        return passing
    failing = [(joint.name, c.binding) for joint in check.joints for c in joint.candidates
               if not c.feasible]
    name, rule = failing[0] if failing else (next(iter(units)), "peak")
    raise hopeless(where or str(trial.legs[0].model.motion.path), name, rule, units[name],
                   len(trial.legs) > 1)


def check_tasks(tasks: Sequence[Task], units: Mapping[str, Unit], options: Options,
                idle: float = 0.0, motors: Mapping[str, Motor] | None = None) -> SizingResult:
    """Given units (and motors), one per sized joint, checked over a duty: no selection.

    As `hdselect.sizing.core.check_units` for one trajectory: each joint's only
    candidate is its unit (paired with its motor, where one is given); with mass
    coupling each unit's mass (and its motor's, else the options' motor mass) is carried;
    the stiffness figures are those of the units.

    Args:
        tasks: The duty's tasks (the same robot file and sized joints).
        units: The unit of every sized joint.
        options: The assumptions.
        idle: The fraction of the time no task runs [-].
        motors: A fixed motor behind the unit of some sized joints.
    """
    robot = tasks[0].robot
    fixed = checked_motors(robot, {name: (motor,) for name, motor in (motors or {}).items()},
                           options) if motors else {}
    resolved, masses = fixed_choice(options, units, fixed, robot.sized_joints)
    samples = pooled(tasks, idle)
    model = DirectTorques(samples.tasks, samples, options.stop_time, threads=options.threads,
                          guess=masses, wrenches=options.bearing_loads)
    joints, masses = select_units(model, {name: (units[name],) for name in robot.sized_joints},
                                  resolved, fixed, slowdowns=False)
    first = samples.tasks[0]
    distinct = tuple(dict.fromkeys(units[name] for name in robot.sized_joints))
    return SizingResult(first.robot, first.trajectory, tuple(joints),
                        options if not fixed else resolved, distinct, first.motion,
                        motors=fixed, loads=model.loads(masses), tasks=tuple(tasks), idle=idle,
                        precision=precision_of(model, joints, masses, options))
