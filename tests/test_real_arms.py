"""The real arms of the test suite get a unit for every revolute joint from the shipped series.

Each arm's starter motion (`hdselect init`, unedited) is sized with every built-in
catalog loaded together; the unit each joint gets is stated here (`EXPECTED`) and in
docs/catalogs.md ("Real arms"), and the two are checked against each other, so a change
of the data or the selection shows as a diff of both. The torques the sizing judges are
checked against MuJoCo's inverse dynamics of the same trajectory (`mujoco_oracle`), with
each chosen unit's mass added to the robot file as a point mass at its joint's origin on
the link before it (what mass coupling carries), written into the URDF MuJoCo reads.
"""

from __future__ import annotations

import importlib.util
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.catalog import load_catalog
from hdselect.catalog.builtin import builtin_catalogs
from helpers import run_redirected
from helpers.robots import ARMS as EXAMPLE_ARMS
from helpers.robots import example_robots
from mujoco_oracle import mujoco_of, mujoco_torques

RTOL = 1e-9
"""Agreement asked of the torques, relative to the joint's largest MuJoCo torque."""

ARMS = {
    **{arm: ("example-robot-data", EXAMPLE_ARMS[arm])
       for arm in ("UR3", "UR5", "UR10", "Panda", "Kinova", "TALOS left arm", "Z1")},
    "KUKA iiwa": ("pybullet", "kuka_iiwa/model.urdf"),
    "xArm6": ("pybullet", "xarm/xarm6_robot.urdf"),
}
"""Each arm: the package that ships it (pip's name) and its file in the package's robots
folder (example-robot-data, a test dependency) or in ``pybullet_data`` (optional)."""

EXPECTED: dict[str, dict[str, str]] = {
    'UR3': {
        'shoulder_pan_joint': 'SHG-14-80-2UH',
        'shoulder_lift_joint': 'CSG-17-100-2UH',
        'elbow_joint': 'CSG-14-80-2UH',
        'wrist_1_joint': 'PSA-08-100',
        'wrist_2_joint': 'PSA-08-80',
        'wrist_3_joint': 'PSA-08-80',
    },
    'UR5': {
        'shoulder_pan_joint': 'SHG-17-100-2UH',
        'shoulder_lift_joint': 'CSG-25-100-2UH',
        'elbow_joint': 'SHG-17-100-2UH',
        'wrist_1_joint': 'CSG-14-80-2UH',
        'wrist_2_joint': 'PSA-08-100',
        'wrist_3_joint': 'PSA-08-100',
    },
    'UR10': {
        'shoulder_pan_joint': 'SHG-20-100-2UH',
        'shoulder_lift_joint': 'CSG-25-100-2UH',
        'elbow_joint': 'SHG-17-100-2UH',
        'wrist_1_joint': 'PSA-08-100',
        'wrist_2_joint': 'PSA-08-80',
        'wrist_3_joint': 'PSA-08-80',
    },
    'Panda': {
        'panda_joint1': 'SHG-14-80-2UH',
        'panda_joint2': 'CSG-17-100-2UH',
        'panda_joint3': 'SHG-14-80-2UH',
        'panda_joint4': 'CSG-17-100-2UH',
        'panda_joint5': 'PSA-10-80',
        'panda_joint6': 'PSA-08-100',
        'panda_joint7': 'PSA-08-80',
    },
    'Kinova': {
        'j2s6s200_joint_1': 'PSA-10-80',
        'j2s6s200_joint_2': 'PSA-14-100',
        'j2s6s200_joint_3': 'PSA-08-100',
        'j2s6s200_joint_4': 'PSA-08-100',
        'j2s6s200_joint_5': 'PSA-08-100',
        'j2s6s200_joint_6': 'PSA-08-80',
    },
    'TALOS left arm': {
        'arm_left_2_joint': 'CSG-17-100-2UH',
        'arm_left_3_joint': 'SHG-14-80-2UH',
        'arm_left_4_joint': 'CSG-14-80-2UH',
        'arm_left_5_joint': 'PSA-08-100',
        'arm_left_6_joint': 'PSA-08-100',
        'arm_left_7_joint': 'PSA-08-100',
        'gripper_left_joint': 'PSA-08-80',
    },
    'Z1': {
        'joint1': 'PSA-08-100',
        'joint2': 'CSG-14-80-2UH',
        'joint3': 'PSA-14-100',
        'joint4': 'PSA-10-80',
        'joint5': 'PSA-08-100',
        'joint6': 'PSA-08-80',
        'jointGripper': 'PSA-08-80',
    },
    'KUKA iiwa': {
        'lbr_iiwa_joint_1': 'SHG-14-80-2UH',
        'lbr_iiwa_joint_2': 'CSG-20-120-2UH',
        'lbr_iiwa_joint_3': 'SHG-14-80-2UH',
        'lbr_iiwa_joint_4': 'CSG-14-80-2UH',
        'lbr_iiwa_joint_5': 'PSA-08-100',
        'lbr_iiwa_joint_6': 'PSA-08-80',
        'lbr_iiwa_joint_7': 'PSA-08-80',
    },
    'xArm6': {
        'joint1': 'PSA-10-80',
        'joint2': 'CSG-17-100-2UH',
        'joint3': 'PSA-14-100',
        'joint4': 'PSA-08-100',
        'joint5': 'PSA-08-100',
        'joint6': 'PSA-08-80',
    },
}
"""The unit each revolute joint of each arm gets on its starter motion, every series loaded."""


def shipped_units() -> tuple[hdselect.Unit, ...]:
    """Every unit of every built-in catalog (`hdselect catalog --list`)."""
    return load_catalog([catalog.name for catalog in builtin_catalogs()])


def arm_file(arm: str) -> Path:
    """The arm's robot file; the test is skipped where its package is not installed."""
    package, relative = ARMS[arm]
    if package == "example-robot-data":
        return example_robots() / relative
    spec = importlib.util.find_spec("pybullet_data")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip(f"{package} is not installed (pip install {package} to size {arm})")
    return Path(list(spec.submodule_search_locations)[0]) / relative


def carrying(text: bytes, masses: dict[str, float]) -> bytes:
    """A URDF document with a point mass [kg] fixed at each named joint's origin on its parent."""
    root = ET.fromstring(text.lstrip())
    joints = {joint.get("name"): joint for joint in root.findall("joint")}
    for name, mass in masses.items():
        joint = joints[name]
        link = ET.SubElement(root, "link", name=f"{name}_gearhead")
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "mass", value=repr(mass))
        ET.SubElement(inertial, "inertia", ixx="0", iyy="0", izz="0", ixy="0", ixz="0",
                      iyz="0")
        mount = ET.SubElement(root, "joint", name=f"{name}_gearhead_mount", type="fixed")
        ET.SubElement(mount, "parent", link=joint.find("parent").get("link"))
        ET.SubElement(mount, "child", link=f"{name}_gearhead")
        origin = joint.find("origin")
        if origin is not None:
            ET.SubElement(mount, "origin", origin.attrib)
    return ET.tostring(root)


@pytest.mark.slow
@pytest.mark.parametrize("arm", list(ARMS))
def test_every_revolute_joint_gets_a_shipped_unit(arm: str, tmp_path: Path) -> None:
    path = arm_file(arm)
    motion = tmp_path / "m.toml"
    status, _, err = run_redirected(["init", path, "--out", motion])
    assert status == 0, err
    result = hdselect.size(None, motion, catalog=shipped_units())
    robot = result.robot
    revolute = [name for name in robot.joint_names
                if robot.joint_type(name) in ("revolute", "continuous")]
    assert [joint.name for joint in result.joints] == revolute
    chosen = {joint.name: joint.selected.unit.id if joint.selected else None
              for joint in result.joints}
    assert chosen == EXPECTED[arm]
    assert result.feasible
    masses = {joint.name: joint.selected.unit.mass for joint in result.joints}
    trajectory = result.trajectory
    theirs = mujoco_torques(mujoco_of(robot, carrying(path.read_bytes(), masses)), robot,
                            trajectory.q, trajectory.qd, trajectory.qdd)
    for joint in result.joints:
        tau = theirs[:, robot.joint_index(joint.name)]
        assert np.abs(joint.torque - tau).max() <= RTOL * np.abs(tau).max(), joint.name
        assert np.abs(tau).max() <= joint.selected.unit.repeated_torque, joint.name
