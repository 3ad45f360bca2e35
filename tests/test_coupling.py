"""Torques of carried gearhead masses against Pinocchio with the masses in the model.

`unit_mass_torques` predicts, by linearity, the torque of a 1 kg point mass at
each joint's mount point (the joint origin, on the link before the joint). The
oracles put real masses into the robot and re-run Pinocchio's full dynamics:
once with `appendBodyToJoint` and once with the masses written into a copy of
the URDF file as extra links (no Pinocchio placement API involved).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from hdselect.coupling import unit_mass_torques
from hdselect.robot import load_robot
from test_dynamics import MOTIONS, REPO, ROBOTS, G, planned, random_states, rnea_loop, thinned

STOP_TIME = 0.1  # [s]


def with_point_masses(model: pin.Model, masses: dict[str, float]) -> pin.Model:
    """A copy of `model` with a point mass m_k at joint k's origin, on its parent body."""
    model = pin.Model(model)
    for name, mass in masses.items():
        k = model.getJointId(name)
        model.appendBodyToJoint(model.parents[k], pin.Inertia(mass, np.zeros(3),
                                                              np.zeros((3, 3))),
                                model.jointPlacements[k])
    return model


# A mass in a URDF link needs a positive-definite inertia (the loader checks it): a solid
# sphere of radius 1e-6 m, I = 2/5 m r^2 <= 4e-13 kg m^2 for m <= 1 kg. Its rotational
# inertia adds at most 6 I (|alpha| + |omega|^2) to any joint torque; with |qd| <= 2 rad/s
# and |qdd| <= 10 rad/s^2 on six joints (|omega| <= 12, |alpha| <= 60 + 144) that is
# below 1e-9 N m, well inside the tolerance used.
SPHERE_RADIUS = 1e-6


def urdf_with_masses(source: Path, target: Path, masses: dict[str, float]) -> Path:
    """Copy a URDF, adding for each joint k a link of mass m_k fixed at k's origin."""
    tree = ET.parse(source)
    root = tree.getroot()
    joints = {j.get("name"): j for j in root.iter("joint")}
    for name, mass in masses.items():
        joint = joints[name]
        parent = joint.find("parent").get("link")
        origin = joint.find("origin")
        xyz = origin.get("xyz", "0 0 0") if origin is not None else "0 0 0"
        rpy = origin.get("rpy", "0 0 0") if origin is not None else "0 0 0"
        inertia = 0.4 * mass * SPHERE_RADIUS**2
        link = ET.SubElement(root, "link", name=f"gearhead_{name}")
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "origin", xyz="0 0 0", rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=repr(mass))
        ET.SubElement(inertial, "inertia", ixx=repr(inertia), iyy=repr(inertia),
                      izz=repr(inertia), ixy="0", ixz="0", iyz="0")
        mount = ET.SubElement(root, "joint", name=f"gearhead_{name}_mount", type="fixed")
        ET.SubElement(mount, "parent", link=parent)
        ET.SubElement(mount, "child", link=f"gearhead_{name}")
        ET.SubElement(mount, "origin", xyz=xyz, rpy=rpy)
    tree.write(target)
    return target


def random_masses(names, seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    return {name: float(rng.uniform(0.2, 1.0)) for name in names}


def predicted(robot, masses, q, qd, qdd, stop_qdd):
    """tau0 + sum_k m_k u_k for the motion and for the stop, from the code under test."""
    names = list(masses)
    m = np.array([masses[n] for n in names])
    per_kg, stop_per_kg = unit_mass_torques(robot, names, q, qd, [qdd, stop_qdd])
    assert per_kg.shape == (len(names), len(q), robot.dof)
    bare = rnea_loop(robot.model, q, qd, qdd), rnea_loop(robot.model, q, qd, stop_qdd)
    return (bare[0] + np.einsum("k,knd->nd", m, per_kg),
            bare[1] + np.einsum("k,knd->nd", m, stop_per_kg))


# --- every shipped robot, random states --------------------------------------------------

@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_prediction_equals_pinocchio_with_appended_masses(path, mounting):
    robot = load_robot(path, mounting=mounting)
    q, qd, qdd = random_states(robot, 200, seed=11)
    stop_qdd = -qd / STOP_TIME
    masses = random_masses(robot.sized_joints, seed=len(path.stem))
    motion_tau, stop_tau = predicted(robot, masses, q, qd, qdd, stop_qdd)
    heavy = with_point_masses(robot.model, masses)
    np.testing.assert_allclose(motion_tau, rnea_loop(heavy, q, qd, qdd), rtol=0, atol=1e-10)
    np.testing.assert_allclose(stop_tau, rnea_loop(heavy, q, qd, stop_qdd), rtol=0, atol=1e-10)


@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
def test_prediction_equals_pinocchio_with_masses_in_the_urdf(path, tmp_path):
    robot = load_robot(path)
    q, qd, qdd = random_states(robot, 200, seed=12)
    stop_qdd = -qd / STOP_TIME
    masses = random_masses(robot.sized_joints, seed=3)
    motion_tau, stop_tau = predicted(robot, masses, q, qd, qdd, stop_qdd)
    heavy = load_robot(urdf_with_masses(path, tmp_path / path.name, masses))
    assert heavy.joint_names == robot.joint_names
    np.testing.assert_allclose(motion_tau, rnea_loop(heavy.model, q, qd, qdd), rtol=0,
                               atol=1e-8)
    np.testing.assert_allclose(stop_tau, rnea_loop(heavy.model, q, qd, stop_qdd), rtol=0,
                               atol=1e-8)


@pytest.mark.parametrize("path", MOTIONS, ids=lambda p: p.stem)
def test_prediction_along_shipped_motions_with_payload(path):
    """Along the planned motion, payload included, masses of 0.3..0.5 kg (the catalog's)."""
    motion, trajectory = planned(path)
    robot = motion.robot
    keep = thinned(trajectory, 150)
    q, qd, qdd = trajectory.q[keep], trajectory.qd[keep], trajectory.qdd[keep]
    stop_qdd = -qd / STOP_TIME
    masses = {name: 0.3 + 0.1 * (i % 3) for i, name in enumerate(robot.sized_joints)}
    motion_tau, stop_tau = predicted(robot, masses, q, qd, qdd, stop_qdd)
    heavy = with_point_masses(robot.model, masses)
    np.testing.assert_allclose(motion_tau, rnea_loop(heavy, q, qd, qdd), rtol=0, atol=1e-10)
    np.testing.assert_allclose(stop_tau, rnea_loop(heavy, q, qd, stop_qdd), rtol=0, atol=1e-10)


# --- where a mass acts: only on the joints that carry it -------------------------------------

def ancestors(model: pin.Model, name: str) -> set[int]:
    """Velocity indices of the joints strictly between the base and joint `name`."""
    out, k = set(), model.parents[model.getJointId(name)]
    while k > 0:
        out.add(model.joints[k].idx_v)
        k = model.parents[k]
    return out


@pytest.mark.parametrize("path", ROBOTS, ids=lambda p: p.stem)
def test_zero_on_the_joint_itself_and_on_non_ancestors(path):
    robot = load_robot(path)
    q, qd, qdd = random_states(robot, 50, seed=4)
    names = list(robot.joint_names)  # every joint, prismatic too
    (per_kg,) = unit_mass_torques(robot, names, q, qd, [qdd])
    for row, name in enumerate(names):
        carriers = ancestors(robot.model, name)
        for dof in range(robot.dof):
            if dof not in carriers:
                np.testing.assert_array_equal(per_kg[row, :, dof], 0.0)
        assert robot.joint_index(name) not in carriers


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
    (per_kg,) = unit_mass_torques(robot, ["left_arm", "right_arm"], q, qd, [qdd])
    turn, left, right = (robot.joint_index(n) for n in ("turn", "left_arm", "right_arm"))
    # both gearheads sit on the hub: they load `turn`, never the sibling branch
    for row in range(2):
        np.testing.assert_array_equal(per_kg[row, :, left], 0.0)
        np.testing.assert_array_equal(per_kg[row, :, right], 0.0)
        assert np.abs(per_kg[row, :, turn]).max() > 0.1
    masses = {"left_arm": 0.7, "right_arm": 0.4}
    motion_tau, _ = predicted(robot, masses, q, qd, qdd, -qd / STOP_TIME)
    np.testing.assert_allclose(motion_tau, rnea_loop(with_point_masses(robot.model, masses),
                                                     q, qd, qdd), rtol=0, atol=1e-10)


# --- by hand ---------------------------------------------------------------------------------

def test_planar2_elbow_mass_at_horizontal_rest_by_hand():
    """1 kg at the elbow mount (x = l1 = 0.3 m on link 1), arm horizontal, at rest.

    The shoulder holds m g l1 (positive: a positive shoulder torque raises the arm,
    robots/planar2.urdf); the elbow carries none of it.
    """
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    still = np.zeros((1, 2))
    (per_kg,) = unit_mass_torques(robot, ["shoulder", "elbow"], still, still, [still])
    assert per_kg[1, 0, 0] == pytest.approx(1.0 * G * 0.3, rel=1e-12)
    assert per_kg[1, 0, 1] == 0.0
    # the shoulder's own gearhead sits on the fixed base: it loads nothing
    np.testing.assert_array_equal(per_kg[0], 0.0)


def test_planar2_elbow_mass_in_motion_by_hand():
    """A point mass at r = l1 (cos q1, sin q1) in the arm's plane: about the shoulder,
    tau = m (l1^2 qdd1 + g l1 cos q1) (no Coriolis term: its distance is fixed)."""
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    q, qd, qdd = random_states(robot, 100, seed=21, speed=4.0, accel=20.0)
    (per_kg,) = unit_mass_torques(robot, ["elbow"], q, qd, [qdd])
    expected = 0.3**2 * qdd[:, 0] + G * 0.3 * np.cos(q[:, 0])
    np.testing.assert_allclose(per_kg[0, :, 0], expected, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(per_kg[0, :, 1], 0.0)


def test_scara_wrist_mass_on_the_prismatic_lift_by_hand():
    """The wrist gearhead rides on the quill: the lift (prismatic, z up) carries
    m (zdd + g) of it; the vertical shoulder carries m (r^2 qdd1 + ...) but no gravity."""
    robot = load_robot(REPO / "robots" / "scara.urdf")
    n = 20
    q = np.zeros((n, 4))
    q[:, 2] = 0.02
    qd = np.zeros((n, 4))
    qdd = np.zeros((n, 4))
    qdd[:, 2] = np.linspace(-1.0, 1.0, n)
    (per_kg,) = unit_mass_torques(robot, ["wrist"], q, qd, [qdd])
    lift = robot.joint_index("lift")
    np.testing.assert_allclose(per_kg[0, :, lift], qdd[:, 2] + G, rtol=1e-12)
    # stretched arm at rest, accelerating only the lift: no torque about vertical axes
    np.testing.assert_allclose(per_kg[0, :, robot.joint_index("shoulder")], 0.0, atol=1e-12)
    # shoulder accelerating alone: the mount is at r = 0.25 + 0.2 = 0.45 m from its axis
    qdd = np.zeros((1, 4))
    qdd[0, 0] = 3.0
    (per_kg,) = unit_mass_torques(robot, ["wrist"], q[:1], qd[:1], [qdd])
    assert per_kg[0, 0, 0] == pytest.approx(0.45**2 * 3.0, rel=1e-12)
    assert math.isclose(per_kg[0, 0, 1], 0.2**2 * 3.0 + 0.25 * 0.2 * 3.0, rel_tol=1e-12)
