"""Tests of hdselect.robot.joints and `hdselect joints`: a robot's joints as motions see them."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hdselect.cli.main import main
from hdselect.robot.joints import describe_joints
from hdselect.robot.model import load_robot
from helpers.robots import gripper, robot_path


def test_scara_joints_in_list_order_with_the_mass_each_moves():
    robot = load_robot(robot_path("scara"))
    infos = describe_joints(robot)
    assert [(i.index, i.name, i.kind, i.sized) for i in infos] == [
        (0, "shoulder", "revolute", True), (1, "elbow", "revolute", True),
        (2, "lift", "prismatic", False), (3, "wrist", "revolute", True)]
    masses = [body.mass for body in robot.model.inertias]
    for info, first in zip(infos, range(1, 5), strict=True):
        # a serial chain: each joint moves its own body and every body further out
        assert info.moved_mass == pytest.approx(sum(masses[first:]), rel=1e-12)
    lift = infos[2]
    assert (lift.lower, lift.upper) == (robot.lower[2], robot.upper[2])
    assert lift.velocity_limit == robot.velocity_limit[2]


def test_followers_are_listed_unnumbered_with_their_leader(tmp_path):
    infos = {i.name: i for i in describe_joints(load_robot(gripper(tmp_path)))}
    outer = infos["right_outer"]
    assert outer.index is None and outer.kind == "mimic" and not outer.sized
    assert (outer.leader, outer.multiplier, outer.offset) == ("finger_joint", -1.0, 0.1)
    assert infos["finger_joint"].index == 1
    assert infos["finger_joint"].moved_mass == pytest.approx(0.1)  # the finger alone
    assert infos["arm_joint"].moved_mass == pytest.approx(1.0 + 0.1 + 0.05 + 0.08)


def test_a_continuous_joint_has_no_range():
    (info,) = describe_joints(load_robot(robot_path("index_table")))
    assert info.kind == "continuous" and info.lower == -math.inf and info.upper == math.inf


def test_joints_command_prints_every_joint_and_the_base(capsys):
    assert main(["joints", str(robot_path("scara"))]) == 0
    out = capsys.readouterr().out
    rows = [cells for cells in map(str.split, out.splitlines())
            if len(cells) > 3 and cells[2] in ("revolute", "prismatic")]  # joint, #, type, sized
    assert [(row[0], row[1]) for row in rows] == [("shoulder", "0"), ("elbow", "1"),
                                                  ("lift", "2"), ("wrist", "3")]
    assert rows[2][2:4] == ["prismatic", "no"] and rows[0][2:4] == ["revolute", "yes"]
    assert "lift: not sized: the catalog is rotary" in out
    assert "base: 'base_link' held fixed; a payload goes on" in out


def test_joints_command_json(tmp_path, capsys):
    assert main(["joints", str(robot_path("benchtop6")), "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["list_order"] == [j["name"] for j in document["joints"]]
    assert document["root_link"] == "base_link" and document["payload_frame"] == "tool0"
    first = document["joints"][0]
    assert first["index"] == 0 and first["unit"] == "rad" and first["effort_limit"] == 25.0
    assert first["velocity_limit"] == pytest.approx(3.14)
    np.testing.assert_allclose(first["moved_mass_kg"],
                               sum(b.mass for b in load_robot(robot_path("benchtop6"))
                                   .model.inertias[1:]))


def test_joints_command_names_a_different_file_order(tmp_path, capsys):
    path = tmp_path / "reversed.urdf"
    text = robot_path("planar2").read_text()
    first, second = text.index('<joint name="shoulder"'), text.index('<joint name="elbow"')
    end_first = text.index("</joint>", first) + len("</joint>")
    end_second = text.index("</joint>", second) + len("</joint>")
    path.write_text(text[:first] + text[second:end_second] + text[end_first:second]
                    + text[first:end_first] + text[end_second:])
    assert main(["joints", str(path)]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "the robot file writes the joints in another order (elbow, shoulder)" in out
