"""The spec of an envelope: each joint's limits, from the caller, a file or the robot file.

Per joint and limit, the first that gives one wins: the caller (options or Python
arguments), the envelope file's ``[limits]``, then, for the velocity only, the robot
file's velocity limit. An acceleration must be given; the jerk (used only to plan
the default duty's moves) defaults to the acceleration reached in `JERK_TIME`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.envelope.box import LimitBox, Limits, limit_box, per_joint_limits
from hdselect.envelope.specfile import EnvelopeFile
from hdselect.robot.model import Robot

JERK_TIME = 0.05
"""Time the default duty's moves take to reach full acceleration where no jerk limit is
given [s]: jerk = acceleration / JERK_TIME."""
SOURCES = ("given", "file", "robot file", "default")
"""Where a joint's limit came from, in the order they are looked at."""


@dataclass(frozen=True, eq=False)
class Spec:
    """The limits an envelope is computed for.

    Attributes:
        box: The limit box: joint ranges, velocity and acceleration limits.
        jerk: Jerk limit of the default duty's moves [rad/s^3 or m/s^3], shape (dof,).
        sources: Per limit (``velocity``, ``acceleration``, ``jerk``), where each joint's
            came from, one of `SOURCES`.
        file: The envelope file read, if any.
    """

    box: LimitBox
    jerk: np.ndarray
    sources: dict[str, tuple[str, ...]]
    file: EnvelopeFile | None = None


def resolve_spec(robot: Robot, *, velocity: Limits = None, acceleration: Limits = None,
                 jerk: Limits = None, file: EnvelopeFile | None = None) -> Spec:
    """Every joint's limits, from the arguments, else the file, else the robot file.

    Args:
        robot: The robot (its joints, ranges and velocity limits).
        velocity: Speed limits [rad/s or m/s]: one number, one per joint, or a mapping of
            some joints' names to their limit.
        acceleration: Acceleration limits [rad/s^2 or m/s^2], as `velocity`.
        jerk: Jerk limits of the default duty [rad/s^3 or m/s^3], as `velocity`.
        file: An envelope file read for this robot.

    Returns:
        The spec.

    Raises:
        InputError: A limit is malformed or out of range, or a joint has no velocity or
            no acceleration limit from anywhere (the message names them).
    """
    given = {"velocity": velocity, "acceleration": acceleration, "jerk": jerk}
    values: dict[str, np.ndarray] = {}
    sources: dict[str, tuple[str, ...]] = {}
    for kind, value in given.items():
        first = per_joint_limits(value, robot, kind, partial=True)
        layers = [("given", first),
                  ("file", file.limits.get(kind) if file is not None else None)]
        if kind == "velocity":
            urdf = robot.velocity_limit
            layers.append(("robot file", np.where((urdf > 0) & np.isfinite(urdf), urdf, np.nan)))
        out = np.full(robot.dof, np.nan)
        where = [""] * robot.dof
        for source, layer in layers:
            if layer is None:
                continue
            fill = np.isnan(out) & ~np.isnan(layer)
            out[fill] = layer[fill]
            for j in np.flatnonzero(fill):
                where[j] = source
        values[kind], sources[kind] = out, tuple(where)
    for kind in ("velocity", "acceleration"):
        missing = [n for n, v in zip(robot.joint_names, values[kind], strict=True) if np.isnan(v)]
        if missing:
            hint = ("; the robot file gives none there" if kind == "velocity" else
                    "; an envelope needs every joint's acceleration limit")
            if file is not None:  # the file was read and gives none: it is the one to fix
                raise InputError(f"no {kind} limit for {', '.join(missing)}: give [limits] "
                                 f"{kind} here, or --{kind}{hint}", path=file.path,
                                 field=f"limits.{kind}")
            raise InputError(f"no {kind} limit for {', '.join(missing)}: give --{kind} or "
                             f"[limits] {kind} in an envelope file{hint}", field=kind)
    lacking = np.isnan(values["jerk"])
    values["jerk"][lacking] = values["acceleration"][lacking] / JERK_TIME
    sources["jerk"] = tuple("default" if missing else source
                            for missing, source in zip(lacking, sources["jerk"], strict=True))
    box = limit_box(robot, values["velocity"], values["acceleration"])
    return Spec(box, frozen(values["jerk"]), sources, file)
