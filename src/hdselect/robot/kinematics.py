"""Forward kinematics of one robot frame: its pose, Jacobian and the joint limits around it.

`FrameKinematics` holds one ``pinocchio.Data`` for a frame of a `Robot`, so that pose
solving, straight lines and branch checks evaluate thousands of configurations without
re-allocating. Configurations are joint positions in the robot's joint order [rad or m]
(`Robot.joint_names`); continuous joints are angles, turned into Pinocchio's (cos, sin)
by `Robot.configuration`. A mimic follower's own limits narrow its leader's
(`leader_range`), so a solved pose keeps every follower in range.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.robot.model import Robot
from hdselect.robot.payload import frame_id

AT_BOUND = 1e-9
"""A joint within this of a limit is at that limit [rad or m]."""


def leader_range(robot: Robot, name: str, lower: float, upper: float) -> tuple[float, float]:
    """The part of a joint's range that keeps every follower of it within its own limits.

    Args:
        robot: The robot.
        name: The joint (a degree of freedom).
        lower: Its lower limit [rad or m] (-inf: none).
        upper: Its upper limit [rad or m] (+inf: none).

    Returns:
        The narrowed range [rad or m]; the joint's own when no position satisfies every
        follower (a motion moving it is then refused naming the follower).
    """
    low, high = lower, upper
    for mimic in robot.mimic.values():
        if mimic.leader != name or mimic.multiplier == 0.0:
            continue
        ends = sorted(((mimic.lower - mimic.offset) / mimic.multiplier,
                       (mimic.upper - mimic.offset) / mimic.multiplier))
        low, high = max(low, ends[0]), min(high, ends[1])
    return (low, high) if low <= high else (lower, upper)


@dataclass(frozen=True)
class LimitContact:
    """A joint sitting at one of its position limits.

    Attributes:
        joint: The joint's name.
        side: ``"lower"`` or ``"upper"``.
        value: The limit [rad or m].
        follower: The mimic follower whose own limit sets this one of its leader's, or
            ``""`` when it is the joint's own.
    """

    joint: str
    side: str
    value: float
    follower: str = ""


class FrameKinematics:
    """The pose and Jacobian of one frame of a robot, within the robot's joint limits.

    Args:
        robot: The robot (its model's frames and joint limits).
        frame: The frame to place, e.g. ``"tool0"``.

    Raises:
        InputError: The robot has no such frame, or no joint moves it.
    """

    def __init__(self, robot: Robot, frame: str) -> None:
        model = robot.model
        if not model.existFrame(frame):
            bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
            raise InputError(f"unknown frame '{frame}'; the robot's links are: "
                             f"{', '.join(bodies)}", path=robot.path, field="tool.frame")
        self.robot = robot
        self.model = model
        self.data = model.createData()
        self.frame = frame
        self.frame_id = frame_id(model, frame)
        if model.frames[self.frame_id].parentJoint == 0:
            raise InputError(f"frame '{frame}' is fixed to the base: no joint moves it",
                             path=robot.path, field="tool.frame")
        ranges = [leader_range(robot, name, lower, upper) for name, lower, upper
                  in zip(robot.joint_names, robot.lower, robot.upper, strict=True)]
        self.lower = np.array([lower for lower, _ in ranges], dtype=float)
        self.upper = np.array([upper for _, upper in ranges], dtype=float)
        """Each joint's limits [rad or m], narrowed to keep its mimic followers within theirs."""
        span = self.upper - self.lower
        self.full_turn = np.asarray(robot.revolute) & np.isfinite(span) & (span >= 2 * np.pi)
        """Revolute joints with a range of a full turn or more: an angle pressed against one
        limit has an equal angle 2 pi away inside the range."""
        self._plain = model.nq == robot.dof  # no (cos, sin) joint: q is Pinocchio's q
        self.length = self._reach()
        """The arm's stretched reach [m], at least 0.1: it makes tool motion in m and in
        rad comparable (`sigma_min`, `tool_motion`)."""

    @property
    def dof(self) -> int:
        """Number of joint positions."""
        return self.robot.dof

    def clip(self, q: np.ndarray) -> np.ndarray:
        """`q` with every joint clipped into its limits (a copy) [rad or m]."""
        return np.clip(np.asarray(q, dtype=float), self.lower, self.upper)

    def configuration(self, q: np.ndarray) -> np.ndarray:
        """Pinocchio's configuration of joint positions `q` [rad or m]."""
        return np.asarray(q, dtype=float) if self._plain else self.robot.configuration(q)[:, 0]

    def placement(self, q: np.ndarray) -> pin.SE3:
        """The frame's pose in the base frame at joint positions `q` [rad or m]."""
        pin.framesForwardKinematics(self.model, self.data, self.configuration(q))
        return self.data.oMf[self.frame_id].copy()

    def jacobian(self, q: np.ndarray, *, aligned: bool = False) -> np.ndarray:
        """The frame's Jacobian, shape (6, dof): linear rows [m per rad or m], then angular.

        Args:
            q: Joint positions [rad or m].
            aligned: Expressed in the base frame's axes at the frame's origin; else in the
                frame's own axes.
        """
        reference = pin.LOCAL_WORLD_ALIGNED if aligned else pin.LOCAL
        jacobian = pin.computeFrameJacobian(self.model, self.data, self.configuration(q),
                                            self.frame_id, reference)
        return np.asarray(jacobian).reshape(6, self.model.nv)  # one joint: pinocchio gives (6,)

    def sigma_min(self, q: np.ndarray) -> float:
        """The smallest singular value of the Jacobian, linear rows divided by `length`.

        Returns:
            [rad per rad]: 0 at a singularity; its inverse bounds the joint speed per
            unit of tool speed.
        """
        jacobian = self.jacobian(q, aligned=True)
        jacobian[:3] /= self.length
        return float(np.linalg.svd(jacobian, compute_uv=False)[-1])

    def tool_motion(self, start: pin.SE3, end: pin.SE3) -> float:
        """The size of a tool move on one scale, |dp| / length + |dtheta| [rad]."""
        dp = float(np.linalg.norm(end.translation - start.translation))
        return dp / self.length + float(np.linalg.norm(pin.log3(start.rotation.T @ end.rotation)))

    def contacts(self, q: np.ndarray) -> list[tuple[int, LimitContact]]:
        """The joints at a limit at `q`, with their index."""
        found = []
        for j, name in enumerate(self.robot.joint_names):
            if q[j] <= self.lower[j] + AT_BOUND:
                found.append((j, LimitContact(name, "lower", float(self.lower[j]),
                                              self._follower_at(name, self.lower[j]))))
            elif q[j] >= self.upper[j] - AT_BOUND:
                found.append((j, LimitContact(name, "upper", float(self.upper[j]),
                                              self._follower_at(name, self.upper[j]))))
        return found

    def _follower_at(self, name: str, value: float) -> str:
        """The follower of joint `name` that reaches one of its own limits at `value` [rad or m]."""
        for follower, mimic in self.robot.mimic.items():
            position = mimic.multiplier * value + mimic.offset
            if mimic.leader == name and any(
                    math.isclose(position, limit, rel_tol=1e-12, abs_tol=1e-12)
                    for limit in (mimic.lower, mimic.upper)):
                return follower
        return ""

    def seed(self, near: Mapping[str, float] | None = None) -> np.ndarray:
        """A start for the solver, clipped into the limits [rad or m].

        The middle of every range (0 where unbounded), hinted joints at their hint.
        """
        return self.hinted(self.middle, near)

    @property
    def middle(self) -> np.ndarray:
        """The middle of every joint's range, 0 where it is unbounded [rad or m]."""
        bounded = np.isfinite(self.lower) & np.isfinite(self.upper)
        return np.where(bounded, 0.5 * (np.where(bounded, self.lower, 0.0)
                                        + np.where(bounded, self.upper, 0.0)), 0.0)

    def hinted(self, q: np.ndarray, near: Mapping[str, float] | None) -> np.ndarray:
        """`q` with the hinted joints at their hint [rad or m], clipped into the limits."""
        q = np.array(q, dtype=float)
        for name, value in (near or {}).items():
            q[self.robot.joint_index(name)] = value
        return self.clip(q)

    def _reach(self) -> float:
        """The reach [m]: joint to joint along the chain, then to the frame; at least 0.1."""
        model = self.model
        joint = model.frames[self.frame_id].parentJoint
        total = float(np.linalg.norm(model.frames[self.frame_id].placement.translation))
        while model.parents[joint] > 0:
            total += float(np.linalg.norm(model.jointPlacements[joint].translation))
            joint = model.parents[joint]
        return max(total, 0.1)
