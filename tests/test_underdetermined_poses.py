"""Tool poses that fix less than six coordinates: an approach axis, a yaw, a position alone.

Oracles that do not come from the code under test: forward kinematics on a Pinocchio
model built here from the robot file (`fk`), the roll about the approach axis and the
yaw computed here from that model's rotation by their definition in words
(docs/tool-poses.md), the straight line and the slerp of directions written here, and
the joint positions `main` (1458381) solved for the shipped 6-axis pose file, recorded
as literals.
"""

from __future__ import annotations

import hashlib
import math
import re

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.motion.planning import plan_motion
from helpers import REPO

LABARM = REPO / "trajectories" / "labarm5_rack_transfer.toml"
SCARA = REPO / "trajectories" / "scara_yaw_transfer.toml"
POSITION_TOLERANCE = 1e-4  # m: 0.1 mm
AXIS_TOLERANCE = math.radians(0.01)


def fk(robot_file, frame: str, q) -> pin.SE3:
    """The frame's pose at joint positions `q` on a Pinocchio model built here."""
    model = pin.buildModelFromUrdf(str(robot_file))
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.asarray(q, dtype=float))
    return data.oMf[model.getFrameId(frame)]


def angle_between(a, b) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), float(np.dot(a, b)))


def roll_about(rotation: np.ndarray, axis_column: int, next_column: int) -> float:
    """The roll as docs/tool-poses.md defines it: about the tool's approach axis, from the
    world x projected across it (the world y where the axis is along x) to the next tool
    axis."""
    axis = rotation[:, axis_column]
    reference = np.array([1.0, 0.0, 0.0]) - axis[0] * axis
    if np.linalg.norm(reference) < 1e-6:
        reference = np.array([0.0, 1.0, 0.0]) - axis[1] * axis
    following = rotation[:, next_column]
    return math.atan2(float(np.dot(np.cross(reference, following), axis)),
                      float(np.dot(reference, following)))


# --- the full 6-D pose: today's answers, bit for bit ------------------------------------------

MAIN_WAYPOINTS = (
    ('-0x1.dcea128e99a94p-3', '-0x1.28074a66d052ep+0', '0x1.71cd18174e1b9p+0',
     '0x1.4859e80a9d3d7p+0', '-0x1.921fb56390732p+0', '-0x1.dcea1274c3be4p-3'),
    ('-0x1.974dfda521004p-1', '-0x1.1e9235d9ed9d3p-1', '0x1.18c1278054304p+0',
     '0x1.08a7a923bf37ep+0', '-0x1.921fb5456ac41p+0', '-0x1.4b921837ba144p-7'),
    ('-0x1.974dfdd1095d0p-1', '-0x1.5845036f3ef46p-2', '0x1.0f88b756dbd18p+0',
     '0x1.b1507e606120dp-1', '-0x1.921fb544af0b2p+0', '-0x1.4b92233daecf1p-7'),
    ('-0x1.974dfe2488101p-1', '-0x1.1e92739590873p-1', '0x1.18c164594ace7p+0',
     '0x1.08a78b1fe776dp+0', '-0x1.921fb54552074p+0', '-0x1.4b923815a4555p-7'),
)
"""benchtop6_pick_place_poses.toml's first four waypoints as main (1458381) solved them."""
MAIN_LINES_SHA256 = "c87aca2d0308f3c8b6a9d4209d21d8d782daa9c16c332fb7269ca5b1b6e8cf54"
"""sha256 of main's line samples (68 rows of 6 float64, in line order), same file."""


def test_a_full_pose_on_six_joints_solves_as_main_did_bit_for_bit():
    _, motion = hdselect.load_case(REPO / "trajectories" / "benchtop6_pick_place_poses.toml")
    expected = np.array([[float.fromhex(x) for x in row] for row in MAIN_WAYPOINTS])
    assert np.array_equal(motion.waypoints[:4], expected)
    samples = np.concatenate([line.q for line in motion.lines])
    assert len(samples) == 68
    assert hashlib.sha256(samples.tobytes()).hexdigest() == MAIN_LINES_SHA256
    assert all(free == () for free in motion.solution.free)


# --- the 5-axis arm: position and approach axis, the roll free ----------------------------------

@pytest.fixture(scope="module")
def labarm():
    robot, motion = hdselect.load_case(LABARM)
    return robot, motion, plan_motion(robot, motion)


def test_labarm_poses_meet_position_and_axis_and_report_the_roll(labarm):
    robot, motion, _ = labarm
    assert robot.dof == 5 and all(p.kind == "axis" for p in motion.tool.poses)
    for pose in motion.tool.poses:
        placed = fk(robot.path, "tool0", motion.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
        assert angle_between(placed.rotation[:, 2], pose.axis) < AXIS_TOLERANCE
        ((name, roll),) = motion.solution.free[pose.index]
        assert name == "roll"
        assert roll == pytest.approx(roll_about(placed.rotation, 2, 0), abs=1e-9)
    # the free roll is the arm's to choose: the wrist roll stays where it started
    assert np.abs(motion.waypoints[:, 4]).max() < math.radians(1.0)


def test_labarm_lines_hold_position_and_slerp_of_the_axis(labarm):
    robot, motion, planned = labarm
    assert len(motion.lines) == 4
    for line in motion.lines:
        start, end = motion.tool.at(line.last - 1), motion.tool.at(line.last)
        a, b = np.array(start.axis), np.array(end.axis)
        turn = angle_between(a, b)
        rolls = []
        for fraction, q in zip(line.fractions, line.q, strict=True):
            placed = fk(robot.path, "tool0", q)
            point = (1 - fraction) * np.array(start.xyz) + fraction * np.array(end.xyz)
            assert np.linalg.norm(placed.translation - point) < POSITION_TOLERANCE
            if turn > 0:  # slerp of the two directions, written here
                wanted = (math.sin((1 - fraction) * turn) * a
                          + math.sin(fraction * turn) * b) / math.sin(turn)
            else:
                wanted = a
            assert angle_between(placed.rotation[:, 2], wanted) < AXIS_TOLERANCE
            rolls.append(roll_about(placed.rotation, 2, 0))
        assert np.abs(np.diff(np.unwrap(rolls))).max() < math.radians(2.0)  # continuous
        assert np.abs(np.diff(line.q, axis=0)).max() < 0.2
    for found in planned.lines:  # and the planned samples on them
        assert found.position.max() < POSITION_TOLERANCE
        assert found.orientation.max() < AXIS_TOLERANCE


def test_labarm_plan_prints_the_free_roll(capsys, tmp_path):
    assert main(["plan", str(LABARM), "--out", str(tmp_path / "t.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "free coordinates as solved (the roll about the approach axis where a pose gives " \
           "an axis): waypoint[0] roll -156.8 deg;" in out


# --- the SCARA: position and yaw, the tilt free ---------------------------------------------------

def test_scara_poses_meet_position_and_yaw_and_report_the_tilt():
    robot, motion = hdselect.load_case(SCARA)
    assert all(p.kind == "yaw" for p in motion.tool.poses)
    tolerance = motion.tool.tolerance
    for pose in motion.tool.poses:
        placed = fk(robot.path, "wafer", motion.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
        x = placed.rotation[:, 0]
        yaw = math.atan2(x[1], x[0])
        assert abs((yaw - pose.yaw + math.pi) % (2 * math.pi) - math.pi) < tolerance.orientation
        (roll_name, roll), (pitch_name, pitch) = motion.solution.free[pose.index]
        assert (roll_name, pitch_name) == ("roll", "pitch")
        # rpy of R = Rz Ry Rx: pitch = -asin(R[2, 0]), roll = atan2(R[2, 1], R[2, 2])
        assert pitch == pytest.approx(-math.asin(placed.rotation[2, 0]), abs=1e-9)
        assert roll == pytest.approx(math.atan2(placed.rotation[2, 1], placed.rotation[2, 2]),
                                     abs=1e-9)
    (line,) = motion.lines  # straight out of the cassette, the yaw held
    for fraction, q in zip(line.fractions, line.q, strict=True):
        placed = fk(robot.path, "wafer", q)
        point = (1 - fraction) * np.array([0.55, -0.09, 0.315]) + fraction * np.array(
            [0.38, -0.09, 0.315])
        assert np.linalg.norm(placed.translation - point) < POSITION_TOLERANCE
        assert abs(math.atan2(placed.rotation[1, 0], placed.rotation[0, 0])) < \
            tolerance.orientation


# --- a position alone on a 3-joint chain ---------------------------------------------------------

CHAIN3 = """<?xml version="1.0"?>
<robot name="chain3">
  <link name="base"/>
  <joint name="yaw" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/></joint>
  <link name="a"><inertial><origin xyz="0 0 0.05"/><mass value="0.5"/>
    <inertia ixx="1e-3" iyy="1e-3" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="lift" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
  <link name="b"><inertial><origin xyz="0.1 0 0"/><mass value="0.4"/>
    <inertia ixx="1e-4" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="bend" type="revolute"><parent link="b"/><child link="c"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 0"/>
    <limit lower="0.1" upper="2.5" effort="10" velocity="2"/></joint>
  <link name="c"><inertial><origin xyz="0.1 0 0"/><mass value="0.3"/>
    <inertia ixx="1e-4" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tip_joint" type="fixed"><parent link="c"/><child link="tip"/>
    <origin xyz="0.2 0 0"/></joint>
  <link name="tip"/>
</robot>
"""

CHAIN3_MOTION = """robot = "chain3.urdf"
planner = "toppra"
angle_unit = "deg"
[limits]
velocity = 90
acceleration = 400
[tool]
frame = "tip"
[[waypoint]]
pose = {xyz = [0.25, 0.10, 0.15]}
dwell = 0.2
[[waypoint]]
pose = {xyz = [0.30, -0.05, 0.25]}
[[waypoint]]
pose = {xyz = [0.20, -0.15, 0.25]}
line = true
"""


def test_a_position_alone_on_a_three_joint_chain(tmp_path):
    (tmp_path / "chain3.urdf").write_text(CHAIN3)
    (tmp_path / "move.toml").write_text(CHAIN3_MOTION)
    robot, motion = hdselect.load_case(tmp_path / "move.toml")
    assert [p.kind for p in motion.tool.poses] == ["position"] * 3
    for pose in motion.tool.poses:
        placed = fk(tmp_path / "chain3.urdf", "tip", motion.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
        roll, pitch, yaw = (value for _, value in motion.solution.free[pose.index])
        assert np.allclose(pin.rpy.rpyToMatrix(roll, pitch, yaw), placed.rotation, atol=1e-9)
    (line,) = motion.lines
    for fraction, q in zip(line.fractions, line.q, strict=True):
        point = (1 - fraction) * np.array([0.30, -0.05, 0.25]) + fraction * np.array(
            [0.20, -0.15, 0.25])
        placed = fk(tmp_path / "chain3.urdf", "tip", q)
        assert np.linalg.norm(placed.translation - point) < POSITION_TOLERANCE
    planned = plan_motion(robot, motion)
    assert planned.lines[0].position.max() < POSITION_TOLERANCE
    assert planned.lines[0].orientation.max() == 0.0  # nothing but the position is fixed


# --- hostile input ----------------------------------------------------------------------------

AXIS_POSE = "pose = {xyz = [0.35, -0.15, 0.22], axis = [0, 0, -1]}"
HOSTILE = [
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], axis = [0, 0, 0]}",
     "waypoint[0].pose.axis: the approach axis has no direction (length 0)"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], axis = [1e-10, 0, 0]}",
     "waypoint[0].pose.axis: the approach axis has no direction (length 0)"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], axis = [0, nan, -1]}",
     "waypoint[0].pose.axis[1]:"),
    (AXIS_POSE, "pose = {xyz = [0.35, nan, 0.22], axis = [0, 0, -1]}",
     "waypoint[0].pose.xyz[1]:"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], rpy = [180, 0, 0], axis = [0, 0, -1]}",
     "waypoint[0].pose.axis: give one of rpy (a full pose), axis (the approach axis, roll free) "
     "or yaw (tilt free), not both rpy and axis"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], rpy = [180, 0, 0], yaw = 30}",
     "waypoint[0].pose.yaw: give one of rpy"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], yaw = inf}", "waypoint[0].pose.yaw:"),
    (AXIS_POSE, "pose = {xyz = [0.35, -0.15, 0.22], axis = [0, 0, -1], tilt = 3}",
     "waypoint[0].pose.tilt: unknown key"),
    ('approach = "z"', 'approach = "w"',
     "tool.approach: unknown tool axis 'w'; choose one of: x, y, z, -x, -y, -z"),
    ('approach = "z"', "approach = 3", "tool.approach: unknown tool axis 3"),
    ('approach = "z"', "allow_flip = 2", "tool.allow_flip: expected true or false"),
]


@pytest.mark.parametrize(("old", "new", "message"), HOSTILE, ids=[m[:36] for _, _, m in HOSTILE])
def test_hostile_pose_forms_are_one_line_naming_the_field(old, new, message, tmp_path, capsys):
    text = LABARM.read_text().replace(old, new, 1).replace("../robots/", f"{REPO}/robots/")
    assert new in text
    path = tmp_path / "motion.toml"
    path.write_text(text)
    assert main(["plan", str(path), "--out", str(tmp_path / "out.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: {message}" in err, err
    assert not (tmp_path / "out.csv").exists()


def test_an_approach_without_an_axis_pose_is_refused(tmp_path, capsys):
    text = SCARA.read_text().replace("../robots/", f"{REPO}/robots/")
    path = tmp_path / "motion.toml"
    path.write_text(text.replace('frame = "wafer"', 'frame = "wafer"\napproach = "-z"'))
    assert main(["plan", str(path), "--out", str(tmp_path / "out.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: tool.approach: approach names the tool axis a " \
        "pose's axis gives; no waypoint gives one" in err, err


# --- a near hint that cannot be honoured ---------------------------------------------------------

NEAR = f"""robot = "{REPO}/robots/labarm5.urdf"
planner = "toppra"
angle_unit = "deg"
[limits]
velocity = 120
acceleration = 600
[[waypoint]]
pose = {{xyz = [0.35, -0.03, 0.22], axis = [0, 0, -1]}}
near = {{elbow = -80}}
[[waypoint]]
pose = {{xyz = [0.35, -0.03, 0.12], axis = [0, 0, -1]}}
"""
"""Elbow back (-80 deg) over a point 4.9 deg off the x axis: only with base_yaw at 175.1
deg, beyond its 170 deg limit; the solver lands elbow forward."""
REFUSED = ("waypoint[0].near.elbow: no solution of the pose keeps elbow within 90 deg of its "
           "hint -80 deg; the solver lands at elbow = 90.02 deg, on another branch; the upper "
           "limit of base_yaw (170 deg) rules that branch out")


def test_a_near_hint_a_limit_rules_out_is_an_error(tmp_path, capsys):
    path = tmp_path / "near.toml"
    path.write_text(NEAR)
    assert main(["plan", str(path), "--out", str(tmp_path / "out.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: {REFUSED}; change or remove the hint, or allow " \
        "the other branch with --allow-flip" in err, err
    assert not (tmp_path / "out.csv").exists()
    with pytest.raises(InputError, match=r"near\.elbow"):
        hdselect.load_case(path)


@pytest.mark.parametrize("how", ["flag", "file"])
def test_allow_flip_turns_it_into_a_warning(how, tmp_path, capsys):
    path = tmp_path / "near.toml"
    path.write_text(NEAR.replace("[limits]", "[tool]\nallow_flip = true\n[limits]")
                    if how == "file" else NEAR)
    extra = ["--allow-flip"] if how == "flag" else []
    assert main(["plan", str(path), "--out", str(tmp_path / "out.csv"), *extra]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert f"WARNING: {path}: {REFUSED}; the solver's branch taken" in err
    robot, motion = hdselect.load_case(path, allow_flip=how == "flag")  # Python: the parameter
    assert any("near.elbow" in w for w in motion.warnings)
    assert motion.waypoints[0, 2] > 0  # elbow forward: the solver's branch


def test_allow_flip_is_refused_without_a_tool_pose(tmp_path, capsys):
    motion = REPO / "trajectories" / "benchtop6_pick_place.toml"
    assert main(["plan", str(motion), "--out", str(tmp_path / "out.csv"), "--allow-flip"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--allow-flip: benchtop6_pick_place.toml has no tool pose" \
        in err, err


# --- unreachable off the floor: where the base is ---------------------------------------

def test_unreachable_on_the_ceiling_says_where_the_base_is(tmp_path, capsys):
    assert main(["plan", str(LABARM), "--mounting", "ceiling", "--out",
                 str(tmp_path / "out.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "waypoint[0].pose: the tool frame 'tool0' cannot reach this pose on the ceiling " \
           "mounting" in err
    assert err.rstrip().endswith(
        "; the base is at (0, 0, 0) m, rpy (180, 0, 0) deg in the world, and the poses are "
        "world poses: move the base (base = {xyz, rpy} in the motion file, or --base) to "
        "bring the poses within reach"), err


def test_unreachable_with_a_base_pose_gives_it_in_the_files_units(tmp_path):
    text = LABARM.read_text().replace("../robots/", f"{REPO}/robots/").replace(
        'mounting = "floor"', "base = {xyz = [0, 0, 0.9], rpy = [3.14159265, 0, 0]}").replace(
        'angle_unit = "deg"', 'angle_unit = "rad"').replace("velocity = 120", "velocity = 2")
    text = text.replace("acceleration = 600", "acceleration = 10").replace(
        "near = {elbow = 80}", "near = {elbow = 1.4}")
    path = tmp_path / "motion.toml"
    path.write_text(text.replace("[0.35, -0.15, 0.22]", "[0.35, -0.15, -0.5]"))
    with pytest.raises(InputError) as raised:
        hdselect.load_case(path)
    assert raised.value.field == "waypoint[0].pose"
    assert "the base is at (0, 0, 0.9) m, rpy (3.142, 0, 0) rad in the world" in str(raised.value)


def test_unreachable_on_the_floor_does_not_talk_of_the_base(tmp_path):
    text = LABARM.read_text().replace("../robots/", f"{REPO}/robots/")
    path = tmp_path / "motion.toml"
    path.write_text(text.replace("[0.35, -0.15, 0.22]", "[0.95, -0.15, 0.22]"))
    with pytest.raises(InputError) as raised:
        hdselect.load_case(path)
    assert "cannot reach this pose on the floor mounting" in str(raised.value)
    assert "the base is at" not in str(raised.value)


# --- init --tool-poses: the form that fits the joint count ----------------------------------------

@pytest.mark.parametrize(("name", "form"), [
    ("benchtop6", "pose"), ("labarm5", "axis"), ("scara", "yaw"), ("planar2", "position"),
    ("pan_tilt", "position"), ("index_table", "position")])
def test_init_writes_the_pose_form_that_fits_the_robot(name, form, tmp_path, capsys):
    out = tmp_path / "starter.toml"
    assert main(["init", str(REPO / "robots" / f"{name}.urdf"), "--tool-poses", "--out",
                 str(out)]) == 0
    robot, motion = hdselect.load_case(out)
    assert {p.kind for p in motion.tool.poses} == {form}
    near = motion.tool.poses[0].near
    np.testing.assert_allclose(motion.waypoints[0], [near[n] for n in robot.joint_names],
                               atol=1e-3)
    assert main(["plan", str(out), "--out", str(tmp_path / "t.csv")]) == 0
    out_text = " ".join(capsys.readouterr().out.split())
    assert ("free coordinates as solved" in out_text) == (form != "pose")


@pytest.mark.parametrize(("motion", "frame"), [(LABARM, "tool0"), (SCARA, "wafer")])
def test_a_base_pose_carries_axis_and_yaw_into_the_world(motion, frame, tmp_path):
    """The base 5 cm over, 2 cm up and turned 20 deg: the world poses are met in the world."""
    text = motion.read_text().replace("../robots/", f"{REPO}/robots/").replace(
        'mounting = "floor"', "base = {xyz = [0.05, 0.0, 0.02], rpy = [0, 0, 20]}")
    path = tmp_path / "motion.toml"
    path.write_text(text)
    robot, solved = hdselect.load_case(path)
    base = pin.SE3(pin.rpy.rpyToMatrix(0.0, 0.0, math.radians(20)), np.array([0.05, 0.0, 0.02]))
    for pose in solved.tool.poses:
        placed = base * fk(robot.path, frame, solved.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
        if pose.kind == "axis":
            assert angle_between(placed.rotation[:, 2], pose.axis) < AXIS_TOLERANCE
            assert solved.solution.free[pose.index][0][1] == pytest.approx(
                roll_about(placed.rotation, 2, 0), abs=1e-9)
        else:
            yaw = math.atan2(placed.rotation[1, 0], placed.rotation[0, 0])
            assert abs((yaw - pose.yaw + math.pi) % (2 * math.pi) - math.pi) < AXIS_TOLERANCE


def test_positions_alone_on_six_joints_use_the_freedom_and_close_the_cycle(tmp_path):
    """benchtop6's pick-and-place as positions alone: three coordinates free at every
    waypoint; the last, back at the first's position, takes the first's joints."""
    text = re.sub(r", rpy = \[[^]]*\]", "", (REPO / "trajectories" /
                                            "benchtop6_pick_place_poses.toml").read_text())
    path = tmp_path / "motion.toml"
    path.write_text(text.replace("../robots/", f"{REPO}/robots/"))
    robot, motion = hdselect.load_case(path)
    assert {p.kind for p in motion.tool.poses} == {"position"}
    for pose in motion.tool.poses:
        placed = fk(robot.path, "tool0", motion.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
    assert motion.tool.poses[-1].xyz == motion.tool.poses[0].xyz
    assert np.array_equal(motion.waypoints[-1], motion.waypoints[0])
    steps = np.abs(np.diff(motion.waypoints, axis=0)).max(axis=1)
    assert steps.max() < math.radians(120)  # each near the waypoint before


def test_full_and_axis_poses_mixed_in_one_file_with_lines_between(tmp_path):
    """benchtop6's pick-and-place, every second pose an axis (tool down): lines from a
    full pose into an axis pose and back start where the tool was put."""
    count = iter(range(100))
    text = re.sub(r", rpy = \[[^]]*\]",
                  lambda m: m[0] if next(count) % 2 == 0 else ", axis = [0, 0, -1]",
                  (REPO / "trajectories" / "benchtop6_pick_place_poses.toml").read_text())
    path = tmp_path / "motion.toml"
    path.write_text(text.replace("../robots/", f"{REPO}/robots/"))
    robot, motion = hdselect.load_case(path)
    assert [p.kind for p in motion.tool.poses] == ["pose", "axis"] * 4
    for pose in motion.tool.poses:
        placed = fk(robot.path, "tool0", motion.waypoints[pose.index])
        assert np.linalg.norm(placed.translation - pose.xyz) < POSITION_TOLERANCE
        if pose.kind == "axis":
            assert angle_between(placed.rotation[:, 2], pose.axis) < AXIS_TOLERANCE
        else:
            wanted = pin.rpy.rpyToMatrix(*pose.rpy)
            assert np.linalg.norm(pin.log3(placed.rotation.T @ wanted)) < AXIS_TOLERANCE
    for line in motion.lines:
        start = fk(robot.path, "tool0", motion.waypoints[line.last - 1]).translation
        end = np.array(motion.tool.at(line.last).xyz)
        for fraction, q in zip(line.fractions, line.q, strict=True):
            placed = fk(robot.path, "tool0", q)
            assert np.linalg.norm(placed.translation - ((1 - fraction) * start
                                                        + fraction * end)) < POSITION_TOLERANCE
