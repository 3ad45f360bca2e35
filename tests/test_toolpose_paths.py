"""A tool-pose motion's planned path through singularities, and cycles that do not close.

Oracles that do not come from the code under test: the arms' geometry in words. planar2
and benchtop6 are stretched out exactly where their elbow angle is 0 (each forearm
continues its upper arm's x axis), so a planned path passes the elbow singularity where
the planned elbow angle changes sign, found here from the trajectory's own columns. A
cycle closes when its last planned sample equals its first.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.ik.branches import SINGULAR, check_branch, path_crossing, whole_turns
from hdselect.ik.poses import Tolerance, pose_error, xyz_rpy
from hdselect.motion.planning import PLANNERS, plan_motion
from hdselect.robot.kinematics import FrameKinematics
from helpers.poses import ROBOTS, pose_motion
from helpers.robots import robot_path


def planar2_swinging_past(folder, reconfigure: bool = False):
    """planar2 through three poses of elbow -120, -2, -60 deg, no rest between: TOPPRA's
    spline carries the elbow past 0 between the first two, though every waypoint bends
    it down."""
    path = pose_motion(folder, str(ROBOTS / "planar2.urdf"), "tool",
                       angles_each=([40.0, -120.0], [30.0, -2.0], [28.0, -60.0]))
    text = path.read_text().replace("dwell = 0.2\n", "")
    if reconfigure:
        parts = text.split("[[waypoint]]")
        parts[2] += "reconfigure = true\n"
        text = "[[waypoint]]".join(parts)
    path.write_text(text)
    return path


def test_a_planar_arm_straightened_between_two_poses_is_found_where_its_elbow_is_zero(
        tmp_path):
    robot, motion = hdselect.load_case(planar2_swinging_past(tmp_path))
    kin = FrameKinematics(robot, "tool")
    for before, after in zip(motion.waypoints[:-1], motion.waypoints[1:], strict=True):
        assert not check_branch(kin, before, after).flipped  # the waypoints see nothing
    raw = PLANNERS["toppra"](robot, motion)  # the planner alone, before any check
    elbow = raw.q[:, 1]
    k = int(np.flatnonzero(np.diff(np.sign(elbow)))[0])  # the arm straightens after sample k
    straight = k + elbow[k] / (elbow[k] - elbow[k + 1])
    found = path_crossing(kin, raw.q)
    assert found is not None and found.changed == ("elbow",) and found.kind == "elbow"
    assert found.position == pytest.approx(straight, abs=1e-6)
    assert abs(found.q[1]) < 1e-9
    with pytest.raises(InputError) as caught:
        hdselect.plan(robot, motion)
    assert caught.value.field == "waypoint[1]"
    t = float(np.interp(straight, np.arange(len(raw.t)), raw.t))
    assert (f"the planned path from waypoint[0] to waypoint[1] passes an elbow singularity "
            f"(arm stretched or folded) at t = {t:.4g} s") in str(caught.value)
    assert "the elbow indicator changes sign" in str(caught.value)
    assert str(caught.value).endswith("or allow it with reconfigure = true")


def test_reconfigure_allows_a_crossing_on_the_planned_path_with_a_note(tmp_path):
    robot, motion = hdselect.load_case(planar2_swinging_past(tmp_path, reconfigure=True))
    planned = plan_motion(robot, motion)
    assert max(planned.trajectory.q[:, 1]) > 0 > planned.trajectory.q[0, 1]
    assert any("passes an elbow singularity" in w and "allowed by waypoint[1].reconfigure" in w
               for w in planned.motion.warnings)


@pytest.mark.slow
def test_an_allowed_crossing_is_among_the_sizings_warnings(tmp_path, capsys):
    """The note reaches `size`'s result (its table, JSON and report), and the terminal once."""
    path = planar2_swinging_past(tmp_path, reconfigure=True)
    result = hdselect.size(None, path)
    assert any("passes an elbow singularity" in w and "allowed by waypoint[1].reconfigure" in w
               for w in result.warnings)
    capsys.readouterr()
    assert main(["size", str(path), "--json", str(tmp_path / "r.json")]) in (0, 1)
    err = capsys.readouterr().err
    document = json.loads((tmp_path / "r.json").read_text())
    assert any("passes an elbow singularity" in w for w in document["warnings"])
    assert err.count("passes an elbow singularity") <= 1


@pytest.mark.parametrize(("elbow", "crossing"), [(0.0, True), (-1e-3, True), (0.05, False)])
def test_a_path_that_touches_a_singularity_is_found_one_that_keeps_clear_is_not(elbow,
                                                                                crossing):
    """benchtop6's elbow bent 0.4 rad, then to `elbow` [rad] and back, in 3 samples."""
    kin = FrameKinematics(hdselect.load_robot(robot_path("benchtop6")), "tool0")
    q = np.tile(np.radians([10.0, -60.0, 0.0, -60.0, 80.0, 20.0]), (3, 1))
    q[:, 2] = [0.4, elbow, 0.4]
    found = path_crossing(kin, q)
    assert (found is not None) == crossing
    if found is not None:  # first below SINGULAR on the way in, the elbow almost straight
        assert found.kind == "elbow" and found.sigma < SINGULAR and found.changed == ()
        assert 0.0 < found.q[2] < 0.02 and found.position < 1.0


CEILING_POSES = [  # on a ceiling 0.44 m up: xyz [m], rpy [deg]
    ([0.06302, -0.14832, 0.13281], [-40.202, 43.4811, -58.1591]),
    ([0.02046, 0.30937, 0.1996], [167.7003, 14.5964, -90.0565]),
    ([0.03968, -0.07752, -0.19373], [-104.9241, -4.8481, -105.0792]),
    ([0.06302, -0.14832, 0.13281], [-40.202, 43.4811, -58.1591]),
]


def ceiling_motion(folder, dwell: float = 0.0):
    lines = [f'robot = "{robot_path("benchtop6")}"', 'planner = "toppra"', 'angle_unit = "deg"',
             "base = {xyz = [0, 0, 0.44], rpy = [180, 0, 0]}", "[limits]", "velocity = 90",
             "acceleration = 400"]
    for xyz, rpy in CEILING_POSES:
        lines += ["[[waypoint]]", f"pose = {{xyz = {xyz}, rpy = {rpy}}}", f"dwell = {dwell}"]
    path = folder / "ceiling.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow
def test_benchtop6_on_a_ceiling_swinging_through_its_stretched_arm_is_refused(tmp_path):
    robot, motion = hdselect.load_case(ceiling_motion(tmp_path))
    assert np.all(motion.waypoints[:, 2] < math.radians(-20))  # every waypoint bent one way
    raw = PLANNERS["toppra"](robot, motion)
    reached = raw.waypoint_times
    between = (raw.t > reached[1]) & (raw.t < reached[2])
    assert raw.q[between, 2].max() > 0  # the spline carries the elbow past straight
    with pytest.raises(InputError) as caught:
        hdselect.plan(robot, motion)
    assert caught.value.field == "waypoint[2]"
    message = str(caught.value)
    assert "passes an elbow singularity (arm stretched or folded) at t = " in message
    assert "the planner's spline swings past them" in message
    t = float(message.split("at t = ")[1].split(" s")[0])
    assert reached[1] < t < reached[2]
    assert abs(np.interp(t, raw.t, raw.q[:, 2])) < math.radians(0.5)


@pytest.mark.slow
def test_resting_at_both_waypoints_keeps_the_ceiling_move_clear(tmp_path):
    """The message's advice: between two rests the move runs straight in joint space."""
    robot, motion = hdselect.load_case(ceiling_motion(tmp_path, dwell=0.1))
    trajectory = hdselect.plan(robot, motion)
    kin = FrameKinematics(robot, "tool0")
    assert min(kin.sigma_min(q) for q in trajectory.q[::4]) > SINGULAR  # every 4th sample
    assert np.all(trajectory.q[:, 2] < 0)


def turning_wrist(folder, wrist_3: list[float], reconfigure: bool = False):
    """benchtop6 on the floor through the tool poses of one arm with wrist_3 at each angle
    [deg], the first pose solved from those joints (wrist_3 at +180 deg)."""
    robot = hdselect.load_robot(robot_path("benchtop6"))
    kin = FrameKinematics(robot, "tool0")
    arm = [-30.0, -60.0, 100.0, -130.0, -90.0]
    lines = [f'robot = "{robot_path("benchtop6")}"', 'planner = "toppra"', 'angle_unit = "deg"',
             "[limits]", "velocity = 90", "acceleration = 400"]
    for k, angle in enumerate(wrist_3):
        xyz, rpy = xyz_rpy(kin.placement(np.radians([*arm, angle])))
        lines += ["[[waypoint]]", f"pose = {{xyz = {[round(float(v), 5) for v in xyz]}, "
                  f"rpy = {[round(math.degrees(v), 4) for v in rpy]}}}", "dwell = 0.2"]
        if k == 0:
            lines.append("near = {" + ", ".join(f"{name} = {value}" for name, value in zip(
                robot.joint_names, [*arm, angle], strict=True)) + "}")
    if reconfigure:
        lines.append("reconfigure = true")
    path = folder / "turning.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow
def test_a_cycle_back_to_its_start_pose_a_turn_away_closes_with_a_note(tmp_path):
    """+180 deg, -5 deg, and the first pose again, which the solver reaches at -180 deg."""
    robot, motion = hdselect.load_case(turning_wrist(tmp_path, [180.0, -5.0, 180.0]))
    assert math.degrees(motion.waypoints[0, 5]) == pytest.approx(180.0, abs=1e-3)
    np.testing.assert_array_equal(motion.waypoints[2], motion.waypoints[0])
    (note,) = motion.warnings
    assert note.startswith("waypoint[2]: the tool is back at waypoint[0]'s pose with wrist_3 "
                           "-360 deg from waypoint[0]'s joints: the cycle does not close")
    assert note.endswith("it takes waypoint[0]'s joints instead, so the move from waypoint[1] "
                         "turns wrist_3 +185 deg")
    kin = FrameKinematics(robot, "tool0")
    written = motion.tool.poses[2].pose
    assert Tolerance().holds(*pose_error(kin.placement(motion.waypoints[2]), written))
    trajectory = hdselect.plan(robot, motion)
    np.testing.assert_allclose(trajectory.q[-1], trajectory.q[0], atol=1e-9)  # it repeats


def test_a_cycle_that_turns_the_part_a_full_turn_is_refused_unless_it_may_turn_back(tmp_path):
    turns = [180.0, 120.0, 60.0, 0.0, -60.0, -120.0, 180.0]
    with pytest.raises(InputError) as caught:
        hdselect.load_case(turning_wrist(tmp_path, turns))
    assert caught.value.field == "waypoint[6]"
    message = str(caught.value)
    assert "with wrist_3 -360 deg from waypoint[0]'s joints: the cycle does not close" in message
    assert message.endswith("allow it with reconfigure = true on waypoint[6], and the cycle "
                            "contains the turn back")
    robot, motion = hdselect.load_case(turning_wrist(tmp_path, turns, reconfigure=True))
    np.testing.assert_array_equal(motion.waypoints[6], motion.waypoints[0])
    assert any("turns wrist_3 +300 deg" in w and w.endswith("allowed by waypoint[6].reconfigure")
               for w in motion.warnings)


def test_whole_turns_counts_bounded_revolute_joints_only():
    kin = FrameKinematics(hdselect.load_robot(robot_path("benchtop6")), "tool0")
    q = np.radians([10.0, -60.0, 90.0, -60.0, 80.0, 170.0])
    turned = q + [0, 0, 0, 0, 0, -2 * np.pi]
    assert whole_turns(kin, q, turned).tolist() == [0, 0, 0, 0, 0, -1]
    assert not whole_turns(kin, q, turned + [0.01, 0, 0, 0, 0, 0]).any()  # another pose
    assert not whole_turns(kin, q, q).any()


def test_a_crossing_between_two_rests_is_not_blamed_on_the_spline(tmp_path):
    """pybullet's Panda between two dwells: the planned path is the straight joint move,
    so 'dwell at both' (they do) and 'the spline swings past' were the wrong advice."""
    data = pytest.importorskip("pybullet_data")
    urdf = Path(data.getDataPath()) / "franka_panda" / "panda.urdf"
    near = ", ".join(f"panda_joint{k} = {v}"
                     for k, v in enumerate((0, 0, 0, -18, 0, 17.4, 0), start=1))
    lines = [f'robot = "{urdf}"', 'planner = "toppra"', 'angle_unit = "deg"', "[limits]",
             "velocity = 100", "acceleration = 200", "[tool]", 'frame = "panda_link7"']
    for xyz, rpy, hint in (([0.2107, 0, 1.03878], [180, 0.6, 0], f"near = {{{near}}}"),
                           ([0.41068, 0.49513, 0.72289], [-146.097, 35.2991, 56.8946], "")):
        lines += ["[[waypoint]]", "dwell = 0.5", f"pose = {{xyz = {xyz}, rpy = {rpy}}}", hint]
    path = tmp_path / "panda.toml"
    path.write_text("\n".join(lines) + "\n")
    robot, motion = hdselect.load_case(path)
    with pytest.raises(InputError) as caught:
        hdselect.plan(robot, motion)
    message = str(caught.value)
    assert caught.value.field == "waypoint[1]" and "passes a singularity" in message
    assert message.endswith("move the poses, or add a waypoint between them that keeps the "
                            "arm away from it, or allow it with reconfigure = true")
