"""The duty an envelope judges its averaged rules on: a motion or mix file, or random moves.

Mean torque, mean speed and life are averages over what the robot does, so no
worst state decides them. A given motion file stands for what it does, a mix file
for its tasks pooled by share (each with its own payload and mounting, as `hdselect
size` of the mix pools them: a motion is a mix of one task); without one,
the default duty is `DUTY_MOVES` moves between poses drawn uniformly (seeded) in the
joint box, each joint moving at its own limits (Ruckig, jerk-limited, every joint as
fast as its limits allow, not slowed to arrive with the others). Either must stay
within the spec, so that its samples are states of the box too.

A motion or mix file is read here (`duty_source`) and resolved and planned by the one
resolver (`hdselect.sizing.problem.problem_of`, `plan_tasks`) into the `Duty`
(`problem_duty`); the robot the envelope searches beside a mix is `mix_robot`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import ruckig

from hdselect.base.errors import InputError, PlanningError
from hdselect.envelope.spec import Spec
from hdselect.envelope.specfile import EnvelopeFile
from hdselect.motion.loading import robot_for_mix
from hdselect.motion.mixfile import Mix, MixTask, is_mix_file, load_mix
from hdselect.motion.motionfile import Motion, load_motion
from hdselect.motion.planning import Trajectory, check_within_limits
from hdselect.motion.planning.grid import MIN_MOVE_SAMPLES
from hdselect.motion.planning.ruckig import sample_profiles
from hdselect.motion.planning.trajectory import Move, assemble
from hdselect.motion.robot_named import other_robot
from hdselect.robot.model import Robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.mixtasks import mix_motors
from hdselect.sizing.problem import Problem
from hdselect.sizing.tasks import Task

DUTY_DT = 0.001
"""Finest sample period of the default duty [s]."""
DUTY_SAMPLES = 30_000
"""Samples of a default duty long enough to need a coarser period than `DUTY_DT`: its
averages stay exact to well under 0.1 %, and the per-sample motor torques of a cycle this
short are kept (`hdselect.sizing.reflect.CHUNK`)."""
WITHIN = 1e-3
"""How far beyond the spec's velocity and acceleration limits a given duty's samples may
go, as a fraction of the limit [-] (TOPPRA keeps its limits to about 1e-4)."""


@dataclass(frozen=True, eq=False)
class Duty:
    """What the averaged rules are judged on.

    Attributes:
        tasks: The robot's tasks (one, for a motion file or the default duty; a mix
            file's, each with its share).
        label: What every output calls it, e.g. ``default duty: 20 random moves at the
            limits (seed 0), 27.1 s``.
        motion: The motion file's motion, or None for the default duty and a mix.
        moves: The default duty's moves, else None.
        seed: The default duty's seed, else None.
        mix: The mix file's mix, else None.
        idle: The fraction of the time no task runs [-] (a mix in cycles per hour).
    """

    tasks: tuple[Task, ...]
    label: str
    motion: Motion | None = None
    moves: int | None = None
    seed: int | None = None
    mix: Mix | None = None
    idle: float = 0.0

    @property
    def default(self) -> bool:
        """It is the default duty of random moves."""
        return self.motion is None and self.mix is None

    @property
    def path(self) -> Path | None:
        """The duty's file (motion or mix), or None for the default duty."""
        given = self.motion if self.motion is not None else self.mix
        return None if given is None else given.path

    @property
    def phrase(self) -> str:
        """The duty in a sentence: ``the default duty: ...`` or ``the duty FILE``."""
        return f"the {self.label}" if self.default else f"the duty {self.label}"


def default_duty(robot: Robot, spec: Spec, moves: int, seed: int, *,
                 max_samples: int) -> Duty:
    """Random point-to-point moves at the limits between poses drawn uniformly in the box.

    Args:
        robot: The robot as the envelope sizes it.
        spec: The limits (the box's ranges and limits, the jerk).
        moves: How many moves.
        seed: Seed of the poses.
        max_samples: Most samples the duty may have.

    Returns:
        The duty, one task.

    Raises:
        PlanningError: Ruckig rejects a move.
        InputError: The duty would exceed `max_samples`.
    """
    box = spec.box
    rng = np.random.default_rng(seed)
    poses = box.lower + rng.random((moves + 1, box.dof)) * (box.upper - box.lower)
    planned = []
    for i in range(moves):
        inp = ruckig.InputParameter(box.dof)
        inp.current_position, inp.target_position = poses[i].tolist(), poses[i + 1].tolist()
        inp.max_velocity = box.velocity.tolist()
        inp.max_acceleration = box.acceleration.tolist()
        inp.max_jerk = spec.jerk.tolist()
        inp.synchronization = ruckig.Synchronization.No  # every joint at its own limits
        traj = ruckig.Trajectory(box.dof)
        try:
            result = ruckig.Ruckig(box.dof).calculate(inp, traj)
        except (ruckig.RuckigError, RuntimeError) as err:
            raise PlanningError(f"the default duty's move {i} cannot be planned: {err}") from err
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise PlanningError(f"the default duty's move {i} cannot be planned ({result.name})")
        planned.append(Move(i, i + 1, traj.duration, partial(sample_profiles, traj)))
    durations = [move.duration for move in planned]
    dt = min(max(DUTY_DT, sum(durations) / DUTY_SAMPLES), min(durations) / MIN_MOVE_SAMPLES)
    motion = Motion(path=Path("default duty"), joint_names=robot.joint_names, planner="ruckig",
                    dt=dt, waypoints=poses, dwells=np.zeros(moves + 1),
                    velocity_limit=box.velocity, acceleration_limit=box.acceleration,
                    jerk_limit=spec.jerk, angle_unit="rad")
    trajectory = assemble(motion, planned, max_samples=max_samples)
    check_within_limits(robot, motion, trajectory, what="default duty")
    label = (f"default duty: {moves} random moves at the limits (seed {seed}), "
             f"{trajectory.duration:.1f} s sampled every {dt * 1e3:.3g} ms")
    return Duty((Task(robot, trajectory, name="default duty"),), label, None, moves, seed)


def problem_duty(problem: Problem) -> Duty:
    """The duty of a motion or mix file: its resolved problem's planned tasks.

    Args:
        problem: The duty's problem (`hdselect.sizing.problem.plan_tasks`): a motion's
            one task, or a mix's tasks with their shares and idle time.

    Raises:
        InputError: The problem is not planned, or has no motion or mix.
    """
    given = problem.mix if problem.mix is not None else problem.motion
    if given is None or not problem.planned:
        raise InputError("a duty is a motion or mix file's planned problem", field="duty")
    return Duty(problem.tasks, given.path.name, problem.motion, mix=problem.mix,
                idle=problem.idle)


def mix_robot(base: Robot, mix: Mix, *, payload: Payload | None, mounting: Mounting | None,
              joints: Sequence[str] | None, exclude: Sequence[str] | None) -> Robot:
    """The robot the envelope searches beside a mix duty: one payload and one mounting.

    The mix's sized joints (given, else the files'); the payload and mounting given,
    else the one every counted task (share or cycles per hour above 0) runs with.

    Raises:
        InputError: The counted tasks differ in payload (field ``payload``) or mounting
            (field ``mounting``) and none is given, the mix gives motors (the envelope
            does not choose them), or the joints are invalid.
    """
    robot = robot_for_mix(base, mix, joints=joints, exclude=exclude)
    if mix_motors(robot, mix):
        raise InputError("envelope does not choose motors yet; the motors given here would be "
                         "left out: remove [motor] (size and compare choose motor and gearhead "
                         "together)", path=mix.path, field="motor")
    counted = _counted(mix)
    if payload is None:
        payload = _one(mix, "payload", task_payloads(mix), repr)
    if mounting is None:
        def where(given: Mounting | None) -> str:
            mounted = robot if given is None else robot.with_mounting(given)
            return repr((mounted.gravity.tolist(), mounted.base_pose))

        mounting = _one(mix, "mounting", [item.mounting if item.mounting is not None
                                          else item.motion.mounting for item in counted], where)
    robot = robot.with_payload(payload) if payload is not None else robot
    return robot.with_mounting(mounting) if mounting is not None else robot


def task_payloads(mix: Mix) -> list[Payload | None]:
    """The payload each counted task of a mix carries: the mix file's, else its motion's."""
    return [item.payload if item.payload is not None else item.motion.payload
            for item in _counted(mix)]


def _counted(mix: Mix) -> list[MixTask]:
    """The tasks of a mix that count: share, else cycles per hour, above 0."""
    return [item for item in mix.tasks
            if (item.share if item.share is not None else item.cycles_per_hour or 0.0) > 0.0]


def _one(mix: Mix, field: str, values: list[Any], key: Callable[[Any], str]) -> Any:
    """The value every counted task shares (by `key`), else an error asking for one."""
    if len({key(value) for value in values}) > 1:
        raise InputError(f"the tasks of {mix.path.name} run with different {field}s; the "
                         f"envelope's worst states need one: give --{field} (or {field} in "
                         "the envelope file)", field=field)
    return values[0] if values else None


def duty_source(duty: Motion | Mix | str | Path | None, file: EnvelopeFile | None,
                robot: Robot) -> Motion | Mix | None:
    """The duty's motion or mix: the argument's, else the envelope file's; None for the default.

    Raises:
        InputError: The file is invalid or written for another robot, or a motion's
            joints differ from the robot's or it gives motors (a mix's: `mix_robot`).
    """
    given = duty if duty is not None else (file.duty if file is not None else None)
    if isinstance(given, str | Path):
        path = given
        if is_mix_file(path):
            return load_mix(path, robot)
        try:
            given = load_motion(path, robot)
        except InputError as err:
            named = other_robot(Path(path), robot)
            if named is None:
                raise
            where = ({"field": "duty"} if duty is not None or file is None
                     else {"path": file.path, "field": "duty.motion"})
            raise InputError(f"{Path(path).name} is written for {named}, but the envelope "
                             f"runs {robot.path}: the motion does not fit it ({err}); give a "
                             "duty motion of this robot", **where) from err
    if isinstance(given, Motion):
        given.check_joints(robot)
        given.refuse_motors("envelope")
    return given


def refuse_default_duty(duty: Motion | Mix | str | Path | None, file: EnvelopeFile | None,
                         **given: object) -> None:
    """Refuse what only the default duty of random moves takes, beside a motion duty.

    Raises:
        InputError: `moves`, `seed` or `jerk` is given (the field names it) while the
            duty is a motion file (`duty`, or the envelope file's ``[duty] motion``).
    """
    for name, value in given.items():
        if value is not None:
            source = ("a motion file (duty, --duty)" if duty is not None or file is None
                      else f"{file.path.name}'s [duty] motion")
            raise InputError(f"acts on the default duty of random moves only, and the duty is "
                             f"{source}: drop one of them", field=name)


@contextmanager
def mounting_named(file: EnvelopeFile | None) -> Iterator[None]:
    """Blame the envelope file's ``mounting`` (where it gave it) for a base it cannot place.

    Raises:
        InputError: The error inside, a mounting given (field ``mounting``, no file)
            renamed to the envelope file's key when `file` gave the mounting.
    """
    try:
        yield
    except InputError as err:
        if file is None or err.field != "mounting" or err.path is not None:
            raise
        raise InputError(err.reason, path=file.path, field="mounting") from err


def check_within(duty: Duty, spec: Spec) -> None:
    """Refuse a duty that goes faster or accelerates harder than the spec allows.

    Raises:
        InputError: A joint of a task exceeds a limit by more than `WITHIN` (the message
            names the duty file, the joint, the value, the limit and when).
    """
    box = spec.box
    for task in duty.tasks:
        traj: Trajectory = task.trajectory
        for kind, values, limit in (("velocity", traj.qd, box.velocity),
                                    ("acceleration", traj.qdd, box.acceleration)):
            over = np.abs(values) / limit
            k, j = np.unravel_index(int(np.argmax(over)), over.shape)
            if over[k, j] > 1.0 + WITHIN:
                per = "/s" if kind == "velocity" else "/s^2"
                rotary = task.robot.revolute[j]
                scale, unit = (180.0 / np.pi, "deg" + per) if rotary else (1.0, "m" + per)
                raise InputError(
                    f"joint '{box.joint_names[j]}' reaches {abs(values[k, j]) * scale:.4g} "
                    f"{unit} at t = {traj.t[k]:.4g} s, above the spec's {kind} limit "
                    f"{limit[j] * scale:.4g} {unit}: a duty must run within the spec (raise "
                    "the limit, or slow the duty)",
                    path=task.motion.path if task.motion is not None else None,
                    field=f"limits.{kind}")

