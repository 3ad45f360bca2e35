"""Tests of hdselect.robot.reading: what a real robot file holds, and what loading it assumes."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.model import load_robot
from hdselect.robot.mounting import STANDARD_GRAVITY
from helpers import REPO
from helpers.robots import BOX, gripper, revolute, robot_path, urdf


def fixed(name: str, parent: str, child: str, xyz: str = "0 0 0") -> str:
    return (f'<joint name="{name}" type="fixed"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{xyz}"/></joint>')


# --- bodies: Pinocchio's, after merging fixed links ------------------------------------------

def test_frame_links_with_no_or_zero_inertial_load_alike(tmp_path):
    zero = ('<inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" '
            'izz="0"/></inertial>')
    body = ('<link name="base"/>' + revolute("hinge", "base", "arm")
            + f'<link name="arm">{BOX.format(x=0.1, m=0.4, i=1e-3)}</link>'
            + fixed("to_tool0", "arm", "tool0", "0.2 0 0") + '<link name="tool0"/>'
            + fixed("to_flange", "arm", "flange", "0.2 0 0") + f'<link name="flange">{zero}</link>')
    robot = load_robot(urdf(tmp_path, body))
    assert robot.model.inertias[1].mass == pytest.approx(0.4)
    assert robot.notes == ()


def test_a_massless_link_carrying_a_point_mass_on_a_fixed_joint_loads(tmp_path):
    # the old per-link check refused 'arm' (mass 0): the body Pinocchio builds is fine
    point = ('<inertial><mass value="0.5"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" '
             'izz="0"/></inertial>')
    body = ('<link name="base"/>' + revolute("hinge", "base", "arm", axis="0 1 0")
            + '<link name="arm"/>' + fixed("to_mass", "arm", "mass", "0.3 0 0")
            + f'<link name="mass">{point}</link>')
    robot = load_robot(urdf(tmp_path, body))
    horizontal = robot.configuration([[0.0]])[:, 0]
    tau = pin.computeGeneralizedGravity(robot.model, robot.model.createData(), horizontal)
    assert tau[0] == pytest.approx(-0.5 * 0.3 * STANDARD_GRAVITY, rel=1e-12)  # -m g r, by hand


def test_merged_body_named_with_its_links_when_not_physical(tmp_path):
    bad = BOX.format(x=0.0, m=0.2, i=1e-3).replace('izz="0.001"', 'izz="-0.01"')
    body = ('<link name="base"/>' + revolute("hinge", "base", "arm")
            + f'<link name="arm">{BOX.format(x=0.1, m=0.4, i=1e-3)}</link>'
            + fixed("to_camera", "arm", "camera") + f'<link name="camera">{bad}</link>')
    with pytest.raises(InputError, match="not positive semi-definite") as info:
        load_robot(urdf(tmp_path, body))
    assert info.value.field == "link[arm].inertial"
    assert "link 'arm' (with camera merged)" in str(info.value)


def test_namespaced_extensions_do_not_break_loading(tmp_path):
    # airo-models' UR files carry drake: tags and attributes with no namespace declared
    body = ('<link name="base"/>' + revolute("hinge", "base", "arm")
            + f'<link name="arm" drake:declare_convex="">{BOX.format(x=0.1, m=0.4, i=1e-3)}'
            '<collision><drake:proximity_properties><drake:compliant_hydroelastic/>'
            "</drake:proximity_properties></collision></link>")
    robot = load_robot(urdf(tmp_path, body))
    assert robot.joint_names == ("hinge",) and robot.file_order == ("hinge",)


# --- what the parser said, in one line ------------------------------------------------------

@pytest.mark.parametrize(("text", "reason"), [
    ('<robot><link name="a"/></robot>', "not a valid URDF robot: No name given for the robot"),
    ('<robot name="x"><link name="a"/>\n<link name="b"/>\n<joint name="j" type="revolute">'
     '<parent link="a"/><child link="b"/></joint></robot>',
     "Joint [j] is of type REVOLUTE but it does not specify limits (line 3)"),
    ('<robot name="x"><link name="a"/>\n<joint name="j" type="revolte"><parent link="a"/>'
     '<child link="b"/></joint><link name="b"/></robot>', "Joint [j] has no known type"),
    ('<robot name="x">\n<link name="a">\n</robot>',
     "malformed XML at line 2 (mismatched element: XMLElement name=link)"),
], ids=["no-name", "no-limits", "unknown-type", "xml"])
def test_urdf_parser_reason_in_one_line(tmp_path, capfd, text, reason):
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    assert main(["joints", str(path)]) == 2
    out, err = capfd.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith(f"hdselect: error: {path}: not a valid URDF robot: ")
    assert reason in err and ".cpp" not in err


def test_mjcf_parser_reason_is_the_message_not_the_source_location(tmp_path):
    path = tmp_path / "bad.xml"
    path.write_text('<mujoco><worldbody><body name="b"><joint name="j" type="weird"/>'
                    '<geom type="sphere" size="0.1"/></body></worldbody></mujoco>')
    with pytest.raises(InputError) as info:
        load_robot(path)
    assert info.value.reason == ("not a valid MJCF robot (MuJoCo's compiler): invalid keyword: "
                                 "'weird' (element 'joint', line 1)")


# --- armature, damping, friction, springs: the motor's and the joint's own ------------------

MJCF_LOSSY = """<mujoco model="pendulum">
  <worldbody>
    <body name="link" pos="0 0 0">
      <joint name="hinge" type="hinge" axis="0 1 0" range="-90 90" armature="0.05"
             damping="2.0" frictionloss="0.3" stiffness="5.0" springref="10"/>
      <inertial pos="0.2 0 0" mass="1.5" diaginertia="0.001 0.01 0.01"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_mjcf_armature_damping_friction_and_springs_never_reach_the_gear_torque(tmp_path):
    path = tmp_path / "pendulum.xml"
    path.write_text(MJCF_LOSSY)
    robot = load_robot(path)
    q = np.array([[0.0], [0.4], [-0.9]])
    qd = np.array([[0.0], [2.0], [-1.5]])
    qdd = np.array([[5.0], [-3.0], [8.0]])
    tau = inverse_dynamics(robot, q, qd, qdd)[:, 0]
    # by hand, the rigid pendulum alone: (I_yy + m r^2) qdd - m g r cos(q)
    m, r, i_yy = 1.5, 0.2, 0.01
    expected = (i_yy + m * r**2) * qdd[:, 0] - m * STANDARD_GRAVITY * r * np.cos(q[:, 0])
    np.testing.assert_allclose(tau, expected, rtol=1e-12, atol=1e-12)
    # Pinocchio's own model of the file does count armature: the difference is 0.05 qdd
    raw = pin.buildModelFromMJCF(str(path))
    raw.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    with_armature = [pin.rnea(raw, raw.createData(), q[k], qd[k], qdd[k])[0] for k in range(3)]
    np.testing.assert_allclose(np.array(with_armature) - tau, 0.05 * qdd[:, 0], atol=1e-12)
    armature, damping, friction, springs = robot.notes
    assert armature == ("armature on 1 joint (up to 0.05 kg m^2 or kg): the motor's reflected "
                        "inertia, not load on the gear output; left out")
    assert damping.startswith("damping on 1 joint (up to 2 N m s/rad or N s/m)")
    assert friction.startswith("frictionloss on 1 joint (up to 0.3 N m or N)")
    assert springs.startswith("springs (stiffness) on 1 joint (up to 5 N m/rad or N/m)")


def test_the_assumption_is_printed_in_every_size_report(capsys, tmp_path):
    report = tmp_path / "r.json"
    assert main(["size", str(REPO / "trajectories" / "planar2_pick_place.toml"),
                 "--json", str(report)]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert ("joint losses: the robot file's armature, joint damping, friction and springs are "
            "the motor's and the joint's own, not load on the gear output: left out") in out
    assert "armature" in json.loads(report.read_text())["assumptions"]["joint_losses"]


# --- mimic joints ---------------------------------------------------------------------------


def test_followers_follow_their_leader_and_get_no_gearhead(tmp_path):
    robot = load_robot(gripper(tmp_path))
    assert robot.joint_names == ("arm_joint", "finger_joint")
    assert robot.sized_joints == ("arm_joint", "finger_joint")
    assert robot.mimic["right_outer"] == hdselect.robot.model.Mimic("finger_joint", -1.0, 0.1,
                                                                     -2.0, 2.0)
    assert robot.joint_type("left_inner") == "mimic"
    # virtual work: the leader carries its own torque plus each follower's, times its multiplier
    free = pin.buildModelFromUrdf(str(robot.path))  # followers as independent joints
    free.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    rng = np.random.default_rng(3)
    q, qd, qdd = rng.uniform(-1, 1, (3, 6, 2))
    tau = inverse_dynamics(robot, q, qd, qdd)
    ids = {name: free.joints[free.getJointId(name)].idx_v for name in
           ("arm_joint", "finger_joint", "left_inner", "right_outer")}
    for k in range(6):
        full = np.zeros((3, free.nv))
        for row, x in enumerate((q[k], qd[k], qdd[k])):
            full[row, ids["arm_joint"]], full[row, ids["finger_joint"]] = x
            full[row, ids["left_inner"]] = x[1]
            full[row, ids["right_outer"]] = -x[1] + (0.1 if row == 0 else 0.0)
        each = pin.rnea(free, free.createData(), *full)
        assert tau[k, 0] == pytest.approx(each[ids["arm_joint"]], rel=1e-12, abs=1e-12)
        assert tau[k, 1] == pytest.approx(each[ids["finger_joint"]] + each[ids["left_inner"]]
                                          - each[ids["right_outer"]], rel=1e-12, abs=1e-12)


def test_a_follower_cannot_be_sized_or_given_a_limit(tmp_path):
    robot = load_robot(gripper(tmp_path))
    with pytest.raises(InputError, match="'left_inner' follows 'finger_joint' \\(mimic\\)"):
        robot.with_sized_joints(["arm_joint", "left_inner"])
    motion = tmp_path / "m.toml"
    motion.write_text('robot = "gripper.urdf"\nplanner = "ruckig"\nangle_unit = "deg"\n'
                      "[limits]\nacceleration = 100\njerk = 1000\nvelocity = {left_inner = 1}\n"
                      "[[waypoint]]\nq = [0, 0]\n[[waypoint]]\nq = [10, 10]\n")
    with pytest.raises(InputError, match="follows 'finger_joint' \\(mimic\\); give its leader"):
        hdselect.load_motion(motion)


def test_size_reports_followers_as_driven_by_their_leader(tmp_path):
    robot = load_robot(gripper(tmp_path))
    motion = tmp_path / "m.toml"
    motion.write_text('robot = "gripper.urdf"\nplanner = "ruckig"\nangle_unit = "deg"\n'
                      'dt = 0.005\n[limits]\n'
                      "acceleration = 300\njerk = 3000\n[[waypoint]]\nq = [0, 0]\n"
                      "[[waypoint]]\nq = [30, 20]\n")
    result = hdselect.size(robot, motion)
    assert [j.name for j in result.joints] == ["arm_joint", "finger_joint"]
    loads = {load.name: load for load in result.loads}
    assert loads["right_outer"].note == "driven by finger_joint (x -1)"
    assert loads["right_outer"].peak is None
    np.testing.assert_allclose(loads["right_outer"].travel,
                               (-math.radians(20) + 0.1, 0.1), atol=1e-9)


def test_followers_pinocchio_cannot_couple_become_unsized_joints_and_say_so(tmp_path):
    # Pinocchio visits sibling joints by name: a follower named before its leader fails
    robot = load_robot(gripper(tmp_path, ("a_follower", "b_follower")))
    assert robot.uncoupled_followers == ("a_follower", "b_follower")
    assert robot.mimic == {}
    assert "a_follower" in robot.joint_names and "a_follower" not in robot.sized_joints
    (note,) = [n for n in robot.notes if "mimic" in n]
    assert note.startswith("Pinocchio cannot couple the mimic joints")
    assert "a_follower, b_follower move as independent joints here" in note


# --- the base -------------------------------------------------------------------------------

def legged(tmp_path: Path) -> Path:
    """A 6 kg body with two 1 kg legs (knees 0.2 m below it): a biped left unbolted."""
    body = f'<link name="torso">{BOX.format(x=0.0, m=6.0, i=0.05)}</link>'
    for side, y in (("left", 0.1), ("right", -0.1)):
        body += (revolute(f"{side}_hip", "torso", f"{side}_thigh", axis="0 1 0", xyz=f"0 {y} 0")
                 + f'<link name="{side}_thigh">{BOX.format(x=0.0, m=0.6, i=1e-3)}</link>'
                 + revolute(f"{side}_knee", f"{side}_thigh", f"{side}_shin", axis="0 1 0",
                            xyz="0 0 -0.2")
                 + f'<link name="{side}_shin">{BOX.format(x=0.0, m=0.4, i=1e-3)}</link>'
                 + fixed(f"{side}_ankle", f"{side}_shin", f"{side}_foot", "0 0 -0.2")
                 + f'<link name="{side}_foot"/>')
    return urdf(tmp_path, body, "biped.urdf")


def test_a_root_standing_on_legs_is_held_fixed_with_a_warning(tmp_path):
    robot = load_robot(legged(tmp_path))
    assert robot.root_link == "torso"
    (note,) = robot.notes
    assert note.startswith("the root link 'torso' is held fixed, yet 2 chains (1, 1 kg) hang 0.2 m")


def test_an_arm_on_its_base_gets_no_warning():
    robot = load_robot(robot_path("benchtop6"))
    assert robot.root_link == "base_link" and robot.notes == ()


def test_loading_prints_nothing(tmp_path, capfd):
    load_robot(gripper(tmp_path))
    load_robot(robot_path("scara"))
    assert capfd.readouterr() == ("", "")
