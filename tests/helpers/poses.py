"""Tool poses by hand: forward kinematics, the arms inverse kinematics is tried on, a
waypoint's written pose, MuJoCo's tool poses and tool-pose motions of the robots.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pinocchio as pin
from scipy.spatial.transform import Rotation

from hdselect.ik.poses import Tolerance, pose_error
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import load_robot
from helpers import REPO
from helpers.robots import configuration, example_robots, robot_path

ROBOTS = REPO / "robots"


ANGLES = ([40.0, -80.0], [10.0, -50.0], [75.0, -45.0])
"""planar2's joint angles (shoulder, elbow) [deg] whose tool poses the motion gives."""


def mujoco_tool_poses(angles_each=ANGLES) -> list[tuple[list[float], list[float]]]:
    """The tool site's pose at each joint angles [deg], by MuJoCo: xyz [m], URDF rpy [deg]."""
    model = mujoco.MjModel.from_xml_path(str(ROBOTS / "planar2.xml"))
    data = mujoco.MjData(model)
    poses = []
    for angles in angles_each:
        data.qpos[:] = np.radians(angles)
        mujoco.mj_kinematics(model, data)
        site = data.site("tool")
        rpy = Rotation.from_matrix(site.xmat.reshape(3, 3)).as_euler("xyz", degrees=True)
        poses.append((site.xpos.tolist(), rpy.tolist()))
    return poses


def pose_motion(folder, robot: str, frame: str, extra: str = "", angles_each=ANGLES) -> object:
    """A toppra motion through `mujoco_tool_poses`, the first near its angles."""
    lines = [f'robot = "{robot}"', 'planner = "toppra"', 'angle_unit = "deg"', extra,
             "[limits]", "velocity = 90", "acceleration = 400", "[tool]", f'frame = "{frame}"']
    for k, (xyz, rpy) in enumerate(mujoco_tool_poses(angles_each)):
        lines += ["[[waypoint]]", f"pose = {{xyz = {xyz!r}, rpy = {rpy!r}}}", "dwell = 0.2"]
        if k == 0:
            lines.append("near = {shoulder = 30, elbow = -70}")
    path = folder / "poses.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


TOLERANCE = Tolerance()


SHORT = """robot = "{robot}"
planner = "toppra"
angle_unit = "deg"

[limits]
velocity = 90
acceleration = 400

[[waypoint]]
pose = {{xyz = [0.26, 0.0, 0.30], rpy = [180, 0, -90]}}
dwell = 0.2

[[waypoint]]
pose = {{xyz = [0.28, -0.20, 0.16], rpy = [180, 0, -135]}}

[[waypoint]]
pose = {{xyz = [0.28, -0.20, 0.08], rpy = [180, 0, -135]}}
line = true
dwell = 0.2
"""
"""A short tool-pose motion of benchtop6: home, above a part, straight down to it."""


def written_pose(motion, i: int) -> pin.SE3:
    """Waypoint i's pose in the world, built here from the file's numbers (URDF's rpy)."""
    pose = motion.tool.at(i)
    return pin.SE3(Rotation.from_euler("xyz", pose.rpy).as_matrix(), np.array(pose.xyz))


UR5_Q = np.array([0.3, -1.2, 1.3, -1.5, 0.9, 0.2])
"""A UR5 configuration away from singularities (elbow bent, wrist_2 well off 0)."""


IK_ARMS = {"UR5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
        "Panda": ("panda_description/urdf/panda.urdf", "panda_hand_tcp")}


def arm(name: str) -> FrameKinematics:
    """The frame of a test arm: example-robot-data's UR5 or Panda, or the shipped benchtop6."""
    if name == "benchtop6":
        return FrameKinematics(load_robot(robot_path("benchtop6")), "tool0")
    file, frame = IK_ARMS[name]
    return FrameKinematics(load_robot(example_robots() / file), frame)


def fk(kin: FrameKinematics, q: np.ndarray) -> pin.SE3:
    """Forward kinematics on a model built here from the file, with a Data of its own."""
    model = pin.buildModelFromUrdf(str(kin.robot.path))
    data = model.createData()
    pin.framesForwardKinematics(model, data, configuration(model, kin.robot.joint_names, q))
    return data.oMf[model.getFrameId(kin.frame)].copy()


def within(kin: FrameKinematics, q: np.ndarray, target: pin.SE3,
           tolerance: Tolerance = TOLERANCE) -> bool:
    return tolerance.holds(*pose_error(fk(kin, q), target))


def rot(axis: str, angle: float) -> np.ndarray:
    """An elementary rotation about x, y or z [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]
