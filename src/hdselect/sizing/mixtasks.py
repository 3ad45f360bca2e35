"""A mix file as the tasks the core sizes: each motion planned with its own payload and mounting.

A task's motion of tool poses is solved for that task's mounting (the mix file's, else
its motion file's), as `hdselect.size` solves a single motion: a wall mounting re-solves
the poses, it does not turn the joint angles.

The duty-wide values (sized joints, options, motors) are the command line's or the
caller's, else the mix file's, else those the motion files agree on
(`hdselect.motion.mixfile.Mix.duty_value`). Shares given in cycles per hour follow
from each planned cycle: task k takes cycles_per_hour_k x n_k dt_k seconds of every
hour (n_k dt_k: the time its samples stand for, the cycle time and one sample period),
and the rest of the hour is idle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from hdselect.base.bounds import SHARE_TOLERANCE
from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.motion.loading import robot_for_motion
from hdselect.motion.mixfile import SECONDS_PER_HOUR, Mix
from hdselect.motion.option_specs import OPTIONS
from hdselect.motion.planning import plan_motion
from hdselect.robot.model import Robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.tasks import Task, cycle_of, task_of


def mix_options(mix: Mix, **given: Any) -> Options:
    """Options from keyword values, else the mix file's, else what its motions agree on.

    Args:
        mix: The mix.
        **given: Fields of `Options`; None means "not given".

    Returns:
        The validated options.

    Raises:
        InputError: A value is out of range, or two files disagree on a duty-wide value.
    """
    values = {name: value for name, value in given.items() if value is not None}
    for option in OPTIONS:  # what a mix file gives (`hdselect.motion.option_specs.Option.files`)
        if "mix" in option.files and option.name not in values:
            value = mix.duty_value(option.name)
            if value is not None:
                values[option.name] = value
    return options_for(None, **values)


def mix_motors(robot: Robot, mix: Mix) -> dict[str, tuple[Motor, ...]]:
    """The duty's candidate motors for the robot's sized joints (empty if none).

    Raises:
        InputError: The files disagree, or a motor is given for a joint not sized.
    """
    motors: Mapping[str, tuple[Motor, ...]] | None = mix.duty_value("motors")
    own = (mix.given.get("motor_joints", ()) if "motors" in mix.given
           else tuple(name for motion in mix.motions for name in motion.motor_joints))
    return sized_motors(robot, motors, own, mix.path)


def sized_motors(robot: Robot, motors: Mapping[str, tuple[Motor, ...]] | None,
                 named: Sequence[str], path: Path) -> dict[str, tuple[Motor, ...]]:
    """A file's candidate motors for the robot's sized joints (empty if none).

    Args:
        robot: The robot as sized.
        motors: The motors by joint name, or None.
        named: The joints the file's ``[motor.JOINT]`` blocks name.
        path: The file, for messages.

    Raises:
        InputError: A block names a joint that is not sized.
    """
    if not motors:
        return {}
    for name in named:
        if name not in robot.sized_joints:
            raise InputError(f"joint '{name}' is not sized (excluded, or a mimic follower), so "
                             "its motor cannot apply; remove the block or size the joint",
                             path=path, field=f"motor.{name}")
    return {name: motors[name] for name in robot.sized_joints if name in motors}


def mix_tasks(robot: Robot, mix: Mix, *, mounting: Mounting | None = None,
              joints: Sequence[str] | None = None, exclude: Sequence[str] | None = None,
              max_samples: int | None = None, shares: Sequence[float] | None = None,
              payloads: Mapping[int, Payload | None] | None = None
              ) -> tuple[tuple[Task, ...], float]:
    """Plan every task of a mix with its own payload and mounting, and give it its share.

    Each task's tool poses, if any, are solved for its own mounting before it is planned;
    the task keeps the solved motion (its lines and how its poses were solved).

    Args:
        robot: The robot (no payload; any mounting is replaced by each task's).
        mix: The mix.
        mounting: Mounting for every task, overriding the files' (a tool pose it cannot
            place is blamed on the field ``mounting``, the caller's).
        joints: Joints to size, overriding the files'.
        exclude: Joints not to size, overriding the files'.
        max_samples: Most samples a trajectory may have (default: `Options`'s).
        shares: Each task's share [-], replacing the file's (a study's parameter).
        payloads: Payload by task index, replacing the file's (a study's parameter).

    Returns:
        The tasks, in the file's order, and the idle fraction of the time [-].

    Raises:
        InputError: A file is inconsistent, a task's tool pose cannot be solved for its
            mounting, or the cycles per hour overfill the hour.
        PlanningError: A motion cannot be planned.
    """
    chosen, left_out = _sized(mix, joints, exclude)
    limit = max_samples if max_samples is not None else Options().max_samples
    planned = []
    for k, item in enumerate(mix.tasks):
        payload = (payloads or {}).get(k, item.payload)
        carrying = robot_for_motion(robot.with_payload(None), item.motion, payload=payload,
                                    mounting=mounting if mounting is not None else item.mounting,
                                    joints=chosen, exclude=left_out)
        try:
            done = plan_motion(carrying, item.motion, max_samples=limit)
        except InputError as err:  # blamed on who gave the mounting: caller, else mix file
            if err.field != "mounting" or (mounting is None and item.mounting is None):
                raise
            where = ({"field": "mounting"} if mounting is not None
                     else {"path": mix.path, "field": f"task[{k}].mounting"})
            raise InputError(f"{item.motion.path.name}: {err.reason}", **where) from err
        planned.append((item, carrying, done.trajectory, done.motion))
    if shares is None:
        shares = [item.share if item.share is not None
                  else (item.cycles_per_hour or 0.0) * cycle_of(traj) / SECONDS_PER_HOUR
                  for item, _, traj, _ in planned]
    idle = 0.0
    if not mix.shares_given:
        busy = math.fsum(shares)
        if busy > 1.0 + SHARE_TOLERANCE:
            each = ", ".join(f"{item.name} {share * SECONDS_PER_HOUR:.1f} s"
                             for share, (item, _, _, _) in zip(shares, planned, strict=True))
            raise InputError(f"the cycles take {busy * SECONDS_PER_HOUR:.1f} s of every hour "
                             f"({each}); run fewer cycles per hour", path=mix.path,
                             field="task.cycles_per_hour")
        if busy <= 0.0:
            raise InputError("every task runs 0 cycles per hour: some task must run",
                             path=mix.path, field="task.cycles_per_hour")
        idle = max(0.0, 1.0 - busy)
    tasks = tuple(task_of(carrying, traj, solved, float(share), item.name)
                  for (item, carrying, traj, solved), share in zip(planned, shares, strict=True))
    return tasks, idle


def _sized(mix: Mix, joints: Sequence[str] | None, exclude: Sequence[str] | None
           ) -> tuple[list[str] | None, tuple[str, ...]]:
    """The duty's sized joints and excluded joints: given, else the files'."""
    chosen = joints if joints is not None else mix.duty_value("joints")
    left_out = exclude if exclude is not None else mix.duty_value("exclude")
    return (None if chosen is None else list(chosen)), tuple(left_out or ())
