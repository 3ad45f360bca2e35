"""Tool poses as rigid transforms: built, carried into the base frame, interpolated, compared.

A pose is a ``pinocchio.SE3``: the frame's rotation and origin in a reference frame
(the world, or the robot's base). Angles are roll, pitch, yaw about fixed axes X, Y, Z
(URDF's ``rpy``): R = Rz(yaw) Ry(pitch) Rx(roll).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.robot.mounting import BasePose, rpy_matrix

DEFAULT_POSITION_TOLERANCE = 1e-4
"""How far a solved tool position may be from the pose asked for, by default [m] (0.1 mm)."""

DEFAULT_ORIENTATION_TOLERANCE = math.radians(0.01)
"""How far a solved tool orientation may be turned from the pose asked for, by default
[rad] (0.01 deg)."""


@dataclass(frozen=True)
class Tolerance:
    """How close a solved pose must come to the pose asked for.

    Attributes:
        position: Largest distance between the tool origins [m].
        orientation: Largest angle of the rotation between the tool orientations [rad].
    """

    position: float = DEFAULT_POSITION_TOLERANCE
    orientation: float = DEFAULT_ORIENTATION_TOLERANCE

    def holds(self, position_error: float, orientation_error: float) -> bool:
        """Both errors [m, rad] are within the tolerance."""
        return position_error <= self.position and orientation_error <= self.orientation

    def scaled(self, factor: float) -> Tolerance:
        """The tolerance times `factor` [-]."""
        return Tolerance(self.position * factor, self.orientation * factor)


def pose_from_xyz_rpy(xyz: Sequence[float], rpy: Sequence[float]) -> pin.SE3:
    """A pose from its origin [m] and roll, pitch, yaw [rad] (URDF's fixed axes X, Y, Z)."""
    return pin.SE3(rpy_matrix(rpy), np.asarray(xyz, dtype=float))


def xyz_rpy(pose: pin.SE3) -> tuple[np.ndarray, np.ndarray]:
    """The origin [m] and roll, pitch, yaw [rad] of a pose (pitch in [-pi/2, pi/2])."""
    return pose.translation.copy(), np.asarray(pin.rpy.matrixToRpy(pose.rotation))


def base_in_world(base: BasePose) -> pin.SE3:
    """The base-to-world transform of a mounting as a pose."""
    return pin.SE3(base.matrix, base.position)


def in_base(base: BasePose, world_pose: pin.SE3) -> pin.SE3:
    """A pose given in the world, expressed in the robot's base frame (base^-1 * pose)."""
    return base_in_world(base).actInv(world_pose)


def interpolate_pose(start: pin.SE3, end: pin.SE3, fraction: float) -> pin.SE3:
    """The pose a fraction [-] along the straight move from `start` to `end`.

    The origin moves on the segment; the orientation turns at a constant rate about one
    fixed axis, the shorter way (slerp): R(f) = R0 exp(f log(R0^T R1)).
    """
    turn = pin.log3(start.rotation.T @ end.rotation)
    return pin.SE3(start.rotation @ pin.exp3(fraction * turn),
                   (1.0 - fraction) * start.translation + fraction * end.translation)


def pose_error(actual: pin.SE3, target: pin.SE3) -> tuple[float, float]:
    """The distance between two poses of a frame: origins [m] and orientations [rad].

    The orientation error is the angle of the rotation taking one to the other. Both
    numbers are the same whether the poses are given in the world or in the base.
    """
    position = float(np.linalg.norm(actual.translation - target.translation))
    orientation = float(np.linalg.norm(pin.log3(actual.rotation.T @ target.rotation)))
    return position, orientation
