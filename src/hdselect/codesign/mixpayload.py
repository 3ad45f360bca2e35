"""The largest payloads a robot's working day (a mix) can carry, found exactly.

Every task that carries a payload has it scaled by one factor x (the same bodies,
denser: mass and inertia about the centre of mass times x); the tasks without one
carry none. On fixed trajectories every task's torque is affine in x,
tau_k(x) = tau_k(0) + x (tau_k(1) - tau_k(0)), so two pairs of batched passes per task
give every rule over the whole duty as a function of x (`hdselect.codesign.maxpayload`'s
intervals on the tasks' pooled samples): the rules of single samples hold on the
intersection of every task's samples, the mean torque and life on the pooled,
share-weighted cubic mean. The units chosen depend on x: the largest x with the
masses of the units selected there is found, the selection redone at it, and the two
repeated until the masses settle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.units import Unit
from hdselect.codesign.maxpayload import (
    Interval,
    UnitBound,
    _binding,
    _feasible,
    _per_kg,
    joint_mean,
    unit_bound,
)
from hdselect.motion.mixfile import Mix
from hdselect.robot.dynamics import cycle_torques
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.sizing.core import size_tasks
from hdselect.sizing.duty import mix_motors, mix_options, mix_tasks
from hdselect.sizing.options import Options
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task, pooled

_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class MixPayloadResult:
    """The largest common factor on a mix's payloads with a feasible unit on every joint.

    Attributes:
        factor: The largest factor x [-] on every scaled task's payload; math.inf when no
            rule depends on it; None when no x >= 0, not even 0, has a unit everywhere.
        scaled: The tasks whose payload is scaled, by name.
        payloads: Each scaled task's payload as the files give it (x = 1), by name.
        ranges: Every interval of factors with a unit on every joint [-].
        joint: The joint that runs out of units at `factor`, or None.
        unit: The last of its units to pass there, or None.
        rule: The rule that unit fails just above `factor`, or None.
        selection: The sizing of the duty at `factor` (just inside it), or None.
        bounds: Per joint, each unit's interval of factors.
        tasks: The duty's tasks at x = 1.
        idle: The fraction of the time no task runs [-].
    """

    factor: float | None
    scaled: tuple[str, ...]
    payloads: Mapping[str, Payload]
    ranges: tuple[Interval, ...]
    joint: str | None
    unit: Unit | None
    rule: str | None
    selection: SizingResult | None
    bounds: Mapping[str, tuple[UnitBound, ...]]
    tasks: tuple[Task, ...]
    idle: float = 0.0

    def masses(self, factor: float | None = None) -> dict[str, float]:
        """Each scaled task's payload mass at a factor (default: the largest) [kg]."""
        x = self.factor if factor is None else factor
        if x is None:
            return {}
        return {name: payload.mass * x for name, payload in self.payloads.items()}


def mix_max_payload(robot: Robot, mix: Mix, options: Options | None = None, *,
                    catalog: Sequence[Unit] | None = None,
                    tasks: Sequence[str] | None = None) -> MixPayloadResult:
    """The largest factor on the payloads of a mix's tasks with a unit on every joint.

    Args:
        robot: The robot with the duty's sized joints (`hdselect.load_case` of the mix).
        mix: The mix.
        options: The assumptions (default: the mix's, `hdselect.sizing.duty.mix_options`).
        catalog: The units (default: the built-in catalog and the mix file's).
        tasks: The tasks whose payload scales, by name (default: every task that carries
            one); the others keep theirs.

    Returns:
        The factor, the masses it gives, where it binds, and the duty's sizing there.

    Raises:
        InputError: A task plans with its payload's dynamics (TOPPRA under torque limits),
            motors are given, a name is not a task, or no task named carries a payload.
        PlanningError: A motion cannot be planned.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(mix, (Mix,), "mix", "a Mix (hdselect.load_case of a mix file)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    for item in mix.tasks:
        if item.motion.planner == "toppra" and item.motion.torque_limit is not None:
            raise InputError("the TOPPRA torque limits make the trajectory depend on the "
                             "payload; max-payload needs trajectories that do not: remove "
                             "them", path=item.motion.path, field="limits.torque")
    if mix_motors(robot, mix):
        raise InputError("max-payload on a mix does not choose motors yet; the motors given "
                         "would be left out: remove [motor]", path=mix.path, field="motor")
    options = options if options is not None else mix_options(mix)
    units = tuple(catalog) if catalog is not None else load_catalog(list(mix.catalog))
    planned, idle = mix_tasks(robot, mix, joints=robot.sized_joints, exclude=(),
                              max_samples=options.max_samples)
    names = [task.label for task in planned]
    for name in tasks or ():
        if name not in names:
            raise InputError(f"no task {name!r} in {mix.path.name}; its tasks are: "
                             f"{', '.join(names)}", field="task")
    chosen = [task.label for task in planned if task.robot.payload is not None
              and (tasks is None or task.label in tasks)]
    if not chosen:
        raise InputError("no task " + ("named " if tasks else "of the mix ")
                         + "carries a payload to scale", path=mix.path, field="task")
    masses: dict[str, float] = {}
    result = None
    for _ in range(_ROUNDS):
        bounds = duty_bounds(planned, idle, chosen, masses, units, options)
        ranges = _feasible(bounds)
        factor = ranges[-1][1] if ranges else None
        selection = None
        if factor is not None and math.isfinite(factor):
            inside = max(factor * (1.0 - 1e-9), ranges[-1][0])
            selection = size_tasks(at_factor(planned, chosen, inside), units, options, idle=idle)
            selection = replace(selection, mix=mix)
        result = (factor, ranges, bounds, selection)
        if selection is None or not options.mass_coupling:
            break
        carried = {joint.name: (joint.selected or joint.strongest).unit.mass + options.motor_mass
                   for joint in selection.joints}
        if carried == masses:
            break
        masses = carried
    assert result is not None
    factor, ranges, bounds, selection = result
    joint = unit = rule = None
    if factor is not None and math.isfinite(factor):
        joint, best = _binding(bounds, factor)
        unit, rule = best.unit, best.limiting(factor)
    payloads = {task.label: task.robot.payload for task in planned if task.label in chosen}
    return MixPayloadResult(factor, tuple(chosen), payloads,  # type: ignore[arg-type]
                            tuple(ranges), joint, unit, rule, selection, bounds, planned, idle)


def at_factor(tasks: Sequence[Task], scaled: Sequence[str], factor: float) -> tuple[Task, ...]:
    """The tasks with the payloads of `scaled` ones times `factor` (mass and inertia) [-]."""
    out = []
    for task in tasks:
        payload = task.robot.payload
        if task.label in scaled and payload is not None:
            robot = task.robot.with_payload(None) if factor <= 0.0 else task.robot.with_payload(
                replace(payload, mass=payload.mass * factor,
                        inertia=tuple(tuple(v * factor for v in row) for row in payload.inertia)))
            task = replace(task, robot=robot)
        out.append(task)
    return tuple(out)


def duty_bounds(tasks: Sequence[Task], idle: float, scaled: Sequence[str],
                masses: Mapping[str, float], units: Sequence[Unit],
                options: Options) -> dict[str, tuple[UnitBound, ...]]:
    """Each unit's interval of payload factors on each sized joint, gearhead masses fixed.

    Args:
        tasks: The duty's tasks, payloads at factor 1.
        idle: The fraction of the time no task runs [-].
        scaled: The tasks whose payload scales, by name.
        masses: The gearhead (and motor) mass per joint's unit [kg].
        units: The catalog.
        options: The assumptions.
    """
    counted = [task for task in tasks if task.share > 0.0]
    samples = pooled(counted, idle)
    parts = []
    for task in counted:
        traj = task.trajectory
        loaded = task.robot.with_gearheads(masses) if masses else task.robot
        empty = loaded.with_payload(None) if task.label in scaled else loaded
        args = (traj.q, traj.qd, traj.qdd, options.stop_time)
        none = cycle_torques(empty, *args, threads=options.threads)
        full = none if empty is loaded else cycle_torques(loaded, *args,
                                                          threads=options.threads)
        parts.append((none, full))
    robot = counted[0].robot
    out = {}
    for name in robot.sized_joints:
        j = robot.joint_index(name)
        tau0 = np.concatenate([none.tau[:, j] for none, _ in parts])
        stop0 = np.concatenate([none.stop[:, j] for none, _ in parts])
        tau1 = np.concatenate([_per_kg(full.tau[:, j], none.tau[:, j]) for none, full in parts])
        stop1 = np.concatenate([_per_kg(full.stop[:, j], none.stop[:, j])
                                for none, full in parts])
        rest, qd = samples.rest[:, j], samples.qd[:, j]
        cubic = joint_mean(samples.dt, rest, qd, tau0, tau1)
        out[name] = tuple(unit_bound(unit, samples.dt, rest, qd, tau0, tau1, stop0, stop1,
                                     options, samples.idle, cubic=cubic)
                          for unit in units)
    return out
