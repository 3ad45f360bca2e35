"""Under-determined tool poses: a position with an approach axis, a yaw, or nothing more.

A full pose (``pin.SE3``) fixes all six coordinates of the tool. A `Target` fixes fewer,
for arms that cannot take every orientation (or need not):

- ``"axis"``: the origin, and the direction in which one tool axis (`Target.approach`,
  the tool's z by default) points; the roll about that axis is free (a 5-axis arm);
- ``"yaw"``: the origin, and the yaw of the tool about the world's vertical, the angle of
  the tool's x axis projected on the world's horizontal plane from the world's x axis
  (the yaw of URDF's ``rpy`` wherever the tool's x axis is not vertical); the tilt is
  free (a SCARA, a palletiser);
- ``"position"``: the origin alone.

A target is held in one reference frame (the world, or the base after `Target.moved`);
it carries the world's axes in that frame (`Target.world`), so that a yaw about the
world's vertical and the free coordinates reported (`Target.free`) mean the same on any
mounting. `goal_error`, `goal_between` and `goal_position` take a full pose or a target:
a full pose goes through `hdselect.ik.poses` unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TypeAlias

import numpy as np
import pinocchio as pin

from hdselect.ik.poses import interpolate_pose, pose_error

KINDS = ("axis", "yaw", "position")
"""What a target fixes beside the origin."""
TOOL_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0),
             "-x": (-1.0, 0.0, 0.0), "-y": (0.0, -1.0, 0.0), "-z": (0.0, 0.0, -1.0)}
"""The tool axes ``[tool] approach`` may name, as unit vectors in the tool frame."""
_NEXT = {"x": "y", "y": "z", "z": "x"}
"""The tool axis whose angle about the approach axis is the roll reported (x for z)."""
_TINY = 1e-12
_NO_COLUMNS = np.zeros((6, 0))
"""A Jacobian of no joints: what `Target.value` passes where only r is wanted."""


@dataclass(frozen=True, eq=False)
class Target:
    """What an under-determined tool pose fixes, in one reference frame (arrays read-only).

    Attributes:
        kind: One of `KINDS`.
        position: The tool origin [m], shape (3,).
        direction: For ``"axis"``: the unit direction the approach axis points [-], (3,).
        yaw: For ``"yaw"``: the yaw about the world's vertical [rad].
        approach: The name of the tool axis that ``"axis"`` points (`TOOL_AXES`).
        world: The world's x, y, z axes in the reference frame, as rows, shape (3, 3).
    """


    kind: str
    position: np.ndarray
    direction: np.ndarray = field(default_factory=lambda: np.zeros(3))
    yaw: float = 0.0
    approach: str = "z"
    world: np.ndarray = field(default_factory=lambda: np.eye(3))

    @property
    def rows(self) -> int:
        """The coordinates fixed [-]: 3 for the origin, 2 more for an axis, 1 for a yaw."""
        return 3 + {"axis": 2, "yaw": 1, "position": 0}[self.kind]

    @property
    def tool_axis(self) -> np.ndarray:
        """The approach axis in the tool frame, a signed unit vector [-]."""
        return np.array(TOOL_AXES[self.approach])

    def moved(self, frame: pin.SE3) -> Target:
        """The target in a frame whose pose in the current reference is `frame`."""
        rotation = frame.rotation
        return Target(self.kind, rotation.T @ (self.position - frame.translation),
                      rotation.T @ self.direction, self.yaw, self.approach,
                      self.world @ rotation)

    def like(self, placement: pin.SE3) -> Target:
        """A target of the same kind fixing what `placement` has (a line's start)."""
        rotation = placement.rotation
        return Target(self.kind, placement.translation.copy(), rotation @ self.tool_axis,
                      _heading(self.world, rotation), self.approach, self.world)

    def residual(self, placement: pin.SE3, jacobian: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
        """The residual r (`rows`,) and its Jacobian dr/dq (`rows`, dof).

        Args:
            placement: The tool's pose in the reference frame.
            jacobian: The tool's Jacobian in the reference frame's axes at the tool origin
                (linear rows, then angular), shape (6, dof).

        Returns:
            r: the origin's offset [m], then for an axis the angle to the direction and 0
            [rad] (the second row turns the axis out of the plane of that angle), for a
            yaw the yaw's offset [rad]; and its derivative.
        """
        linear, angular = jacobian[:3], jacobian[3:]
        offset = placement.translation - self.position
        if self.kind == "position":
            return offset, linear
        if self.kind == "axis":
            axis = placement.rotation @ self.tool_axis
            angle, normal = _turn(axis, self.direction)
            return (np.r_[offset, angle, 0.0],
                    np.vstack([linear, -normal @ angular, -np.cross(axis, normal) @ angular]))
        tool_x = placement.rotation[:, 0]
        x, y = self.world[0] @ tool_x, self.world[1] @ tool_x
        gradient = (x * np.cross(tool_x, self.world[1]) - y * np.cross(tool_x, self.world[0])) \
            / max(x * x + y * y, _TINY)
        return np.r_[offset, _wrap(math.atan2(y, x) - self.yaw)], \
            np.vstack([linear, gradient @ angular])

    def value(self, placement: pin.SE3) -> np.ndarray:
        """The residual r alone (`rows`,), as `residual` gives it, with no Jacobian to carry.

        `residual` of a Jacobian of no columns: r does not depend on the Jacobian.
        """
        return self.residual(placement, _NO_COLUMNS)[0]

    def errors(self, placement: pin.SE3) -> tuple[float, float]:
        """The origin's distance [m] and the angle off what is fixed [rad] (0 for a position)."""
        position = float(np.linalg.norm(placement.translation - self.position))
        if self.kind == "axis":
            return position, _turn(placement.rotation @ self.tool_axis, self.direction)[0]
        if self.kind == "yaw":
            return position, abs(_wrap(_heading(self.world, placement.rotation) - self.yaw))
        return position, 0.0

    def between(self, end: Target, fraction: float) -> Target:
        """The target a fraction [-] of the straight move to `end`.

        The origin moves on the segment; an axis turns at a constant rate in the plane of
        the two directions, the shorter way (the slerp of the directions); a yaw turns at
        a constant rate the shorter way.
        """
        position = (1.0 - fraction) * self.position + fraction * end.position
        direction, yaw = self.direction, self.yaw
        if self.kind == "axis":
            angle, normal = _turn(self.direction, end.direction)
            direction = pin.exp3(fraction * angle * normal) @ self.direction
        elif self.kind == "yaw":
            yaw = self.yaw + fraction * _wrap(end.yaw - self.yaw)
        return Target(self.kind, position, direction, yaw, self.approach, self.world)

    def angle_to(self, end: Target) -> float:
        """The turn of what is fixed from this target to `end` [rad] (0 for positions)."""
        if self.kind == "axis":
            return _turn(self.direction, end.direction)[0]
        return abs(_wrap(end.yaw - self.yaw)) if self.kind == "yaw" else 0.0

    def nearest_turn(self, end: Target, placement: pin.SE3) -> tuple[float, float]:
        """How far `placement` turns from the line to `end`, and where along it.

        Returns:
            The angle [rad] from the nearest target of the line, and that target's
            fraction [-] (an end, or the turn projected on the line's).
        """
        total = self.angle_to(end)
        candidates = [0.0, 1.0]
        if total > 0.0 and self.kind == "axis":
            _, normal = _turn(self.direction, end.direction)
            axis = placement.rotation @ self.tool_axis
            along = math.atan2(float(np.cross(self.direction, axis) @ normal),
                               float(self.direction @ axis))
            candidates.append(min(max(along / total, 0.0), 1.0))
        elif total > 0.0 and self.kind == "yaw":
            step = _wrap(end.yaw - self.yaw)
            along = _wrap(_heading(self.world, placement.rotation) - self.yaw) / step
            candidates.append(min(max(along, 0.0), 1.0))
        return min(((self.between(end, f).errors(placement)[1], f) for f in candidates),
                   key=lambda c: c[0])

    def free(self, placement: pin.SE3) -> tuple[tuple[str, float], ...]:
        """The coordinates this target leaves free, as `placement` has them [rad].

        ``"axis"``: ``roll``, the angle about the tool's approach axis (right-handed) from
        the world's x axis projected on the plane across it (the world's y where the axis
        is along x) to the next tool axis (x for an approach along z, y for x, z for y).
        ``"yaw"``: ``roll`` and ``pitch`` of the tool's ``rpy`` in the world; ``"position"``:
        ``roll``, ``pitch`` and ``yaw``.
        """
        rotation = placement.rotation
        if self.kind == "axis":
            axis = rotation @ self.tool_axis
            reference = self.world[0] - (self.world[0] @ axis) * axis
            if np.linalg.norm(reference) < 1e-6:
                reference = self.world[1] - (self.world[1] @ axis) * axis
            following = rotation[:, "xyz".index(_NEXT[self.approach[-1]])]
            return (("roll", math.atan2(float(np.cross(reference, following) @ axis),
                                        float(reference @ following))),)
        roll, pitch, yaw = (float(a) for a in pin.rpy.matrixToRpy(self.world @ rotation))
        return (("roll", roll), ("pitch", pitch)) if self.kind == "yaw" else \
            (("roll", roll), ("pitch", pitch), ("yaw", yaw))


Goal: TypeAlias = pin.SE3 | Target
"""What a waypoint asks of the tool: a full pose, or an under-determined `Target`."""


def goal_error(placement: pin.SE3, goal: Goal) -> tuple[float, float]:
    """How far a tool pose is from a goal: origin [m] and the orientation fixed [rad]."""
    return goal.errors(placement) if isinstance(goal, Target) else pose_error(placement, goal)


def goal_between(start: Goal, end: Goal, fraction: float) -> Goal:
    """The goal a fraction [-] of the straight move from `start` to `end` (same kind)."""
    if isinstance(start, Target) and isinstance(end, Target):
        return start.between(end, fraction)
    if isinstance(start, Target) or isinstance(end, Target):
        raise TypeError("a line between a full pose and a target")
    return interpolate_pose(start, end, fraction)


def goal_position(goal: Goal) -> np.ndarray:
    """The origin a goal fixes [m]."""
    return goal.position if isinstance(goal, Target) else goal.translation


def goal_in(frame: pin.SE3, goal: Goal) -> Goal:
    """A goal carried into a frame whose pose in the goal's reference is `frame`."""
    return goal.moved(frame) if isinstance(goal, Target) else frame.actInv(goal)


def _turn(a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray]:
    """The angle [rad] from unit vector `a` to `b`, and the unit axis turning `a` onto `b`.

    Any axis across `a` when the two are parallel.
    """
    cross = np.cross(a, b)
    sine = float(np.linalg.norm(cross))
    angle = math.atan2(sine, float(a @ b))
    if sine > _TINY:
        return angle, cross / sine
    across = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])
    return angle, across / np.linalg.norm(across)


def _heading(world: np.ndarray, rotation: np.ndarray) -> float:
    """The yaw of a tool orientation about the world's vertical [rad]."""
    tool_x = rotation[:, 0]
    return math.atan2(float(world[1] @ tool_x), float(world[0] @ tool_x))


def _wrap(angle: float) -> float:
    """An angle in [-pi, pi) [rad]."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi
