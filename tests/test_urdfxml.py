"""A URDF is read as the format defines it, or refused (hdselect.robot.urdfxml, urdfcheck).

Each class of file urdfdom reads otherwise than it is written (issue 17) is refused
with one line naming the file, the link or joint and the attribute; each variant a
URDF reader must accept gives exactly the model of the plain file. The oracle for
"exactly" is the shipped planar2, whose torques test_robot checks against the
closed form of a two-link arm.
"""

from __future__ import annotations

import io
import math
import os
import re
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.pinurdf import build_urdf
from hdselect.robot.urdfcheck import check_model
from hdselect.robot.urdfxml import parse_elements, read_urdf_tree
from helpers import REPO
from helpers.robots import FINGER, example_robots

PLANAR2 = (REPO / "robots" / "planar2.urdf").read_text()
MOTION = REPO / "trajectories" / "planar2_pick_place.toml"
MASS = '<mass value="0.243"/>'
INERTIA = ('<inertia ixx="2.025e-05" ixy="0" ixz="0" iyy="0.00184072" iyz="0" '
           'izz="0.00182452"/>')
LINK1_ORIGIN = '<origin xyz="0.15 0 0" rpy="0 0 0"/>\n      <mass'
ELBOW_AXIS = '<axis xyz="0 -1 0"/>\n    <limit lower="-2.6179939"'
ELBOW_LIMIT = '<limit lower="-2.6179939" upper="2.6179939"'


def variant(tmp_path: Path, old: str, new: str, name: str = "variant.urdf") -> Path:
    """planar2 with `old` replaced by `new` once (`old` must be there)."""
    assert PLANAR2.count(old) >= 1, old
    path = tmp_path / name
    path.write_text(PLANAR2.replace(old, new, 1))
    return path


def refused(argv: list[str]) -> str:
    """Run the command line; it must refuse with exit 2 and exactly one line. The line."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(argv)
    assert status == 2 and out.getvalue() == "", (status, err.getvalue())
    assert err.getvalue().count("\n") == 1, err.getvalue()
    return err.getvalue().strip()


def torques(robot: hdselect.Robot) -> np.ndarray:
    """The robot's torques at a few fixed states [N m]."""
    rng = np.random.default_rng(7)
    q, qd, qdd = rng.uniform(-1.0, 1.0, (3, 5, robot.dof))
    return inverse_dynamics(robot, q, qd, qdd)


# --- what urdfdom drops: refused, naming the link and the attribute -----------------------

@pytest.mark.parametrize(("old", "new", "field", "reason"), [
    (MASS, '<mass value="nan"/>', "link[link1].inertial.mass", "'nan' is not a number"),
    (MASS, '<mass value="0.243kg"/>', "link[link1].inertial.mass", "'0.243kg' is not a number"),
    (MASS, '<mass value=""/>', "link[link1].inertial.mass", "'' is not a number"),
    (MASS, '<mass value="0.243 "/>', "link[link1].inertial.mass", "'0.243 ' is not a number"),
    (MASS, '<mass value="1e400"/>', "link[link1].inertial.mass", "too large"),
    (MASS, "", "link[link1].inertial", "has no <mass>"),
    (MASS, "<mass/>", "link[link1].inertial.mass", "<mass> has no value"),
    (MASS, '<mass value="${m1}"/>', "link[link1].inertial.mass",
     "'${m1}' is an unexpanded xacro expression; name the file .xacro"),
    ('izz="0.00182452"', 'izz="nan"', "link[link1].inertial.inertia.izz", "'nan' is not a"),
    (' izz="0.00182452"', "", "link[link1].inertial.inertia", "<inertia> has no izz"),
    (INERTIA, "", "link[link1].inertial", "has no <inertia>"),
    (LINK1_ORIGIN, '<origin xyz="0.15 0"/>\n      <mass', "link[link1].inertial.origin.xyz",
     "'0.15 0' is not 3 numbers"),
    (LINK1_ORIGIN, '<origin xyz="0.15\t0\t0"/>\n      <mass', "link[link1].inertial",
     "Pinocchio's body moved by joint 'shoulder' has mass 0 kg, the file's links (link1) 0.243"),
    (LINK1_ORIGIN, '<origin xyz="0.15 0 0" rpy="0 0"/>\n      <mass',
     "link[link1].inertial.origin.rpy", "'0 0' is not 3 numbers"),
], ids=["mass-nan", "mass-kg", "mass-empty", "mass-trailing-blank", "mass-overflow",
        "mass-missing", "mass-no-value", "mass-xacro", "izz-nan", "izz-missing",
        "inertia-missing", "origin-two-numbers", "origin-tabs", "rpy-two-numbers"])
def test_an_inertial_urdfdom_would_drop_is_refused_naming_link_and_attribute(
        tmp_path, old, new, field, reason):
    path = variant(tmp_path, old, new)
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert info.value.field == field and reason in info.value.reason
    assert "urdfdom would drop the link's whole <inertial>" in info.value.reason \
        or "xacro" in reason or "has no" in reason or "urdfdom said: Unable to parse" in \
        info.value.reason  # tabs: XML reads blanks, urdfdom does not; the check finds it
    line = refused(["size", str(path), str(MOTION)])
    assert line.split() == f"hdselect: error: {path}: {field}: {info.value.reason}".split()


def test_pinocchio_alone_drops_such_an_inertial():
    """The class is real: urdfdom gives link1 no mass at all, and says so only on stderr."""
    text = PLANAR2.replace(MASS, '<mass value="0.243kg"/>')
    saved = os.dup(2)
    with open(os.devnull, "w") as sink:
        os.dup2(sink.fileno(), 2)
        try:
            model = pin.buildModelFromXML(text)
        finally:
            os.dup2(saved, 2)
            os.close(saved)
    assert model.inertias[model.getJointId("shoulder")].mass == 0.0


@pytest.mark.parametrize(("old", "new"), [
    (MASS, '<mass value="+0.243"/>'), (MASS, '<mass value="2.43e-1"/>'),
    (MASS, '<mass value="  0.243"/>'), (MASS, '<mass value=".243"/>'),
    (LINK1_ORIGIN, '<origin xyz=" 0.15  0 0 " rpy="0 0 0"/>\n      <mass'),
    (ELBOW_AXIS, '<axis xyz="0 -2 0"/>\n    <limit lower="-2.6179939"'),
], ids=["plus", "exponent", "leading-blanks", "no-leading-zero", "blanks-in-vector",
        "axis-not-unit"])
def test_what_urdf_allows_gives_exactly_the_plain_model(tmp_path, old, new):
    plain = hdselect.load_robot(REPO / "robots" / "planar2.urdf")
    robot = hdselect.load_robot(variant(tmp_path, old, new))
    np.testing.assert_array_equal(torques(robot), torques(plain))


@pytest.mark.parametrize("axis", ["0 0 0", "nan 0 0", "0 1", "1e-13 0 0"])
def test_a_joint_axis_without_direction_is_refused_naming_the_joint(tmp_path, axis):
    path = variant(tmp_path, ELBOW_AXIS, f'<axis xyz="{axis}"/>\n    <limit lower="-2.6179939"')
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert info.value.field == "joint[elbow].axis"
    line = refused(["joints", str(path)])
    assert "joint[elbow].axis" in line


@pytest.mark.parametrize(("old", "new", "field"), [
    ('velocity="4.0"', 'velocity="-4.0"', "joint[shoulder].limit.velocity"),
    ('effort="8.0"', 'effort="-8"', "joint[elbow].limit.effort"),
])
def test_a_negative_velocity_or_effort_limit_is_refused_naming_the_joint(tmp_path, old, new,
                                                                        field):
    """urdfdom's own words name neither the joint nor the attribute."""
    path = variant(tmp_path, old, new)
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert info.value.field == field
    value = new.split('"')[1].removesuffix(".0")
    key = field.rsplit(".", 1)[1]
    assert info.value.reason == (f"is {value}; a limit's {key} is a magnitude, 0 or more "
                                 "(urdfdom refuses a negative one)")
    line = refused(["joints", str(path)])
    assert line == f"hdselect: error: {path}: {field}: {info.value.reason}"


def test_a_link_with_two_parent_joints_is_refused_naming_the_link_and_both_joints(tmp_path):
    path = variant(tmp_path, "</robot>", '<joint name="extra" type="fixed"><parent '
                   'link="base_link"/><child link="link2"/></joint>\n</robot>')
    line = refused(["joints", str(path)])
    assert line == (f"hdselect: error: {path}: link[link2]: is the child of 2 joints (elbow, "
                    "extra); a URDF is a tree, each link the child of one joint (urdfdom would "
                    "keep one of them and lose the rest)")


@pytest.mark.parametrize(("mimic", "field"), [
    ('multiplier="1" offset="1e308"', "joint[finger].mimic.offset"),
    ('multiplier="1e308"', "joint[finger].mimic.multiplier"),
    ('multiplier="x"', "joint[finger].mimic.multiplier"),
])
def test_a_mimic_out_of_range_is_refused_at_load(tmp_path, mimic, field):
    path = tmp_path / "finger.urdf"
    path.write_text(PLANAR2.replace("</robot>", FINGER.format(mimic=f'<mimic joint="elbow" '
                                                                    f'{mimic}/>') + "</robot>"))
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert info.value.field == field


# --- limits 0 .. 0: no range given ---------------------------------------------------------

def test_a_revolute_joint_limited_0_to_0_is_unlimited_with_a_note(tmp_path):
    path = variant(tmp_path, ELBOW_LIMIT, '<limit lower="0" upper="0"')
    robot = hdselect.load_robot(path)
    elbow = robot.joint_index("elbow")
    assert (robot.lower[elbow], robot.upper[elbow]) == (-math.inf, math.inf)
    assert ("joint elbow: the file's position limits are 0 .. 0 (no range given): treated as "
            "unlimited, as a continuous joint") in robot.notes
    continuous = hdselect.load_robot(variant(tmp_path, '"elbow" type="revolute"',
                                             '"elbow" type="continuous"', "continuous.urdf"))
    np.testing.assert_allclose(torques(robot), torques(continuous), rtol=1e-14, atol=1e-14)
    assert robot.joint_type("elbow") == "revolute"  # one coordinate, no limits


def test_the_same_size_as_the_continuous_joint(tmp_path):
    """The sizing of a joint limited 0 .. 0 equals the sizing of the same joint continuous."""
    zero = hdselect.size(variant(tmp_path, ELBOW_LIMIT, '<limit lower="0" upper="0"'), MOTION)
    free = hdselect.size(variant(tmp_path, '"elbow" type="revolute"',
                                 '"elbow" type="continuous"', "continuous.urdf"), MOTION)
    for a, b in zip(zero.joints, free.joints, strict=True):
        assert a.selected == b.selected
        np.testing.assert_allclose(a.torque, b.torque, rtol=1e-12, atol=1e-12)


# --- SDF ----------------------------------------------------------------------------------

def test_an_sdf_file_is_named_as_such(tmp_path):
    path = tmp_path / "arm.sdf"
    path.write_text('<?xml version="1.0"?>\n<sdf version="1.6"><model name="arm">'
                    '<link name="base"/></model></sdf>\n')
    line = refused(["joints", str(path)])
    assert line == (f"hdselect: error: {path}: an SDF file (root element <sdf>): SDF is not "
                    "supported; hdselect reads URDF, xacro and MJCF (convert it to URDF or MJCF)")


# --- the check of Pinocchio's model against the file can fail -------------------------------

def parsed(text: str):
    path = Path("planar2.urdf")
    root = parse_elements(text.encode())
    assert root is not None
    return build_urdf(path, text, mimic=True), read_urdf_tree(root, path), path


def lighter_link1(model: pin.Model) -> None:
    body = model.inertias[1]
    model.inertias[1] = pin.Inertia(0.2, body.lever, body.inertia)


def elbow_further_out(model: pin.Model) -> None:
    model.jointPlacements[2] = pin.SE3(np.eye(3), np.array([0.31, 0.0, 0.0]))


def elbow_upper_limit_2(model: pin.Model) -> None:
    upper = model.upperPositionLimit.copy()
    upper[1] = 2.0
    model.upperPositionLimit = upper


def shoulder_effort_21(model: pin.Model) -> None:
    effort = model.upperEffortLimit.copy()
    effort[0] = 21.0
    model.upperEffortLimit = effort


@pytest.mark.parametrize(("change", "field", "reason"), [
    (lighter_link1, "link[link1].inertial", "Pinocchio's body moved by joint 'shoulder' has "
     "mass 0.2 kg, the file's links (link1) 0.243 kg"),
    (elbow_further_out, "joint[elbow].origin", "Pinocchio places it at xyz 0.31 0 0, the file "
     "at 0.3 0 0"),
    (elbow_upper_limit_2, "joint[elbow].limit.upper", "Pinocchio reads 2, the file says 2.61799"),
    (shoulder_effort_21, "joint[shoulder].limit.effort", "Pinocchio reads 21, the file says 20"),
])
def test_a_model_that_differs_from_the_file_is_refused(change, field, reason):
    model, tree, path = parsed(PLANAR2)
    check_model(model, tree, path)  # as Pinocchio built it: the same
    change(model)
    with pytest.raises(InputError) as info:
        check_model(model, tree, path)
    assert info.value.field == field and info.value.reason.startswith(reason)


@pytest.mark.slow
def test_every_urdf_of_example_robot_data_passes_the_check():
    """Real files (zero-mass frame links, point masses on fixed joints, mimic joints)."""
    folder = example_robots()
    checked = 0
    for path in sorted(folder.rglob("*.urdf")):
        data = path.read_bytes()
        root = parse_elements(data)
        if root is None or root.tag != "robot":
            continue
        try:
            tree = read_urdf_tree(root, path)
            model = build_urdf(path, None, mimic=False)
        except InputError as err:
            assert re.search(r"No name given|limit\.lower: must be a position", str(err)), err
            continue
        check_model(model, tree, path)
        checked += 1
    assert checked >= 60
