"""What a robot's joints are, in the order a motion file's lists use: `hdselect joints`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from hdselect.base.bounds import expect_type
from hdselect.robot.model import Robot

GRIPPER_WORDS = ("gripper", "finger", "jaw", "hand", "claw")
"""Name parts of joints that are probably a gripper's, for hints only [-]."""


@dataclass(frozen=True)
class JointInfo:
    """One joint of a robot file, as hdselect reads it.

    Angles are lengths and torques forces for a prismatic joint: [rad or m], [N m or N].

    Attributes:
        name: Joint name.
        index: Its position in a motion file's lists (``q = [...]``, ``velocity = [...]``);
            None for a mimic follower, which has no value of its own.
        kind: ``"revolute"``, ``"continuous"``, ``"prismatic"`` or ``"mimic"``.
        lower: Lower position limit [rad or m]; -inf when none.
        upper: Upper position limit [rad or m]; +inf when none.
        velocity_limit: The file's velocity limit [rad/s or m/s]; inf when none.
        effort_limit: The file's effort limit [N m or N]; inf when none.
        moved_mass: Mass of everything the joint moves (links further out, payload) [kg].
        sized: It gets a gearhead by default.
        leader: For a follower, the joint it follows.
        multiplier: For a follower, its motion per unit of its leader's [-].
        offset: For a follower, its position when the leader is at zero [rad or m].
    """

    name: str
    index: int | None
    kind: str
    lower: float
    upper: float
    velocity_limit: float
    effort_limit: float
    moved_mass: float
    sized: bool
    leader: str | None = None
    multiplier: float = 1.0
    offset: float = 0.0

    @property
    def gripper_like(self) -> bool:
        """Its name reads like a gripper's joint (a hint to exclude it from sizing)."""
        return any(word in self.name.lower() for word in GRIPPER_WORDS)


def describe_joints(robot: Robot) -> tuple[JointInfo, ...]:
    """Every joint of the robot, degrees of freedom and mimic followers, in the model's order.

    The degrees of freedom come in the order of a motion file's lists; each
    follower comes where Pinocchio places it (after its leader's branch), unnumbered.

    Args:
        robot: The loaded robot.

    Returns:
        One record per joint.

    Raises:
        InputError: `robot` is not a Robot.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_robot)")
    model = robot.model
    infos = []
    for joint_id in range(1, model.njoints):
        name = model.names[joint_id]
        mass = robot.moved_mass(name)
        if name in robot.mimic:
            mimic = robot.mimic[name]
            infos.append(JointInfo(name, None, "mimic", mimic.lower, mimic.upper, math.inf,
                                   math.inf, mass, False, mimic.leader, mimic.multiplier,
                                   mimic.offset))
            continue
        j = robot.joint_index(name)
        velocity, effort = float(robot.velocity_limit[j]), float(robot.effort_limit[j])
        infos.append(JointInfo(
            name, j, robot.joint_type(name), float(robot.lower[j]), float(robot.upper[j]),
            velocity if velocity > 0.0 else math.inf, effort if effort > 0.0 else math.inf,
            mass, name in robot.sized_joints))
    return tuple(infos)
