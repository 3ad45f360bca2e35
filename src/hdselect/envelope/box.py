"""The limit box of a spec: every state a motion within the spec may pass through.

q in the joint ranges, |qd| <= v, |qdd| <= a, per joint. A continuous joint (no
position limits) ranges over one turn, [-pi, pi]: its dynamics repeat every turn.
States are addressed by points of the unit cube [0, 1]^(2 dof), positions first,
then velocities, which is where the search draws and moves them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from numbers import Real

import numpy as np

from hdselect.base import bounds
from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.robot.model import Robot


@dataclass(frozen=True, eq=False)
class LimitBox:
    """The states a spec allows, joint by joint in the robot's order.

    Attributes:
        joint_names: Every degree of freedom, in the robot's velocity order.
        lower: Lowest position [rad or m], shape (dof,).
        upper: Highest position [rad or m], shape (dof,).
        velocity: Speed limit v [rad/s or m/s], shape (dof,).
        acceleration: Acceleration limit a [rad/s^2 or m/s^2], shape (dof,).
        periodic: A continuous joint, its range one turn [-pi, pi], per joint.
    """

    joint_names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    periodic: tuple[bool, ...]

    @property
    def dof(self) -> int:
        """Number of degrees of freedom."""
        return len(self.joint_names)

    @property
    def dimension(self) -> int:
        """Coordinates of a state in the unit cube: positions and velocities, 2 dof."""
        return 2 * self.dof

    def states(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities of points of the unit cube.

        Args:
            x: Points in [0, 1]^(2 dof), shape (n, 2 dof): 0 is a joint's lower position
                or -v, 1 its upper position or +v.

        Returns:
            q [rad or m] and qd [rad/s or m/s], each of shape (n, dof).
        """
        dof = self.dof
        q = self.lower + x[:, :dof] * (self.upper - self.lower)
        qd = self.velocity * (2.0 * x[:, dof:] - 1.0)
        return q, qd

    def points(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """The unit-cube points of states (the inverse of `states`), shape (n, 2 dof)."""
        q, qd = np.atleast_2d(q), np.atleast_2d(qd)
        return np.hstack([(q - self.lower) / (self.upper - self.lower),
                          (qd / self.velocity + 1.0) / 2.0])


Limits = float | Sequence[float] | Mapping[str, float] | np.ndarray | None
"""A limit per joint as a caller gives it: one number for every joint, one per joint in the
robot's order, or a mapping of joint name to number (every joint); None for none."""


def limit_box(robot: Robot, velocity: np.ndarray, acceleration: np.ndarray) -> LimitBox:
    """The box of a robot's joint ranges and the given limits.

    Args:
        robot: The robot (its position limits; continuous joints range over one turn).
        velocity: Speed limit per joint [rad/s or m/s], shape (dof,).
        acceleration: Acceleration limit per joint [rad/s^2 or m/s^2], shape (dof,).

    Returns:
        The box, its arrays read-only.

    Raises:
        InputError: A limit is not a positive finite number in range, or a joint that is
            not continuous has no finite position limits.
    """
    for name, values in (("velocity", velocity), ("acceleration", acceleration)):
        if np.shape(values) != (robot.dof,):
            raise InputError(f"expected {robot.dof} limits, got shape {np.shape(values)}",
                             field=name)
        for j, value in enumerate(values):
            bounds.MOTION_LIMITS[name].check(value, field=f"{name}.{robot.joint_names[j]}")
    periodic = tuple(robot.joint_type(name) == "continuous" for name in robot.joint_names)
    lower = np.where(periodic, -math.pi, robot.lower)
    upper = np.where(periodic, math.pi, robot.upper)
    for j, name in enumerate(robot.joint_names):
        if not (math.isfinite(lower[j]) and math.isfinite(upper[j])):
            raise InputError(f"joint '{name}' has no finite position limits; the envelope "
                             "needs the range it may move over", path=robot.path,
                             field=f"joint[{name}].limit")
    return LimitBox(robot.joint_names, frozen(lower), frozen(upper), frozen(velocity),
                    frozen(acceleration), periodic)


def per_joint_limits(value: Limits, robot: Robot, field: str, *,
                     partial: bool = False) -> np.ndarray | None:
    """A caller's limit per joint as an array in the robot's order [SI]; None if not given.

    Args:
        value: One number, a sequence in the robot's joint order, or a mapping of joint
            names to numbers; None when not given.
        robot: The robot (its joints).
        field: The argument's name (``velocity``, ``acceleration`` or ``jerk``).
        partial: A mapping may leave joints out (NaN there); else it must give every joint.

    Raises:
        InputError: A joint is unknown or missing, the count is wrong, or a value is not a
            number in range.
    """
    if value is None:
        return None
    bound = bounds.MOTION_LIMITS[field]
    names = robot.joint_names
    if isinstance(value, Mapping):
        for name in value:
            if not isinstance(name, str):
                raise InputError(f"expected joint names, got {name!r}", field=field)
            robot.joint_index(name, field=field)
        missing = [name for name in names if name not in value]
        if missing and not partial:
            raise InputError(f"missing joint(s) {', '.join(missing)}; give every joint: "
                             f"{', '.join(names)}", field=field)
        return np.array([bound.check(value[name], field=f"{field}.{name}")
                         if name in value else math.nan for name in names])
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray | Real):
        raise InputError(f"expected a number, a list per joint or a mapping of joint names, "
                         f"got {type(value).__name__}", field=field)
    if isinstance(value, Real):
        values: list[object] = [value] * robot.dof
    else:
        values = list(value)  # type: ignore[arg-type]
        if len(values) != robot.dof:
            raise InputError(f"expected {robot.dof} values (joints {', '.join(names)}), got "
                             f"{len(values)}", field=field)
    return np.array([bound.check(item, field=f"{field}.{name}")
                     for name, item in zip(names, values, strict=True)])
