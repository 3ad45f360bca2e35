"""Mimic followers in a motion: their positions follow from their leaders', checked like any joint.

A follower (a URDF ``<mimic>``, an MJCF joint equality) has no value of its own:
q_follower = multiplier x q_leader + offset. Its own position limits still hold,
so a waypoint, a logged sample or a planned trajectory that takes a follower past
them is refused, naming the follower and its leader. A motion may list a
follower's value (a ``joint_states`` export does): it must agree with its leader's
to `AGREEMENT`, else it is refused naming both.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number
from hdselect.motion.limits import LIMIT_ROUNDING
from hdselect.robot.model import Robot

AGREEMENT = 1e-4
"""How far a listed follower value may lie from where its leader puts it [the file's unit:
deg, rad or m] (rounding of an export to 4 decimals)."""


def follower_scale(robot: Robot, name: str, angle_scale: float, angle_unit: str
                   ) -> tuple[float, str]:
    """SI per file unit of a follower's positions, and the unit's label (``m`` if it slides)."""
    return (angle_scale, angle_unit) if robot.mimic[name].revolute else (1.0, "m")


def describe(robot: Robot, name: str) -> str:
    """``finger (= 3 x elbow + 0.1)``: a follower and how it follows, for messages."""
    mimic = robot.mimic[name]
    offset = f" {'+' if mimic.offset >= 0 else '-'} {abs(mimic.offset):g}" if mimic.offset else ""
    return f"mimic follower '{name}' (= {mimic.multiplier:g} x {mimic.leader}{offset})"


def check_agreement(robot: Robot, name: str, given: float, leader: float, scale: float,
                    unit: str, path: Path, field: str) -> None:
    """A listed follower value agrees with its leader's.

    Args:
        robot: The robot.
        name: The follower.
        given: The value listed for it [the file's unit].
        leader: Its leader's position [rad or m].
        scale: SI per file unit of the follower's positions.
        unit: That unit's label.
        path: The motion file or log, for messages.
        field: Where the value is, for messages.

    Raises:
        InputError: It does not (the message names the follower and its leader).
    """
    expected = float(robot.mimic[name].follow(np.asarray(leader))) / scale
    if abs(given - expected) > AGREEMENT:
        raise InputError(f"{given:g} {unit} for {describe(robot, name)} disagrees with its "
                         f"leader, which puts it at {expected:.6g} {unit}; give the leader's "
                         "value only, or one that agrees", path=path, field=field)


def outside(robot: Robot, q: np.ndarray) -> tuple[str, int, float] | None:
    """The first follower that leaves its limits along `q`, where, and its position.

    Args:
        robot: The robot.
        q: Joint positions of the robot's degrees of freedom [rad or m], shape (n, dof).

    Returns:
        (follower, sample index of its furthest excursion, its position [rad or m]),
        or None when every follower stays within its limits (within `LIMIT_ROUNDING` of
        one is on it: its file's rounding, as for a waypoint of any joint).
    """
    for name, mimic in robot.mimic.items():
        if not (math.isfinite(mimic.lower) or math.isfinite(mimic.upper)):
            continue
        positions = mimic.follow(q[:, robot.joint_index(mimic.leader)])
        over = np.maximum(
            (mimic.lower - positions) - LIMIT_ROUNDING * max(1.0, abs(mimic.lower)),
            (positions - mimic.upper) - LIMIT_ROUNDING * max(1.0, abs(mimic.upper)))
        k = int(np.argmax(over))
        if over[k] > 0.0:
            return name, k, float(positions[k])
    return None


def outside_reason(robot: Robot, name: str, position: float, angle_scale: float,
                   angle_unit: str) -> str:
    """Why a follower's position is refused: its limits and the leader's range that keeps it in.

    Args:
        robot: The robot.
        name: The follower.
        position: Where it goes [rad or m].
        angle_scale: SI per unit of the motion's angles (pi/180 for degrees).
        angle_unit: That unit's label.
    """
    mimic = robot.mimic[name]
    scale, unit = follower_scale(robot, name, angle_scale, angle_unit)
    text = (f"{describe(robot, name)} goes to {position / scale:.6g} {unit}, outside its limits "
            f"[{mimic.lower / scale:g}, {mimic.upper / scale:g}] {unit}")
    if mimic.multiplier != 0.0:
        leader_scale, leader_unit = (angle_scale, angle_unit) if robot.revolute[
            robot.joint_index(mimic.leader)] else (1.0, "m")
        ends = sorted(((mimic.lower - mimic.offset) / mimic.multiplier,
                       (mimic.upper - mimic.offset) / mimic.multiplier))
        text += (f"; keep {mimic.leader} within [{ends[0] / leader_scale:.6g}, "
                 f"{ends[1] / leader_scale:.6g}] {leader_unit}")
    return text


def check_waypoint_followers(robot: Robot, q: np.ndarray, listed: dict[str, Any],
                     angle: tuple[float, str], path: Path, field: str) -> None:
    """Listed follower values agree with their leaders; every follower within its limits.

    Args:
        robot: The robot.
        q: The waypoint's positions of the robot's degrees of freedom [rad or m].
        listed: Follower values the waypoint's table lists, by follower [the file's unit].
        angle: SI per unit of the motion's angles, and the unit's label.
        path: The motion file.
        field: The waypoint's ``q``, for messages.

    Raises:
        InputError: A listed value disagrees, or a follower leaves its limits (the field
            names its leader).
    """
    for name, value in listed.items():
        follower_unit = follower_scale(robot, name, *angle)
        number = as_number(value, path, f"{field}.{name}", bound=bounds.POSITION,
                           scale=follower_unit[0], unit=follower_unit[1])
        leader = q[robot.joint_index(robot.mimic[name].leader)]
        check_agreement(robot, name, number, leader, *follower_unit, path, f"{field}.{name}")
    found = outside(robot, q[np.newaxis])
    if found is not None:
        name, _, position = found
        raise InputError(outside_reason(robot, name, position, *angle), path=path,
                         field=f"{field}.{robot.mimic[name].leader}")


def check_logged_followers(robot: Robot, columns: dict[str, np.ndarray],
                           arrays: dict[str, np.ndarray], angle: tuple[float, str], log: Path,
                           where: Callable[[int], str]) -> None:
    """A log's follower columns agree with their leaders'; every follower within its limits.

    Args:
        robot: The robot.
        columns: Each follower column (``q_``, ``qd_`` or ``qdd_`` and the follower's
            name) as logged [the file's unit, per s, per s^2].
        arrays: The logged ``q`` (and ``qd``, ``qdd`` if logged) of the degrees of freedom
            [rad or m, per s, per s^2], each (n, dof).
        angle: SI per unit of the log's angles, and the unit's label.
        log: The CSV file.
        where: ``data row R (line L)`` of a 1-based data row.

    Raises:
        InputError: A column disagrees with its leader, or has no leader's column to agree
            with; or a follower leaves its limits (the field names the column).
    """
    for column, values in columns.items():
        kind, _, name = column.partition("_")
        mimic = robot.mimic[name]
        scale, unit = follower_scale(robot, name, *angle)
        if kind not in arrays:
            raise InputError(f"{describe(robot, name)}: its leader has no {kind}_ column to "
                             "agree with", path=log, field=column)
        leader = arrays[kind][:, robot.joint_index(mimic.leader)]
        expected = (mimic.follow(leader) if kind == "q" else mimic.multiplier * leader) / scale
        disagree = np.flatnonzero(~(np.abs(values - expected) <= AGREEMENT))
        if disagree.size:
            k = int(disagree[0])
            per = {"q": "", "qd": "/s", "qdd": "/s^2"}[kind]
            raise InputError(f"{where(k + 1)}: {values[k]:g} {unit}{per} for "
                             f"{describe(robot, name)} disagrees with its leader, which puts it "
                             f"at {expected[k]:.6g} {unit}{per}", path=log, field=column)
    found = outside(robot, arrays["q"])
    if found is not None:
        name, k, position = found
        raise InputError(f"{where(k + 1)}: {outside_reason(robot, name, position, *angle)}",
                         path=log, field=f"q_{robot.mimic[name].leader}")
