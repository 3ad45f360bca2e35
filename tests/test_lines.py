"""Tests of hdselect.ik.lines and linefit: straight tool moves as joint paths.

Oracles: forward kinematics on a model built here from the file (`test_ik.fk`), the
line's pose computed here (position linear, orientation R0 exp(f log(R0^T R1))), a
brute-force search over the line for the nearest pose, and built cases whose answer
is known (a turn about the tool axis of UR5 turns its last joint only, so a limit
half-way stops the line half-way).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

from hdselect.ik.lines import LinePath, LineStop, refine, solve_line
from hdselect.ik.poses import Tolerance
from hdselect.motion.planning.linefit import deviation
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import load_robot
from helpers.poses import UR5_Q, arm, fk, rot, within
from helpers.robots import example_robots

TOLERANCE = Tolerance()
STARTS = {"UR5": UR5_Q, "benchtop6": np.array([0.3, -1.0, 1.2, -1.0, 0.8, 0.2]),
          "Panda": np.array([0.2, -0.3, 0.1, -2.0, 0.1, 1.8, 0.5, 0.0])}


def line_pose(start: pin.SE3, end: pin.SE3, fraction: float) -> pin.SE3:
    """The line's pose, computed here: origin linear, rotation at a constant rate."""
    turn = pin.log3(start.rotation.T @ end.rotation)
    return pin.SE3(start.rotation @ pin.exp3(fraction * turn),
                   start.translation + fraction * (end.translation - start.translation))


@pytest.mark.parametrize("name", sorted(STARTS))
def test_line_within_tolerance_at_samples_and_chord_midpoints(name):
    kin = arm(name)
    q0 = STARTS[name]
    start = fk(kin, q0)
    end = pin.SE3(start.rotation @ rot("x", 0.3) @ rot("z", -0.4),
                  start.translation + np.array([0.04, -0.05, 0.03]))
    line = solve_line(kin, 1, start, end, q0, TOLERANCE)
    assert isinstance(line, LinePath)
    assert line.fractions[0] == 0 and line.fractions[-1] == 1
    assert np.all(np.diff(line.fractions) > 0) and len(line.fractions) >= 3
    for k, (fraction, q) in enumerate(zip(line.fractions, line.q, strict=True)):
        assert within(kin, q, line_pose(start, end, fraction))
        assert np.all(q >= kin.lower) and np.all(q <= kin.upper)
        if k:
            middle = 0.5 * (line.fractions[k - 1] + fraction)
            assert within(kin, 0.5 * (line.q[k - 1] + q), line_pose(start, end, middle))


def narrowed_ur5(tmp_path, joint: str, lower: float, upper: float) -> FrameKinematics:
    """UR5 with one joint's limits narrowed, written to a file of its own."""
    text = (example_robots() / "ur_description/urdf/ur5_robot.urdf").read_text()
    limit = text.index("<limit", text.index(f'name="{joint}"'))
    end = text.index("/>", limit)
    path = tmp_path / "ur5.urdf"
    path.write_text(text[:limit] + f'<limit effort="28.0" lower="{lower}" upper="{upper}" '
                    'velocity="3.2"' + text[end:])
    return FrameKinematics(load_robot(path), "tool0")


def test_line_stops_at_a_joint_limit_half_way(tmp_path):
    kin = narrowed_ur5(tmp_path, "wrist_3_joint", -6.0, UR5_Q[5] + np.pi / 4)
    start = fk(kin, UR5_Q)
    end = pin.SE3(start.rotation @ rot("z", np.pi / 2), start.translation)  # about tool z
    stop = solve_line(kin, 1, start, end, UR5_Q, TOLERANCE)
    assert isinstance(stop, LineStop) and stop.reason == "joint limit"
    assert [(c.joint, c.side) for c in stop.limits] == [("wrist_3_joint", "upper")]
    assert stop.fraction == pytest.approx(0.5, abs=1e-3)


def test_line_through_the_wrist_singularity_stops_there():
    kin = arm("UR5")
    before, after = UR5_Q.copy(), UR5_Q.copy()
    before[4], after[4] = 0.3, -0.3
    stop = solve_line(kin, 1, fk(kin, before), fk(kin, after), before, TOLERANCE)
    assert isinstance(stop, LineStop) and stop.reason == "singularity"
    assert stop.singularity == "wrist" and 0.3 < stop.fraction < 0.7


def test_line_out_of_reach_stops_at_the_edge():
    kin = arm("UR5")
    start = fk(kin, UR5_Q)
    end = pin.SE3(start.rotation, start.translation * 4.0)
    stop = solve_line(kin, 1, start, end, UR5_Q, TOLERANCE)
    assert isinstance(stop, LineStop) and 0 < stop.fraction < 1
    assert stop.reason == "out of reach" or stop.singularity == "elbow"  # the stretched arm
    shoulder = kin.robot.model.jointPlacements[2].translation  # shoulder_lift's origin
    reach = np.linalg.norm(line_pose(start, end, stop.fraction).translation - shoulder)
    assert 0.7 < reach < 1.0  # UR5 reaches about 0.95 m from its shoulder


def test_refine_adds_a_sample_on_the_line():
    kin = arm("UR5")
    start = fk(kin, UR5_Q)
    end = pin.SE3(start.rotation @ rot("y", 0.2), start.translation + [0.0, 0.05, -0.05])
    line = solve_line(kin, 1, start, end, UR5_Q, TOLERANCE)
    assert isinstance(line, LinePath)
    middle = 0.5 * (line.fractions[0] + line.fractions[1])
    finer = refine(kin, line, middle, TOLERANCE)
    assert finer is not None and len(finer.fractions) == len(line.fractions) + 1
    assert finer.fractions[1] == middle
    assert within(kin, finer.q[1], line_pose(start, end, middle))


@pytest.mark.slow
def test_deviation_matches_a_brute_force_search():
    """Distance from the segment and angle from the arc, against 20,001 points of the line."""
    start = pin.SE3(rot("z", 0.3), np.array([0.1, 0.2, 0.3]))
    end = pin.SE3(rot("z", 0.3) @ rot("x", 0.8), np.array([0.3, 0.1, 0.2]))
    line = LinePath(1, start.homogeneous, end.homogeneous, np.array([0.0, 1.0]),
                    np.zeros((2, 1)), np.zeros(2), np.zeros(2))
    rng = np.random.default_rng(5)
    poses = [pin.SE3(line_pose(start, end, f).rotation @ pin.exp3(rng.normal(0, 0.02, 3)),
                     line_pose(start, end, f).translation + rng.normal(0, 0.01, 3))
             for f in rng.uniform(-0.2, 1.2, 40)]
    distance, angle, _ = deviation(line, poses)
    fractions = np.linspace(0, 1, 20001)
    grid = [line_pose(start, end, f) for f in fractions]
    origins = np.array([g.translation for g in grid])
    orientations = Rotation.from_matrix(np.array([g.rotation for g in grid]))
    for pose, d, a in zip(poses, distance, angle, strict=True):
        nearest = np.linalg.norm(origins - pose.translation, axis=1).min()
        turned = (orientations.inv() * Rotation.from_matrix(pose.rotation)).magnitude().min()
        assert d == pytest.approx(nearest, abs=1e-6)
        assert a == pytest.approx(turned, abs=1e-6)
        assert a <= turned + 1e-12  # never above the search's best
