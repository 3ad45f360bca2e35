"""A motion file's waypoints: joint positions (``q``) or tool poses (``pose``), in any mix.

Joint positions are in the robot's joint order or keyed by joint name, in the file's
``angle_unit`` (m for prismatic joints), and must lie within the joint limits. Tool poses
are read by `hdselect.motion.toolposes`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import check_keys, number, table_of
from hdselect.motion.followers import check_waypoint_followers
from hdselect.motion.limits import LIMIT_ROUNDING, JointLists, per_joint
from hdselect.motion.toolposes import (
    POSE_KEYS,
    PoseWaypoint,
    ToolPoses,
    read_flags,
    read_pose,
    read_tool,
)
from hdselect.robot.model import Robot


def read_waypoints(doc: dict[str, Any], path: Path, robot: Robot, scale: np.ndarray,
               units: list[str], lists: JointLists, angle: tuple[float, str]
               ) -> tuple[np.ndarray, np.ndarray, ToolPoses | None]:
    """The ``[[waypoint]]`` tables (and ``[tool]``), checked against the robot.

    Args:
        doc: The motion file.
        path: The motion file's path, for messages.
        robot: The robot.
        scale: SI per file unit of each joint's positions.
        units: Each joint's unit, for messages.
        lists: How lists map onto joints.
        angle: The size of the file's angle unit [rad] and its name.

    Returns:
        The joint waypoints [rad or m], shape (k, dof), NaN rows where a waypoint is a
        tool pose; the dwells [s], shape (k,); the tool poses, or None.

    Raises:
        InputError: A waypoint is malformed, outside the joint limits (a mimic follower's
            included; a follower's value listed must agree with its leader's), or gives
            both or neither of q and pose.
    """
    value = doc.get("waypoint")
    if not isinstance(value, list) or len(value) < 2:
        raise InputError("give at least two [[waypoint]] tables", path=path, field="waypoint")
    points, dwells = [], []
    poses: list[PoseWaypoint] = []
    reconfigure: set[int] = set()
    for i, item in enumerate(value):
        where = f"waypoint[{i}]"
        table = table_of(item, path, where)
        check_keys(table, ("q", "dwell", "attach", "release", *POSE_KEYS), path, where)
        if ("q" in table) == ("pose" in table):
            raise InputError("give either q (joint positions) or pose (a tool pose in the world)"
                             if "q" in table else "required key is missing: q (joint positions) "
                             "or pose (a tool pose in the world)", path=path, field=f"{where}.q")
        if read_flags(table, i, path, pose="pose" in table):
            reconfigure.add(i)
        dwells.append(number(table, "dwell", path, where, default=0.0, bound=bounds.DWELL))
        if "pose" in table:
            poses.append(read_pose(table, i, path, robot, *angle))
            points.append(np.full(robot.dof, np.nan))
            continue
        if not isinstance(table["q"], list | dict):
            raise InputError("expected a list or a table keyed by joint name", path=path,
                             field=f"{where}.q")
        positions, followers = table["q"], {}
        if isinstance(positions, dict):  # a follower's value listed, as joint_states gives it
            followers = {k: v for k, v in positions.items() if k in robot.mimic}
            positions = {k: v for k, v in positions.items() if k not in robot.mimic}
        given = per_joint(positions, robot, path, f"{where}.q", bound=bounds.POSITION,
                           scale=scale, units=units, lists=lists)
        q = given * scale
        lower, upper = robot.lower, robot.upper
        slack_low = LIMIT_ROUNDING * np.maximum(1.0, np.abs(lower))
        slack_high = LIMIT_ROUNDING * np.maximum(1.0, np.abs(upper))
        for j in np.flatnonzero((q < lower - slack_low) | (q > upper + slack_high)):
            name = robot.joint_names[j]
            listed = isinstance(table["q"], list)
            key = f"[{j}]" if listed else f".{name}"
            raise InputError(
                f"{given[j]:g} {units[j]} is outside the limits of joint '{name}' "
                f"[{robot.lower[j] / scale[j]:g}, {robot.upper[j] / scale[j]:g}] {units[j]}"
                + (f" ({lists.order})" if listed else ""),
                path=path, field=f"{where}.q{key}")
        q = np.clip(q, lower, upper)  # on the limit its file rounded
        check_waypoint_followers(robot, q, followers, angle, path, f"{where}.q")
        points.append(q)
    tool = read_tool(doc.get("tool"), path, *angle, poses, reconfigure)
    return np.array(points), np.array(dwells), tool
