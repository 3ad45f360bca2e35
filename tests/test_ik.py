"""Tests of hdselect.ik.poses, kinematics, ik and branches: one tool pose solved.

Oracles that do not come from the code under test: the closed-form inverse kinematics
of the shipped two-link arm (robots/planar2.urdf), forward kinematics re-run on a fresh
``pinocchio.Data`` of a model built here from the file, URDF's roll-pitch-yaw composed
by hand from elementary rotations, and built cases whose answer is known (a 2 pi turn of
a wrist leaves the tool where it was; an elbow limit that forbids the bend a pose needs).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from hdselect.ik.branches import check_branch, indicators
from hdselect.ik.poses import (
    in_base,
    interpolate_pose,
    pose_error,
    pose_from_xyz_rpy,
    xyz_rpy,
)
from hdselect.ik.solver import solve_pose
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import load_robot
from hdselect.robot.mounting import NAMED_BASES, BasePose
from helpers.poses import IK_ARMS, TOLERANCE, UR5_Q, arm, fk, rot, within
from helpers.robots import example_robots, robot_path

# --- poses ---------------------------------------------------------------------------------

def test_rpy_is_urdfs_fixed_axes():
    pose = pose_from_xyz_rpy([1, 2, 3], [0.1, -0.4, 2.0])
    np.testing.assert_allclose(pose.rotation, rot("z", 2.0) @ rot("y", -0.4) @ rot("x", 0.1),
                               atol=1e-12)
    xyz, rpy = xyz_rpy(pose)
    np.testing.assert_allclose(xyz, [1, 2, 3])
    np.testing.assert_allclose(rpy, [0.1, -0.4, 2.0], atol=1e-12)


def test_world_pose_into_the_base_frame_and_back():
    base = BasePose.from_xyz_rpy([0.2, -0.1, 1.5], [0.3, 0.2, -1.0])
    world = pose_from_xyz_rpy([0.4, 0.3, 0.9], [1.0, 0.5, 0.2])
    in_the_base = in_base(base, world)
    back = pin.SE3(base.matrix, base.position) * in_the_base
    assert pose_error(back, world) == pytest.approx((0.0, 0.0), abs=1e-12)


def test_straight_line_pose_moves_evenly():
    start = pose_from_xyz_rpy([0, 0, 0], [0, 0, 0])
    end = pose_from_xyz_rpy([0.2, 0.4, 0], [0, 0, 1.2])
    quarter = interpolate_pose(start, end, 0.25)
    np.testing.assert_allclose(quarter.translation, [0.05, 0.1, 0])
    np.testing.assert_allclose(quarter.rotation, rot("z", 0.3), atol=1e-12)
    assert pose_error(interpolate_pose(start, end, 1.0), end) == pytest.approx((0, 0), abs=1e-12)


# --- one pose ------------------------------------------------------------------------------

def planar_closed_form(x: float, z: float, elbow: float) -> np.ndarray:
    """The two joint angles [rad] of robots/planar2.urdf that put `tool` at (x, z) [m].

    Shoulder 0.30 m above the base, links l1 = 0.30 m and l2 = 0.25 m, both axes -y (a
    positive angle raises the arm). With z' = z - 0.30 and the law of cosines,
    cos q2 = (x^2 + z'^2 - l1^2 - l2^2) / (2 l1 l2), q2 = +-acos(...) (`elbow` gives the
    sign), q1 = atan2(z', x) - atan2(l2 sin q2, l1 + l2 cos q2).
    """
    l1, l2, zz = 0.30, 0.25, z - 0.30
    q2 = elbow * math.acos((x * x + zz * zz - l1 * l1 - l2 * l2) / (2 * l1 * l2))
    return np.array([math.atan2(zz, x) - math.atan2(l2 * math.sin(q2), l1 + l2 * math.cos(q2)),
                     q2])


@pytest.mark.parametrize("elbow", [1.0, -1.0])
def test_two_link_arm_matches_its_closed_form(elbow):
    kin = FrameKinematics(load_robot(robot_path("planar2")), "tool")
    rng = np.random.default_rng(3)
    checked = 0
    while checked < 25:
        radius, angle = rng.uniform(0.1, 0.53), rng.uniform(-1.0, 1.4)
        x, z = radius * math.cos(angle), 0.30 + radius * math.sin(angle)
        expected = planar_closed_form(x, z, elbow)
        if np.any(expected < kin.lower + 0.05) or np.any(expected > kin.upper - 0.05):
            continue  # this branch is outside the joint limits
        checked += 1
        # the tool is turned by -(q1 + q2) about y (both axes are -y)
        target = pin.SE3(rot("y", -expected.sum()), np.array([x, 0.0, z]))
        solved = solve_pose(kin, target, np.array([0.3, 0.6 * elbow]))
        assert solved.converged and solved.restart == 0
        np.testing.assert_allclose(solved.q, expected, atol=1e-4)
        assert within(kin, solved.q, target)
        # elbow indicator: z2 . (x1 x x2) with z2 = -y and x1 x x2 = -sin(q2) y: sin(q2)
        assert np.sign(indicators(kin, solved.q)["elbow"]) == elbow


@pytest.mark.slow
@pytest.mark.parametrize("name", ["UR5", "Panda", "benchtop6"])
def test_random_poses_solve_from_near_and_far_seeds(name):
    kin = arm(name)
    rng = np.random.default_rng(11)
    lower, upper = np.maximum(kin.lower, -np.pi), np.minimum(kin.upper, np.pi)
    far_solved = found_again = 0
    for _ in range(60):
        truth = rng.uniform(lower, upper)
        target = fk(kin, truth)
        near = kin.clip(truth + rng.normal(0.0, 0.1, kin.dof))
        solved = solve_pose(kin, target, near)
        assert solved.converged and within(kin, solved.q, target)
        assert np.all(solved.q >= kin.lower) and np.all(solved.q <= kin.upper)
        found_again += bool(np.allclose(solved.q, truth, atol=1e-3))
        far = solve_pose(kin, target, rng.uniform(lower, upper), restarts=30)
        if far.converged:
            far_solved += 1
            assert within(kin, far.q, target)
    assert far_solved >= 57
    if name != "Panda":  # 6 joints: isolated solutions, the seed's branch is found again
        assert found_again >= 45


def test_unreachable_out_of_reach_names_no_limit():
    kin = arm("UR5")
    solved = solve_pose(kin, pin.SE3(np.eye(3), np.array([2.0, 0.0, 0.5])), UR5_Q)
    assert not solved.converged and solved.blocking == ()
    assert 0.9 < solved.position_error < 2.0  # UR5 reaches about 0.95 m from its shoulder
    assert solved.position_error == pytest.approx(pose_error(
        fk(kin, solved.q), pin.SE3(np.eye(3), np.array([2.0, 0.0, 0.5])))[0], rel=1e-9)


def test_unreachable_behind_a_joint_limit_names_it(tmp_path):
    text = (example_robots() / IK_ARMS["UR5"][0]).read_text()
    # the elbow may bend 0.1 rad at most: the pose of UR5_Q needs 1.3 rad
    start = text.index('name="elbow_joint"')
    limit = text.index("<limit", start)
    end = text.index("/>", limit)
    text = text[:limit] + '<limit effort="150.0" lower="-0.1" upper="0.1" velocity="3.15"' \
        + text[end:]
    path = tmp_path / "ur5_stiff_elbow.urdf"
    path.write_text(text)
    narrow = FrameKinematics(load_robot(path), "tool0")
    target = fk(arm("UR5"), UR5_Q)
    solved = solve_pose(narrow, target, np.where(np.arange(6) == 2, 0.0, UR5_Q))
    assert not solved.converged
    assert [(c.joint, c.side) for c in solved.blocking] == [("elbow_joint", "upper")]
    assert solved.q[2] == pytest.approx(0.1)


def test_near_hint_seeds_and_clips():
    kin = arm("UR5")
    seed = kin.seed({"elbow_joint": -1.0, "wrist_2_joint": 9.0})
    assert seed[2] == -1.0 and seed[4] == kin.upper[4]
    assert seed[0] == pytest.approx(0.5 * (kin.lower[0] + kin.upper[0]))


def test_mounted_pose_is_the_world_pose():
    """A world pose solved through each mounting's base pose lands on that world pose."""
    kin = arm("UR5")
    world = pose_from_xyz_rpy([0.35, 0.25, 0.30], np.radians([180, 20, 45]))
    for base in (*NAMED_BASES.values(), BasePose.from_xyz_rpy([0.1, -0.2, 0.3], [0.4, -0.3, 1])):
        solved = solve_pose(kin, in_base(base, world), kin.seed(), restarts=30)
        assert solved.converged
        reached = pin.SE3(base.matrix, base.position) * fk(kin, solved.q)
        assert TOLERANCE.holds(*pose_error(reached, world))


# --- branches ------------------------------------------------------------------------------

def test_small_moves_keep_the_branch():
    kin = arm("UR5")
    step = np.array([0.05, 0.03, -0.04, 0.02, 0.05, 0.1])
    for k in range(4):
        assert not check_branch(kin, UR5_Q + k * step, UR5_Q + (k + 1) * step).flipped


def test_elbow_flip_is_named():
    """The other elbow branch of the same pose: bend the elbow the other way."""
    kin = arm("UR5")
    target = fk(kin, UR5_Q)
    down = solve_pose(kin, target, np.array([0.3, -0.2, -1.3, -2.5, 0.9, 0.2]))
    assert down.converged and down.q[2] < 0
    check = check_branch(kin, UR5_Q, down.q)
    assert check.flipped and check.changed == ("elbow",)


def test_wrist_flip_crosses_the_singularity():
    kin = arm("UR5")
    before, after = UR5_Q.copy(), UR5_Q.copy()
    before[4], after[4] = 0.25, -0.25  # wrist_2 through 0: axes 4 and 6 align
    check = check_branch(kin, before, after)
    assert check.flipped and "wrist" in check.changed and check.min_sigma < 1e-3


def test_full_turn_of_a_wrist_is_a_jump():
    kin = arm("UR5")
    turned = UR5_Q + np.array([0, 0, 0, 0, 0, 2 * np.pi])  # the same tool pose
    assert pose_error(fk(kin, turned), fk(kin, UR5_Q)) == pytest.approx((0, 0), abs=1e-9)
    check = check_branch(kin, UR5_Q, turned)
    assert check.flipped and check.changed == ()
    assert check.joint_move == pytest.approx(2 * np.pi) and check.needed_move < 1e-6
