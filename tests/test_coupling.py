"""Carried gearhead masses against Pinocchio with the masses written in independently.

`Robot.with_gearheads` puts a point mass at each joint's mount point (the joint
origin, on the link before the joint). The oracles put the masses into the
robot another way and re-run Pinocchio's full dynamics: with the masses written
into a copy of the URDF file as extra links (no Pinocchio placement API
involved), and by hand on the planar arm and the SCARA.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from hdselect.robot.model import load_robot
from helpers import REPO
from helpers.dynamics import (
    MOTIONS,
    ROBOTS,
    G,
    planned,
    random_states,
    rnea_loop,
    thinned,
    urdf_with_masses,
    with_point_masses,
)

STOP_TIME = 0.1  # [s]


def random_masses(names, seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    return {name: float(rng.uniform(0.2, 1.0)) for name in names}


def carrying(robot, masses, q, qd, qdd):
    """Torques of the robot carrying the masses, from the code under test."""
    return rnea_loop(robot.with_gearheads(masses).model, q, qd, qdd)


# --- every shipped robot, random states --------------------------------------------------

@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_gearheads_equal_masses_written_into_the_urdf(path, mounting, tmp_path):
    robot = load_robot(path, mounting=mounting)
    q, qd, qdd = random_states(robot, 200, seed=12)
    masses = random_masses(robot.sized_joints, seed=3)
    heavy = load_robot(urdf_with_masses(path, tmp_path / path.name, masses), mounting=mounting)
    assert heavy.joint_names == robot.joint_names
    for accel in (qdd, -qd / STOP_TIME):
        np.testing.assert_allclose(carrying(robot, masses, q, qd, accel),
                                   rnea_loop(heavy.model, q, qd, accel), rtol=0, atol=1e-8)


@pytest.mark.slow
@pytest.mark.parametrize("path", MOTIONS, ids=lambda p: p.stem)
def test_gearheads_along_shipped_motions_with_payload(path):
    """Along the planned motion, payload included, masses of 0.3..0.5 kg (the catalog's)."""
    robot, motion, trajectory = planned(path)
    keep = thinned(trajectory, 150)
    q, qd, qdd = trajectory.q[keep], trajectory.qd[keep], trajectory.qdd[keep]
    masses = {name: 0.3 + 0.1 * (i % 3) for i, name in enumerate(robot.sized_joints)}
    heavy = with_point_masses(robot.model, masses)
    np.testing.assert_allclose(carrying(robot, masses, q, qd, qdd), rnea_loop(heavy, q, qd, qdd),
                               rtol=0, atol=1e-10)


def test_the_robot_given_is_not_changed():
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    bodies = robot.model.inertias[1].mass, robot.model.inertias[2].mass
    heavy = robot.with_gearheads({"elbow": 1.0})
    assert (robot.model.inertias[1].mass, robot.model.inertias[2].mass) == bodies
    assert heavy.model.inertias[1].mass == pytest.approx(bodies[0] + 1.0)


# --- where a mass acts: only on the joints that carry it -------------------------------------

def ancestors(model: pin.Model, name: str) -> set[int]:
    """Velocity indices of the joints strictly between the base and joint `name`."""
    out, k = set(), model.parents[model.getJointId(name)]
    while k > 0:
        out.add(model.joints[k].idx_v)
        k = model.parents[k]
    return out


@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
def test_a_mass_loads_only_the_joints_nearer_the_base(path):
    robot = load_robot(path)
    q, qd, qdd = random_states(robot, 50, seed=4)
    bare = rnea_loop(robot.model, q, qd, qdd)
    for name in robot.joint_names:  # every joint, prismatic too
        added = carrying(robot, {name: 1.0}, q, qd, qdd) - bare
        carriers = ancestors(robot.model, name)
        assert robot.joint_index(name) not in carriers
        for dof in range(robot.dof):
            if dof not in carriers:
                np.testing.assert_allclose(added[:, dof], 0.0, atol=1e-12)


BRANCHED = """\
<robot name="branched">
  <link name="base"/>
  <link name="hub"><inertial><origin xyz="0.05 0 0"/><mass value="1.0"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="left"><inertial><origin xyz="0 0.1 0"/><mass value="0.5"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.002"/></inertial></link>
  <link name="right"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
  <joint name="turn" type="revolute"><parent link="base"/><child link="hub"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
  <joint name="left_arm" type="revolute"><parent link="hub"/><child link="left"/>
    <origin xyz="0.1 0.05 0" rpy="0.3 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
  <joint name="right_arm" type="revolute"><parent link="hub"/><child link="right"/>
    <origin xyz="0.1 -0.05 0.02"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
</robot>
"""


def test_branched_tree_masses_load_only_their_own_branch(tmp_path):
    path = tmp_path / "branched.urdf"
    path.write_text(BRANCHED)
    robot = load_robot(path, mounting="wall")
    q, qd, qdd = random_states(robot, 100, seed=8)
    bare = rnea_loop(robot.model, q, qd, qdd)
    masses = {"left_arm": 0.7, "right_arm": 0.4}
    added = carrying(robot, masses, q, qd, qdd) - bare
    turn, left, right = (robot.joint_index(n) for n in ("turn", "left_arm", "right_arm"))
    # both gearheads sit on the hub: they load `turn`, never the sibling branch
    np.testing.assert_allclose(added[:, [left, right]], 0.0, atol=1e-12)
    assert np.abs(added[:, turn]).max() > 0.1
    heavy = load_robot(urdf_with_masses(path, tmp_path / "heavy.urdf", masses), mounting="wall")
    np.testing.assert_allclose(carrying(robot, masses, q, qd, qdd),
                               rnea_loop(heavy.model, q, qd, qdd), rtol=0, atol=1e-8)
    # carried mass: `turn` carries both, each arm carries neither
    assert robot.with_gearheads(masses).carried_mass("turn") == pytest.approx(1.1)
    assert robot.with_gearheads(masses).carried_mass("left_arm") == 0.0
    assert robot.with_gearheads(masses).carried_mass("right_arm") == 0.0


# --- by hand ---------------------------------------------------------------------------------

def test_planar2_elbow_mass_at_horizontal_rest_by_hand():
    """1 kg at the elbow mount (x = l1 = 0.3 m on link 1), arm horizontal, at rest.

    The shoulder holds m g l1 more (positive: a positive shoulder torque raises the arm,
    robots/planar2.urdf); the elbow carries none of it. The shoulder's own gearhead sits
    on the fixed base: it loads nothing.
    """
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    still = np.zeros((1, 2))
    added = carrying(robot, {"shoulder": 1.0, "elbow": 1.0}, still, still, still) \
        - rnea_loop(robot.model, still, still, still)
    assert added[0, 0] == pytest.approx(1.0 * G * 0.3, rel=1e-12)
    assert added[0, 1] == pytest.approx(0.0, abs=1e-14)


def test_planar2_elbow_mass_in_motion_by_hand():
    """A point mass at r = l1 (cos q1, sin q1) in the arm's plane: about the shoulder,
    tau = m (l1^2 qdd1 + g l1 cos q1) (no Coriolis term: its distance is fixed)."""
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    q, qd, qdd = random_states(robot, 100, seed=21, speed=4.0, accel=20.0)
    added = carrying(robot, {"elbow": 1.0}, q, qd, qdd) - rnea_loop(robot.model, q, qd, qdd)
    expected = 0.3**2 * qdd[:, 0] + G * 0.3 * np.cos(q[:, 0])
    np.testing.assert_allclose(added[:, 0], expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(added[:, 1], 0.0, atol=1e-12)


def test_scara_wrist_mass_on_the_prismatic_lift_by_hand():
    """The wrist gearhead rides on the quill: the lift (prismatic, z up) carries
    m (zdd + g) of it; the vertical shoulder carries m r^2 qdd1 but no gravity."""
    robot = load_robot(REPO / "robots" / "scara.urdf")
    n = 20
    q = np.zeros((n, 4))
    q[:, 2] = 0.02
    qd = np.zeros((n, 4))
    qdd = np.zeros((n, 4))
    qdd[:, 2] = np.linspace(-1.0, 1.0, n)
    added = carrying(robot, {"wrist": 1.0}, q, qd, qdd) - rnea_loop(robot.model, q, qd, qdd)
    lift = robot.joint_index("lift")
    np.testing.assert_allclose(added[:, lift], qdd[:, 2] + G, rtol=1e-12)
    # stretched arm, accelerating only the lift: no torque about the vertical axes
    np.testing.assert_allclose(added[:, robot.joint_index("shoulder")], 0.0, atol=1e-12)
    # shoulder accelerating alone: the mount is at r = 0.25 + 0.2 = 0.45 m from its axis
    qdd = np.zeros((1, 4))
    qdd[0, 0] = 3.0
    added = carrying(robot, {"wrist": 1.0}, q[:1], qd[:1], qdd) \
        - rnea_loop(robot.model, q[:1], qd[:1], qdd)
    assert added[0, 0] == pytest.approx(0.45**2 * 3.0, rel=1e-12)
    assert added[0, 1] == pytest.approx(0.2**2 * 3.0 + 0.25 * 0.2 * 3.0, rel=1e-12)
