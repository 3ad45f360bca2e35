"""A study's cases on a mix file: the duty's rules from one basis per task, or each case direct.

A mix case gives the shares of its tasks and per-task payload masses as parameters
(``shares``, ``payloads``), on top of the mix file's. Its tasks are planned once per
group: each task's path gets its own basis of batched passes
(`hdselect.study.group.build_basis`), and each case's torques are the bases' linear
combinations (`BasisTorques`), pooled with the case's shares by `MixTorques` and fed to
the core's own selection (`hdselect.sizing.core.select_units`): the answer
`hdselect.size` reaches for the same mix, to rounding. A case whose task plans with
its payload's dynamics (TOPPRA under torque limits) is sized direct.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Generator, Iterable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from hdselect.base.errors import HdselectError, InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS
from hdselect.catalog.units import Unit
from hdselect.motion.case import robot_for_mix, robot_for_motion
from hdselect.motion.mixfile import Mix, is_mix_file, load_mix, mix_robot_file
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import check_bearing_options, checked_motors
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.core import select_units, size_tasks
from hdselect.sizing.duty import mix_motors, mix_options, mix_tasks
from hdselect.sizing.loads import JointLoad, merged_loads
from hdselect.sizing.options import Options
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.summary import Summary, summarize
from hdselect.sizing.tasks import Samples, Task, check_shares, merged
from hdselect.sizing.torques import TorqueModel
from hdselect.study.case import Case, Outcome
from hdselect.study.group import Basis, BasisTorques, build_basis, plan_depends_on_payload


def scaled(trajectory: Trajectory, time_scale: float) -> Trajectory:
    """The same path run s times slower [-]: times times s, speeds / s, accelerations / s^2."""
    if time_scale == 1.0:
        return trajectory
    y = 1.0 / time_scale
    return replace(trajectory, dt=trajectory.dt * time_scale,
                   duration=trajectory.duration * time_scale, t=trajectory.t * time_scale,
                   qd=trajectory.qd * y, qdd=trajectory.qdd * y**2,
                   qdd_uncertainty=None if trajectory.qdd_uncertainty is None
                   else trajectory.qdd_uncertainty * y**2)


class MixTorques:
    """Several tasks' torque models pooled with their shares: a `TorqueModel` of the duty.

    Each model gives one task's torques on its own samples; the duty's samples are
    theirs in task order, each task weighted by how often its cycle runs
    (`hdselect.sizing.tasks.merged`), and its torques theirs, concatenated.
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
        parts = [model.torques(joint, masses) for model in self.models]
        return _joined(parts)

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
        if any(part is None for part in parts):
            return None
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
        return merged_loads([model.loads(masses) for model in self.models])


def _joined(parts: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    if len(parts) == 1:
        return parts[0]
    return np.concatenate([a for a, _ in parts]), np.concatenate([b for _, b in parts])


def is_mix_case(case: Case) -> bool:
    """The case's motion is a mix file (a file that cannot be read is not: it fails later)."""
    try:
        return is_mix_file(case.motion)
    except InputError:
        return False


def case_mix(case: Case, robots: dict[Path, Robot]) -> tuple[Robot, Mix]:
    """The robot (sized joints applied, no payload) and the mix of a case, robots cached.

    Raises:
        InputError: A file is bad, or the case gives a single ``payload`` for a mix.
    """
    if case.payload is not None:
        raise InputError("a mix's tasks carry their own payloads: vary `payloads` (task name "
                         "-> mass [kg]) instead of `payload`", field="payload")
    file = case.robot if case.robot is not None else mix_robot_file(case.motion)
    if file not in robots:
        robots[file] = load_robot(file)
    mix = load_mix(case.motion, robots[file])
    return robot_for_mix(robots[file], mix), mix


def case_payloads(case: Case, mix: Mix) -> dict[int, Payload]:
    """The case's payload per task index, from its ``payloads`` masses.

    Each mass goes in its task's payload shape, as a study's ``payload`` does (centre of
    mass, inertia about it and frame kept): the mix file's, else the motion file's, else
    a point mass at the robot's default payload frame.

    Raises:
        InputError: A task name is not the mix's.
    """
    names = [task.name for task in mix.tasks]
    check_task_keys(None, case.payloads, names, mix.path.name)
    out: dict[int, Payload] = {}
    for name, mass in case.payloads or ():
        k = names.index(name)
        shape = _shape(mix, k)
        out[k] = Payload(mass) if shape is None else replace(shape, mass=mass)
    return out


def _shape(mix: Mix, k: int) -> Payload | None:
    """Task k's payload as the files give it: the mix file's, else the motion file's."""
    item = mix.tasks[k]
    return item.payload if item.payload is not None else item.motion.payload


def case_shares(case: Case, mix: Mix) -> list[float] | None:
    """The case's shares in task order, or None for the mix file's.

    Raises:
        InputError: Their count is not the mix's number of tasks.
    """
    if case.shares is None:
        return None
    check_task_keys(case.shares, None, [t.name for t in mix.tasks], mix.path.name)
    return list(case.shares)


def check_task_keys(shares: Sequence[float] | None,
                    payloads: Iterable[tuple[str, float]] | Mapping[str, float] | None,
                    names: Sequence[str], file: str) -> None:
    """Refuse a case's ``shares`` and ``payloads`` that do not fit a mix's tasks.

    Args:
        shares: One share per task, or None.
        payloads: Payload masses by task name [kg], or None.
        names: The mix's task names, in order.
        file: The mix file's name, for the message.

    Raises:
        InputError: Not one share per task (field ``shares``), or a payload names no task
            (field ``payloads``).
    """
    if shares is not None and len(shares) != len(names):
        raise InputError(f"{len(shares)} share{'s' if len(shares) != 1 else ''} for the "
                         f"{len(names)} tasks of {file} ({', '.join(names)})", field="shares")
    for name in (payloads.keys() if isinstance(payloads, Mapping) else
                 (name for name, _ in payloads or ())):
        if name not in names:
            raise InputError(f"no task {name!r} in {file}; its tasks are: {', '.join(names)}",
                             field="payloads")


MotorsOf = Callable[[Case, Robot, Mix], Motors]
"""The candidate motors of a case for its robot and mix (its motor file's, else the mix's)."""


def size_mix_direct(case: Case, units: Sequence[Unit], motors_of: MotorsOf,
                    robots: dict[Path, Robot]) -> Summary:
    """One mix case on its own: every task planned, run s times slower, sized as one duty.

    Args:
        case: The case.
        units: The case's candidate units.
        motors_of: The case's motors.
        robots: Robots already loaded, by file (added to).

    Raises:
        HdselectError: An input is bad or a motion cannot be planned.
    """
    robot, mix = case_mix(case, robots)
    options = mix_case_options(case, mix)
    tasks, idle = mix_tasks(robot, mix, mounting=case.mounting, joints=robot.sized_joints,
                            exclude=(), max_samples=options.max_samples,
                            shares=case_shares(case, mix), payloads=case_payloads(case, mix))
    tasks = tuple(replace(task, trajectory=scaled(task.trajectory, case.time_scale))
                  for task in tasks)
    result = size_tasks(tasks, units, options, motors=motors_of(case, robot, mix), idle=idle)
    return summarize(replace(result, mix=mix))


def mix_group(cases: Sequence[Case], units_of: Callable[[Case], Sequence[Unit]],
              motors_of: MotorsOf, robots: dict[Path, Robot], host: str
              ) -> Generator[Outcome, None, list[tuple[Case, str | None]]]:
    """The cases of one mix group (one mix, robot and mounting) from one basis per task.

    Yields the outcome of each case as it completes, its seconds including its share of
    the bases; returns the cases to size direct (a task plans with its payload's
    dynamics: TOPPRA under torque limits), each with why.
    """
    start = time.perf_counter()
    try:
        robot, mix = case_mix(cases[0], robots)
        if any(plan_depends_on_payload(task.motion) for task in mix.tasks):
            return [(case, "a task's TOPPRA plans under torque limits with its payload's "
                           "dynamics: sized on its own") for case in cases]
        motors = {case.index: motors_of(case, robot, mix) for case in cases}
        varied = {k for case in cases for k in case_payloads(case, mix)}
        bases = []
        for k, item in enumerate(mix.tasks):
            mounting = cases[0].mounting if cases[0].mounting is not None else item.mounting
            mounted = robot_for_motion(robot, replace(item.motion, payload=None),
                                       mounting=mounting, joints=robot.sized_joints, exclude=())
            shape = _shape(mix, k) or (Payload(1.0) if k in varied else None)
            bases.append(build_basis(mounted, item.motion, shape,
                                     inertias=any(motors.values())))
    except HdselectError as err:
        for case in cases:
            yield _outcome(case, err, time.perf_counter() - start, host)
        return []
    share = (time.perf_counter() - start) / len(cases)
    for case in cases:
        begun = time.perf_counter()
        try:
            summary: Summary | HdselectError = size_mix_case(bases, mix, case, units_of(case),
                                                             motors[case.index])
        except HdselectError as err:
            summary = err
        yield _outcome(case, summary, share + time.perf_counter() - begun, host)
    return []


def _outcome(case: Case, summary: Summary | HdselectError, seconds: float,
             host: str) -> Outcome:
    if isinstance(summary, HdselectError):
        return Outcome(case.index, case.key, False, str(summary), None, "grouped", None,
                       seconds, host)
    return Outcome(case.index, case.key, True, None, summary.to_dict(), "grouped", None,
                   seconds, host)


def size_mix_case(bases: Sequence[Basis], mix: Mix, case: Case, units: Sequence[Unit],
                  motors: Motors) -> Summary:
    """One mix case from its tasks' bases (one per task, in task order), sized by the core.

    Raises:
        InputError: The shares, payloads or motors are not valid for the mix.
    """
    units = tuple(units)
    options = mix_case_options(case, mix)
    motors = checked_motors(bases[0].robot, motors, options)
    if options.prefer is None:
        options = replace(options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors
                          else DEFAULT_PREFER)
    check_bearing_options(bases[0].robot, units, options)
    payloads = case_payloads(case, mix)
    shares = case_shares(case, mix)
    if shares is None:
        if not mix.shares_given:
            raise InputError("a mix in cycles per hour is grouped from its shares: give "
                             "`shares`, or run the study with --no-grouping", field="shares")
        shares = [float(task.share or 0.0) for task in mix.tasks]
    check_shares(shares, field="shares")
    models, tasks = [], []
    for k, (basis, item) in enumerate(zip(bases, mix.tasks, strict=True)):
        given = payloads.get(k, _shape(mix, k))
        if basis.payload is None and given is not None:
            raise InputError(f"task {item.name!r} has no payload to give a mass",
                             field="payloads")
        mass = None if basis.payload is None else (0.0 if given is None else given.mass)
        traj = basis.trajectory
        timing = replace(traj, dt=traj.dt * case.time_scale,
                         duration=traj.duration * case.time_scale)
        task = Task(basis.robot, timing, shares[k], item.motion, item.name)
        tasks.append(task)
        if task.share > 0.0:
            model = BasisTorques(basis, mass, case.time_scale, options.stop_time,
                                 wrenches=options.bearing_loads)
            model.samples = replace(model.samples, tasks=(task,))
            models.append(model)
    pooled = MixTorques(models)
    joints, masses = select_units(pooled, {name: units for name in bases[0].robot.sized_joints},
                                  options, motors, detail=False)
    first = pooled.samples.tasks[0]
    summary = summarize(SizingResult(first.robot, first.trajectory, tuple(joints), options,
                                     units, first.motion, motors=motors,
                                     loads=pooled.loads(masses), tasks=tuple(tasks), mix=mix))
    # the bases' robots carry the reference payload; each task carries its own mass
    carried = [payloads.get(k, _shape(mix, k)) for k in range(len(tasks))]
    masses_of = [0.0 if payload is None else float(payload.mass) for payload in carried]
    lead = next(k for k, task in enumerate(tasks) if task.share > 0.0)
    return replace(summary, payload_mass=masses_of[lead],
                   tasks=tuple({**entry, "payload_mass": mass}
                               for entry, mass in zip(summary.tasks, masses_of, strict=False)))


def mix_case_options(case: Case, mix: Mix) -> Options:
    """A mix case's options over the mix file's (and its motions'), one thread."""
    return mix_options(mix, **case.options, threads=1)


def mix_case_motors(case: Case, robot: Robot, mix: Mix,
                    motor_file: Sequence[Motor] | None) -> dict[str, tuple[Motor, ...]]:
    """A mix case's motors: its motor file's for every sized joint, else the mix's."""
    if motor_file is not None:
        return {name: tuple(motor_file) for name in robot.sized_joints}
    return mix_motors(robot, mix)
