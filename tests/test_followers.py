"""Mimic followers are held to their own limits along the motion (hdselect.motion.followers).

A follower's position is multiplier x leader + offset; it is checked at every
waypoint, every logged sample and along every planned trajectory like any joint's,
and a motion may list a follower's value (as a ``joint_states`` export does) if it
agrees with its leader. The arm: planar2 with a finger on link2 following the elbow.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.planning import Trajectory, check_within_limits
from helpers import REPO, run_redirected
from helpers.robots import ARMS, example_robots, finger_arm

MOTION = (REPO / "trajectories" / "planar2_pick_place.toml").read_text()


def motion_file(folder: Path, text: str = MOTION) -> Path:
    path = folder / "motion.toml"
    path.write_text(text.replace('robot = "../robots/planar2.urdf"', 'robot = "finger.urdf"'))
    return path


def test_the_follower_keeps_its_range_in_the_listing_and_the_robot(tmp_path):
    robot = hdselect.load_robot(finger_arm(tmp_path))
    mimic = robot.mimic["finger"]
    assert (mimic.multiplier, mimic.offset, mimic.lower, mimic.upper) == (3.0, 0.0, -0.5, 0.5)
    (info,) = [i for i in hdselect.describe_joints(robot) if i.name == "finger"]
    assert (info.lower, info.upper, info.kind) == (-0.5, 0.5, "mimic")


def test_a_waypoint_that_takes_a_follower_past_its_limits_is_refused(tmp_path):
    """Multiplier 3: the elbow's -80 deg puts the finger at -240 deg against +-28.6 deg."""
    finger_arm(tmp_path)
    status, out, err = run_redirected(["size", str(motion_file(tmp_path))])
    assert status == 2 and out == "" and err.count("\n") == 1
    limit = math.degrees(0.5)
    assert err == (f"hdselect: error: {tmp_path / 'motion.toml'}: waypoint[0].q.elbow: mimic "
                   f"follower 'finger' (= 3 x elbow) goes to -240 deg, outside its limits "
                   f"[-{limit:g}, {limit:g}] deg; keep elbow within [-{limit / 3:.6g}, "
                   f"{limit / 3:.6g}] deg\n")


def test_the_same_motion_within_the_follower_range_sizes(tmp_path):
    finger_arm(tmp_path, multiplier=0.1)  # -80 .. 20 deg of elbow: -8 .. 2 deg of finger
    result = hdselect.size(None, motion_file(tmp_path))
    (load,) = [load for load in result.loads if load.name == "finger"]
    np.testing.assert_allclose(load.travel, (math.radians(-8), math.radians(2)), atol=1e-9)


def test_an_offset_moves_the_follower_out_of_range(tmp_path):
    finger_arm(tmp_path, multiplier=0.1, offset=0.6)
    status, _, err = run_redirected(["size", str(motion_file(tmp_path))])
    assert status == 2 and "mimic follower 'finger' (= 0.1 x elbow + 0.6)" in err


def test_a_follower_without_range_is_not_limited(tmp_path):
    finger_arm(tmp_path, limits='lower="0" upper="0"')
    robot = hdselect.load_robot(tmp_path / "finger.urdf")
    assert (robot.mimic["finger"].lower, robot.mimic["finger"].upper) == (-math.inf, math.inf)
    hdselect.load_motion(motion_file(tmp_path))


def test_a_trajectory_that_takes_a_follower_past_its_limits_is_refused(tmp_path):
    """Between waypoints within range, a path may overshoot: the trajectory check finds it."""
    finger_arm(tmp_path, multiplier=0.3)
    robot, motion = hdselect.load_case(motion_file(tmp_path))
    t = np.linspace(0.0, 1.0, 11)
    q = np.zeros((11, 2))
    q[:, 1] = np.linspace(0.0, 2.0, 11)  # the elbow to 2 rad: the finger to 0.6 rad
    zero = np.zeros_like(q)
    trajectory = Trajectory(robot.joint_names, 0.1, 1.0, t, q, zero, zero)
    with pytest.raises(PlanningError) as info:
        check_within_limits(robot, motion, trajectory)
    assert str(info.value).startswith(f"{motion.path}: the ruckig trajectory: mimic follower "
                                      "'finger' (= 0.3 x elbow) goes to 34.3775 deg, outside its "
                                      "limits [-28.6479, 28.6479] deg")
    assert str(info.value).endswith("(t = 1 s)")


def log_motion(folder: Path, header: str, rows: list[str]) -> Path:
    (folder / "log.csv").write_text("\n".join([header, *rows]) + "\n")
    path = folder / "logged.toml"
    path.write_text('robot = "finger.urdf"\nplanner = "samples"\nangle_unit = "rad"\n'
                    'dt = 0.01\n[samples]\nfile = "log.csv"\n')
    return path


ROWS = [f"{0.01 * k:.2f},{0.1 * math.sin(k / 5):.12f},{-0.5 * math.sin(k / 7):.12f}"
        for k in range(60)]


def with_follower(rows: list[str], multiplier: float, shift: float = 0.0) -> list[str]:
    """Each row with the finger's column, as the mimic puts it (plus `shift`) [rad]."""
    return [f"{row},{multiplier * float(row.split(',')[2]) + shift:.12f}" for row in rows]


def test_a_log_listing_followers_that_agree_is_read_as_without_them(tmp_path):
    """A joint_states export lists every joint, followers too."""
    finger_arm(tmp_path, multiplier=0.1)
    plain = hdselect.size(None, log_motion(tmp_path, "t,q_shoulder,q_elbow", ROWS))
    listed = hdselect.size(None, log_motion(tmp_path, "t,q_shoulder,q_elbow,q_finger",
                                            with_follower(ROWS, 0.1)))
    for a, b in zip(plain.joints, listed.joints, strict=True):
        np.testing.assert_array_equal(a.torque, b.torque)


def test_a_log_whose_follower_disagrees_is_refused_naming_both(tmp_path):
    finger_arm(tmp_path, multiplier=0.1)
    motion = log_motion(tmp_path, "t,q_shoulder,q_elbow,q_finger",
                        with_follower(ROWS, 0.1, shift=0.01))
    status, _, err = run_redirected(["size", str(motion)])
    assert status == 2 and err.count("\n") == 1
    assert f"{tmp_path / 'log.csv'}: q_finger: data row 1 (line 2): 0.01 rad for mimic " \
           "follower 'finger' (= 0.1 x elbow) disagrees with its leader, which puts it at 0 " \
           "rad" in err


def test_a_log_that_takes_a_follower_past_its_limits_is_refused(tmp_path):
    finger_arm(tmp_path, multiplier=3.0)
    motion = log_motion(tmp_path, "t,q_shoulder,q_elbow", ROWS)
    status, _, err = run_redirected(["size", str(motion)])
    assert status == 2 and err.count("\n") == 1
    assert "q_elbow: data row" in err and "mimic follower 'finger' (= 3 x elbow)" in err


@pytest.mark.parametrize(("value", "agrees"), [(-8.0, True), (-8.00004, True), (-7.9, False)])
def test_a_waypoint_may_list_a_follower_that_agrees(tmp_path, value, agrees):
    finger_arm(tmp_path, multiplier=0.1)
    text = MOTION.replace("q = {shoulder = 40, elbow = -80}     # home, raised",
                          f"q = {{shoulder = 40, elbow = -80, finger = {value}}}")
    path = motion_file(tmp_path, text)
    if agrees:
        listed = hdselect.load_motion(path)
        plain = hdselect.load_motion(motion_file(tmp_path))
        np.testing.assert_array_equal(listed.waypoints, plain.waypoints)
        return
    with pytest.raises(InputError) as info:
        hdselect.load_motion(path)
    assert info.value.field == "waypoint[0].q.finger"
    assert info.value.reason == ("-7.9 deg for mimic follower 'finger' (= 0.1 x elbow) disagrees "
                                 "with its leader, which puts it at -8 deg; give the leader's "
                                 "value only, or one that agrees")


def test_panda_finger_followers_multiplier_3_leave_their_range(tmp_path):
    """Panda's second finger follows the first; x 3 it passes 0.04 m where the first is 0.02."""
    text = (example_robots() / ARMS["Panda"]).read_text()
    old = '<mimic joint="panda_finger_joint1"'
    assert old in text
    path = tmp_path / "panda.urdf"
    path.write_text(text.replace(old, f'{old} multiplier="3"', 1))
    motion = tmp_path / "panda.toml"
    motion.write_text('robot = "panda.urdf"\nplanner = "ruckig"\nangle_unit = "deg"\n'
                      "[limits]\nvelocity = 30\nacceleration = 100\njerk = 1000\n"
                      "[[waypoint]]\nq = [0, 0, 0, -90, 0, 90, 0, 0.0]\n"
                      "[[waypoint]]\nq = [0, 0, 0, -90, 0, 90, 0, 0.02]\n")
    with pytest.raises(InputError) as info:
        hdselect.load_motion(motion)
    assert info.value.field == "waypoint[1].q.panda_finger_joint1"
    assert "mimic follower 'panda_finger_joint2' (= 3 x panda_finger_joint1) goes to 0.06 m, " \
           "outside its limits [0, 0.04] m; keep panda_finger_joint1 within [0, 0.0133333] m" \
           in info.value.reason
