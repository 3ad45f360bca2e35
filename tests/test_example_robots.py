"""Real robot files, used as a new user would: example-robot-data's fixed-base arms.

Each arm is loaded by path, gets a starter motion from `hdselect init`, plans it,
and its sizing torques are checked sample by sample against `pinocchio.rnea` on
a model built here, independently (mimic joints coupled, armature zeroed, no
gearheads). `hdselect size` may find no unit for a big arm's shoulder (exit 1);
it must never refuse the file (exit 2).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.cli.main import main
from hdselect.robot.mounting import STANDARD_GRAVITY
from hdselect.sizing.records import size_json
from helpers.robots import ARMS, configuration, example_robots


def independent_model(path: Path) -> pin.Model:
    """Pinocchio's model of the file with nothing of hdselect: armature and friction zeroed."""
    model = pin.buildModelFromUrdf(str(path), mimic=True)
    model.armature = np.zeros(model.nv)
    model.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    return model


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> dict[str, Path]:
    """A starter motion per arm, written by ``hdselect init`` beside a copy-free robot path."""
    folder = tmp_path_factory.mktemp("arms")
    motions = {}
    for name, relative in ARMS.items():
        out = folder / f"{Path(relative).stem}.toml"
        assert main(["init", str(example_robots() / relative), "--out", str(out)]) == 0
        motions[name] = out
    return motions


@pytest.mark.parametrize("arm", ARMS)
def test_starter_motion_plans_and_its_torques_equal_rnea(arm, written):
    path = example_robots() / ARMS[arm]
    robot, motion = hdselect.load_case(written[arm])
    assert robot.path.resolve() == path.resolve() and motion.warnings == ()
    trajectory = hdselect.plan(robot, motion)
    assert trajectory.duration > 1.0
    assert np.all(trajectory.q >= robot.lower - 1e-9) and np.all(trajectory.q <= robot.upper + 1e-9)
    step = max(1, len(trajectory.t) // 150)  # ~150 samples: the oracle is a per-sample loop
    short = type(trajectory)(trajectory.joint_names, trajectory.dt * step, trajectory.duration,
                             trajectory.t[::step], trajectory.q[::step], trajectory.qd[::step],
                             trajectory.qdd[::step])
    result = hdselect.size_trajectory(robot, short, hdselect.load_catalog(),
                                      hdselect.Options(mass_coupling=False))
    model = independent_model(path)
    data = model.createData()
    expected = np.array([pin.rnea(model, data, configuration(model, robot.joint_names, q), qd, qdd)
                         for q, qd, qdd in zip(short.q, short.qd, short.qdd, strict=True)])
    names = [model.names[j] for j in range(1, model.njoints) if model.joints[j].nv == 1]
    assert [j.name for j in result.joints] == [n for n in names if n in robot.sized_joints]
    for joint in result.joints:
        column = names.index(joint.name)
        np.testing.assert_allclose(joint.torque, expected[:, column], rtol=1e-9, atol=1e-9)
    for load in result.loads:
        if load.peak is not None:
            column = names.index(load.name)
            assert load.peak == pytest.approx(np.abs(expected[:, column]).max(), rel=1e-9, abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("arm", ARMS)
def test_size_never_refuses_the_file(arm, written, capsys, tmp_path):
    report = tmp_path / "result.json"
    status = main(["size", str(written[arm]), "--json", str(report)])
    out, err = capsys.readouterr()
    assert status in (0, 1), err
    document = json.loads(report.read_text())
    unsized = [j["name"] for j in document["joints"] if j["selected"] is None]
    assert (status == 1) == bool(unsized)
    assert document["root_link"] and document["payload"]["mass_kg"] == 0.0
    assert "base: '" in out and "Every joint over the cycle" in out
    assert main(["joints", str(example_robots() / ARMS[arm])]) == 0


@pytest.mark.parametrize(("arm", "frame"), [
    ("UR5", "tool0"), ("Panda", "panda_hand_tcp"), ("Kinova", "j2s6s200_end_effector"),
    ("xArm7", "link_eef"), ("TALOS left arm", "gripper_left_motor_double_link"),
])
def test_default_payload_frame_is_the_tip_of_the_longest_sized_chain(arm, frame):
    robot = hdselect.load_robot(example_robots() / ARMS[arm])
    assert robot.default_payload_frame == frame
    # excluding the gripper's joint moves the tip to the wrist's tool frame
    if arm == "TALOS left arm":
        assert robot.with_sized_joints(None, ["gripper_left_joint"]).default_payload_frame \
            == "wrist_left_ft_tool_link"


def test_panda_fingers_are_reported_not_sized(written):
    robot, motion = hdselect.load_case(written["Panda"])
    assert robot.joint_type("panda_finger_joint1") == "prismatic"
    assert robot.mimic["panda_finger_joint2"].leader == "panda_finger_joint1"
    assert "panda_finger_joint2" not in robot.joint_names  # a follower has no value of its own
    assert robot.sized_joints == tuple(f"panda_joint{i}" for i in range(1, 8))
    result = hdselect.size(robot, motion)
    loads = {load["name"]: load for load in size_json(result)["joint_loads"]}
    follower = loads["panda_finger_joint2"]
    assert follower["type"] == "mimic" and follower["leader"] == "panda_finger_joint1"
    assert follower["peak_force_n"] is None and follower["travel_m"] == loads[
        "panda_finger_joint1"]["travel_m"]
    assert loads["panda_finger_joint1"]["note"] == "not sized: the catalog is rotary"


def test_so101_lists_follow_the_model_not_the_file_and_say_so(tmp_path):
    robot = hdselect.load_robot(example_robots() / ARMS["SO-101"])
    assert robot.file_order == tuple(reversed(robot.joint_names))
    motion = tmp_path / "so101.toml"
    motion.write_text(f'robot = "{robot.path}"\nplanner = "ruckig"\nangle_unit = "deg"\n'
                      "[limits]\nvelocity = 90\nacceleration = 180\njerk = 1800\n"
                      "[[waypoint]]\nq = [0, 0, 0, 0, 0, 0]\n"
                      "[[waypoint]]\nq = [10, 0, 0, 0, 0, 0]\n")
    loaded = hdselect.load_motion(motion, robot)
    (warning,) = loaded.warnings
    assert "model's joint order (shoulder_pan, shoulder_lift" in warning
    assert "not the order the robot file writes them (gripper, wrist_roll" in warning
    assert loaded.waypoints[1, 0] == pytest.approx(np.radians(10))  # shoulder_pan


def test_ur3_without_a_robot_name_is_refused_with_the_parsers_reason(capfd):
    status = main(["joints", str(example_robots() / "ur_description/urdf/ur3.urdf")])
    out, err = capfd.readouterr()
    assert status == 2 and out == ""
    assert err.count("\n") == 1
    assert "ur3.urdf: not a valid URDF robot: No name given for the robot" in err
