from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.motion.loading import load_case, robot_for_motion
from hdselect.motion.motionfile import load_motion
from hdselect.robot.model import load_robot
from hdselect.robot.payload import Payload
from helpers.robots import write_chain, write_motion, write_robot

NAMES6 = ("j1", "j2", "j3", "j4", "j5", "j6")


GOOD = """\
robot = "arm.urdf"
planner = "ruckig"
angle_unit = "deg"
dt = 0.002
mounting = "wall"
[payload]
mass = 1.5
com = [0, 0, 0.05]
[limits]
velocity = 120
acceleration = {j1 = 600, j2 = 600, j3 = 600, j4 = 900, j5 = 900, j6 = 900}
jerk = 6000
[safety]
stop_time = 0.05
[requirements]
life_hours = 20000
[[waypoint]]
q = [0, 30, -45, 0, 60, 0]
dwell = 0.5
[[waypoint]]
q = {j1 = 90, j2 = 0, j3 = 0, j4 = 10, j5 = 0, j6 = -90}
"""


@pytest.fixture
def arm(tmp_path):
    write_robot(tmp_path)
    return tmp_path


# --- good input ------------------------------------------------------------------------------

def test_good_file_is_converted_to_si(arm):
    robot, motion = load_case(write_motion(arm, GOOD))
    deg = math.pi / 180
    assert motion.planner == "ruckig" and motion.dt == 0.002
    assert robot.dof == 6 and motion.joint_names == robot.joint_names
    np.testing.assert_allclose(motion.waypoints[0], np.array([0, 30, -45, 0, 60, 0]) * deg)
    np.testing.assert_allclose(motion.waypoints[1], np.array([90, 0, 0, 10, 0, -90]) * deg)
    np.testing.assert_allclose(motion.dwells, [0.5, 0.0])
    np.testing.assert_allclose(motion.velocity_limit, 120 * deg)
    np.testing.assert_allclose(motion.acceleration_limit, np.array([600] * 3 + [900] * 3) * deg)
    np.testing.assert_allclose(motion.jerk_limit, 6000 * deg)
    assert motion.torque_limit is None
    assert motion.stop_time == 0.05 and motion.life_hours == 20000
    assert motion.samples is None
    assert motion.payload.mass == 1.5 and motion.mounting == "wall"
    assert motion.robot_file == arm / "arm.urdf"
    assert robot.payload == motion.payload
    np.testing.assert_allclose(robot.gravity, [-9.80665, 0, 0])
    np.testing.assert_allclose(robot.model.gravity.linear, [-9.80665, 0, 0])
    with pytest.raises(ValueError):
        motion.waypoints[0, 0] = 1.0


def test_keyword_arguments_override_the_file(arm):
    robot, motion = load_case(write_motion(arm, GOOD), arm / "arm.urdf", payload=Payload(2.0),
                              mounting="ceiling")
    assert robot.payload.mass == 2.0 and motion.payload.mass == 1.5  # the file keeps its own
    np.testing.assert_allclose(robot.gravity, [0, 0, 9.80665])


def test_the_motion_does_not_hold_the_robot(arm):
    """Loading a motion applies nothing: payload and mounting are the robot's transformations."""
    robot = load_robot(arm / "arm.urdf")
    motion = load_motion(write_motion(arm, GOOD), robot)
    assert robot.payload is None and not hasattr(motion, "robot")
    run = robot_for_motion(robot, motion)
    assert run.payload == motion.payload and robot.payload is None
    heavier = robot_for_motion(robot, motion, payload=Payload(3.0))
    assert heavier.payload.mass == 3.0
    with pytest.raises(InputError, match="already carries a payload"):
        robot_for_motion(robot.with_payload(Payload(2.0)), motion)


def test_robot_object_and_radians(arm):
    robot = load_robot(arm / "arm.urdf")
    body = GOOD.replace('robot = "arm.urdf"\n', "").replace('"deg"', '"rad"')
    body = body.replace("q = [0, 30, -45, 0, 60, 0]", "q = [0, 0.5, -1, 0, 1, 0]")
    body = body.replace("j1 = 90,", "j1 = 1.5,").replace("j6 = -90", "j6 = -1.5").replace(
        "j4 = 10,", "j4 = 0.1,")
    motion = load_motion(write_motion(arm, body), robot)
    assert motion.joint_names == robot.joint_names and motion.robot_file is None
    np.testing.assert_allclose(motion.velocity_limit, 120)
    np.testing.assert_allclose(motion.waypoints[0], [0, 0.5, -1, 0, 1, 0])


def test_prismatic_joint_is_never_scaled(tmp_path):
    write_chain(tmp_path, [("turn", "revolute", -3, 3), ("slide", "prismatic", 0, 0.5)])
    motion = load_motion(write_motion(tmp_path, """\
        robot = "arm.urdf"
        planner = "toppra"
        angle_unit = "deg"
        [limits]
        velocity = {turn = 90, slide = 0.2}
        acceleration = 180
        torque = 20
        [[waypoint]]
        q = [0, 0]
        [[waypoint]]
        q = [90, 0.3]
    """))
    np.testing.assert_allclose(motion.waypoints[1], [math.pi / 2, 0.3])
    np.testing.assert_allclose(motion.velocity_limit, [math.pi / 2, 0.2])
    np.testing.assert_allclose(motion.acceleration_limit, [math.pi, 180])
    np.testing.assert_allclose(motion.torque_limit, [20, 20])


def test_samples_log_is_parsed(tmp_path):
    write_robot(tmp_path, 2)
    (tmp_path / "log.csv").write_text("t,q_j1,q_j2,qd_j1,qd_j2\n0,0,90,0,0\n0.1,10,80,5,6\n"
                                      "0.2,20,70,7,8\n")
    motion = load_motion(write_motion(tmp_path, """\
        robot = "arm.urdf"
        planner = "samples"
        angle_unit = "deg"
        [samples]
        file = "log.csv"
    """))
    log = motion.samples
    np.testing.assert_allclose(log.t, [0, 0.1, 0.2])
    np.testing.assert_allclose(log.q[:, 1], np.radians([90, 80, 70]))
    np.testing.assert_allclose(log.qd[2], np.radians([7, 8]))
    assert log.qdd is None
    assert motion.waypoints.shape == (0, 2)


# --- bad input -------------------------------------------------------------------------------

def _error(directory: Path, body: str, robot=None) -> InputError:
    path = write_motion(directory, body)
    with pytest.raises(InputError) as info:
        load_motion(path, robot)
    return info.value


BAD = [
    ('planner = "ruckig"', 'planner = "rucksack"', "planner", "ruckig, toppra, samples"),
    ('angle_unit = "deg"', 'angle_unit = "grad"', "angle_unit", "deg, rad"),
    ('angle_unit = "deg"\n', "", "angle_unit", "required"),
    ("dt = 0.002", "dt = 0", "dt", "positive"),
    ("dt = 0.002", "dtt = 0.002", "dtt", "did you mean 'dt'"),
    ('mounting = "wall"', 'mounting = "roof"', "mounting", "floor"),
    ('mounting = "wall"', "mounting = [0, 0]", "mounting", "3 numbers"),
    ("mass = 1.5", "mass = -1", "payload.mass", "positive"),
    ("com = [0, 0, 0.05]", "com = [0, 0, nan]", "payload.com[2]", "finite"),
    ("velocity = 120", "velocity = 0", "limits.velocity",
     "between 5.72958e-05 and 5.72958e+07 deg/s"),
    ("velocity = 120", "velocity = inf", "limits.velocity", "finite"),
    ("velocity = 120", "velocty = 120", "limits.velocty", "did you mean 'velocity'"),
    ("jerk = 6000", "", "limits.jerk", "required by planner 'ruckig'"),
    ("jerk = 6000", "jerk = 6000\ntorque = 3", "limits.torque", "not used by planner"),
    ("j1 = 600, j2 = 600,", "j1 = 600, elbo = 600,", "limits.acceleration.elbo",
     "joints are: j1, j2"),
    ("j1 = 600, j2 = 600,", "j1 = 600,", "limits.acceleration", "missing joint(s) j2"),
    ("stop_time = 0.05", "stop_time = 0", "safety.stop_time", "between 0.0001 and 1000 s"),
    ("stop_time = 0.05", "stop_time = 1e308", "safety.stop_time", "between 0.0001 and 1000 s"),
    ("dt = 0.002", "dt = 1e400", "dt", "finite"),
    ("mass = 1.5", "mass = 1e308", "payload.mass", "at most 100000 kg"),
    ("com = [0, 0, 0.05]", "com = [0, 0, 1e6]", "payload.com[2]", "between -1000 and 1000 m"),
    ('mounting = "wall"', "mounting = [0, 0, -1e308]", "mounting[2]", "between -1000 and 1000"),
    ("jerk = 6000", "jerk = 1e-300", "limits.jerk", "between"),
    ("dwell = 0.5", "dwell = nan", "waypoint[0].dwell", "finite"),
    ("life_hours = 20000", "life_hours = 0", "requirements.life_hours", "positive"),
    ("q = [0, 30, -45, 0, 60, 0]", "q = [0, 30, -45, 0, 60]", "waypoint[0].q", "6 values"),
    ("q = [0, 30, -45, 0, 60, 0]", "q = [0, 30, -45, 0, 'x', 0]", "waypoint[0].q[4]",
     "expected a number"),
    ("q = [0, 30, -45, 0, 60, 0]", "q = [0, 30, -190, 0, 60, 0]", "waypoint[0].q[2]",
     "-190 deg is outside the limits of joint 'j3' [-180, 180] deg"),
    ("j3 = 0,", "j3 = 200,", "waypoint[1].q.j3", "200 deg is outside"),
    ("j3 = 0,", "elbow = 0,", "waypoint[1].q.elbow", "unknown joint 'elbow'"),
    ("j3 = 0,", "", "waypoint[1].q", "missing joint(s) j3"),
    ("dwell = 0.5", "dwell = -0.5", "waypoint[0].dwell", "at least 0"),
    ("dwell = 0.5", "dwel = 0.5", "waypoint[0].dwel", "did you mean 'dwell'"),
    ("q = {j1", "qq = {j1", "waypoint[1].qq", "did you mean 'q'"),
]


@pytest.mark.parametrize(("old", "new", "field", "text"), BAD)
def test_bad_input_names_file_and_field(arm, old, new, field, text):
    assert old in GOOD
    err = _error(arm, GOOD.replace(old, new, 1))
    assert err.field == field
    assert "motion.toml" in str(err) and field in str(err)
    assert text in str(err)


def test_missing_and_malformed_file(tmp_path):
    with pytest.raises(InputError, match="nowhere.toml: file not found"):
        load_motion(tmp_path / "nowhere.toml")
    err = _error(tmp_path, "planner = \n")
    assert "motion.toml" in str(err) and "not valid TOML" in str(err)


def test_no_robot(arm):
    err = _error(arm, GOOD.replace('robot = "arm.urdf"\n', ""))
    assert err.field == "robot" and "motion.toml" in str(err)


def test_robot_file_not_found(arm):
    err = _error(arm, GOOD.replace("arm.urdf", "nowhere.urdf"))
    assert err.field == "robot" and "motion.toml" in str(err) and "nowhere.urdf" in str(err)


def test_one_waypoint_is_not_enough(arm):
    body = GOOD[:GOOD.index("[[waypoint]]\nq = {")]
    err = _error(arm, body)
    assert err.field == "waypoint" and "at least two" in str(err)


SAMPLES = """\
robot = "arm.urdf"
planner = "samples"
angle_unit = "rad"
[samples]
file = "log.csv"
"""


@pytest.mark.parametrize(("csv", "field", "text"), [
    (None, "samples.file", "log file not found"),
    ("q_j1,q_j2\n0,0\n1,1\n", "t", "column 't' is missing"),
    ("t,q_j1\n0,0\n1,1\n", "q_j2", "column 'q_j2' is missing"),
    ("t,q_j1,q_j2,q_elbow\n0,0,0,0\n1,1,1,1\n", "q_elbow", "unknown joint 'elbow'"),
    ("t,q_j1,q_j2\n0,0,0\n0.1,abc,1\n", "q_j1", "data row 2 (line 3)"),
    ("t,q_j1,q_j2\n0,0,0\n0.1,1,1\n0.2,nan,1\n", "q_j1", "data row 3 (line 4)"),
    ("t,q_j1,q_j2\n0,0,0\n0.1,1,1\n0.1,2,1\n", "t", "data row 3 (line 4)"),
    ("t,q_j1,q_j2,qd_j1\n0,0,0,0\n0.1,1,1,1\n", "qd_j2", "column 'qd_j2' is missing"),
])
def test_bad_log(tmp_path, csv, field, text):
    write_robot(tmp_path, 2)
    if csv is not None:
        (tmp_path / "log.csv").write_text(csv)
    err = _error(tmp_path, SAMPLES)
    assert err.field == field
    assert text in str(err)
    assert ("motion.toml" if csv is None else "log.csv") in str(err)


def test_planner_specific_keys(arm):
    err = _error(arm, SAMPLES + GOOD[GOOD.index("[[waypoint]]"):])
    assert err.field == "waypoint"
    err = _error(arm, GOOD + '[samples]\nfile = "x.csv"\n')
    assert err.field == "samples"  # the planner that takes it, and the one given
    assert "only for planner 'samples' (a logged trajectory), not 'ruckig'" in str(err)
    toppra = GOOD.replace('"ruckig"', '"toppra"')
    err = _error(arm, toppra)
    assert err.field == "limits.jerk" and "planner 'toppra' takes: velocity" in str(err)


# --- lists follow the model's order, and say so -----------------------------------------------

def test_a_list_error_names_the_list_order(arm):
    err = _error(arm, GOOD.replace("q = [0, 30, -45, 0, 60, 0]", "q = [0, 30, -190, 0, 60, 0]"))
    assert "(list order: j1, j2, j3, j4, j5, j6)" in str(err)
    err = _error(arm, GOOD.replace("q = [0, 30, -45, 0, 60, 0]", "q = [0, 30, -45, 0, 'x', 0]"))
    assert "for joint 'j5' (list order: j1, j2, j3, j4, j5, j6)" in str(err)


# --- velocity limits: the robot file's where the motion file gives none ------------------------

def test_velocity_defaults_to_the_robot_files(arm):
    robot, motion = load_case(write_motion(arm, GOOD.replace("velocity = 120\n", "")))
    np.testing.assert_array_equal(motion.velocity_limit, robot.velocity_limit)
    assert motion.velocity_limit[0] == 10.0  # write_chain's <limit velocity="10">
    assert motion.velocity_from_robot == NAMES6
    # no velocity warning; the file's wall mounting moves its joint waypoints with the robot
    assert [w for w in motion.warnings if "moved with the robot" not in w] == []


def test_velocity_table_may_leave_joints_to_the_robot_file(arm):
    body = GOOD.replace("velocity = 120", "velocity = {j2 = 90, j5 = 45}")
    _, motion = load_case(write_motion(arm, body))
    deg = math.pi / 180
    np.testing.assert_allclose(motion.velocity_limit, [10, 90 * deg, 10, 10, 45 * deg, 10])
    assert motion.velocity_from_robot == ("j1", "j3", "j4", "j6")


def test_asking_more_than_the_robot_file_allows_warns_once_per_joint(arm):
    body = GOOD.replace("velocity = 120", "velocity = {j1 = 5000, j2 = 90, j3 = 600, j4 = 90, "
                                          "j5 = 90, j6 = 90}")
    _, motion = load_case(write_motion(arm, body))
    assert motion.warnings == (
        "limits.velocity: joint 'j1' may move at 5000 deg/s, above the robot file's velocity "
        "limit 573 deg/s",
        "limits.velocity: joint 'j3' may move at 600 deg/s, above the robot file's velocity "
        "limit 573 deg/s",
        "the joint waypoints keep their joint angles on the wall mounting: the task moved with "
        "the robot; write them as tool poses (pose = {xyz, rpy}) to keep the task where it is "
        "in the world")  # the file's mounting is "wall"


def test_no_velocity_anywhere_is_an_error_naming_the_joints(tmp_path):
    write_chain(tmp_path, [("j1", "revolute", -1, 1), ("spin", "continuous", 0, 0)])
    err = _error(tmp_path, 'robot = "arm.urdf"\nplanner = "toppra"\nangle_unit = "rad"\n'
                           "[limits]\nacceleration = 1\n[[waypoint]]\nq = [0, 0]\n"
                           "[[waypoint]]\nq = [0.5, 0.5]\n")
    assert err.field == "limits.velocity"
    assert "required by planner 'toppra' for spin: the robot file gives no velocity limit" \
        in str(err)


# --- [sizing] ---------------------------------------------------------------------------------

def test_sizing_section_chooses_the_joints(arm):
    robot, motion = load_case(write_motion(arm, GOOD + '[sizing]\nexclude = ["j6", "j4"]\n'))
    assert motion.excluded_joints == ("j6", "j4")
    assert robot.sized_joints == ("j1", "j2", "j3", "j5")
    robot, _ = load_case(write_motion(arm, GOOD + '[sizing]\njoints = ["j3", "j1"]\n'
                                                  'exclude = ["j3"]\n'))
    assert robot.sized_joints == ("j1",)
    robot, _ = load_case(write_motion(arm, GOOD + '[sizing]\nexclude = ["j6"]\n'), joints=["j2"])
    assert robot.sized_joints == ("j2",)  # an argument overrides the file's [sizing]


@pytest.mark.parametrize(("sizing", "field", "text"), [
    ('exclude = ["elbow"]', "sizing.exclude", "unknown joint 'elbow'; joints are: j1"),
    ('joints = "j1"', "sizing.joints", "expected a list of joint names"),
    ('exclude = ["j1", "j2", "j3", "j4", "j5", "j6"]', "sizing.exclude", "no joint left to size"),
    ("size = 3", "sizing.size", "valid keys: joints, exclude"),
])
def test_bad_sizing_section(arm, sizing, field, text):
    err = _error(arm, GOOD + f"[sizing]\n{sizing}\n")
    assert err.field == field and "motion.toml" in str(err) and text in str(err)
