"""A group's cases sized from one basis per task, pooled with each case's shares.

A case is a duty of tasks (`hdselect.study.casetasks`): a motion file is one task
with share 1, a mix file several. Each task's path gets one basis of batched passes
per payload shape (`hdselect.study.group.build_basis`), shared by every case of the
group; a case's torques are the bases' linear combinations (`BasisTorques`), pooled
with its shares by `PooledTorques` (one task: its own samples, exactly) and fed to
the core's own selection (`hdselect.sizing.core.select_units`): the answer
`hdselect.size` reaches for the same motion or mix, to rounding. A case whose task
plans with its payload's dynamics (TOPPRA under torque limits) is sized direct.
"""

from __future__ import annotations

import time
from collections.abc import Generator, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from hdselect.base.errors import HdselectError, InputError
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS
from hdselect.catalog.units import Unit
from hdselect.motion.events import Carried
from hdselect.motion.mixfile import Mix
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import check_bearing_options, checked_motors
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.core import select_units
from hdselect.sizing.diagnosis import diagnose
from hdselect.sizing.loads import JointLoad, merged_loads
from hdselect.sizing.options import Options
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.stiffening import targets_of
from hdselect.sizing.summary import Summary, summarize
from hdselect.sizing.tasks import Samples, Task, merged
from hdselect.sizing.torques import TorqueModel
from hdselect.study.case import Case, Outcome
from hdselect.study.casetasks import CaseDuty, CaseTask, Inputs
from hdselect.study.group import Basis, BasisTorques, build_basis, plan_depends_on_payload
from hdselect.study.precise import grouped_stiffened

PAYLOAD_PLAN = ("TOPPRA plans under torque limits with the payload's dynamics: sized on "
                "its own")
"""Why a case whose plan depends on its payload is sized direct."""


def scaled(trajectory: Trajectory, time_scale: float) -> Trajectory:
    """The same path run s times slower [-]: times times s, speeds / s, accelerations / s^2."""
    if time_scale == 1.0:
        return trajectory
    y = 1.0 / time_scale
    return replace(trajectory, dt=trajectory.dt * time_scale,
                   duration=trajectory.duration * time_scale, t=trajectory.t * time_scale,
                   qd=trajectory.qd * y, qdd=trajectory.qdd * y**2,
                   waypoint_times=None if trajectory.waypoint_times is None
                   else trajectory.waypoint_times * time_scale,
                   qdd_uncertainty=None if trajectory.qdd_uncertainty is None
                   else trajectory.qdd_uncertainty * y**2)


def slower_events(carried: Carried | None, time_scale: float) -> Carried | None:
    """A task's payload events on its path run s times slower [-]: their times times s."""
    if carried is None or time_scale == 1.0:
        return carried
    return replace(carried, events=tuple((t * time_scale, part, attached)
                                         for t, part, attached in carried.events))


class PooledTorques:
    """Tasks' torque models pooled with their shares: a `TorqueModel` of the duty.

    Each model gives one task's torques on its own samples; the duty's samples are
    theirs in task order, each task weighted by how often its cycle runs
    (`hdselect.sizing.tasks.merged`: one task's samples as they are), and its torques
    theirs, concatenated.
    """

    def __init__(self, models: Sequence[TorqueModel], idle: float = 0.0) -> None:
        """Pool the models (each of one task, its share above 0, in task order).

        Args:
            models: One model per counted task; its samples' task carries the share.
            idle: The fraction of the time no task runs [-].
        """
        self.models = tuple(models)
        self.robot = self.models[0].robot
        self.samples: Samples = merged([model.samples for model in self.models], idle)

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along the pooled samples [N m]."""
        return _joined([model.torques(joint, masses) for model in self.models])

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity and coasting parts along the pooled samples [N m]."""
        return _joined([model.scaling_parts(joint, masses) for model in self.models])

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over every task's poses [N m], (dof,)."""
        return np.max([model.gravity(masses) for model in self.models], axis=0)

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over every task's poses [kg m^2]."""
        return max(model.load_inertia(joint, masses) for model in self.models)

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj over each task's poses [kg m^2], in task order."""
        return tuple(model.load_inertia(joint, masses) for model in self.models)

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along the pooled samples [N, N m]."""
        parts = [model.wrench(joint, masses) for model in self.models]
        if len(parts) == 1 or any(part is None for part in parts):
            return parts[0] if len(parts) == 1 else None
        full = [part.full() for part in parts if part is not None]
        return SampledWrench(np.concatenate(full, axis=1))

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each pooled sample's pose still [N, N m], (5, n)."""
        parts = [model.gravity_wrench(joint, masses) for model in self.models]
        if any(part is None for part in parts):
            return None
        return np.concatenate([part for part in parts if part is not None], axis=1)

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint against its file's limits over every task."""
        if len(self.models) == 1:
            return self.models[0].loads(masses)
        return merged_loads([model.loads(masses) for model in self.models])


def _joined(parts: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    if len(parts) == 1:
        return parts[0]
    return np.concatenate([a for a, _ in parts]), np.concatenate([b for _, b in parts])


def diagnosed(result: SizingResult) -> SizingResult:
    """A case's sizing with the diagnosis of each joint without a unit, without next steps.

    The shortfalls and gravity alone are the case's; the next steps are left out: their
    commands would size the motion file, not the case (its parameters, its time scale).
    """
    if result.feasible:
        return result
    return replace(result, diagnoses={name: replace(found, steps=()) for name, found
                                      in diagnose(result, catalogs={}).items()})


def needs_inertias(options: Options, joints: Sequence[str], motors: Motors | None) -> bool:
    """Whether a case's selection reads its joints' load inertia M_jj.

    Where motors are given (the inertia ratio) or a joint has a natural-frequency target
    (`min_natural_frequency`).
    """
    return bool(motors) or any(options.joint_value("min_natural_frequency", name) is not None
                               for name in joints)


def size_pooled(bases: Sequence[Basis], tasks: Sequence[CaseTask], time_scale: float,
                units: Sequence[Unit], options: Options, motors: Motors | None = None,
                mix: Mix | None = None) -> Summary:
    """One case from its tasks' bases (one per task, in task order), sized by the core.

    Args:
        bases: Each task's basis (with `Basis.inertia` where `needs_inertias`).
        tasks: The case's tasks: the payload each carries (its mass; its shape is the
            basis's) and its share.
        time_scale: Every path run s times slower [-].
        units: The candidate units.
        options: The assumptions; ``prefer`` None is resolved as the core resolves it.
        motors: Candidate motors per sized joint, as `hdselect.size_trajectory` takes them.
        mix: The mix file the tasks come from, or None for a motion file.

    Returns:
        The case's summary; its robot and motion are the first counted task's files.

    Raises:
        InputError: The shares, payloads or motors are not valid (as the core says), or a
            mix in cycles per hour gives no shares.
    """
    units = tuple(units)
    motors = checked_motors(bases[0].robot, motors, options)
    if options.prefer is None:
        options = replace(options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors
                          else DEFAULT_PREFER)
    if needs_inertias(options, bases[0].robot.sized_joints, motors) and any(
            basis.inertia is None for basis in bases):
        raise ValueError("a case with motors or a natural-frequency target needs bases "
                         "built with inertias=True")
    check_bearing_options(bases[0].robot, units, options)
    models, planned, cases = [], [], []
    for basis, item in zip(bases, tasks, strict=True):
        if item.share is None:
            raise InputError("a mix in cycles per hour is grouped from its shares: give "
                             "`shares`, or run the study with --no-grouping", field="shares")
        if basis.payload is None and item.payload is not None:
            raise InputError(f"task {item.name!r} has no payload to give a mass",
                             field="payloads")
        mass = None if basis.payload is None else (
            0.0 if item.payload is None else item.payload.mass)
        traj = basis.trajectory
        timing = replace(traj, dt=traj.dt * time_scale, duration=traj.duration * time_scale)
        model = BasisTorques(basis, mass, time_scale, options.stop_time,
                             wrenches=options.bearing_loads)
        case = model.case_task()  # the parts it carries when, at the case's masses
        task = Task(basis.robot, timing, item.share, basis.motion, item.name,
                    slower_events(case.carried, time_scale))
        planned.append(task)
        cases.append(replace(case, trajectory=scaled(traj, time_scale), share=item.share,
                             name=item.name, carried=task.carried))
        if task.share > 0.0:
            model.samples = replace(model.samples, tasks=(task,))
            models.append(model)
    pooled = PooledTorques(models)
    per_joint = {name: units for name in bases[0].robot.sized_joints}
    joints, masses = select_units(pooled, per_joint, options, motors, detail=False)
    if any(joint.selected is None for joint in joints):  # its diagnosis reads every check
        joints, masses = select_units(pooled, per_joint, options, motors)
    precision = None
    if options.precision or targets_of(options):  # on every sample, as size: `precise`
        own = [case for case in cases if case.share > 0.0]
        found = grouped_stiffened(pooled, models, own, per_joint, joints, masses, options,
                                  motors)
        joints, masses, precision = found.joints, found.masses, found.precision
    first = pooled.samples.tasks[0]
    result = SizingResult(first.robot, first.trajectory, tuple(joints), options, units,
                          first.motion, motors=motors, loads=pooled.loads(masses),
                          tasks=tuple(planned), mix=mix, precision=precision)
    if not result.feasible:  # the diagnosis reads the poses with each task's own payload
        carrying = tuple(replace(case, trajectory=task.trajectory)
                         for task, case in zip(planned, cases, strict=True))
        result = replace(diagnosed(replace(result, tasks=carrying)), tasks=tuple(planned))
    summary = summarize(result)
    # the bases' robots carry the reference payload; each task carries its own mass
    carried = [0.0 if item.payload is None else float(item.payload.mass) for item in tasks]
    lead = next(k for k, task in enumerate(planned) if task.share > 0.0)
    return replace(summary, payload_mass=carried[lead],
                   tasks=tuple({**entry, "payload_mass": mass}
                               for entry, mass in zip(summary.tasks, carried, strict=False)))


def size_case(basis: Basis, mass: float | None, time_scale: float, units: Sequence[Unit],
              options: Options, motors: Motors | None = None) -> Summary:
    """One case of a motion file (a duty of one task) from its basis, sized by the core.

    Args:
        basis: The group's basis (with `Basis.inertia` where `needs_inertias`).
        mass: Payload mass [kg] (None exactly when the basis has no payload).
        time_scale: The path run s times slower [-].
        units: The candidate units.
        options: The assumptions; ``prefer`` None is resolved as the core resolves it.
        motors: Candidate motors per sized joint, as `hdselect.size_trajectory` takes them.

    Returns:
        The case's summary; its robot and motion are the basis's files.

    Raises:
        InputError: The motors are not valid for this robot and these options (as the
            core says).
    """
    payload = (None if basis.payload is None or mass is None
               else replace(basis.payload, mass=mass))
    return size_pooled([basis], [CaseTask(basis.motion, None, payload, 1.0, "", basis.part)],
                       time_scale,
                       units, options, motors)


def group_cases(cases: Sequence[Case], inputs: Inputs, host: str
                ) -> Generator[Outcome, None, list[tuple[Case, str | None]]]:
    """The cases of one group (one robot, motion or mix file, mounting) from shared bases.

    Every task of the group gets one basis per payload shape its cases carry in it.
    Yields the outcome of each case as it completes, its seconds including its share of
    the bases; a case whose inputs are bad fails alone. Returns the cases to size
    direct (a task plans with its payload's dynamics: TOPPRA under torque limits), each
    with why.
    """
    start = time.perf_counter()
    ready: list[tuple[Case, CaseDuty, list[Any], Motors]] = []
    alone: list[tuple[Case, str | None]] = []
    mounted: dict[Any, Robot] = {}
    wanted: dict[Any, tuple[Robot, CaseTask, bool]] = {}
    for case in cases:
        try:
            duty = inputs.duty(case)
            if any(plan_depends_on_payload(task.motion) for task in duty.tasks):
                alone.append((case, PAYLOAD_PLAN if duty.mix is None else
                              "a task's " + PAYLOAD_PLAN))
                continue
            places = [(k, task.motion.path, repr(task.mounting))
                      for k, task in enumerate(duty.tasks)]
            for k, place in enumerate(places):
                if place not in mounted:
                    mounted[place] = duty.mounted(k)
            robots = [mounted[place] for place in places]
            motors = inputs.duty_motors(case, duty, robots[0])
        except HdselectError as err:
            yield _outcome(case, err, "grouped", time.perf_counter() - start, host)
            continue
        keys = [(place, _shape_key(task)) for place, task in zip(places, duty.tasks, strict=True)]
        for key, robot, task in zip(keys, robots, duty.tasks, strict=True):
            first = wanted.setdefault(key, (robot, task, False))
            wanted[key] = (*first[:2], first[2] or needs_inertias(
                duty.options, robot.sized_joints, motors))
        ready.append((case, duty, keys, motors))
    bases: dict[Any, Basis | HdselectError] = {}
    for key, (robot, task, inertias) in wanted.items():
        try:
            bases[key] = build_basis(robot, task.motion, task.payload, inertias=inertias,
                                     part=task.part)
        except HdselectError as err:
            bases[key] = err
    share = (time.perf_counter() - start) / max(len(ready), 1)
    for case, duty, keys, motors in ready:
        begun = time.perf_counter()
        built = [bases[key] for key in keys]
        summary: Summary | HdselectError
        try:
            failed = next((basis for basis in built if isinstance(basis, HdselectError)), None)
            if failed is not None:
                raise failed
            summary = size_pooled([b for b in built if isinstance(b, Basis)], duty.tasks,
                                  case.time_scale, inputs.catalog(case), duty.options, motors,
                                  duty.mix)
        except HdselectError as err:
            summary = err
        yield _outcome(case, summary, "grouped", share + time.perf_counter() - begun, host)
    return alone


def _shape_key(task: CaseTask) -> Any:
    """What a basis depends on of a task's payload: its shape, not its mass."""
    payload = task.payload
    return task.part, None if payload is None else (payload.com, payload.inertia, payload.frame)


def _outcome(case: Case, summary: Summary | HdselectError, method: str, seconds: float,
             host: str) -> Outcome:
    """A case's outcome: its summary, or why it failed."""
    if isinstance(summary, HdselectError):
        return Outcome(case.index, case.key, False, str(summary), None, method, None,
                       seconds, host)
    return Outcome(case.index, case.key, True, None, summary.to_dict(), method, None,
                   seconds, host)
