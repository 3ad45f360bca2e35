"""A payload: a rigid body carried at a robot frame, validated once."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError


@dataclass(frozen=True)
class Payload:
    """A rigid payload attached to a frame of the robot.

    Attributes:
        mass: Mass [kg], positive.
        com: Centre of mass in the frame it is attached to [m], shape (3,).
        inertia: Rotational inertia about the centre of mass, frame axes [kg m^2], (3, 3),
            symmetric positive semi-definite.
        frame: Name of the frame it is attached to; None means the tip of the longest chain
            of sized joints (`Robot.default_payload_frame`), or for a part the payload's frame.
        name: A part's name (``[payloads.NAME]``; ``"payload"`` for ``[payload]`` moved by
            payload events, `hdselect.motion.events`); empty for the payload itself.

    Raises:
        InputError: A value is not finite or not physical (the field names it).
    """

    mass: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[tuple[float, ...], ...] = ((0.0,) * 3,) * 3
    frame: str | None = None
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise InputError(f"expected a part's name, got {self.name!r}", field="payload.name")
        table = self.table
        mass = float(_finite_array(self.mass, (), f"{table}.mass", bounds.MASS))
        com = _finite_array(self.com, (3,), f"{table}.com", bounds.LENGTH)
        inertia = _finite_array(self.inertia, (3, 3), f"{table}.inertia", bounds.INERTIA)
        if not np.allclose(inertia, inertia.T) or np.linalg.eigvalsh(inertia)[0] < -1e-12:
            raise InputError("must be symmetric positive semi-definite [kg m^2]",
                             field=f"{table}.inertia")
        if self.frame is not None and (not isinstance(self.frame, str) or not self.frame):
            raise InputError(f"expected a frame name, got {self.frame!r}", field=f"{table}.frame")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "com", tuple(float(c) for c in com))
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in row)
                                                  for row in inertia))

    @property
    def table(self) -> str:
        """The file's table that gives it: ``payload``, or ``payloads.NAME`` for a part."""
        return f"payloads.{self.name}" if self.name not in ("", "payload") else "payload"


def _finite_array(value: object, shape: tuple[int, ...], field: str,
                  bound: bounds.Bound) -> np.ndarray:
    """`value` as a float array of `shape`, every element finite and within `bound`.

    Raises:
        InputError: It is not.
    """
    if isinstance(value, bool | str | bytes) or (
            isinstance(value, Sequence) and any(isinstance(v, bool | str | bytes) for v in value)):
        raise InputError(f"expected numbers, got {value!r}", field=field)
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as err:
        raise InputError(f"expected numbers, got {value!r}", field=field) from err
    if array.shape != shape:
        raise InputError(f"expected shape {shape or 'a single number'}, got {value!r}",
                         field=field)
    for index in np.ndindex(shape):
        where = field + "".join(f"[{i}]" for i in index)
        bound.check(float(array[index]), field=where)
    return array


def frame_id(model: pin.Model, name: str) -> int:
    """The id of the frame `name` (it exists): the link, where a fixed joint shares its name.

    URDF names joints and links apart; Pinocchio makes a frame of each, so a fixed joint
    named like a link is a second frame of that name (placed at its child link).
    """
    if model.existFrame(name, pin.FrameType.BODY):
        return model.getFrameId(name, pin.FrameType.BODY)
    return model.getFrameId(name)


def payload_frame(model: pin.Model, payload: Payload, path: Path, default: str) -> pin.Frame:
    """The frame a payload is attached to: its own, or `default`."""
    frame_name = payload.frame or default
    what = f"part '{payload.name}'" if payload.table != "payload" else "payload"
    try:
        known = model.existFrame(frame_name)
    except UnicodeEncodeError:  # bytes of no text in a command-line name: no frame's
        known = False
    if not known:
        bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        raise InputError(f"unknown frame '{frame_name}' for the {what}; links are: "
                         f"{', '.join(bodies)}", path=path, field=f"{payload.table}.frame")
    frame = model.frames[frame_id(model, frame_name)]
    if frame.parentJoint == 0:
        raise InputError(f"frame '{frame_name}' does not move; a {what} there loads no joint",
                         path=path, field=f"{payload.table}.frame")
    return frame


_TOOL_FRAMES = ("tcp", "tool0", "tool", "end_effector", "endeffector", "eef", "ee_link", "ee",
                "flange")
"""Name parts of the frames users attach tools to, in order of preference."""


def tip_frame(model: pin.Model, sized: Sequence[str]) -> str:
    """The tip of the longest chain of `sized` joints (see `default_payload_frame`).

    Of the links its last joint moves rigidly, a tool frame (named like one of
    `_TOOL_FRAMES`) wins, else the joint's own link. With no sized joint, the
    deepest joint of the model ends the chain.
    """
    chosen = set(sized)
    best, best_length = model.njoints - 1, -1
    for joint_id in range(1, model.njoints):
        if model.names[joint_id] in chosen:
            length = sum(model.names[k] in chosen for k in model.supports[joint_id])
            if length > best_length:
                best, best_length = joint_id, length
    if best_length < 0:
        best = max(range(1, model.njoints), key=lambda j: (len(model.supports[j]), j))
    links = [f.name for f in model.frames
             if f.type == pin.FrameType.BODY and f.parentJoint == best]
    for part in _TOOL_FRAMES:
        for link in links:
            if re.search(rf"(^|[^a-z]){part}([^a-z]|$)", link.lower()):
                return link
    return links[0]
