"""Inverse dynamics against oracles: Pinocchio per sample, and closed forms by hand.

The batched `inverse_dynamics` is compared with a plain Python loop of
`pinocchio.rnea` (a second method), the gravity part with
`pinocchio.computeGeneralizedGravity`, and two robots with their own
textbook equations: the index table (tau = J qdd) and the vertical two-link
arm (M(q) qdd + C(q, qd) qd + g(q)), written out below from the derivations in
the URDF comments.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import cycle_torques, inverse_dynamics
from hdselect.robot.model import load_robot
from hdselect.robot.mounting import STANDARD_GRAVITY
from helpers import REPO
from helpers.dynamics import (
    J_TABLE,
    L1,
    L2,
    LC1,
    LC2,
    M1,
    M2,
    MOTIONS,
    ROBOTS,
    G,
    composite_link2,
    pin_config,
    planned,
    random_states,
    rnea_loop,
    thinned,
    two_link,
)


def joint_torques(robot, trajectory: Trajectory):
    """Torques along a trajectory with their gravity part (stop time 0.1 s)."""
    return cycle_torques(robot, trajectory.q, trajectory.qd, trajectory.qdd, 0.1, split=True)


# --- a second method: Pinocchio one sample at a time -----------------------------------------

@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_batched_equals_per_sample_rnea(path, mounting):
    robot = load_robot(path, mounting=mounting)
    # 600 samples: more than 256, so the batched call runs on more than one thread
    q, qd, qdd = random_states(robot, 600, seed=len(path.stem))
    expected = rnea_loop(robot.model, q, qd, qdd)
    got = inverse_dynamics(robot, q, qd, qdd)
    assert got.shape == (600, robot.dof)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10)


def test_repeated_states_are_computed_once_and_equal():
    # dwells: 3,001 copies of states after 400 moving ones; every sample checked
    robot = load_robot(REPO / "robots" / "benchtop6.urdf")
    q, qd, qdd = random_states(robot, 400, seed=7)
    hold = np.repeat([0, 1, 2, 399], [1000, 1500, 500, 1])
    q, qd, qdd = (np.concatenate([x, x[hold]]) for x in (q, qd, qdd))
    got = inverse_dynamics(robot, q, qd, qdd)
    assert got.shape == (3401, robot.dof)
    np.testing.assert_array_equal(got, inverse_dynamics(robot, q[:400], qd[:400],
                                                        qdd[:400])[np.r_[:400, hold]])
    np.testing.assert_allclose(got[::17], rnea_loop(robot.model, q[::17], qd[::17],
                                                    qdd[::17]), rtol=0, atol=1e-10)


@pytest.mark.slow
@pytest.mark.parametrize("path", MOTIONS, ids=lambda p: p.stem)
def test_joint_torques_along_shipped_motions(path):
    robot, motion, trajectory = planned(path)
    model = robot.model  # with the motion file's payload and mounting
    torques = joint_torques(robot, trajectory)
    keep = thinned(trajectory)
    q, qd, qdd = trajectory.q[keep], trajectory.qd[keep], trajectory.qdd[keep]
    np.testing.assert_allclose(torques.tau[keep], rnea_loop(model, q, qd, qdd), rtol=0,
                               atol=1e-10)
    data = model.createData()
    gravity = np.array([pin.computeGeneralizedGravity(model, data, pin_config(model, x)).copy()
                        for x in q])
    np.testing.assert_allclose(torques.gravity[keep], gravity, rtol=0, atol=1e-10)
    assert not torques.tau.flags.writeable and not torques.gravity.flags.writeable


def test_payload_enters_the_dynamics():
    """The motion file's payload is in the model: torques differ from the bare robot's."""
    robot, motion, trajectory = planned(REPO / "trajectories" / "planar2_pick_place.toml")
    bare = load_robot(REPO / "robots" / "planar2.urdf")
    with_payload = joint_torques(robot, trajectory).gravity
    without = inverse_dynamics(bare, trajectory.q, 0 * trajectory.qd, 0 * trajectory.qdd)
    # 0.4 kg at 0.28 m along link 2: the shoulder holds at most m g (l1 + 0.28) more
    extra = np.abs(with_payload[:, 0] - without[:, 0])
    assert 0.0 < extra.max() <= 0.4 * G * (0.3 + 0.28) + 1e-9


# --- the index table: tau = J qdd -------------------------------------------------------------


def test_index_table_inertia_from_the_urdf_comment():
    assert J_TABLE == pytest.approx(0.061581, abs=5e-7)


def test_index_table_torque_is_inertia_times_acceleration():
    robot, motion, trajectory = planned(REPO / "trajectories" / "index_table_indexing.toml")
    torques = joint_torques(robot, trajectory)
    # one axis, vertical: no Coriolis or centrifugal term about it, no gravity torque
    np.testing.assert_allclose(torques.tau[:, 0], J_TABLE * trajectory.qdd[:, 0], rtol=0,
                               atol=1e-10)
    np.testing.assert_allclose(torques.gravity, 0.0, atol=1e-12)
    # the motion reaches its acceleration limit (2000 deg/s^2): peak torque J alpha_max
    alpha_max = 2000 * math.pi / 180
    assert np.abs(torques.tau).max() == pytest.approx(J_TABLE * alpha_max, rel=1e-9)


# --- the vertical two-link arm: M(q) qdd + C(q, qd) qd + g(q) ---------------------------------


def test_two_link_closed_form_random_states():
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    assert robot.joint_names == ("shoulder", "elbow")
    q, qd, qdd = random_states(robot, 500, seed=2, speed=4.0, accel=20.0)
    np.testing.assert_allclose(inverse_dynamics(robot, q, qd, qdd), two_link(q, qd, qdd),
                               rtol=0, atol=1e-10)


def test_two_link_hand_poses():
    """At rest, horizontal: tau1 = (m1 lc1 + m2 (l1 + lc2)) g, tau2 = m2 lc2 g; upright: 0."""
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    rest = np.zeros((2, 2))
    q = np.array([[0.0, 0.0], [math.pi / 2, 0.0]])
    tau = inverse_dynamics(robot, q, rest, rest)
    np.testing.assert_allclose(tau[0], [(M1 * LC1 + M2 * (L1 + LC2)) * G, M2 * LC2 * G],
                               rtol=1e-12)
    np.testing.assert_allclose(tau[1], [0.0, 0.0], atol=1e-12)
    assert STANDARD_GRAVITY == G


def test_two_link_closed_form_along_the_shipped_ruckig_motion():
    """planar2_pick_place carries a 0.15 kg gripper at the tool frame (x = l2 on link 2),
    com 0.03 m further along x: a point mass at d = 0.28 m on link 2's axis, folded into
    link 2; holding its 0.25 kg part there too, 0.4 kg."""
    robot, motion, trajectory = planned(REPO / "trajectories" / "planar2_pick_place.toml")
    assert motion.planner == "ruckig"
    m2, lc2, i2 = composite_link2(0.15, L2 + 0.03)
    expected = two_link(trajectory.q, trajectory.qd, trajectory.qdd, m2=m2, lc2=lc2, i2=i2)
    torques = joint_torques(robot, trajectory)
    np.testing.assert_allclose(torques.tau, expected, rtol=0, atol=1e-10)
    still = np.zeros_like(trajectory.q)
    np.testing.assert_allclose(torques.gravity, two_link(trajectory.q, still, still, m2=m2,
                                                         lc2=lc2, i2=i2), rtol=0, atol=1e-10)
    holding = robot.with_parts([motion.parts["part"]])
    m2, lc2, i2 = composite_link2(0.4, L2 + 0.03)
    np.testing.assert_allclose(
        inverse_dynamics(holding, trajectory.q, trajectory.qd, trajectory.qdd),
        two_link(trajectory.q, trajectory.qd, trajectory.qdd, m2=m2, lc2=lc2, i2=i2),
        rtol=0, atol=1e-10)
    # the motion really exercises the velocity terms (it is not a quasi-static check)
    assert np.abs(trajectory.qd).max() > 3.0 and np.abs(trajectory.qdd).max() > 15.0


def test_two_link_on_the_ceiling_flips_gravity():
    robot = load_robot(REPO / "robots" / "planar2.urdf", mounting="ceiling")
    q, qd, qdd = random_states(robot, 50, seed=5)
    np.testing.assert_allclose(inverse_dynamics(robot, q, qd, qdd), two_link(q, qd, qdd, g=-G),
                               rtol=0, atol=1e-10)


def test_benchtop6_payload_in_the_rotated_tool_frame_by_hand():
    """benchtop6_pick_place holding its part: 0.5 kg at com (0, 0, 0.03) in tool0, which
    sits at (0, 0.01, 0) on wrist_3_link rotated -90 deg about x, so tool0's z is
    wrist_3_link's +y: the payload
    is at (0, 0.04, 0) on wrist_3_link. At the zero configuration (arm stretched along +x)
    it is 0.240 + 0.210 = 0.450 m along x from the shoulder_lift axis (+y). Holding it
    takes -0.45 m g about +y (a negative shoulder_lift raises the arm), 0.21 m g less at the
    elbow; wrist_1 (+y) holds 0 (payload on its axis line), shoulder_pan (z) nothing."""
    robot, motion, _ = planned(REPO / "trajectories" / "benchtop6_pick_place.toml")
    robot = robot.with_parts([motion.parts["part"]])  # holding it: 0.3 + 0.2 kg, one centre
    bare = load_robot(REPO / "robots" / "benchtop6.urdf")
    zero = np.zeros((1, 6))
    extra = (inverse_dynamics(robot, zero, zero, zero)
             - inverse_dynamics(bare, zero, zero, zero))[0]
    m = 0.5
    np.testing.assert_allclose(extra, [0.0, -0.45 * m * G, -0.21 * m * G, 0.0, 0.0, 0.0],
                               rtol=0, atol=1e-12)
    # its centre of mass lies on the wrist_3 axis (offset along it), so accelerating wrist_3
    # alone takes only the payload's own inertia, m a^2 / 6 = 2.1e-4 kg m^2 (50 mm cube)
    qdd = np.zeros((1, 6))
    qdd[0, 5] = 10.0
    extra = (inverse_dynamics(robot, zero, zero, qdd)
             - inverse_dynamics(bare, zero, zero, qdd))[0]
    assert extra[5] == pytest.approx(2.1e-4 * 10.0, rel=1e-9)
