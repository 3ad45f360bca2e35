"""The robot: its file read as the format defines it, its joints, and its inverse dynamics.

`load_robot` reads a URDF or MJCF file (`reading`, checked by `checks`) into an
immutable `Robot` (`model`) that payload and mounting variants are made from (a
mounting places the base in the world: `BasePose`);
`dynamics` is the one place that calls Pinocchio's inverse dynamics.
"""

from hdselect.robot.joints import JointInfo, describe_joints
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import BasePose
from hdselect.robot.payload import Payload

__all__ = ["BasePose", "JointInfo", "Payload", "Robot", "describe_joints", "load_robot"]
