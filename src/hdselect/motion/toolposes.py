"""A motion file's tool poses: waypoints written where the work is, read and validated.

A waypoint gives either joint positions (``q``) or a tool pose in the world (``pose``),
in any mix::

    base = {xyz = [0, 0, 0], rpy = [0, 0, 0]}   # optional: where the base sits [m, angle_unit]

    [tool]
    frame = "tool0"                  # the frame the poses place (default: the payload's)
    position_tolerance = 0.0001      # m (default 0.1 mm)
    orientation_tolerance = 0.01     # in angle_unit (default 0.01 deg)
    approach = "z"                   # the tool axis an ``axis`` points (x, y, z, -x, -y, -z)
    allow_flip = false               # a near hint not honoured is a warning, not an error

    [[waypoint]]
    pose = {xyz = [0.32, -0.22, 0.05], rpy = [180, 0, 0]}   # m and angle_unit, world frame
    # or pose = {xyz = [...], axis = [0, 0, -1]}: the approach axis only, roll free
    # or pose = {xyz = [...], yaw = 30}: the yaw about the world's vertical, tilt free
    # or pose = {xyz = [...]}: the position alone
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
from hdselect.ik.targets import TOOL_AXES, Goal, Target
from hdselect.motion.limits import LIMIT_ROUNDING, vector
from hdselect.robot.model import Robot
from hdselect.robot.mounting import BasePose

TOOL_KEYS = ("frame", "position_tolerance", "orientation_tolerance", "approach", "allow_flip")
"""Keys of the ``[tool]`` table."""

POSE_KEYS = ("pose", "line", "near", "reconfigure")
"""The keys a waypoint may give besides ``q`` and ``dwell``."""

POSE_FORMS = ("xyz", "rpy", "axis", "yaw")
"""The keys of a waypoint's ``pose``: the origin, and at most one of the others."""


@dataclass(frozen=True)
class PoseWaypoint:
    """A waypoint written as a tool pose, in SI.

    Attributes:
        index: Its place among the motion file's waypoints.
        xyz: The tool frame's origin in the world [m].
        rpy: Its roll, pitch, yaw in the world [rad] (fixed axes X, Y, Z), or None where
            the pose fixes less (`kind`).
        line: Reached from the waypoint before along a straight line.
        hints: The joints the solver starts at, as (name, position [rad or m]) pairs
            (empty: all from the waypoint before).
        axis: The unit direction of the tool's approach axis in the world [-], or None.
        yaw: The tool's yaw about the world's vertical [rad], or None.
    """

    index: int
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float] | None
    line: bool = False
    hints: tuple[tuple[str, float], ...] = ()
    axis: tuple[float, float, float] | None = None
    yaw: float | None = None

    @property
    def kind(self) -> str:
        """``"pose"`` (xyz and rpy), ``"axis"``, ``"yaw"`` or ``"position"``."""
        return ("pose" if self.rpy is not None else "axis" if self.axis is not None
                else "yaw" if self.yaw is not None else "position")

    @property
    def near(self) -> dict[str, float]:
        """The file's ``near``: the hinted joints' positions by name [rad or m]."""
        return dict(self.hints)

    @property
    def pose(self) -> pin.SE3:
        """The pose in the world (a full pose only)."""
        if self.rpy is None:
            raise ValueError(f"waypoint[{self.index}] is a {self.kind} pose, not a full one")
        return pose_from_xyz_rpy(self.xyz, self.rpy)

    def goal(self, approach: str = "z") -> Goal:
        """What the waypoint asks of the tool in the world: the full pose, or a `Target`.

        Args:
            approach: The tool axis an ``axis`` pose points (`TOOL_AXES`).
        """
        if self.rpy is not None:
            return self.pose
        return Target(self.kind, np.array(self.xyz), np.array(self.axis or (0.0, 0.0, 0.0)),
                      self.yaw or 0.0, approach)


@dataclass(frozen=True)
class ToolPoses:
    """The motion file's ``[tool]`` table and its waypoints written as poses.

    Attributes:
        frame: The frame the poses place; None: the robot's payload frame.
        tolerance: How close a solved pose must come, and a line stay.
        poses: The waypoints written as poses, in file order.
        reconfigure: Waypoints that may be reached on another branch than the one
            before them (``reconfigure = true``).
        approach: The tool axis an ``axis`` pose points (``[tool] approach``, `TOOL_AXES`).
        allow_flip: ``[tool] allow_flip``: a ``near`` hint that cannot be honoured is a
            warning, not an error.
    """

    frame: str | None
    tolerance: Tolerance
    poses: tuple[PoseWaypoint, ...]
    reconfigure: frozenset[int] = frozenset()
    approach: str = "z"
    allow_flip: bool = False

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
        free: Per waypoint, the coordinates its pose leaves free as solved, (name, value
            [rad]) pairs (`hdselect.ik.targets.Target.free`); empty for joint waypoints
            and full poses.
    """

    frame: str
    base: BasePose
    position_error: np.ndarray
    orientation_error: np.ndarray
    notes: tuple[str, ...]
    key: tuple[Any, ...]
    free: tuple[tuple[tuple[str, float], ...], ...] = ()


FREE_WORDS = {"axis": "the roll about the approach axis where a pose gives an axis",
              "yaw": "the tool's roll and pitch where it gives a yaw",
              "position": "the tool's roll, pitch and yaw where it gives a position alone"}
"""What the free coordinates of each kind of pose are, in words."""


def free_note(tool: ToolPoses, solution: ToolSolution, angle: float,
              angle_unit: str) -> str | None:
    """The coordinates the poses left free, as solved, per waypoint; None for full poses.

    Args:
        tool: The motion's tool poses.
        solution: How they were solved (`ToolSolution.free`).
        angle: Size of the file's angle unit [rad].
        angle_unit: Its name.
    """
    items = []
    for i, free in enumerate(solution.free):
        if free:
            values = ", ".join(f"{name} {value / angle + 0.0:.4g}" for name, value in free)
            items.append(f"waypoint[{i}] {values} {angle_unit}")
    if not items:
        return None
    kinds = sorted({p.kind for p in tool.poses if p.kind in FREE_WORDS})
    words = "; ".join(FREE_WORDS[k] for k in kinds)
    return f"free coordinates as solved ({words}): {'; '.join(items)}."


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
    form = table_of(table["pose"], path, f"{where}.pose")
    check_keys(form, POSE_FORMS, path, f"{where}.pose")
    forms = [key for key in POSE_FORMS[1:] if key in form]
    if len(forms) > 1:
        raise InputError(f"give one of rpy (a full pose), axis (the approach axis, roll free) "
                         f"or yaw (tilt free), not both {forms[0]} and {forms[1]}", path=path,
                         field=f"{where}.pose.{forms[1]}")
    xyz, rpy = read_xyz_rpy({k: v for k, v in form.items() if k in ("xyz", "rpy")}, path,
                            f"{where}.pose", angle, angle_unit, need_rpy=False)
    axis = _direction(form["axis"], path, f"{where}.pose.axis") if "axis" in form else None
    yaw = (as_number(form["yaw"], path, f"{where}.pose.yaw", bound=bounds.ANGLE, scale=angle,
                     unit=angle_unit) * angle if "yaw" in form else None)
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
    return PoseWaypoint(index, xyz, rpy if "rpy" in form else None, line, tuple(near.items()),
                        axis, yaw)


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
    approach = table.get("approach", "z")
    if approach not in TOOL_AXES:
        raise InputError(f"unknown tool axis {approach!r}; choose one of: "
                         f"{', '.join(TOOL_AXES)}", path=path, field="tool.approach")
    if "approach" in table and not any(p.axis is not None for p in poses):
        raise InputError("approach names the tool axis a pose's axis gives; no waypoint gives "
                         "one (pose = {xyz, axis})", path=path, field="tool.approach")
    return ToolPoses(frame, Tolerance(position, orientation), tuple(poses),
                     frozenset(reconfigure), approach, _flag(table, "allow_flip", path, "tool"))


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


def _direction(value: Any, path: Path, field: str) -> tuple[float, float, float]:
    """A pose's ``axis``: three numbers, not all zero, made a unit vector [-].

    Raises:
        InputError: It is malformed, not finite or of zero length.
    """
    given = np.array(vector(value, 3, path, field), dtype=float)
    biggest = float(np.abs(given).max())
    size = float(np.linalg.norm(given / biggest)) * biggest if biggest > 0.0 else 0.0
    if not size > 1e-9:
        raise InputError("the approach axis has no direction (length 0): give a vector such "
                         "as [0, 0, -1] (tool down)", path=path, field=field)
    unit = (given / biggest) / (size / biggest)
    return (float(unit[0]), float(unit[1]), float(unit[2]))


def _flag(table: Mapping[str, Any], key: str, path: Path, where: str) -> bool:
    value = table.get(key, False)
    if not isinstance(value, bool):
        raise InputError(f"expected true or false, got {value!r}", path=path,
                         field=f"{where}.{key}")
    return value
