"""A motion file's tool poses: waypoints written where the work is, read and validated.

A waypoint gives either joint positions (``q``) or a tool pose in the world (``pose``),
in any mix::

    base = {xyz = [0, 0, 0], rpy = [0, 0, 0]}   # optional: where the base sits [m, angle_unit]

    [tool]
    frame = "tool0"                  # the frame the poses place (default: the payload's)
    position_tolerance = 0.0001      # m (default 0.1 mm)
    orientation_tolerance = 0.01     # in angle_unit (default 0.01 deg)

    [[waypoint]]
    pose = {xyz = [0.32, -0.22, 0.05], rpy = [180, 0, 0]}   # m and angle_unit, world frame
    near = {elbow = 90}              # optional: start the solver with these joints here
    [[waypoint]]
    pose = {xyz = [0.32, -0.22, 0.15], rpy = [180, 0, 0]}
    line = true                      # reach it along a straight line (planner "toppra")
    reconfigure = true               # optional: the arm may change branch on the way here

Everything is converted to SI here (m, rad); the poses are solved for a robot's
mounting by `hdselect.motion.planning.solve`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, table_of
from hdselect.ik.poses import Tolerance, pose_from_xyz_rpy
from hdselect.motion.limits import LIMIT_ROUNDING, vector
from hdselect.robot.model import Robot
from hdselect.robot.mounting import BasePose

TOOL_KEYS = ("frame", "position_tolerance", "orientation_tolerance")
"""Keys of the ``[tool]`` table."""

POSE_KEYS = ("pose", "line", "near", "reconfigure")
"""The keys a waypoint may give besides ``q`` and ``dwell``."""


@dataclass(frozen=True)
class PoseWaypoint:
    """A waypoint written as a tool pose, in SI.

    Attributes:
        index: Its place among the motion file's waypoints.
        xyz: The tool frame's origin in the world [m].
        rpy: Its roll, pitch, yaw in the world [rad] (fixed axes X, Y, Z).
        line: Reached from the waypoint before along a straight line.
        hints: The joints the solver starts at, as (name, position [rad or m]) pairs
            (empty: all from the waypoint before).
    """

    index: int
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    line: bool = False
    hints: tuple[tuple[str, float], ...] = ()

    @property
    def near(self) -> dict[str, float]:
        """The file's ``near``: the hinted joints' positions by name [rad or m]."""
        return dict(self.hints)

    @property
    def pose(self) -> pin.SE3:
        """The pose in the world."""
        return pose_from_xyz_rpy(self.xyz, self.rpy)


@dataclass(frozen=True)
class ToolPoses:
    """The motion file's ``[tool]`` table and its waypoints written as poses.

    Attributes:
        frame: The frame the poses place; None: the robot's payload frame.
        tolerance: How close a solved pose must come, and a line stay.
        poses: The waypoints written as poses, in file order.
        reconfigure: Waypoints that may be reached on another branch than the one
            before them (``reconfigure = true``).
    """

    frame: str | None
    tolerance: Tolerance
    poses: tuple[PoseWaypoint, ...]
    reconfigure: frozenset[int] = frozenset()

    def at(self, index: int) -> PoseWaypoint | None:
        """The pose of waypoint `index`, or None for a joint waypoint."""
        return next((p for p in self.poses if p.index == index), None)

    @property
    def lines(self) -> tuple[int, ...]:
        """The waypoints reached along a straight line."""
        return tuple(p.index for p in self.poses if p.line)


@dataclass(frozen=True, eq=False)
class ToolSolution:
    """How a motion's tool poses were solved for one robot and mounting.

    Attributes:
        frame: The frame placed.
        base: The mounting solved for: where the base sits in the world.
        position_error: Per waypoint, the solved tool origin's distance from the pose
            [m], shape (k,); NaN for joint waypoints.
        orientation_error: Per waypoint, the solved tool orientation's angle from the
            pose [rad], shape (k,); NaN for joint waypoints.
        notes: What the solving noticed, one line each: branch changes allowed by
            ``reconfigure``, joint waypoints that moved with the robot.
        key: What the solution depends on: the robot file and its xacro arguments, its
            joint limits, the frame and the base pose.
    """

    frame: str
    base: BasePose
    position_error: np.ndarray
    orientation_error: np.ndarray
    notes: tuple[str, ...]
    key: tuple[Any, ...]


def read_pose(table: Mapping[str, Any], index: int, path: Path, robot: Robot,
              angle: float, angle_unit: str) -> PoseWaypoint:
    """One ``[[waypoint]]`` with a ``pose``, checked.

    Args:
        table: The waypoint's table.
        index: Its place in the file.
        path: The motion file, for messages.
        robot: The robot (joint names and units of ``near``).
        angle: Size of the file's angle unit [rad].
        angle_unit: Its name, for messages.

    Raises:
        InputError: A key is malformed, or ``line`` and ``near`` are both given.
    """
    where = f"waypoint[{index}]"
    xyz, rpy = read_xyz_rpy(table["pose"], path, f"{where}.pose", angle, angle_unit,
                            need_rpy=True)
    line = _flag(table, "line", path, where)
    if line and index == 0:
        raise InputError("the first waypoint has no waypoint before it to draw a line from",
                         path=path, field=f"{where}.line")
    near: dict[str, float] = {}
    if "near" in table:
        if line:
            raise InputError("a line decides its joints from the waypoint before; remove "
                             "near (or line)", path=path, field=f"{where}.near")
        for name, value in table_of(table["near"], path, f"{where}.near").items():
            j = robot.joint_index(name, source=path, field=f"{where}.near.{name}")
            scale = angle if robot.revolute[j] else 1.0
            unit = angle_unit if robot.revolute[j] else "m"
            given = as_number(value, path, f"{where}.near.{name}", bound=bounds.POSITION,
                              scale=scale, unit=unit)
            low, high = robot.lower[j], robot.upper[j]
            if not low - LIMIT_ROUNDING * max(1.0, abs(low)) <= given * scale <= (
                    high + LIMIT_ROUNDING * max(1.0, abs(high))):  # the solver cannot start there
                raise InputError(f"{given:g} {unit} is outside the limits of joint '{name}' "
                                 f"[{low / scale:g}, {high / scale:g}] {unit}", path=path,
                                 field=f"{where}.near.{name}")
            near[name] = given * scale
    return PoseWaypoint(index, xyz, rpy, line, tuple(near.items()))


def read_flags(table: Mapping[str, Any], index: int, path: Path, pose: bool) -> bool:
    """A waypoint's ``reconfigure`` flag; ``line`` and ``near`` refused on joint waypoints.

    Raises:
        InputError: A pose key on a joint waypoint, or a flag that is not true or false.
    """
    where = f"waypoint[{index}]"
    if not pose:
        for key in ("line", "near"):
            if key in table:
                raise InputError(f"{key} applies to a waypoint written as a tool pose; this one "
                                 "gives joint positions (q)", path=path, field=f"{where}.{key}")
    reconfigure = _flag(table, "reconfigure", path, where)
    if reconfigure and index == 0:
        raise InputError("the first waypoint has no waypoint before it", path=path,
                         field=f"{where}.reconfigure")
    return reconfigure


def read_tool(value: Any, path: Path, angle: float, angle_unit: str,
              poses: list[PoseWaypoint], reconfigure: set[int]) -> ToolPoses | None:
    """The ``[tool]`` table and the pose waypoints, or None when the file has neither.

    Raises:
        InputError: A key is unknown or out of range, or ``[tool]`` comes without poses.
    """
    if value is None and not poses:
        if reconfigure:
            raise InputError("reconfigure applies where a tool pose is solved; no waypoint "
                             "of this file is a pose", path=path,
                             field=f"waypoint[{min(reconfigure)}].reconfigure")
        return None
    table = table_of(value if value is not None else {}, path, "tool")
    check_keys(table, TOOL_KEYS, path, "tool")
    if not poses:
        raise InputError("no waypoint is a tool pose (pose = {xyz, rpy}); remove [tool] or "
                         "write the waypoints as poses", path=path, field="tool")
    frame = table.get("frame")
    if frame is not None and (not isinstance(frame, str) or not frame):
        raise InputError(f"expected a frame name, got {frame!r}", path=path, field="tool.frame")
    default = Tolerance()
    position = as_number(table.get("position_tolerance", default.position), path,
                         "tool.position_tolerance", bound=bounds.POSE_POSITION_TOLERANCE)
    orientation = as_number(table.get("orientation_tolerance", default.orientation / angle),
                            path, "tool.orientation_tolerance",
                            bound=bounds.POSE_ORIENTATION_TOLERANCE, scale=angle,
                            unit=angle_unit) * angle
    return ToolPoses(frame, Tolerance(position, orientation), tuple(poses),
                     frozenset(reconfigure))


def read_base(value: Any, path: Path, angle: float, angle_unit: str) -> BasePose:
    """The file's ``base = {xyz, rpy}``: where the robot's base sits in the world.

    Raises:
        InputError: It is malformed.
    """
    xyz, rpy = read_xyz_rpy(value, path, "base", angle, angle_unit, need_rpy=False)
    return BasePose.from_xyz_rpy(xyz, rpy)


def read_xyz_rpy(value: Any, path: Path, where: str, angle: float, angle_unit: str, *,
                 need_rpy: bool) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """``{xyz = [m], rpy = [angle_unit]}`` as (xyz [m], rpy [rad]).

    Raises:
        InputError: A key is unknown or missing, or a number is malformed.
    """
    table = table_of(value, path, where)
    check_keys(table, ("xyz", "rpy"), path, where)
    for key in ("xyz", "rpy") if need_rpy else ("xyz",):
        if key not in table:
            raise InputError("required key is missing"
                             + ("; a tool pose needs its orientation (rpy = [roll, pitch, yaw] "
                                f"in {angle_unit})" if key == "rpy" else ""),
                             path=path, field=f"{where}.{key}")
    xyz = vector(table["xyz"], 3, path, f"{where}.xyz")
    for i, x in enumerate(xyz):
        bounds.LENGTH.check(x, path=path, field=f"{where}.xyz[{i}]")
    rpy = vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, path, f"{where}.rpy")
    for i, a in enumerate(rpy):
        bounds.ANGLE.check(a, path=path, field=f"{where}.rpy[{i}]", scale=angle, unit=angle_unit)
    return ((xyz[0], xyz[1], xyz[2]), (rpy[0] * angle, rpy[1] * angle, rpy[2] * angle))


def _flag(table: Mapping[str, Any], key: str, path: Path, where: str) -> bool:
    value = table.get(key, False)
    if not isinstance(value, bool):
        raise InputError(f"expected true or false, got {value!r}", path=path,
                         field=f"{where}.{key}")
    return value
