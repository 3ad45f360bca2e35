"""Per-joint lists of a motion file: limits, waypoints, one number or one per joint.

A list is in the robot's joint order (`hdselect joints` prints it) or a table keyed
by joint name; angles are in the file's ``angle_unit`` and converted to SI here.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number
from hdselect.robot.model import Robot

LIMIT_ROUNDING = 5e-6
"""How far a waypoint may lie beyond a robot file's position limit and still be taken as on
it, relative to max(1, |limit|) [-]. A limit written to 6 significant digits differs from
the angle its author meant by less (pi/2 written 1.5707963 or 1.5708: 2.7e-8 and 3.7e-6 rad;
pi written 3.14159: 2.7e-6 rad), so a waypoint at 90 deg against 1.5707963 rad is that
limit. The waypoint is moved onto the limit, by at most this much."""


def vector(value: Any, size: int, path: Path, field: str) -> list[float]:
    """A list of `size` numbers from a motion file, each checked finite."""
    if not isinstance(value, list) or len(value) != size:
        raise InputError(f"expected a list of {size} numbers, got {value!r}", path=path,
                         field=field)
    return [as_number(v, path, f"{field}[{i}]") for i, v in enumerate(value)]


class JointLists:
    """How a motion file's lists map onto joints: the model's order, named in every message.

    Remembers whether the file used a list, to warn once when the model's order is not
    the order the robot file writes its joints.
    """

    def __init__(self, robot: Robot):
        self.robot = robot
        self.used: list[str] = []

    @property
    def order(self) -> str:
        """The joints in list order, for messages."""
        return f"list order: {', '.join(self.robot.joint_names)}"

    def warnings(self) -> list[str]:
        """One line if a list was used and the robot file writes its joints in another order."""
        written = self.robot.file_order
        if not self.used or written is None or written == self.robot.joint_names:
            return []
        return [f"{self.used[0]} and any other list follows the model's joint order "
                f"({', '.join(self.robot.joint_names)}), not the order the robot file writes "
                f"them ({', '.join(written)}); tables keyed by joint name avoid the question"]


def per_joint(value: Any, robot: Robot, path: Path, field: str, *, bound: bounds.Bound,
               scale: np.ndarray, units: Sequence[str], lists: JointLists | None = None
               ) -> np.ndarray:
    """One number per joint: from a number (all joints), a list or a table keyed by joint.

    Each value, times its joint's `scale` (SI per file unit), must lie within `bound`.
    """
    def read(raw: Any, j: int, where: str) -> float:
        return as_number(raw, path, where, bound=bound, scale=float(scale[j]), unit=units[j])

    if isinstance(value, dict):
        for name in value:
            _joint_key(robot, name, path, f"{field}.{name}")
        missing = [n for n in robot.joint_names if n not in value]
        if missing:
            raise InputError(f"missing joint(s) {', '.join(missing)}; give every joint: "
                             f"{', '.join(robot.joint_names)}", path=path, field=field)
        return np.array([read(value[n], j, f"{field}.{n}")
                         for j, n in enumerate(robot.joint_names)])
    if isinstance(value, list):
        lists = lists or JointLists(robot)
        lists.used.append(field)
        if len(value) != robot.dof:
            raise InputError(f"expected {robot.dof} values ({lists.order}), got {len(value)}",
                             path=path, field=field)
        numbers = []
        for j, v in enumerate(value):
            try:
                numbers.append(read(v, j, f"{field}[{j}]"))
            except InputError as err:
                raise InputError(f"{err.reason} for joint '{robot.joint_names[j]}' ({lists.order})",
                                 path=path, field=err.field) from err
        return np.array(numbers)
    return np.array([read(value, j, field) for j in range(robot.dof)])


def limit_units(kind: str, units: Sequence[str]) -> list[str]:
    """The unit labels of a ``[limits]`` kind per joint, e.g. ``deg/s^2``."""
    if kind == "torque":
        return ["N m" if unit != "m" else "N" for unit in units]
    power = {"velocity": "/s", "acceleration": "/s^2", "jerk": "/s^3"}[kind]
    return [unit + power for unit in units]


def _joint_key(robot: Robot, name: str, path: Path, field: str) -> None:
    """Reject a table key that is not a degree of freedom (a mimic follower explained)."""
    if name in robot.mimic:
        raise InputError(f"joint '{name}' follows '{robot.mimic[name].leader}' (mimic); give "
                         "its leader instead", path=path, field=field)
    robot.joint_index(name, source=path, field=field)


def velocity_limit(value: Any, robot: Robot, path: Path, scale: np.ndarray,
                    units: Sequence[str], lists: JointLists,
                    planner: str) -> tuple[np.ndarray, tuple[str, ...]]:
    """Velocity limits [rad/s or m/s]: the file's, else per joint the robot file's.

    Every limit, the robot file's included, lies within ``bounds.MOTION_LIMITS["velocity"]``.

    Returns:
        The limits and the joints whose limit came from the robot file.

    Raises:
        InputError: A joint has neither (the message names them), or a limit is out of range.
    """
    bound = bounds.MOTION_LIMITS["velocity"]
    labels = limit_units("velocity", units)
    urdf = np.where((robot.velocity_limit > 0.0) & np.isfinite(robot.velocity_limit),
                    robot.velocity_limit, np.nan)
    if value is None:
        given: dict[str, Any] = {}
    elif isinstance(value, dict):
        given = value
    else:
        return per_joint(value, robot, path, "limits.velocity", bound=bound, scale=scale,
                          units=labels, lists=lists) * scale, ()
    for name in given:
        _joint_key(robot, name, path, f"limits.velocity.{name}")
    missing = [n for n in robot.joint_names if n not in given]
    lacking = [n for n in missing if np.isnan(urdf[robot.joint_index(n)])]
    if lacking:
        raise InputError(f"required by planner '{planner}' for {', '.join(lacking)}: the robot "
                         "file gives no velocity limit there", path=path, field="limits.velocity")
    for name in missing:
        j = robot.joint_index(name)
        try:
            bound.check(float(urdf[j]), path=robot.path, field=f"joint[{name}].limit.velocity")
        except InputError as err:
            raise InputError(f"{err.reason} (used for {path.name}'s limits.velocity; give the "
                             "limit there)", path=robot.path, field=err.field) from err
    velocity = urdf.copy()
    for name, limit in given.items():
        j = robot.joint_index(name)
        velocity[j] = as_number(limit, path, f"limits.velocity.{name}", bound=bound,
                                scale=float(scale[j]), unit=labels[j]) * scale[j]
    return velocity, tuple(missing)


def beyond_robot(velocity: np.ndarray, robot: Robot, scale: np.ndarray, units: list[str],
                  from_robot: tuple[str, ...]) -> list[str]:
    """One line per joint whose velocity limit exceeds the robot file's."""
    lines = []
    for j, name in enumerate(robot.joint_names):
        urdf = robot.velocity_limit[j]
        if name in from_robot or not (0.0 < urdf < np.inf) or velocity[j] <= urdf * (1 + 1e-9):
            continue
        lines.append(f"limits.velocity: joint '{name}' may move at {velocity[j] / scale[j]:g} "
                     f"{units[j]}/s, above the robot file's velocity limit "
                     f"{urdf / scale[j]:.4g} {units[j]}/s")
    return lines
