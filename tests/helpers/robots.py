"""Robot files written by the tests (URDF chains, grippers with mimic joints, a ROS-style
arm) and the robots of example-robot-data with the ones hdselect refuses.
"""

from __future__ import annotations

import importlib.metadata
import math
import textwrap
from pathlib import Path

import numpy as np
import pinocchio as pin

from helpers import REPO

PLANAR2_URDF = (REPO / "robots" / "planar2.urdf").read_text()


def finger_arm(folder: Path, multiplier: float = 3.0, offset: float = 0.0,
               limits: str = 'lower="-0.5" upper="0.5"') -> Path:
    path = folder / "finger.urdf"
    joint = FINGER.format(mimic=f'<mimic joint="elbow" multiplier="{multiplier!r}" '
                                f'offset="{offset!r}"/>')
    path.write_text(PLANAR2_URDF.replace(
        "</robot>", joint.replace('lower="-0.5" upper="0.5"', limits) + "</robot>"))
    return path


KNOWN_REFUSALS = {
    "ur3.urdf": "not a valid URDF robot: No name given for the robot",
    "iris.urdf": "limit.lower: must be a position between -1e+06 and 1e+06 rad, got -1e+16",
    "iris_simple.urdf": "the robot has no movable joint",
    "quadrotor_base.urdf": "the robot has no movable joint",
    "romeo_laas_small.urdf": "inertia is not positive semi-definite",
}
"""The example-robot-data URDFs hdselect refuses, and why: every other one must load."""


BOX = ('<inertial><origin xyz="{x} 0 0"/><mass value="{m}"/>'
       '<inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial>')


LIMIT = '<limit lower="-2" upper="2" effort="20" velocity="3"/>'


def urdf(tmp_path: Path, body: str, name: str = "robot.urdf", robot: str = "arm") -> Path:
    path = tmp_path / name
    path.write_text(f'<?xml version="1.0"?>\n<robot name="{robot}">\n{body}\n</robot>\n')
    return path


def revolute(name: str, parent: str, child: str, *, axis: str = "0 0 1", xyz: str = "0 0 0",
             extra: str = "") -> str:
    return (f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/>{LIMIT}{extra}'
            "</joint>")


def gripper(tmp_path: Path, follower_names=("left_inner", "right_outer")) -> Path:
    """An arm joint, a gripper leader and two followers (one reversed, with an offset)."""
    first, second = follower_names
    body = ('<link name="base"/>' + revolute("arm_joint", "base", "arm", axis="0 1 0")
            + f'<link name="arm">{BOX.format(x=0.2, m=1.0, i=2e-3)}</link>'
            + revolute("finger_joint", "arm", "finger", axis="1 0 0", xyz="0.4 0 0")
            + f'<link name="finger">{BOX.format(x=0.03, m=0.1, i=2e-5)}</link>'
            + revolute(first, "arm", "inner", axis="1 0 0", xyz="0.4 0.02 0",
                       extra='<mimic joint="finger_joint"/>')
            + f'<link name="inner">{BOX.format(x=0.03, m=0.05, i=1e-5)}</link>'
            + revolute(second, "arm", "outer", axis="1 0 0", xyz="0.4 -0.02 0",
                       extra='<mimic joint="finger_joint" multiplier="-1" offset="0.1"/>')
            + f'<link name="outer">{BOX.format(x=0.04, m=0.08, i=1e-5)}</link>')
    return urdf(tmp_path, body, "gripper.urdf")


ROBOTS = REPO / "robots"


JOINTS = {
    "index_table": ("table",),
    "planar2": ("shoulder", "elbow"),
    "scara": ("shoulder", "elbow", "lift", "wrist"),
    "pan_tilt": ("pan", "tilt"),
    "benchtop6": ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"),
}


def robot_path(name: str) -> Path:
    return ROBOTS / f"{name}.urdf"


LONG = {"shoulder": "left_arm_shoulder_lift_joint", "elbow": "left_arm_elbow_flex_joint"}


def ros_arm(directory: Path) -> Path:
    """planar2 with ROS-style joint names, swinging 1.5 kg too fast for any shoulder unit."""
    urdf = PLANAR2_URDF
    for short, long in LONG.items():
        urdf = urdf.replace(f'joint name="{short}"', f'joint name="{long}"')
    robot = directory / "ros_arm.urdf"
    robot.write_text(urdf)
    motion = directory / "swing.toml"
    motion.write_text(f"""\
robot = "{robot.as_posix()}"
planner = "ruckig"
angle_unit = "deg"
[payload]
mass = 1.5
frame = "tool"
[limits]
velocity = 300
acceleration = 3000
jerk = 60000
[safety]
stop_time = 0.5
[[waypoint]]
q = [60, -30]
dwell = 0.3
[[waypoint]]
q = [-20, 40]
dwell = 0.3
[[waypoint]]
q = [60, -30]
""")
    return motion


FINGER = """
  <joint name="finger" type="revolute">
    <parent link="link2"/><child link="finger_link"/>
    <origin xyz="0.25 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-0.5" upper="0.5" effort="2.0" velocity="4.0"/>
    {mimic}
  </joint>
  <link name="finger_link">
    <inertial><origin xyz="0.02 0 0"/><mass value="0.05"/>
      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
"""


def example_robots() -> Path:
    """The robots folder the example-robot-data wheel installs (cmeel layout)."""
    dist = importlib.metadata.distribution("example-robot-data")
    folder = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    assert folder.is_dir(), f"example-robot-data has no robots folder at {folder}"
    return folder


EXAMPLE_ROBOTS = sorted(example_robots().rglob("*.urdf"))


ARMS = {
    "UR3": "ur_description/urdf/ur3_robot.urdf",
    "UR5": "ur_description/urdf/ur5_robot.urdf",
    "UR10": "ur_description/urdf/ur10_robot.urdf",
    "Panda": "panda_description/urdf/panda.urdf",
    "Kinova": "kinova_description/robots/kinova.urdf",
    "SO-100": "so_arm_description/urdf/so100.urdf",
    "SO-101": "so_arm_description/urdf/so101.urdf",
    "Z1": "z1_description/urdf/z1.urdf",
    "TALOS left arm": "talos_data/robots/talos_left_arm.urdf",
    "xArm7": "xarm_description/urdf/xarm7.urdf",
    "Baxter": "baxter_description/urdf/baxter.urdf",
    "TriFinger finger": "finger_edu_description/robots/finger_edu.urdf",
    "TIAGo arm": "tiago_description/robots/tiago_no_hand.urdf",
}


def configuration(model: pin.Model, names, q: np.ndarray) -> np.ndarray:
    """Pinocchio's q of one sample from joint angles in `names` order (cos/sin for continuous)."""
    config = np.zeros(model.nq)
    for name, value in zip(names, q, strict=True):
        joint = model.joints[model.getJointId(name)]
        if joint.nq == 2:
            config[joint.idx_q:joint.idx_q + 2] = np.cos(value), np.sin(value)
        else:
            config[joint.idx_q] = value
    return config


def write_chain(directory: Path, joints, name: str = "arm") -> Path:
    """A serial chain URDF; `joints` is a list of (name, type, lower, upper) with limits [rad/m]."""
    links = ['<link name="base"/>']
    parts = []
    parent = "base"
    axes = ("0 0 1", "0 1 0", "0 1 0", "1 0 0", "0 1 0", "0 0 1")
    for i, (joint, kind, lower, upper) in enumerate(joints):
        child = f"link{i + 1}"
        links.append(
            f'<link name="{child}"><inertial><origin xyz="0.1 0 0"/><mass value="1.0"/>'
            '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
        )
        limit = "" if kind == "continuous" else \
            f'<limit lower="{lower}" upper="{upper}" effort="50" velocity="10"/>'
        parts.append(
            f'<joint name="{joint}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0 0 {0.2 if i else 0.1}"/><axis xyz="{axes[i % 6]}"/>{limit}</joint>'
        )
        parent = child
    path = directory / f"{name}.urdf"
    path.write_text(f'<robot name="{name}">{"".join(links + parts)}</robot>')
    return path


def write_robot(directory: Path, dof: int = 6, name: str = "arm") -> Path:
    """A chain of `dof` revolute joints j1..jN with limits +-pi [rad]."""
    return write_chain(directory, [(f"j{i + 1}", "revolute", -math.pi, math.pi)
                                   for i in range(dof)], name)


def write_motion(directory: Path, body: str, name: str = "motion.toml") -> Path:
    path = directory / name
    path.write_text(textwrap.dedent(body))
    return path
