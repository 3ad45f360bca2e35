"""A robot and its motion (or mix) together: the files' payload, mounting and joints applied."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.motion.events import whole_cycle
from hdselect.motion.mixfile import Mix, is_mix_file, load_mix
from hdselect.motion.motionfile import Motion, load_motion
from hdselect.motion.planning.solve import solve_motion
from hdselect.motion.robot_named import load_motion_robot
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload


def robot_for_motion(
    robot: Robot,
    motion: Motion,
    *,
    payload: Payload | None = None,
    mounting: Mounting | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
) -> Robot:
    """The robot as the motion runs it: payload, parts, mounting and sized joints applied.

    Each of payload and mounting comes from the argument if given, else from the
    motion file if it gives one, else it is the robot's own. The file's parts no payload
    event names (`hdselect.motion.events.whole_cycle`) replace the robot's. Nothing is dropped in
    silence: a robot that already carries a payload and a motion file that gives
    another, with no argument to choose, is an error.

    Args:
        robot: The robot, as loaded (or already transformed).
        motion: The motion read for it.
        payload: Payload overriding the motion file's.
        mounting: Mounting overriding the motion file's.
        joints: Joints to size, overriding the file's ``[sizing] joints`` (default: the
            file's, else the robot's choice).
        exclude: Joints not to size, overriding the file's ``[sizing] exclude``.

    Returns:
        The robot to plan and size with.

    Raises:
        InputError: The joints differ from the motion's, the payload is ambiguous, or
            its frame does not exist (the message names the file that set it).
    """
    bounds.expect_type(robot, Robot, "robot", "a Robot")
    bounds.expect_type(motion, Motion, "motion", "a Motion")
    bounds.expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    motion.check_joints(robot)
    if payload is None and motion.payload is not None:
        if robot.payload is not None and robot.payload != motion.payload:
            raise InputError("the robot already carries a payload and this file gives another;"
                             " pass the payload to use explicitly", path=motion.path,
                             field="payload")
        try:
            robot = robot.with_payload(motion.payload)
        except InputError as err:
            raise InputError(err.reason, path=motion.path, field=err.field) from err
    elif payload is not None:
        robot = robot.with_payload(payload)
    parts = whole_cycle(motion.parts, motion.events)
    if parts or robot.parts:
        try:
            robot = robot.with_parts(parts)
        except InputError as err:
            raise InputError(err.reason, path=motion.path, field=err.field) from err
    mounting = mounting if mounting is not None else motion.mounting
    if mounting is not None:
        robot = robot.with_mounting(mounting)
    chosen = joints if joints is not None else motion.sized_joints
    left_out = exclude if exclude is not None else motion.excluded_joints
    if chosen is not None or left_out:
        try:
            robot = robot.with_sized_joints(chosen, left_out)
        except InputError as err:
            given = joints if err.field == "joints" else exclude
            if given is not None or err.field not in ("joints", "exclude"):
                raise
            raise InputError(err.reason, path=motion.path, field=f"sizing.{err.field}") from err
    return robot


def load_case(
    motion: Motion | Mix | str | Path,
    robot: Robot | str | Path | None = None,
    *,
    payload: Payload | None = None,
    mounting: Mounting | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
) -> tuple[Robot, Motion | Mix]:
    """A motion (or mix) and the robot that runs it, payload, mounting and sized joints applied.

    Files or loaded objects alike. A mix (``[[task]]`` tables, `hdselect.motion.mixfile`)
    gives the robot with the duty's sized joints and the `Mix` (`mounting` on every
    task): each task's payload and mounting apply when its motion is planned
    (`hdselect.sizing.mixtasks.mix_tasks`).

    Args:
        motion: The motion file or a loaded `Motion`; or a mix file or a loaded `Mix`.
        robot: The robot or its file; None loads the file the motion (or mix) names (a
            ``.xacro`` with the motion file's ``xacro_args``).
        payload: Payload overriding the motion file's (refused for a mix: its tasks give
            theirs).
        mounting: Mounting overriding the motion file's (a mix's: every task's).
        joints: Joints to size, overriding the file's ``[sizing] joints``.
        exclude: Joints not to size, overriding the file's ``[sizing] exclude``.

    Returns:
        The robot as the motion runs it (see `robot_for_motion`) and the motion, its
        tool poses solved for that robot's mounting (`hdselect.motion.planning.solve.solve_motion`);
        or the robot with the duty's sized joints and the mix.

    Raises:
        InputError: A file or argument is invalid (a payload given for a mix), or a tool
            pose cannot be solved.
    """
    bounds.expect_type(robot, (Robot, str, Path, type(None)), "robot",
                       "a Robot, a robot file or None")
    bounds.expect_type(motion, (Motion, Mix, str, Path), "motion",
                       "a Motion, a Mix, a motion file or a mix file")
    bounds.expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    if isinstance(motion, str | Path):
        path = bounds.file_argument(motion, "motion")
        if is_mix_file(path):
            _refuse_payload(payload)
            motion = load_mix(path, robot)
            robot = robot if isinstance(robot, Robot) else load_robot(motion.robot_file)
        else:
            robot = (load_motion_robot(path) if robot is None
                     else robot if isinstance(robot, Robot) else load_robot(robot))
            motion = load_motion(path, robot)
    if isinstance(motion, Mix):
        _refuse_payload(payload)
        robot = robot if isinstance(robot, Robot) else load_robot(
            robot if robot is not None else motion.robot_file)
        if mounting is not None:
            robot.with_mounting(mounting)  # a bad mounting refused once, not task by task
            motion = motion.with_mounting(mounting)
        return robot_for_mix(robot, motion, joints=joints, exclude=exclude), motion
    if not isinstance(robot, Robot):
        file = robot if robot is not None else motion.robot_file
        if file is None:
            raise InputError("no robot given, and the motion file names none",
                             path=motion.path, field="robot")
        robot = load_robot(file, xacro_args=motion.xacro_args if robot is None else None)
    robot = robot_for_motion(robot, motion, payload=payload, mounting=mounting,
                             joints=joints, exclude=exclude)
    return robot, solved_on(robot, motion, mounting)


def solved_on(robot: Robot, motion: Motion, mounting: Mounting | None) -> Motion:
    """The motion's tool poses solved for the robot, a mounting given blamed as given.

    Args:
        robot: The robot as the motion runs it (its mounting applied).
        motion: The motion.
        mounting: The mounting given over the file's (a parameter or a flag), else None.

    Raises:
        InputError: As `hdselect.motion.planning.solve.solve_motion`; a base the given
            mounting cannot place (a gravity vector) names the parameter ``mounting``, not
            the motion file's key.
    """
    try:
        return solve_motion(robot, motion)
    except InputError as err:
        if mounting is None or err.field != "mounting":
            raise
        raise InputError(f"{motion.path.name}: {err.reason}", field="mounting") from err


def _refuse_payload(payload: Payload | None) -> None:
    """Refuse a payload given for a whole mix: its tasks carry their own."""
    if payload is not None:
        raise InputError("a mix's tasks carry their own payloads: give each task's "
                         "`payload` in the mix file", field="payload")


def robot_for_mix(robot: Robot, mix: Mix, *, joints: Sequence[str] | None = None,
                  exclude: Sequence[str] | None = None) -> Robot:
    """The robot with a mix's sized joints: given, else the files' (no payload, no mounting).

    Each task's payload and mounting apply when its motion is planned (its tool poses
    solved for its own mounting).

    Raises:
        InputError: The joints differ from the mix's, the files disagree on the sized
            joints, or they are invalid.
    """
    bounds.expect_type(robot, Robot, "robot", "a Robot")
    bounds.expect_type(mix, Mix, "motion", "a Mix")
    mix.check_joints(robot)
    chosen = joints if joints is not None else mix.duty_value("joints")
    left_out = exclude if exclude is not None else mix.duty_value("exclude")
    if chosen is None and not left_out:
        return robot
    try:
        return robot.with_sized_joints(None if chosen is None else list(chosen),
                                       tuple(left_out or ()))
    except InputError as err:
        if (joints if err.field == "joints" else exclude) is not None:
            raise
        raise InputError(err.reason, path=mix.path, field=f"sizing.{err.field}") from err
