"""The payload that scales where a task's payload events move parts, and figures by carried state.

max-payload and a study's ``payload`` scale one payload per task (`scaled_part`): the one
part the task's events move (`hdselect.motion.events`), else its ``[payload]``. The torque
stays affine in that part's mass at every sample: its term is zero at the samples that do
not carry it (each carried state evaluated with its own robot:
`hdselect.sizing.tasks.over_states`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from hdselect.base.errors import InputError
from hdselect.motion.motionfile import Motion
from hdselect.robot.payload import Payload
from hdselect.sizing.tasks import Task


def scaled_part(task: Task) -> Payload | None:
    """The payload that max-payload (and a study's ``payload``) scales in a task.

    The one part the task's events move (`hdselect.motion.events`), else its
    ``[payload]``; None where it carries neither.

    Raises:
        InputError: Its events move several parts (the message names them).
    """
    carried = task.carried
    if carried is None or not carried.parts:
        return task.robot.payload
    return _one_part(carried.parts, task.motion)


def moved_part(motion: Motion) -> Payload | None:
    """The one part a motion's payload events move, as its file gives it; None: no events.

    Raises:
        InputError: They move several parts (the message names them).
    """
    names = sorted({event.part for event in motion.events})
    return _one_part([motion.parts[name] for name in names], motion) if names else None


def _one_part(parts: Sequence[Payload], motion: Motion | None) -> Payload:
    """The only part of `parts`: what scales is one part.

    Raises:
        InputError: There are several (the message names them).
    """
    if len(parts) > 1:
        names = ", ".join(part.name for part in parts)
        raise InputError(f"the events move {len(parts)} parts ({names}); max-payload and a "
                         "study's payload scale one part: give the others no events, or size "
                         "them as they are", path=None if motion is None else motion.path,
                         field="payloads")
    return parts[0]


def with_part(task: Task, payload: Payload | None) -> Task:
    """The task with its scaled part (`scaled_part`) replaced by `payload`; None takes it off.

    A part its events move stays carried between them (its events kept); a part given
    without a name takes the name of the one it replaces.

    Raises:
        InputError: Its events move several parts (`scaled_part`'s refusal).
    """
    carried = task.carried
    if carried is None or not carried.parts:
        return replace(task, robot=task.robot.with_payload(payload))
    part = _one_part(carried.parts, task.motion)
    if payload is None:
        return replace(task, carried=replace(carried, parts=(), mask=carried.mask[:, :0]))
    return replace(task, carried=carried.with_part(
        payload if payload.name else replace(payload, name=part.name)))
