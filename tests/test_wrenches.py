"""The force and moment through every joint, against oracles.

Oracles: per-sample `pinocchio.rnea` (its ``data.f``, read one sample at a time);
`inverse_dynamics` (the batched torques) for the axis row; the subtree's weight and
centre of mass from Pinocchio's `centerOfMass` (statics); the subtree's momentum
rate from finite differences of Pinocchio's kinematics (Newton-Euler for the subtree);
and closed forms by hand: an arm held horizontal, a mass spinning about a vertical axis.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from hdselect.base.errors import InputError
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.joint_motions import joint_motions
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.payload import Payload
from hdselect.robot.wrenches import BLOCK, axis_wrenches, bearing_loads, joint_wrenches
from helpers import REPO
from helpers.robots import example_robots

G = 9.80665  # standard gravity [m/s^2], written out

MIXED = """<?xml version="1.0"?>
<robot name="mixed">
  <link name="base"/>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="carriage"/>
    <origin xyz="0.1 0 0.2" rpy="0.1 0.2 0.3"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-0.5" upper="0.5" effort="100" velocity="1"/></joint>
  <link name="carriage"><inertial><origin xyz="0.02 0.01 -0.03"/><mass value="2.0"/>
    <inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.02" iyz="0.002" izz="0.015"/></inertial></link>
  <joint name="spin" type="continuous"><parent link="carriage"/><child link="rotor"/>
    <origin xyz="0 0.1 0" rpy="0.5 0 0"/><axis xyz="0 0 1"/></joint>
  <link name="rotor"><inertial><origin xyz="0.1 0.02 0.01"/><mass value="1.0"/>
    <inertia ixx="0.003" ixy="0" ixz="0.0005" iyy="0.004" iyz="0" izz="0.005"/></inertial></link>
  <joint name="tilt" type="revolute"><parent link="rotor"/><child link="arm"/>
    <origin xyz="0.2 0 0" rpy="0 0.3 0"/><axis xyz="1 2 3"/>
    <limit lower="-2" upper="2" effort="20" velocity="3"/></joint>
  <link name="arm"><inertial><origin xyz="0.15 0 0.02"/><mass value="0.7"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.005" iyz="0" izz="0.005"/></inertial></link>
  <joint name="finger" type="revolute"><parent link="arm"/><child link="finger_link"/>
    <origin xyz="0.3 0 0"/><axis xyz="-1 0 0"/>
    <limit lower="-2" upper="2" effort="20" velocity="3"/></joint>
  <link name="finger_link"><inertial><origin xyz="0.03 0 0.01"/><mass value="0.1"/>
    <inertia ixx="2e-5" ixy="0" ixz="0" iyy="2e-5" iyz="0" izz="2e-5"/></inertial></link>
  <joint name="follower" type="revolute"><parent link="arm"/><child link="follower_link"/>
    <origin xyz="0.3 0.02 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="20" velocity="3"/>
    <mimic joint="finger" multiplier="-1.5" offset="0.1"/></joint>
  <link name="follower_link"><inertial><origin xyz="0.04 0.01 0"/><mass value="0.08"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>
</robot>
"""


# --- factories -------------------------------------------------------------------------------

def ur5_carrying() -> Robot:
    """UR5 from example-robot-data with a payload and two gearhead masses, as sizing loads it."""
    robot = load_robot(example_robots() / "ur_description/urdf/ur5_robot.urdf")
    robot = robot.with_payload(Payload(2.5, (0.01, -0.02, 0.08), ((4e-3, 0, 0), (0, 5e-3, 0),
                                                                   (0, 0, 3e-3))))
    return robot.with_gearheads({"elbow_joint": 0.5, "wrist_2_joint": 0.4})


def benchtop6() -> Robot:
    return load_robot(REPO / "robots" / "benchtop6.urdf")


def mixed(tmp_path: Path) -> Robot:
    """Prismatic (unaligned), continuous, unaligned revolute joints and a mimic follower."""
    path = tmp_path / "mixed.urdf"
    path.write_text(MIXED)
    return load_robot(path)


def one_link(tmp_path: Path, axis: str, com: str, mass: float = 2.0,
             inertia: float = 0.0) -> Robot:
    """One continuous joint about `axis`, 0.3 m above the base, carrying a body of `mass`
    [kg] with its centre of mass at `com` [m] in the joint frame and `inertia` [kg m^2]
    about each axis."""
    path = tmp_path / "one.urdf"
    path.write_text(f"""<?xml version="1.0"?>
<robot name="one"><link name="base"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.3"/><axis xyz="{axis}"/></joint>
  <link name="arm"><inertial><origin xyz="{com}"/><mass value="{mass}"/>
    <inertia ixx="{inertia}" ixy="0" ixz="0" iyy="{inertia}" iyz="0" izz="{inertia}"/>
  </inertial></link></robot>""")
    return load_robot(path)


def random_states(robot: Robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random positions within the limits (+-pi where none), speeds and accelerations, (n, dof)."""
    rng = np.random.default_rng(seed)
    lower = np.maximum(robot.lower, -math.pi)
    upper = np.minimum(robot.upper, math.pi)
    q = rng.uniform(lower, upper, (n, robot.dof))
    return q, rng.uniform(-3.0, 3.0, (n, robot.dof)), rng.uniform(-20.0, 20.0, (n, robot.dof))


def rnea_forces(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Oracle: ``data.f[1:]`` of one `pinocchio.rnea` call per sample, (n_joints, 6, n)."""
    model = robot.model
    data = model.createData()
    config = robot.configuration(q)
    out = np.empty((model.njoints - 1, 6, q.shape[0]))
    for k in range(q.shape[0]):
        pin.rnea(model, data, config[:, k], qd[k], qdd[k])
        out[:, :, k] = [data.f[i].vector for i in range(1, model.njoints)]
    return out


def at_rest(robot: Robot, angle: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One sample of a one-joint robot held still at `angle` [rad]."""
    return np.array([[angle]]), np.zeros((1, robot.dof)), np.zeros((1, robot.dof))


# --- against Pinocchio -----------------------------------------------------------------------

@pytest.mark.parametrize("name", ["ur5_carrying", "benchtop6", "mixed"])
def test_wrenches_equal_rnea_data_f(name, tmp_path):
    robot = mixed(tmp_path) if name == "mixed" else {"ur5_carrying": ur5_carrying,
                                                      "benchtop6": benchtop6}[name]()
    q, qd, qdd = random_states(robot, 150, seed=1)
    wrenches = joint_wrenches(robot, q, qd, qdd)
    assert wrenches.shape == (robot.model.njoints - 1, 6, 150)
    np.testing.assert_allclose(wrenches, rnea_forces(robot, q, qd, qdd), rtol=0, atol=1e-10)


@pytest.mark.parametrize("name", ["ur5_carrying", "mixed"])
def test_the_axis_row_is_the_batched_torque(name, tmp_path):
    """Row 5 of a revolute joint's axis frame is its torque: `inverse_dynamics`' to rounding,
    over three blocks of samples, threads or not."""
    robot = mixed(tmp_path) if name == "mixed" else ur5_carrying()
    q, qd, qdd = random_states(robot, 2 * BLOCK + 7, seed=2)
    tau = inverse_dynamics(robot, q, qd, qdd)
    rotary = [n for n, r in zip(robot.joint_names, robot.revolute, strict=True)
              if r and n not in ("finger",)]  # the mimic leader's torque adds its follower's
    axis = axis_wrenches(robot, q, qd, qdd, rotary, threads=1)
    columns = [robot.joint_index(n) for n in rotary]
    scale = np.abs(tau).max()
    np.testing.assert_allclose(axis[:, 5].T, tau[:, columns], rtol=0, atol=1e-13 * scale)
    assert np.array_equal(axis_wrenches(robot, q, qd, qdd, rotary, threads=3), axis)


def test_axis_frames_turn_the_joint_frames_wrench_about_the_axis():
    """The axis frame's z is the joint axis: the axial row is axis . f, the torque axis . m,
    and the radial and tilting magnitudes are those of the parts normal to the axis."""
    robot = ur5_carrying()
    q, qd, qdd = random_states(robot, 40, seed=3)
    names = robot.sized_joints
    aligned = axis_wrenches(robot, q, qd, qdd, names)
    frame = joint_wrenches(robot, q, qd, qdd)
    for s, name in enumerate(names):
        (motion,) = [m for m in joint_motions(robot.model) if m.name == name]
        i = robot.model.getJointId(name) - 1
        f, m = frame[i, :3], frame[i, 3:]
        np.testing.assert_allclose(aligned[s, 2], motion.axis @ f, atol=1e-10)
        np.testing.assert_allclose(aligned[s, 5], motion.axis @ m, atol=1e-10)
        axial, radial, tilting = bearing_loads(aligned[s])
        np.testing.assert_allclose(radial, np.linalg.norm(f - np.outer(motion.axis, axial),
                                                          axis=0), atol=1e-10)
        normal = m - np.outer(motion.axis, motion.axis @ m)
        np.testing.assert_allclose(tilting, np.linalg.norm(normal, axis=0), atol=1e-10)


def test_dwells_are_computed_once_and_give_the_same_wrenches():
    robot = benchtop6()
    q, qd, qdd = random_states(robot, 300, seed=4)
    held = np.repeat(np.arange(300), 20)  # every state 20 times: 6000 samples, a dwell each
    repeated = axis_wrenches(robot, q[held], qd[held], qdd[held], robot.sized_joints)
    once = axis_wrenches(robot, q, qd, qdd, robot.sized_joints)
    assert np.array_equal(repeated, once[:, :, held])


# --- the convention of data.f, from independent oracles ----------------------------------------

def test_at_rest_each_joint_holds_up_its_subtree():
    """Joint i holds its subtree's weight: force M g upward, moment c x (M g up) about its
    origin, M and c the subtree's mass and centre of mass (Pinocchio's centerOfMass, c in
    joint i's frame), "up" turned into the joint frame."""
    robot = ur5_carrying()
    model = robot.model
    q, _, _ = random_states(robot, 12, seed=5)
    still = np.zeros_like(q)
    wrenches = joint_wrenches(robot, q, still, still)
    data = model.createData()
    config = robot.configuration(q)
    for k in range(12):
        pin.centerOfMass(model, data, config[:, k])
        for i in range(1, model.njoints):
            support = data.mass[i] * data.oMi[i].rotation.T @ np.array([0.0, 0.0, G])
            np.testing.assert_allclose(wrenches[i - 1, :3, k], support, atol=1e-9)
            np.testing.assert_allclose(wrenches[i - 1, 3:, k], np.cross(data.com[i], support),
                                       atol=1e-9)


def test_moving_each_joint_transmits_its_subtrees_momentum_rate_minus_its_weight():
    """Newton-Euler for subtree i: the joint's wrench (world frame, about the origin) is the
    rate of the subtree's spatial momentum, by central differences, less its weight's."""
    robot = benchtop6()
    model = robot.model
    data = model.createData()
    rng = np.random.default_rng(6)
    amplitude, frequency, phase = rng.uniform(0.3, 1.0, (3, robot.dof))
    frequency *= 3.0

    def state(t: float):
        angle = frequency * t + phase
        return (amplitude * np.sin(angle), amplitude * frequency * np.cos(angle),
                -amplitude * frequency**2 * np.sin(angle))

    def momenta(t: float) -> np.ndarray:
        q, qd, _ = state(t)
        pin.forwardKinematics(model, data, q, qd)
        out = np.zeros((model.njoints, 6))
        for i in reversed(range(1, model.njoints)):
            out[i] += data.oMi[i].act(model.inertias[i] * data.v[i]).vector
            out[model.parents[i]] += out[i]
        return out

    step = 1e-5
    for t in (0.1, 0.7, 1.3):
        q, qd, qdd = state(t)
        rate = (momenta(t + step) - momenta(t - step)) / (2 * step)
        wrenches = joint_wrenches(robot, q[None], qd[None], qdd[None])[:, :, 0]
        pin.centerOfMass(model, data, q)
        for i in range(1, model.njoints):
            weight = data.mass[i] * model.gravity.linear
            centre = data.oMi[i].act(data.com[i])
            world = data.oMi[i].act(pin.Force(wrenches[i - 1])).vector
            np.testing.assert_allclose(world, rate[i] - np.concatenate(
                (weight, np.cross(centre, weight))), atol=1e-6)


# --- closed forms by hand ----------------------------------------------------------------------

M, L = 2.0, 0.5  # the arm's mass [kg] and the distance of its centre of mass [m]


@pytest.mark.parametrize("angle", [0.0, 1.0, -2.5])
def test_an_arm_held_horizontal_on_a_roll_axis(angle, tmp_path):
    """Axis along the arm (x): the bearing carries F_r = m g and M = m g L, no torque;
    turned about its own axis the centre of mass stays on it: the same loads."""
    robot = one_link(tmp_path, "1 0 0", f"{L} 0 0", M)
    wrench = axis_wrenches(robot, *at_rest(robot, angle), ["j"])[0]
    axial, radial, tilting = bearing_loads(wrench)
    np.testing.assert_allclose([axial[0], radial[0], tilting[0], wrench[5, 0]],
                               [0.0, M * G, M * G * L, 0.0], atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 0.5 * math.pi, 2.0])
def test_an_arm_held_horizontal_on_a_vertical_axis(angle, tmp_path):
    """Pan axis (z): F_a = m g, F_r = 0, M = m g L at every angle (the frame turns with it)."""
    robot = one_link(tmp_path, "0 0 1", f"{L} 0 0", M)
    axial, radial, tilting = bearing_loads(axis_wrenches(robot, *at_rest(robot, angle),
                                                         ["j"])[0])
    np.testing.assert_allclose([axial[0], radial[0], tilting[0]], [M * G, 0.0, M * G * L],
                               atol=1e-12)


def test_an_arm_held_horizontal_on_a_pitch_axis_puts_the_moment_in_the_torque(tmp_path):
    """Axis across the arm (y): F_r = m g; m g L is the torque about y, so M = 0."""
    robot = one_link(tmp_path, "0 1 0", f"{L} 0 0", M)
    wrench = axis_wrenches(robot, *at_rest(robot, 0.0), ["j"])[0]
    axial, radial, tilting = bearing_loads(wrench)
    np.testing.assert_allclose([axial[0], radial[0], tilting[0], abs(wrench[5, 0])],
                               [0.0, M * G, 0.0, M * G * L], atol=1e-12)


@pytest.mark.parametrize("omega", [0.0, 3.0, -10.0])
def test_a_mass_spinning_about_a_vertical_axis(omega, tmp_path):
    """Mass m at radius r, height h above the joint origin, spinning at omega about z:
    F_r = m w^2 r (centripetal, toward the axis), F_a = m g, M = m r (g + h w^2) (gravity's
    lever r and the centripetal force's lever h), torque 0."""
    r, h, mass = 0.3, 0.2, 1.5
    robot = one_link(tmp_path, "0 0 1", f"{r} 0 {h}", mass, inertia=1e-3)  # symmetric body
    n = 5
    angle = np.linspace(0.0, 2.0, n)[:, None]
    wrench = axis_wrenches(robot, angle, np.full((n, 1), omega), np.zeros((n, 1)), ["j"])[0]
    axial, radial, tilting = bearing_loads(wrench)
    force = joint_wrenches(robot, angle, np.full((n, 1), omega), np.zeros((n, 1)))[0, :3]
    np.testing.assert_allclose(force, np.tile([[-mass * omega**2 * r], [0.0], [mass * G]], n),
                               atol=1e-12)  # in the joint frame, turning with the mass
    np.testing.assert_allclose(axial, mass * G, atol=1e-12)
    np.testing.assert_allclose(radial, mass * omega**2 * r, atol=1e-12)
    np.testing.assert_allclose(tilting, mass * r * (G + h * omega**2), atol=1e-12)
    np.testing.assert_allclose(wrench[5], 0.0, atol=1e-12)


# --- the bearing centre ------------------------------------------------------------------------

@pytest.mark.parametrize("offset", [-0.1, 0.0, 0.2, 0.5])
def test_moving_the_bearing_centre_along_a_roll_axis(offset, tmp_path):
    """The roll-axis arm seen from a centre `offset` toward the mass: M = m g |L - offset|."""
    robot = one_link(tmp_path, "1 0 0", f"{L} 0 0", M)
    wrench = axis_wrenches(robot, *at_rest(robot, 0.3), ["j"])[0]
    _, radial, tilting = bearing_loads(wrench, offset)
    assert tilting[0] == pytest.approx(M * G * abs(L - offset), abs=1e-12)
    assert radial[0] == pytest.approx(M * G, abs=1e-12)
    _, _, either = bearing_loads(wrench, 0.0, spread=0.2)  # 0.2 m either way: the worse side
    assert either[0] == pytest.approx(M * G * (L + 0.2), abs=1e-12)


def test_bearing_loads_of_general_wrenches():
    """Random wrenches: F_a and F_r recompose the force; an offset d moves the moment by
    -d e_z x f (so M changes by at most F_r |d|); a spread takes the worse of d +- spread."""
    rng = np.random.default_rng(7)
    wrench = rng.normal(size=(6, 200))
    force, moment = wrench[:3], wrench[3:]
    for offset in (0.0, 0.05, -0.3):
        axial, radial, tilting = bearing_loads(wrench, offset)
        np.testing.assert_allclose(axial**2 + radial**2, np.sum(force**2, axis=0))
        shifted = moment - offset * np.cross([0.0, 0.0, 1.0], force, axis=0)
        np.testing.assert_allclose(tilting, np.linalg.norm(shifted[:2], axis=0))
        assert np.all(np.abs(tilting - bearing_loads(wrench)[2]) <= radial * abs(offset) + 1e-12)
        worse = np.maximum(bearing_loads(wrench, offset + 0.1)[2],
                           bearing_loads(wrench, offset - 0.1)[2])
        np.testing.assert_array_equal(bearing_loads(wrench, offset, 0.1)[2], worse)


# --- refusals ----------------------------------------------------------------------------------

def test_a_joint_the_wrench_pass_does_not_handle_is_refused_by_name():
    model = pin.Model()
    ball = model.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    model.appendBodyToJoint(ball, pin.Inertia.Random(), pin.SE3.Identity())
    with pytest.raises(InputError, match="joint 'ball' is a JointModelSpherical"):
        joint_motions(model)


def test_an_axis_pinocchio_reads_as_zero_is_refused_by_field(tmp_path):
    """An axis written 1e308 long overflows Pinocchio's normalisation: no motion at all.

    Loading the file refuses it (Pinocchio's axis compared with the file's); the wrench
    pass refuses it too in a model built by Pinocchio alone, without that comparison.
    """
    path = tmp_path / "long.urdf"
    path.write_text(MIXED.replace('<axis xyz="1 2 3"/>', '<axis xyz="0 0 1e308"/>'))
    with pytest.raises(InputError, match="Pinocchio's axis is 0 0 0") as caught:
        load_robot(path)
    assert caught.value.field == "joint[tilt].axis" and caught.value.path == path
    with pytest.raises(InputError, match="Pinocchio reads its axis as zero") as caught:
        joint_motions(pin.buildModelFromUrdf(str(path)), path)
    assert caught.value.field == "joint[tilt].axis" and caught.value.path == path
