"""The force and moment through each joint of robots read from MJCF and xacro, against MuJoCo.

hdselect builds an MJCF robot from MuJoCo's compiled model (hdselect.robot.mjcf) and
expands a .xacro into a URDF (hdselect.robot.xacrofile); the output bearings' wrench
pass (hdselect.robot.wrenches) must hold on both as test_wrenches shows it does on a
URDF read directly.

Oracles:
- MuJoCo's own force between each body and its parent (``cfrc_int`` after
  ``mj_inverse`` and ``mj_rnePostConstraint``), moved to the joint's origin and split
  along its axis (tests/mujoco_oracle.py `mujoco_joint_loads`): the axial force, the
  radial force, the tilting moment and the moment along the axis, each a quantity that
  does not depend on how the axis frame is turned about the axis;
- `inverse_dynamics` (Pinocchio's batched rnea) for the axis row, a mimic leader's torque
  being its own plus each follower's times the follower's multiplier (virtual work);
- the sizing's own torque along the planned cycle, for `hdselect size` on the MJCF and
  xacro versions of planar2, and planar2.urdf's bearing loads for its MJCF twin.
"""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xacro

import hdselect
from hdselect import Payload
from hdselect.cli.main import main
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.wrenches import axis_wrenches, bearing_loads
from helpers import REPO
from mujoco_oracle import mujoco_joint_loads, mujoco_of, states

ROBOTS = REPO / "robots"
PICK = REPO / "trajectories" / "planar2_pick_place.toml"
XACRO = ROBOTS / "planar2_gripper.urdf.xacro"
GRIPPER = {"gripper_mass": "0.3"}
"""A gripper planar2 carries through its cycle with a unit on each joint."""
SAMPLES = 40
"""Random states per robot."""

BENT = """\
    <mujoco model="bent">
      <compiler angle="radian"/>
      <worldbody>
        <body name="column" pos="0.1 0 0.2" quat="0.9 0.1 0.2 0.1">
          <joint name="pan" type="hinge" axis="0.2 0.3 1" pos="0.02 -0.01 0.05" range="-2 2"
                 ref="0.3"/>
          <geom type="box" size="0.05 0.04 0.03" pos="0.01 0.02 0.04" mass="3"/>
          <body name="carriage" pos="0.1 0.05 0.1" euler="0.2 0.1 -0.3">
            <joint name="lift" type="slide" axis="0 0.6 0.8" range="-0.2 0.2" ref="0.05"/>
            <geom type="capsule" fromto="0 0 0 0.2 0.05 0" size="0.02" mass="1.5"/>
            <body name="upper" pos="0.2 0.05 0">
              <joint name="tilt" type="hinge" axis="1 0 0" pos="0 0.01 0" range="-1.5 1.5"/>
              <geom type="box" size="0.15 0.02 0.02" pos="0.15 0.03 0.01" mass="1.2"/>
              <body name="wrist" pos="0.3 0 0">
                <joint name="roll" type="hinge" axis="1 0 0" range="-3 3"/>
                <joint name="pitch" type="hinge" axis="0 1 0.2" pos="0.01 0 0.005"
                       range="-2 2"/>
                <geom type="box" size="0.04 0.02 0.02" pos="0.04 0.01 0" mass="0.6"/>
                <body name="finger" pos="0.08 0 0">
                  <joint name="finger" type="hinge" axis="0 0 1" range="-1 1"/>
                  <geom type="box" size="0.03 0.01 0.01" pos="0.03 0.01 0" mass="0.2"/>
                  <body name="pad" pos="0.06 0 0">
                    <joint name="pad" type="hinge" axis="0 1 0" range="-1 1"/>
                    <geom type="box" size="0.02 0.01 0.01" pos="0.02 0 0.005" mass="0.05"/>
                  </body>
                </body>
              </body>
            </body>
          </body>
        </body>
      </worldbody>
      <equality><joint joint1="pad" joint2="finger" polycoef="0.1 -2 0 0 0"/></equality>
    </mujoco>
"""
"""Every case of the MJCF reader the wrench pass meets: a turning top body, unaligned
axes, anchors off the body origin, ``ref`` on a hinge and on a slide, a prismatic joint,
two joints in one body (a massless frame between them), a joint coupling (a mimic
follower), and masses off every axis (tilting moments and axial forces)."""


def bent(folder: Path) -> Path:
    path = folder / "bent.xml"
    path.write_text(textwrap.dedent(BENT))
    return path


def loaded(name: str, folder: Path) -> tuple[hdselect.Robot, bytes | None]:
    """The robot, and for the xacro the URDF the xacro package expands it to (MuJoCo reads it)."""
    if name == "planar2.xml":
        return hdselect.load_robot(ROBOTS / name), None
    if name == "bent.xml":
        return hdselect.load_robot(bent(folder)), None
    expanded = xacro.process_file(str(XACRO), mappings=dict(GRIPPER)).toxml()
    return hdselect.load_robot(XACRO, xacro_args=GRIPPER), expanded.encode()


ROBOT_FILES = ["planar2.xml", "planar2_gripper.urdf.xacro", "bent.xml"]


def test_the_bent_arm_is_read_with_every_case_it_is_meant_to_show(tmp_path):
    robot = hdselect.load_robot(bent(tmp_path))
    assert robot.joint_names == ("pan", "lift", "tilt", "roll", "pitch", "finger")
    assert robot.mimic["pad"].leader == "finger" and robot.mimic["pad"].multiplier == -2.0
    assert not robot.revolute[robot.joint_index("lift")]
    assert any("wrist (roll, pitch)" in note for note in robot.notes)


@pytest.mark.parametrize("name", ROBOT_FILES)
def test_the_wrench_through_each_joint_is_mujocos(name, tmp_path):
    """F_a, F_r, M about the joint origin and the moment along the axis, joint by joint
    (the mimic follower too), equal MuJoCo's at random states to rounding."""
    robot, expanded = loaded(name, tmp_path)
    q, qd, qdd = states(robot, SAMPLES, seed=5)
    theirs = mujoco_joint_loads(mujoco_of(robot, expanded), robot, q, qd, qdd)
    names = [*robot.joint_names, *robot.mimic]
    ours = axis_wrenches(robot, q, qd, qdd, names)
    force_scale = max(np.abs(loads[:2]).max() for loads in theirs.values())
    moment_scale = max(np.abs(loads[2:]).max() for loads in theirs.values())
    for wrench, joint in zip(ours, names, strict=True):
        axial, radial, tilting = bearing_loads(wrench)
        expected = theirs[joint]
        np.testing.assert_allclose(axial, expected[0], rtol=0, atol=1e-10 * force_scale,
                                   err_msg=joint)
        np.testing.assert_allclose(radial, expected[1], rtol=0, atol=1e-10 * force_scale,
                                   err_msg=joint)
        np.testing.assert_allclose(tilting, expected[2], rtol=0, atol=1e-10 * moment_scale,
                                   err_msg=joint)
        np.testing.assert_allclose(wrench[5], expected[3], rtol=0, atol=1e-10 * moment_scale,
                                   err_msg=joint)
    if name == "bent.xml":  # the arm loads its bearings every way, so the check means something
        pan = theirs["pan"]
        assert pan[0].std() > 1.0 and pan[2].std() > 0.1


@pytest.mark.parametrize("name", ROBOT_FILES)
def test_the_axis_row_is_the_joint_torque(name, tmp_path):
    """The moment (force) along a rotary (prismatic) joint's axis is its inverse-dynamics
    torque (force); a leader's adds its follower's times the multiplier."""
    robot, _ = loaded(name, tmp_path)
    q, qd, qdd = states(robot, SAMPLES, seed=6)
    tau = inverse_dynamics(robot, q, qd, qdd)
    names = [*robot.joint_names, *robot.mimic]
    wrenches = axis_wrenches(robot, q, qd, qdd, names)
    along = {joint: wrench[5] if name_is_rotary(robot, joint) else wrench[2]
             for joint, wrench in zip(names, wrenches, strict=True)}
    expected = {joint: along[joint].copy() for joint in robot.joint_names}
    for follower, mimic in robot.mimic.items():
        expected[mimic.leader] += mimic.multiplier * along[follower]
    scale = np.abs(tau).max()
    for j, joint in enumerate(robot.joint_names):
        np.testing.assert_allclose(expected[joint], tau[:, j], rtol=0, atol=1e-12 * scale,
                                   err_msg=joint)


def name_is_rotary(robot: hdselect.Robot, joint: str) -> bool:
    """A degree of freedom's kind, or a follower's (it turns as its leader does)."""
    leader = robot.mimic[joint].leader if joint in robot.mimic else joint
    return bool(robot.revolute[robot.joint_index(leader)])


@pytest.mark.parametrize("name", ["planar2.xml", "planar2_gripper.urdf.xacro"])
def test_sizing_a_robot_file_gives_each_joint_the_wrench_of_its_torque(name):
    """`hdselect.size` on the MJCF and the xacro planar2: every sized joint's wrench along
    the cycle has the joint's output torque as its axis row and loads its bearing."""
    robot = (hdselect.load_robot(ROBOTS / name) if name.endswith(".xml") else
             hdselect.load_robot(XACRO, xacro_args=GRIPPER))
    frame = "tool" if name.endswith(".xml") else "gripper"
    result = hdselect.size(robot, PICK, payload=Payload(0.4, (0.03, 0.0, 0.0), frame=frame))
    assert [joint.name for joint in result.joints] == ["shoulder", "elbow"]
    for joint in result.joints:
        assert joint.selected is not None and joint.wrench is not None
        wrench = joint.wrench.full()
        assert wrench.shape == (6, joint.torque.size)
        np.testing.assert_allclose(wrench[5], joint.torque, rtol=0,
                                   atol=1e-12 * np.abs(joint.torque).max())
        assert joint.bearing is not None and joint.bearing.max_radial > 1.0


def test_the_command_line_gives_the_mjcf_twin_the_urdfs_bearing_loads(tmp_path):
    """planar2.xml (MuJoCo derives its inertias from boxes) and planar2.urdf (written to 6
    digits): the same arm, so the same bearing loads in the JSON to that precision."""
    documents = {}
    for robot in ("planar2.xml", "planar2.urdf"):
        out = tmp_path / f"{robot}.json"
        assert main(["size", str(ROBOTS / robot), str(PICK), "--json", str(out)]) == 0
        documents[robot] = json.loads(out.read_text())
    for mjcf, urdf in zip(documents["planar2.xml"]["joints"], documents["planar2.urdf"]["joints"],
                          strict=True):
        assert mjcf["bearing"].keys() == urdf["bearing"].keys()
        assert mjcf["bearing"]["max_radial_n"] > 1.0
        for key, value in urdf["bearing"].items():
            if isinstance(value, float):
                assert mjcf["bearing"][key] == pytest.approx(value, rel=1e-5, abs=1e-9), key
            else:
                assert mjcf["bearing"][key] == value, key


def test_mujocos_interaction_force_is_read_in_the_world(tmp_path):
    """The oracle itself: one arm of mass m held still horizontal about a vertical axis,
    by hand: F_a = m g (up, along the axis), F_r = 0, M = m g r, no moment along the axis."""
    path = tmp_path / "hand.xml"
    path.write_text("""<mujoco><compiler angle="radian"/><worldbody>
      <body name="arm" pos="0 0 0.3"><joint name="j" type="hinge" axis="0 0 1"/>
        <geom type="sphere" size="0.01" pos="0.4 0 0" mass="2"/></body>
    </worldbody></mujoco>""")
    robot = hdselect.load_robot(path)
    mj = mujoco_of(robot)
    zero = np.zeros((1, 1))
    loads = mujoco_joint_loads(mj, robot, zero + 0.7, zero, zero)["j"][:, 0]
    g = float(np.linalg.norm(robot.gravity))
    np.testing.assert_allclose(loads, [2.0 * g, 0.0, 2.0 * g * 0.4, 0.0], rtol=1e-12,
                               atol=1e-12)
