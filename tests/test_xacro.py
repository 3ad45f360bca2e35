"""A .xacro robot is expanded by the xacro package (hdselect.robot.xacrofile), arguments and all.

The oracle is the same robot written out by hand as plain URDF: planar2 carrying a
gripper of the given mass, which the xacro version builds from a property, an
included macro and an argument.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.robot.dynamics import inverse_dynamics
from helpers import REPO, run_redirected

PLANAR2 = (REPO / "robots" / "planar2.urdf").read_text()
MOTION = (REPO / "trajectories" / "planar2_pick_place.toml").read_text()

GRIPPER_MACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="gripper" params="parent mass">
    <joint name="gripper_mount" type="fixed">
      <parent link="${parent}"/><child link="gripper"/><origin xyz="0.25 0 0"/>
    </joint>
    <link name="gripper">
      <inertial>
        <origin xyz="0.04 0 0"/><mass value="${mass}"/>
        <inertia ixx="${mass * 0.0004}" ixy="0" ixz="0" iyy="${mass * 0.0006}" iyz="0"
                 izz="${mass * 0.0006}"/>
      </inertial>
    </link>
  </xacro:macro>
</robot>
"""

BY_HAND = """
  <joint name="gripper_mount" type="fixed">
    <parent link="link2"/><child link="gripper"/><origin xyz="0.25 0 0"/>
  </joint>
  <link name="gripper">
    <inertial>
      <origin xyz="0.04 0 0"/><mass value="{m}"/>
      <inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" iyz="0" izz="{iyy}"/>
    </inertial>
  </link>
</robot>
"""


def xacro_robot(folder: Path) -> Path:
    """planar2 with a property for link1's mass and an included 2 kg gripper (an argument)."""
    (folder / "parts").mkdir(exist_ok=True)
    (folder / "parts" / "gripper.xacro").write_text(GRIPPER_MACRO)
    text = PLANAR2.replace(
        '<robot name="planar2">',
        '<robot name="planar2" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="m1" value="0.243"/>\n'
        '  <xacro:arg name="gripper_mass" default="2.0"/>\n'
        '  <xacro:include filename="parts/gripper.xacro"/>')
    text = text.replace('<mass value="0.243"/>', '<mass value="${m1}"/>')
    text = text.replace("</robot>", '  <xacro:gripper parent="link2" '
                                    'mass="$(arg gripper_mass)"/>\n</robot>')
    path = folder / "planar2_gripper.urdf.xacro"
    path.write_text(text)
    return path


def by_hand(folder: Path, mass: float) -> Path:
    path = folder / f"by_hand_{mass:g}.urdf"
    path.write_text(PLANAR2.replace("</robot>", BY_HAND.format(
        m=mass, ixx=repr(mass * 0.0004), iyy=repr(mass * 0.0006))))
    return path


def same_dynamics(a: hdselect.Robot, b: hdselect.Robot) -> None:
    rng = np.random.default_rng(3)
    q, qd, qdd = rng.uniform(-1.0, 1.0, (3, 6, a.dof))
    np.testing.assert_allclose(inverse_dynamics(a, q, qd, qdd), inverse_dynamics(b, q, qd, qdd),
                               rtol=1e-13, atol=1e-13)
    assert a.moved_mass("shoulder") == pytest.approx(b.moved_mass("shoulder"), rel=1e-14)


@pytest.mark.parametrize(("arguments", "mass"), [(None, 2.0), ({"gripper_mass": "1.0"}, 1.0),
                                                 ({"gripper_mass": 0.5}, 0.5)])
def test_includes_properties_and_arguments_are_expanded(tmp_path, arguments, mass):
    robot = hdselect.load_robot(xacro_robot(tmp_path), xacro_args=arguments)
    same_dynamics(robot, hdselect.load_robot(by_hand(tmp_path, mass)))
    assert robot.moved_mass("shoulder") == pytest.approx(0.243 + 0.16875 + mass)
    assert dict(robot.xacro_args) == ({} if arguments is None else
                                      {k: str(v) for k, v in arguments.items()})


def test_the_command_line_takes_xacro_arguments(tmp_path):
    path = xacro_robot(tmp_path)
    status, out, err = run_redirected(["joints", str(path), "--xacro-arg", "gripper_mass:=1.0",
                                       "--json", "-"])
    assert status == 0 and err == ""
    listed = {joint["name"]: joint for joint in json.loads(out)["joints"]}
    assert listed["shoulder"]["moved_mass_kg"] == pytest.approx(0.243 + 0.16875 + 1.0)


@pytest.mark.slow
def test_a_motion_file_gives_its_xacro_robot_arguments_and_the_command_line_overrides(tmp_path):
    path = xacro_robot(tmp_path)
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.replace('robot = "../robots/planar2.urdf"',
                                     f'robot = "{path.name}"\nxacro_args = {{gripper_mass = '
                                     '"1.0"}'))
    assert f'robot = "{path.name}"' in motion.read_text()
    robot, loaded = hdselect.load_case(motion)
    same_dynamics(robot, hdselect.load_case(motion, by_hand(tmp_path, 1.0))[0])
    assert loaded.xacro_args == {"gripper_mass": "1.0"}
    given = hdselect.size(None, motion)
    expected = hdselect.size(by_hand(tmp_path, 1.0), motion)
    assert [j.selected for j in given.joints] == [j.selected for j in expected.joints]
    for report in ("a.json", "b.json"):
        flag = ["--xacro-arg", "gripper_mass:=0.5"] if report == "a.json" else []
        robot_file = [] if flag else [str(by_hand(tmp_path, 0.5))]
        status, _, err = run_redirected(["size", *robot_file, str(motion), *flag, "--json",
                                         str(tmp_path / report)])
        assert status in (0, 1), err
    a, b = (json.loads((tmp_path / r).read_text()) for r in ("a.json", "b.json"))
    assert [j["peak_torque_nm"] for j in a["joints"]] == pytest.approx(
        [j["peak_torque_nm"] for j in b["joints"]], rel=1e-12)


@pytest.mark.parametrize(("argv", "field", "reason"), [
    (["--xacro-arg", "gripper_mass=1"], "--xacro-arg", "expected name:=value, got "
     "'gripper_mass=1'"),
    (["--xacro-arg", ":=1"], "--xacro-arg", "expected an argument name, got ''"),
    (["--xacro-arg", "gripper_mass:=1", "--xacro-arg", "gripper_mass:=2"], "--xacro-arg",
     "gripper_mass given twice (1 and 2); give it once"),  # the last won unseen, before
])
def test_a_malformed_argument_is_one_line(tmp_path, argv, field, reason):
    status, out, err = run_redirected(["joints", str(xacro_robot(tmp_path)), *argv])
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err == f"hdselect: error: {field}: {reason}\n"


def test_arguments_for_a_file_that_takes_none_are_refused():
    status, _, err = run_redirected(["joints", str(REPO / "robots" / "planar2.urdf"), "--xacro-arg",
                                     "a:=1"])
    assert status == 2 and err.count("\n") == 1
    assert "--xacro-arg: xacro arguments given (a) for a URDF file; only a .xacro file" in err


@pytest.mark.parametrize(("change", "reason"), [
    (lambda t: t.replace("parts/gripper.xacro", "parts/missing.xacro"), "No such file"),
    (lambda t: t.replace("$(arg gripper_mass)", "$(arg no_such_argument)"),
     "no_such_argument"),
    (lambda t: t.replace("${m1}", "${m1 *}"), "invalid syntax"),
    (lambda t: t.replace("parts/gripper.xacro", "package://nowhere/gripper.xacro"),
     "ROS package paths need a ROS installation"),
])
def test_what_xacro_cannot_expand_is_one_line_naming_the_file(tmp_path, change, reason):
    path = xacro_robot(tmp_path)
    path.write_text(change(path.read_text()))
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert info.value.path == path and info.value.reason.startswith("xacro cannot expand it: ")
    assert reason in info.value.reason
    status, out, err = run_redirected(["joints", str(path)])
    assert status == 2 and out == "" and err.count("\n") == 1 and str(path) in err


def test_a_urdf_named_file_holding_xacro_elements_is_expanded_too(tmp_path):
    path = xacro_robot(tmp_path).rename(tmp_path / "planar2_gripper.urdf")
    same_dynamics(hdselect.load_robot(path), hdselect.load_robot(by_hand(tmp_path, 2.0)))


def test_init_writes_the_xacro_arguments_into_the_starter(tmp_path):
    path = xacro_robot(tmp_path)
    status, _, err = run_redirected(["init", str(path), "--xacro-arg", "gripper_mass:=1.0", "--out",
                                     str(tmp_path / "starter.toml")])
    assert status == 0, err
    assert 'xacro_args = {gripper_mass = "1.0"}' in (tmp_path / "starter.toml").read_text()
    robot, _ = hdselect.load_case(tmp_path / "starter.toml")
    same_dynamics(robot, hdselect.load_robot(by_hand(tmp_path, 1.0)))


@pytest.mark.slow
@pytest.mark.parametrize(("command", "output"), [
    ("size", "--json"), ("compare", "--json"), ("fastest", "--json"), ("max-payload", "--json"),
    ("plan", "--out"), ("joints", "--json"), ("init", "--out")])
def test_every_command_takes_xacro_arguments(tmp_path, command, output):
    """--xacro-arg changes what each command writes (the gripper's mass)."""
    path = xacro_robot(tmp_path)
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.replace('robot = "../robots/planar2.urdf"', f'robot = "{path.name}"'))
    written = []
    suffix = {"plan": "csv", "init": "toml"}.get(command, "json")
    for tag, extra in (("default", []), ("given", ["--xacro-arg", "gripper_mass:=0.2"])):
        out = tmp_path / f"{tag}.{suffix}"
        target = [str(path)] if command in ("joints", "init") else [str(motion)]
        status, _, err = run_redirected([command, *target, *extra, output, str(out)])
        assert status in (0, 1), err
        written.append(out.read_text())
    assert written[0] != written[1]


@pytest.mark.slow
def test_a_mix_on_a_xacro_robot_takes_xacro_arguments(tmp_path):
    """A mix file names its robot itself: --xacro-arg expands that robot too (the gripper's
    mass changes the day's answer), and reaches every task."""
    path = xacro_robot(tmp_path)
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.replace('robot = "../robots/planar2.urdf"', f'robot = "{path.name}"'))
    mix = tmp_path / "day.toml"
    mix.write_text(f'robot = "{path.name}"\n\n[[task]]\nname = "a"\nmotion = "motion.toml"\n'
                   'share = 0.6\n\n[[task]]\nname = "b"\nmotion = "motion.toml"\nshare = 0.4\n')
    written = []
    for tag, extra in (("default", []), ("given", ["--xacro-arg", "gripper_mass:=0.2"])):
        out = tmp_path / f"{tag}.json"
        status, _, err = run_redirected(["size", str(mix), *extra, "--json", str(out)])
        assert status in (0, 1), err
        written.append(json.loads(out.read_text()))
    assert written[0]["joints"] != written[1]["joints"]
    peaks = [[joint["peak_torque_nm"] for joint in doc["joints"]] for doc in written]
    assert peaks[1][0] < peaks[0][0]  # a lighter gripper: less torque at the shoulder


@pytest.mark.slow
def test_the_envelope_takes_xacro_arguments(tmp_path):
    """envelope reads a robot file too: --xacro-arg expands it (a lighter gripper, less
    worst-case torque at the shoulder); an argument for a plain URDF is refused by flag."""
    path = xacro_robot(tmp_path)
    peaks = []
    for tag, extra in (("default", []), ("given", ["--xacro-arg", "gripper_mass:=0.2"])):
        out = tmp_path / f"{tag}.json"
        status, _, err = run_redirected(["envelope", str(path), "--acceleration", "200", *extra,
                                         "--json", str(out)])
        assert status in (0, 1), err
        peaks.append(json.loads(out.read_text())["joints"][0])
    assert peaks[0] != peaks[1]
    status, _, err = run_redirected(["envelope", str(REPO / "robots" / "planar2.urdf"),
                                     "--acceleration", "200", "--xacro-arg", "gripper_mass:=0.2"])
    assert status == 2 and "--xacro-arg" in err and len(err.strip().splitlines()) == 1, err


def test_an_argument_the_file_does_not_declare_is_refused_naming_its_arguments(tmp_path):
    """xacro itself drops a misspelt argument: the 2 kg default gripper would be sized."""
    path = xacro_robot(tmp_path)
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path, xacro_args={"gripper_mas": "1.0"})
    assert info.value.path == path and info.value.field == "xacro_args.gripper_mas"
    assert info.value.reason == ("planar2_gripper.urdf.xacro has no xacro argument "
                                 "'gripper_mas'; its arguments are: gripper_mass")
    for command in (["joints", str(path)], ["envelope", str(path), "--acceleration", "200"]):
        status, out, err = run_redirected([*command, "--xacro-arg", "gripper_mas:=1.0"])
        assert status == 2 and out == "", err
        assert err == ("hdselect: error: --xacro-arg: planar2_gripper.urdf.xacro has no xacro "
                       "argument 'gripper_mas'; its arguments are: gripper_mass\n")


def test_an_undeclared_argument_of_a_motion_file_names_the_motion_file(tmp_path):
    path = xacro_robot(tmp_path)
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.replace('robot = "../robots/planar2.urdf"',
                                     f'robot = "{path.name}"\nxacro_args = {{nosuch = "1"}}'))
    expected = (f"{motion}: xacro_args.nosuch: planar2_gripper.urdf.xacro has no xacro "
                "argument 'nosuch'; its arguments are: gripper_mass")
    with pytest.raises(InputError) as info:
        hdselect.load_case(motion)
    assert str(info.value) == expected
    status, out, err = run_redirected(["size", str(motion)])
    assert status == 2 and out == "" and err == f"hdselect: error: {expected}\n"
    status, _, err = run_redirected(["size", str(motion), "--xacro-arg", "nosuch:=2"])  # overridden
    assert status == 2 and err.startswith("hdselect: error: --xacro-arg: planar2_gripper"), err


def test_an_argument_read_by_arg_without_a_declaration_is_the_files_own(tmp_path):
    """``$(arg name)`` with no ``<xacro:arg>`` takes the value given (as ROS launch does)."""
    path = xacro_robot(tmp_path)
    path.write_text(path.read_text().replace(
        '  <xacro:arg name="gripper_mass" default="2.0"/>\n', ""))
    robot = hdselect.load_robot(path, xacro_args={"gripper_mass": "1.0"})
    same_dynamics(robot, hdselect.load_robot(by_hand(tmp_path, 1.0)))


@pytest.mark.parametrize("value", ["", "  "])
def test_an_empty_argument_value_is_refused(tmp_path, value):
    status, out, err = run_redirected(["joints", str(xacro_robot(tmp_path)), "--xacro-arg",
                                       f"gripper_mass:={value}"])
    assert status == 2 and out == ""
    assert err == "hdselect: error: --xacro-arg: no value given for gripper_mass\n"
    with pytest.raises(InputError, match="no value given for gripper_mass") as info:
        hdselect.load_robot(xacro_robot(tmp_path), xacro_args={"gripper_mass": value})
    assert info.value.field == "xacro_args.gripper_mass"


@pytest.mark.parametrize(("value", "shown"), [("nan", "'nan' is not a number"),
                                              ("1e400", "'inf' is not a number"),
                                              ("-1", "got -1")])
def test_a_bad_number_from_an_argument_is_blamed_on_the_argument_and_its_source(
        tmp_path, value, shown):
    path = xacro_robot(tmp_path)
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.replace(
        'robot = "../robots/planar2.urdf"',
        f'robot = "{path.name}"\nxacro_args = {{gripper_mass = "{value}"}}'))
    said = (f"gripper_mass:={value} makes link[gripper].inertial.mass of the expanded "
            "planar2_gripper.urdf.xacro fail: ")
    status, out, err = run_redirected(["size", str(motion)])
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"hdselect: error: {motion}: xacro_args.gripper_mass: {said}")
    assert shown in err
    status, out, err = run_redirected(["joints", str(path), "--xacro-arg",
                                       f"gripper_mass:={value}"])
    assert status == 2 and err.startswith(f"hdselect: error: --xacro-arg: {said}"), err


def test_a_bad_number_no_single_argument_gives_lists_the_arguments(tmp_path):
    path = xacro_robot(tmp_path)
    path.write_text(path.read_text().replace('value="${m1}"', 'value="nan"'))
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path, xacro_args={"gripper_mass": "1.0"})
    assert info.value.field == "link[link1].inertial.mass"
    assert info.value.reason.endswith("(in the file expanded with the xacro arguments "
                                      "gripper_mass:=1.0)")
