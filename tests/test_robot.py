"""Tests of hdselect.robot.model on the shipped robots and on small hand-written URDFs."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from hdselect.base.errors import InputError
from hdselect.robot.model import load_robot
from hdselect.robot.mounting import STANDARD_GRAVITY
from hdselect.robot.payload import Payload
from helpers.robots import JOINTS, robot_path

AL, STEEL, SI = 2700.0, 7850.0, 2329.0

SIZED = {**JOINTS, "scara": ("shoulder", "elbow", "wrist")}

# planar2 geometry, as stated in the file's comment: aluminium bars l x w x h.
L1, W1, H1 = 0.30, 0.010, 0.030
L2, W2, H2 = 0.25, 0.010, 0.025


def planar2(**kwargs):
    return load_robot(robot_path("planar2"), **kwargs)


def gravity_torque(robot, positions) -> np.ndarray:
    q = robot.configuration(np.asarray(positions, dtype=float))[:, 0]
    return pin.computeGeneralizedGravity(robot.model, robot.model.createData(), q)


def urdf_inertial(path: Path, link: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass [kg], com [m] and inertia diagonal [kg m^2] of a link, read with ElementTree."""
    element = ET.parse(path).getroot().find(f"link[@name='{link}']/inertial")
    assert element is not None, f"{link} has no inertial"
    inertia = element.find("inertia").attrib
    off_diagonal = [float(inertia[k]) for k in ("ixy", "ixz", "iyz")]
    assert off_diagonal == [0.0, 0.0, 0.0]
    com = [float(x) for x in element.find("origin").get("xyz").split()]
    diagonal = [float(inertia[k]) for k in ("ixx", "iyy", "izz")]
    return float(element.find("mass").get("value")), np.array(com), np.array(diagonal)


# Independent derivations of the shipped links from their stated geometry.
def solid_box(rho, a, b, c):
    m = rho * a * b * c
    return m, np.array([b * b + c * c, a * a + c * c, a * a + b * b]) * m / 12.0


def solid_cylinder_z(rho, r, h):
    m = rho * math.pi * r * r * h
    return m, np.array([(3 * r * r + h * h) / 12.0, (3 * r * r + h * h) / 12.0, r * r / 2]) * m


def round_tube_x(rho, ro, ri, length):
    m = rho * math.pi * (ro * ro - ri * ri) * length
    perp = m * (3 * (ro * ro + ri * ri) + length * length) / 12.0
    return m, np.array([m * (ro * ro + ri * ri) / 2, perp, perp])


def square_tube_x(rho, length, side, wall):
    m_out, i_out = solid_box(rho, length, side, side)
    m_in, i_in = solid_box(rho, length, side - 2 * wall, side - 2 * wall)
    return m_out - m_in, i_out - i_in


DERIVED = [
    ("index_table", "disk", solid_cylinder_z(AL, 0.15, 0.02), (0.0, 0.0, 0.01)),
    ("index_table", "fixture_1", solid_box(STEEL, 0.04, 0.04, 0.03), (0.0, 0.0, 0.015)),
    ("planar2", "link1", solid_box(AL, L1, W1, H1), (L1 / 2, 0.0, 0.0)),
    ("planar2", "link2", solid_box(AL, L2, W2, H2), (L2 / 2, 0.0, 0.0)),
    ("scara", "wafer", solid_cylinder_z(SI, 0.15, 0.000775), (0.0, 0.0, 0.0003875)),
    ("scara", "end_effector", solid_box(AL, 0.20, 0.06, 0.004), (0.1, 0.0, -0.002)),
    ("pan_tilt", "laser", square_tube_x(AL, 0.25, 0.08, 0.004), (0.075, 0.0, 0.0)),
    ("pan_tilt", "laser_optics", solid_box(STEEL, 0.20, 0.06, 0.01), (0.0, 0.0, 0.0)),
    ("benchtop6", "upper_arm_link", round_tube_x(AL, 0.025, 0.0225, 0.24), (0.12, 0.0, 0.0)),
    ("benchtop6", "forearm_link", round_tube_x(AL, 0.020, 0.018, 0.21), (0.105, 0.0, 0.0)),
]


@pytest.mark.parametrize("name", sorted(JOINTS))
def test_shipped_robot_loads_with_its_joints(name):
    robot = load_robot(robot_path(name))
    assert robot.joint_names == JOINTS[name]
    assert robot.sized_joints == SIZED[name]
    assert robot.sized_joints == tuple(
        n for n, r in zip(robot.joint_names, robot.revolute, strict=True) if r)
    np.testing.assert_allclose(robot.gravity, [0.0, 0.0, -STANDARD_GRAVITY])


@pytest.mark.parametrize("name", sorted(JOINTS))
def test_shipped_robot_joints_have_realistic_limits(name):
    robot = load_robot(robot_path(name))
    assert np.all(robot.velocity_limit > 0.0) and np.all(robot.velocity_limit <= 10.0)
    assert np.all(robot.effort_limit > 0.0)
    for dof, joint in enumerate(robot.joint_names):
        if joint == "table":  # the index table turns on and on: continuous
            assert np.isinf(robot.lower[dof]) and np.isinf(robot.upper[dof])
        else:
            assert robot.lower[dof] <= 0.0 <= robot.upper[dof]
            assert robot.upper[dof] > robot.lower[dof]
            assert robot.upper[dof] - robot.lower[dof] <= 2 * math.pi + 1e-6


@pytest.mark.parametrize("name", sorted(JOINTS))
def test_every_moving_link_is_physically_consistent(name):
    robot = load_robot(robot_path(name))
    assert robot.model.nbodies == robot.model.njoints
    for body in list(robot.model.inertias)[1:]:
        moments = np.linalg.eigvalsh(body.inertia)
        assert body.mass > 0.0
        assert moments[0] > 0.0
        assert moments[0] + moments[1] >= moments[2]


@pytest.mark.parametrize(("name", "link", "derived", "com"), DERIVED,
                         ids=[f"{r}-{link}" for r, link, _, _ in DERIVED])
def test_link_inertial_matches_its_derivation(name, link, derived, com):
    mass, urdf_com, diagonal = urdf_inertial(robot_path(name), link)
    expected_mass, expected_diagonal = derived
    assert mass == pytest.approx(expected_mass, rel=1e-5)
    np.testing.assert_allclose(diagonal, expected_diagonal, rtol=1e-5)
    np.testing.assert_allclose(urdf_com, com, atol=1e-12)
    # The comment at the top of the file states the same mass.
    comment = robot_path(name).read_text().split("-->")[0]
    assert f"{expected_mass:.6g} kg" in comment


def test_index_table_inertia_about_its_axis():
    robot = load_robot(robot_path("index_table"))
    m_disk, i_disk = solid_cylinder_z(AL, 0.15, 0.02)
    m_block, i_block = solid_box(STEEL, 0.04, 0.04, 0.03)
    expected = i_disk[2] + 4 * (i_block[2] + m_block * 0.11**2)
    assert robot.model.inertias[1].mass == pytest.approx(m_disk + 4 * m_block)
    q = robot.configuration(np.array([[0.7]]))[:, 0]
    mass_matrix = pin.crba(robot.model, robot.model.createData(), q)
    assert mass_matrix[0, 0] == pytest.approx(expected, rel=1e-6)
    assert gravity_torque(robot, [[0.7]]) == pytest.approx([0.0], abs=1e-12)


def planar2_gravity(q1, q2, gravity, payload=0.0):
    """Closed-form gravity torque of the textbook two-link arm for any base gravity vector."""
    m1, _ = solid_box(AL, L1, W1, H1)
    m2, _ = solid_box(AL, L2, W2, H2)

    def along(theta):  # d/dtheta of the unit vector (cos, 0, sin) in the base x-z plane
        return np.array([-math.sin(theta), 0.0, math.cos(theta)])

    g = np.asarray(gravity, dtype=float)
    distal = m2 * L2 / 2 + payload * L2
    tau2 = -distal * g @ along(q1 + q2)
    tau1 = -(m1 * L1 / 2 + (m2 + payload) * L1) * g @ along(q1) + tau2
    return np.array([tau1, tau2])


@pytest.mark.parametrize("q", [(0.0, 0.0), (0.4, -1.1), (-1.2, 2.0), (1.5, 0.3)])
def test_planar2_gravity_matches_closed_form(q):
    robot = planar2()
    floor = [0.0, 0.0, -STANDARD_GRAVITY]
    np.testing.assert_allclose(gravity_torque(robot, [q]), planar2_gravity(*q, floor),
                               rtol=1e-9, atol=1e-12)


def test_payload_adds_m_g_d_of_static_torque():
    mass = 0.7
    bare = gravity_torque(planar2(), [[0.0, 0.0]])
    loaded = gravity_torque(planar2(payload=Payload(mass=mass, frame="tool")), [[0.0, 0.0]])
    extra = loaded - bare
    assert extra[0] == pytest.approx(mass * STANDARD_GRAVITY * (L1 + L2), rel=1e-12)
    assert extra[1] == pytest.approx(mass * STANDARD_GRAVITY * L2, rel=1e-12)
    # Positive angles raise the arm: holding a load up takes positive torque.
    assert bare[0] > 0.0 and extra[0] > 0.0


def test_payload_defaults_to_the_last_link_and_honours_its_com():
    mass, com = 0.5, (0.04, 0.0, 0.0)
    default = planar2(payload=Payload(mass=mass, com=com))
    at_tool = planar2(payload=Payload(mass=mass, com=com, frame="tool"))
    np.testing.assert_allclose(gravity_torque(default, [[0.3, 0.2]]),
                               gravity_torque(at_tool, [[0.3, 0.2]]))
    extra = gravity_torque(at_tool, [[0.0, 0.0]]) - gravity_torque(planar2(), [[0.0, 0.0]])
    assert extra[0] == pytest.approx(mass * STANDARD_GRAVITY * (L1 + L2 + com[0]))


def test_choosing_the_joints_to_size_does_not_move_the_payload():
    """A payload without a frame stays at the tip when only the shoulder is sized;
    excluding the elbow (as a gripper's joint is) moves it, as documented."""
    payload = Payload(mass=0.5)
    for robot in (planar2(payload=payload, joints=["shoulder"]),
                  planar2(payload=payload).with_sized_joints(["shoulder"])):
        assert robot.sized_joints == ("shoulder",)
        assert robot.payload_frame == "tool"
        extra = gravity_torque(robot, [[0.0, 0.0]]) - gravity_torque(planar2(), [[0.0, 0.0]])
        assert extra[0] == pytest.approx(0.5 * STANDARD_GRAVITY * (L1 + L2), rel=1e-12)
    assert planar2(payload=payload, exclude=["elbow"]).payload_frame == "link1"


def test_a_link_and_a_fixed_joint_of_one_name_place_the_payload_on_the_link(tmp_path):
    """Pinocchio's two frames 'tool' were an internal error (ValueError, exit 70)."""
    inertial = ('<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
                'ixz="0" iyz="0"/></inertial>')
    path = tmp_path / "arm.urdf"
    path.write_text(
        f'<robot name="a"><link name="base_link"/><link name="tool">{inertial}</link>'
        f'<link name="flange">{inertial}</link>'
        '<joint name="j1" type="revolute"><parent link="base_link"/><child link="tool"/>'
        '<origin xyz="0.5 0 0"/><axis xyz="0 -1 0"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
        '<joint name="tool" type="fixed"><parent link="tool"/><child link="flange"/>'
        '<origin xyz="0.2 0 0"/></joint></robot>')
    bare = gravity_torque(load_robot(path), [[0.0]])
    for payload in (Payload(mass=2.0, frame="tool"), Payload(mass=2.0)):
        robot = load_robot(path, payload=payload)
        assert robot.payload_frame == "tool"
        extra = gravity_torque(robot, [[0.0]]) - bare
        assert extra[0] == pytest.approx(0.0, abs=1e-12)  # on the axis: the link's origin
    at_flange = load_robot(path, payload=Payload(mass=2.0, frame="flange"))
    assert (gravity_torque(at_flange, [[0.0]]) - bare)[0] == pytest.approx(
        2.0 * STANDARD_GRAVITY * 0.2, rel=1e-12)  # where the joint's frame 'tool' sits
    from hdselect.robot.kinematics import FrameKinematics

    robot = load_robot(path)
    assert FrameKinematics(robot, "tool").frame_id == robot.model.getFrameId(
        "tool", pin.FrameType.BODY)


def test_payload_sign_follows_gravity():
    payload = Payload(mass=0.7, frame="tool")
    floor = gravity_torque(planar2(payload=payload), [[0.0, 0.0]])
    ceiling = gravity_torque(planar2(payload=payload, mounting="ceiling"), [[0.0, 0.0]])
    extra_floor = floor - gravity_torque(planar2(), [[0.0, 0.0]])
    extra_ceiling = ceiling - gravity_torque(planar2(mounting="ceiling"), [[0.0, 0.0]])
    np.testing.assert_allclose(extra_ceiling, -extra_floor, rtol=1e-12)
    assert extra_ceiling[0] == pytest.approx(-0.7 * STANDARD_GRAVITY * (L1 + L2))


@pytest.mark.parametrize("name", ["planar2", "pan_tilt", "benchtop6"])
def test_ceiling_mounting_flips_gravity_torques(name):
    floor = load_robot(robot_path(name))
    ceiling = load_robot(robot_path(name), mounting="ceiling")
    rng = np.random.default_rng(7)
    for _ in range(5):
        positions = rng.uniform(floor.lower, floor.upper)[None, :]
        tau_floor = gravity_torque(floor, positions)
        assert np.max(np.abs(tau_floor)) > 0.05
        np.testing.assert_allclose(gravity_torque(ceiling, positions), -tau_floor,
                                   rtol=1e-9, atol=1e-12)


def test_wall_mounting_of_the_planar_arm():
    robot = planar2(mounting="wall")
    np.testing.assert_allclose(robot.gravity, [-STANDARD_GRAVITY, 0.0, 0.0])
    m1, _ = solid_box(AL, L1, W1, H1)
    m2, _ = solid_box(AL, L2, W2, H2)
    # Horizontal (+x) pose: on the wall gravity points along the links, no torque.
    np.testing.assert_allclose(gravity_torque(robot, [[0.0, 0.0]]), [0.0, 0.0], atol=1e-12)
    # Arm straight along base +z: gravity (-x) now acts across the links, pulling the
    # arm towards -x, i.e. towards positive angles; holding it takes negative torque.
    first_moment = m1 * L1 / 2 + m2 * (L1 + L2 / 2)
    expected = [-first_moment * STANDARD_GRAVITY, -m2 * L2 / 2 * STANDARD_GRAVITY]
    np.testing.assert_allclose(gravity_torque(robot, [[math.pi / 2, 0.0]]), expected,
                               rtol=1e-9)


def test_explicit_gravity_vector():
    gravity = [3.0, 4.0, -8.0]
    robot = planar2(mounting=gravity)
    np.testing.assert_allclose(robot.gravity, gravity)
    for q in [(0.0, 0.0), (0.8, -0.5), (-1.0, 1.7)]:
        np.testing.assert_allclose(gravity_torque(robot, [q]), planar2_gravity(*q, gravity),
                                   rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("mounting", ["roof", [0.0, 9.8], [0.0, float("nan"), -9.8]])
def test_bad_mounting_is_rejected(mounting):
    with pytest.raises(InputError, match="mounting"):
        planar2(mounting=mounting)


def write_urdf(tmp_path: Path, link_body: str, name: str = "arm.urdf") -> Path:
    path = tmp_path / name
    path.write_text(f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <joint name="hinge" type="revolute">
    <parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="5" velocity="2"/>
  </joint>
  <link name="arm">{link_body}</link>
</robot>
""")
    return path


def inertial_xml(mass, ixx, iyy, izz, ixy=0.0):
    return (f'<inertial><origin xyz="0.1 0 0"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" ixy="{ixy}" ixz="0" iyy="{iyy}" iyz="0" izz="{izz}"/>'
            "</inertial>")


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.urdf"
    with pytest.raises(InputError, match="file not found") as info:
        load_robot(path)
    assert str(path) in str(info.value)


def test_malformed_xml(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text('<robot name="arm"><link name="base"')
    with pytest.raises(InputError, match="not a valid URDF") as info:
        load_robot(path)
    assert info.value.path == path
    assert str(path) in str(info.value)


@pytest.mark.parametrize(("inertial", "reason"), [
    (inertial_xml(0.0, 1e-3, 1e-3, 1e-3), "positive mass"),
    (inertial_xml(-0.2, 1e-3, 1e-3, 1e-3), "mass: must be a mass of at least 0"),
    (inertial_xml(0.2, 1e-3, 1e-3, -1e-3), "not positive semi-definite"),
    (inertial_xml(0.2, 1e-3, 1e-3, 1e-3, ixy=2e-3), "not positive semi-definite"),
], ids=["zero-mass", "negative-mass", "negative-moment", "indefinite"])
def test_inconsistent_inertia_is_rejected(tmp_path, inertial, reason):
    path = write_urdf(tmp_path, inertial)
    with pytest.raises(InputError, match=reason) as info:
        load_robot(path)
    assert str(info.value.field).startswith("link[arm].inertial")  # the mass itself, or the body
    assert str(path) in str(info.value) and "link[arm].inertial" in str(info.value)


def test_a_body_violating_the_triangle_inequality_loads_with_a_note(tmp_path):
    robot = load_robot(write_urdf(tmp_path, inertial_xml(0.2, 1e-3, 1e-3, 3e-3)))
    (note,) = robot.notes
    assert "link 'arm'" in note and "triangle inequality" in note and "used as written" in note


def test_consistent_small_urdf_loads(tmp_path):
    robot = load_robot(write_urdf(tmp_path, inertial_xml(0.2, 1e-3, 2e-3, 2.5e-3)))
    assert robot.joint_names == ("hinge",)
    assert robot.model.inertias[1].mass == pytest.approx(0.2)


def test_missing_meshes_still_load(tmp_path):
    mesh = ('<visual><geometry><mesh filename="package://absent/meshes/arm.stl"/></geometry>'
            '</visual><collision><geometry><mesh filename="meshes/arm_collision.dae"/>'
            "</geometry></collision>")
    path = write_urdf(tmp_path, inertial_xml(0.2, 1e-3, 2e-3, 2.5e-3) + mesh)
    assert not (tmp_path / "meshes").exists()
    robot = load_robot(path)
    assert robot.sized_joints == ("hinge",)


def test_unknown_payload_frame_lists_the_links():
    with pytest.raises(InputError, match="unknown frame 'gripper'") as info:
        planar2(payload=Payload(mass=0.3, frame="gripper"))
    message = str(info.value)
    assert "planar2.urdf" in message and "payload.frame" in message
    for link in ("base_link", "link1", "link2", "tool"):
        assert link in message


def test_payload_on_the_fixed_base_is_rejected():
    with pytest.raises(InputError, match="does not move"):
        planar2(payload=Payload(mass=0.3, frame="base_link"))


def test_unknown_joint_lists_the_joints():
    with pytest.raises(InputError, match="unknown joint 'elbo'") as info:
        planar2(joints=["shoulder", "elbo"])
    message = str(info.value)
    assert "planar2.urdf" in message and info.value.field == "joints"
    assert "joints are: shoulder, elbow" in message


def test_prismatic_joint_cannot_be_sized():
    with pytest.raises(InputError, match="'lift' is prismatic") as info:
        load_robot(robot_path("scara"), joints=["shoulder", "lift"])
    assert "scara.urdf" in str(info.value) and info.value.field == "joints"


def test_chosen_joints_keep_the_model_order():
    robot = load_robot(robot_path("benchtop6"), joints=["wrist_2", "shoulder_lift"])
    assert robot.sized_joints == ("shoulder_lift", "wrist_2")


def test_continuous_joint_configuration_is_cos_sin():
    robot = load_robot(robot_path("index_table"))
    assert robot.model.nq == 2 and robot.dof == 1
    angles = np.array([0.0, 0.5, math.pi, 2 * math.pi + 0.25])
    config = robot.configuration(angles[:, None])
    assert config.shape == (2, 4) and config.flags.f_contiguous
    np.testing.assert_allclose(config[0], np.cos(angles))
    np.testing.assert_allclose(config[1], np.sin(angles))


def test_configuration_mixes_prismatic_and_revolute():
    robot = load_robot(robot_path("scara"))
    positions = np.array([[0.1, -0.2, 0.03, 1.0], [0.0, 0.0, 0.0, 0.0]])
    config = robot.configuration(positions)
    assert config.shape == (4, 2)
    np.testing.assert_allclose(config.T, positions)
    assert robot.revolute == (True, True, False, True)


def test_scara_gravity_loads_only_the_lift():
    robot = load_robot(robot_path("scara"))
    tau = gravity_torque(robot, [[0.3, -1.0, 0.02, 0.5]])
    np.testing.assert_allclose(tau[[0, 1, 3]], 0.0, atol=1e-12)
    moved = sum(robot.model.inertias[j].mass for j in (3, 4))  # quill, end effector + wafer
    assert tau[2] == pytest.approx(moved * STANDARD_GRAVITY)


MJCF_PENDULUM = """<mujoco model="pendulum">
  <worldbody>
    <body name="link" pos="0 0 0">
      <joint name="hinge" type="hinge" axis="0 1 0" range="-90 90"/>
      <inertial pos="0.2 0 0" mass="1.5" diaginertia="0.001 0.01 0.01"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_mjcf_pendulum_loads_with_limits_and_gravity_by_hand(tmp_path):
    path = tmp_path / "pendulum.xml"
    path.write_text(MJCF_PENDULUM)
    robot = load_robot(path)
    assert robot.joint_names == ("hinge",) and robot.sized_joints == ("hinge",)
    np.testing.assert_allclose([robot.lower[0], robot.upper[0]], [-np.pi / 2, np.pi / 2])
    # 1.5 kg at x = 0.2 m, hinge about +y, gravity -z: holding it horizontal takes
    # tau = -(r x F)_y = -(0.2 * 1.5 * 9.80665) = -2.941995 N m
    model = robot.model
    horizontal = robot.configuration([[0.0]])[:, 0]
    tau = pin.computeGeneralizedGravity(model, model.createData(), horizontal)
    assert tau[0] == pytest.approx(-0.2 * 1.5 * STANDARD_GRAVITY, rel=1e-12)


def test_malformed_mjcf_is_an_input_error(tmp_path):
    path = tmp_path / "broken.xml"
    path.write_text("<mujoco><worldbody><body>")
    with pytest.raises(InputError, match="broken.xml"):
        load_robot(path)
