"""Tests of hdselect.motion.starter and `hdselect init`: a starter motion that plans and sizes."""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.cli.main import main
from hdselect.motion.starter import ACCELERATION_TIME, JERK_TIME, starter_motion
from helpers import REPO
from helpers.robots import JOINTS, LIMIT, gripper, revolute, robot_path, urdf


@pytest.mark.parametrize("name", JOINTS)
def test_init_writes_a_motion_that_loads_plans_and_sizes(name, tmp_path, capsys):
    out = tmp_path / "motions" / f"{name}.toml"
    out.parent.mkdir()
    assert main(["init", str(robot_path(name)), "--out", str(out)]) == 0
    assert " ".join(capsys.readouterr().out.split()) == (  # may wrap
        f"wrote {out}; edit its waypoints, limits and payload, then: hdselect size {out}")
    doc = tomllib.loads(out.read_text())
    assert (out.parent / doc["robot"]).resolve() == robot_path(name).resolve()
    robot, motion = hdselect.load_case(out)
    assert motion.warnings == ()  # never above the file's velocity limits
    deg = np.where(robot.revolute, math.pi / 180, 1.0)
    for j, joint in enumerate(robot.joint_names):
        velocity = doc["limits"]["velocity"][joint] * deg[j]
        if math.isfinite(robot.velocity_limit[j]):
            assert velocity <= robot.velocity_limit[j] < velocity * 1.001
        assert doc["limits"]["acceleration"][joint] == pytest.approx(
            doc["limits"]["velocity"][joint] / ACCELERATION_TIME, rel=1e-5)
        assert doc["limits"]["jerk"][joint] == pytest.approx(
            doc["limits"]["acceleration"][joint] / JERK_TIME, rel=1e-5)
    start, second, back = motion.waypoints
    np.testing.assert_array_equal(start, back)
    assert np.all(start > robot.lower) and np.all(start < robot.upper)
    assert np.all(second >= robot.lower) and np.all(second <= robot.upper)
    assert np.all(np.abs(second - start) <= np.where(robot.revolute, math.radians(30), 0.05)
                  + 1e-12)
    result = hdselect.size(robot, motion)
    assert result.cycle_time > 1.5


def test_init_prints_to_stdout_and_never_overwrites(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["init", str(robot_path("planar2"))]) == 0
    text = capsys.readouterr().out
    written = Path(tomllib.loads(text)["robot"])  # absolute: where it is saved is not known
    assert written.is_absolute() and written.resolve() == robot_path("planar2").resolve()
    mine = tmp_path / "mine.toml"
    mine.write_text("# my edits\n")
    assert main(["init", str(robot_path("planar2")), "--out", str(mine)]) == 2
    assert "mine.toml: --out: exists; choose another path or remove it first" in \
        capsys.readouterr().err
    assert mine.read_text() == "# my edits\n"


def test_the_start_pose_keeps_off_a_limit_at_zero(tmp_path):
    # zero on a stop (like Z1's and SO-100's home poses): the start moves 10 % inside
    body = ('<link name="base"/>' + revolute("j", "base", "a").replace(
        LIMIT, '<limit lower="0" upper="2" effort="20" velocity="3"/>')
        + '<link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" '
          'iyy="0.01" iyz="0" izz="0.01"/></inertial></link>')
    robot = hdselect.load_robot(urdf(tmp_path, body))
    doc = tomllib.loads(starter_motion(robot, "robot.urdf"))
    start, second = (w["q"]["j"] for w in doc["waypoint"][:2])
    assert start == pytest.approx(round(math.degrees(0.2), 1))
    assert second == pytest.approx(start + 28.6, abs=0.05)  # 25 % of the 114.6 deg range


def test_followers_get_no_value_and_gripper_joints_a_hint(tmp_path):
    robot = hdselect.load_robot(gripper(tmp_path))
    text = starter_motion(robot, "gripper.urdf")
    doc = tomllib.loads(text)
    assert set(doc["waypoint"][0]["q"]) == {"arm_joint", "finger_joint"}
    assert '# exclude = ["finger_joint"]   # named like a gripper\'s' in text
    assert doc["sizing"] == {}


def test_joint_names_that_are_not_bare_keys_are_quoted(tmp_path):
    body = ('<link name="base"/>' + revolute("link_3.0 joint", "base", "a")
            + '<link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" '
              'iyy="0.01" iyz="0" izz="0.01"/></inertial></link>')
    robot = hdselect.load_robot(urdf(tmp_path, body))
    doc = tomllib.loads(starter_motion(robot, "robot.urdf"))
    assert list(doc["limits"]["velocity"]) == ["link_3.0 joint"]


@pytest.mark.parametrize("tool_poses", [False, True])
def test_a_printed_starter_saved_in_another_folder_plans(tool_poses, tmp_path, capsys,
                                                         monkeypatch):
    """`hdselect init robots/scara.urdf > out/x.toml` from the repository's root: the robot
    path the starter prints must hold from wherever the text is saved."""
    monkeypatch.chdir(REPO)
    assert main(["init", "robots/scara.urdf", *(["--tool-poses"] * tool_poses)]) == 0
    saved = tmp_path / "out" / "x.toml"
    saved.parent.mkdir()
    saved.write_text(capsys.readouterr().out)
    monkeypatch.chdir(tmp_path)
    assert main(["plan", "out/x.toml", "--out", "-"]) == 0
    assert capsys.readouterr().err == ""


def uncommented(text: str, keys: str) -> str:
    """`text` with its commented lines that start with one of `keys` (a regex) uncommented."""
    return re.sub(rf"^# ((?:{keys})(?=[ =]))", r"\1", text, flags=re.MULTILINE)


SUGGESTIONS = {
    "payload": lambda text: uncommented(text, r"\[payload\]|mass|com|frame"),
    "tolerances": lambda text: uncommented(text, "position_tolerance|orientation_tolerance"),
    "line": lambda text: uncommented(text, "line"),
    "ruckig": lambda text: re.sub(  # the commented [limits.jerk] table, uncommented
        r"^# (\[limits\.jerk\].*?)\n\n", lambda m: m[1].replace("\n# ", "\n") + "\n\n",
        text.replace('planner = "toppra"', 'planner = "ruckig"'), flags=re.MULTILINE | re.DOTALL),
    "toppra": lambda text: re.sub(r"^\[limits\.jerk\][^[]*", "", text.replace(
        'planner = "ruckig"', 'planner = "toppra"'), flags=re.MULTILINE),
}
"""Each suggestion a starter's comments make, carried out as its comment says."""


@pytest.mark.slow
@pytest.mark.parametrize(("name", "tool_poses", "suggestion"), [
    ("benchtop6", True, "payload"), ("benchtop6", True, "tolerances"),
    ("benchtop6", True, "line"), ("benchtop6", True, "ruckig"), ("scara", True, "line"),
    ("planar2", True, "line"),
    ("benchtop6", False, "payload"), ("benchtop6", False, "toppra"),
    ("gripper", False, "exclude")])
def test_every_suggestion_a_starter_comments_plans(name, tool_poses, suggestion, tmp_path):
    robot = (hdselect.load_robot(gripper(tmp_path)) if name == "gripper"
             else hdselect.load_robot(robot_path(name)))
    text = starter_motion(robot, str(robot.path), tool_poses=tool_poses)
    # planar2's poses are positions alone (2 joints): a straight line of positions it follows
    if suggestion == "exclude":
        changed = uncommented(text, "exclude")
    else:
        changed = SUGGESTIONS[suggestion](text)
    assert changed != text
    doc = tomllib.loads(changed)
    if suggestion == "line":
        assert doc["waypoint"][1]["line"] is True
    if suggestion in ("ruckig", "toppra"):
        assert doc["planner"] == suggestion and ("jerk" in doc["limits"]) == (
            suggestion == "ruckig")
    path = tmp_path / "motion.toml"
    path.write_text(changed)
    loaded, motion = hdselect.load_case(path)
    trajectory = hdselect.plan(loaded, motion)
    assert trajectory.duration > 1.0
    if suggestion == "exclude":
        assert "finger_joint" not in loaded.sized_joints


def test_a_redundant_arms_tool_pose_starter_plans_and_ends_where_it_starts(tmp_path):
    """pybullet's Panda (7 joints): the return pose solved elsewhere in the null space and
    the move passed a near-singularity the planner refuses; now it plans as written."""
    data = pytest.importorskip("pybullet_data")
    urdf = Path(data.getDataPath()) / "franka_panda" / "panda.urdf"
    path = tmp_path / "panda.toml"
    path.write_text(starter_motion(hdselect.load_robot(urdf), str(urdf), tool_poses=True))
    robot, motion = hdselect.load_case(path)
    trajectory = hdselect.plan(robot, motion)
    np.testing.assert_allclose(trajectory.q[-1], trajectory.q[0], atol=1e-9)
    assert trajectory.duration > 1.0


def test_the_tool_pose_starter_does_not_promise_another_mounting(tmp_path):
    """Its comment said `--mounting ceiling` solves the same poses again: on benchtop6 (and
    9 of 12 arms tried) they are out of reach there; it now says so."""
    robot = hdselect.load_robot(robot_path("benchtop6"))
    text = starter_motion(robot, str(robot.path), tool_poses=True)
    assert "solves the same poses again" not in text
    assert "often out of reach: write poses for it there" in text
    path = tmp_path / "motion.toml"
    path.write_text(text)
    with pytest.raises(hdselect.InputError, match="cannot reach this pose on the ceiling"):
        hdselect.load_case(path, mounting="ceiling")
