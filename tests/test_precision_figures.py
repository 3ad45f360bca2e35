"""The precision figures against independent calculations: kinematics, hand formulas.

- the tool's deflection against central finite differences of Pinocchio's forward
  kinematics (a twist dtheta moves the tool by J dtheta) and, for a bearing's tilt,
  against the forward kinematics of a model whose child link is tilted for real;
- the arm's two modes of a 2-link arm from the 2 x 2 problem det(K - w^2 M) = 0 solved in
  closed form with M(q) written by hand from the links' masses;
- the single-axis natural frequency of the index table by hand (its file derives J);
- the sign: an arm sagging under gravity moves its tool down.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.catalog.builtin import catalog_file
from hdselect.catalog.units import Stiffness
from hdselect.robot.compliance import (
    arm_frequencies,
    arm_modes,
    mass_matrices,
    placements,
    tool_deflection,
    unit_rotation,
)
from hdselect.robot.dynamics import gravity_torques, inverse_dynamics, joint_inertias
from hdselect.robot.payload import frame_id
from hdselect.robot.wrenches import axis_turns, axis_wrenches
from helpers.robots import finger_arm, gripper

ROOT = Path(__file__).resolve().parents[1]
BENCHTOP = ROOT / "robots" / "benchtop6.urdf"
PLANAR = ROOT / "robots" / "planar2.urdf"


def shg_units() -> list[hdselect.Unit]:
    """The built-in SHG-2UH series (every unit rates K1)."""
    return [u for u in hdselect.load_catalog([catalog_file("shg-2uh")]) if u.series == "SHG-2UH"]


def frame_pose(robot: hdselect.Robot, q: np.ndarray, frame: str) -> pin.SE3:
    """Pinocchio's pose of a frame at one configuration (the oracle's forward kinematics)."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.configuration(q[None, :])[:, 0])
    return data.oMf[frame_id(robot.model, frame)].copy()


def test_placements_and_mass_matrices_equal_pinocchio_per_pose() -> None:
    robot = hdselect.load_robot(BENCHTOP).with_gearheads({"elbow": 1.2, "wrist_2": 0.4})
    q = np.random.default_rng(1).uniform(-2.5, 2.5, (40, robot.dof))
    names = list(robot.joint_names)
    placed = placements(robot, q)
    mass = mass_matrices(robot, q, names, placed=placed)
    data = robot.model.createData()
    config = robot.configuration(q)
    for i in range(len(q)):
        pin.forwardKinematics(robot.model, data, config[:, i])
        for name in names:
            j = robot.model.getJointId(name)
            np.testing.assert_allclose(placed.rotation[j][i], data.oMi[j].rotation, atol=1e-12)
            np.testing.assert_allclose(placed.origin[j][i], data.oMi[j].translation, atol=1e-12)
        crba = pin.crba(robot.model, data, config[:, i])
        np.testing.assert_allclose(mass[i], np.triu(crba) + np.triu(crba, 1).T, atol=1e-12)
    sub = ["shoulder_lift", "wrist_1"]  # the others held rigid: M's rows and columns kept
    np.testing.assert_allclose(np.diagonal(mass_matrices(robot, q, sub), axis1=1, axis2=2),
                               joint_inertias(robot, q, sub), rtol=1e-12, atol=1e-14)


def test_twists_move_the_tool_as_finite_differences_of_the_kinematics() -> None:
    robot = hdselect.load_robot(BENCHTOP)
    rng = np.random.default_rng(2)
    q = rng.uniform(-2.0, 2.0, (12, robot.dof))
    twist = rng.uniform(-1e-3, 1e-3, (12, robot.dof))
    rotations = {}
    for k, name in enumerate(robot.joint_names):  # a twist about the axis: q moved by it
        rotations[name] = np.zeros((12, 3))
        rotations[name][:, 2] = twist[:, k]
    translation, turn = tool_deflection(robot, q, "tool0", rotations)
    h = 1e-6
    for i in range(len(q)):
        moved, spun = np.zeros(3), np.zeros(3)
        for k in range(robot.dof):
            step = np.zeros(robot.dof)
            step[k] = h
            ahead, behind = frame_pose(robot, q[i] + step, "tool0"), \
                frame_pose(robot, q[i] - step, "tool0")
            moved += (ahead.translation - behind.translation) / (2 * h) * twist[i, k]
            spun += pin.log3(ahead.rotation @ behind.rotation.T) / (2 * h) * twist[i, k]
        np.testing.assert_allclose(translation[i], moved, atol=1e-9)
        np.testing.assert_allclose(turn[i], spun, atol=1e-9)


def test_a_bearing_tilt_moves_the_tool_as_a_tilted_child_link_does() -> None:
    robot = hdselect.load_robot(BENCHTOP)
    name, offset = "elbow", 0.03
    q = np.random.default_rng(3).uniform(-2.0, 2.0, (6, robot.dof))
    tilt = np.array([4e-4, -7e-4, 0.0])
    translation, _ = tool_deflection(robot, q, "tool0", {name: np.tile(tilt, (6, 1))},
                                     {name: offset})
    model = robot.model.copy()
    j = model.getJointId(name)
    turn = axis_turns(robot, [name])[0]
    for sign in (1.0, -1.0):  # the child side turned about the bearing centre, both ways
        centre = offset * turn[:, 2]
        tilted = pin.SE3(pin.exp3(sign * turn @ tilt), centre - pin.exp3(sign * turn @ tilt)
                         @ centre)
        bent = model.copy()
        for child in range(1, bent.njoints):
            if bent.parents[child] == j:
                bent.jointPlacements[child] = tilted * bent.jointPlacements[child]
        for f in range(len(bent.frames)):
            frame = bent.frames[f]
            if frame.parentJoint == j:
                frame.placement = tilted * frame.placement
                bent.frames[f] = frame
        data = bent.createData()
        tip = []
        for row in robot.configuration(q).T:
            pin.framesForwardKinematics(bent, data, row)
            tip.append(data.oMf[frame_id(bent, "tool0")].translation.copy())
        if sign > 0:
            ahead = np.array(tip)
        else:
            behind = np.array(tip)
    np.testing.assert_allclose(translation, (ahead - behind) / 2, atol=1e-10)


def planar_mass(robot: hdselect.Robot, elbow: float) -> np.ndarray:
    """M(q) of the 2-link planar arm by hand, from each link's mass, centre and inertia."""
    first, second = robot.model.inertias[1], robot.model.inertias[2]
    l1 = float(np.linalg.norm(robot.model.jointPlacements[2].translation))
    m1, m2 = first.mass, second.mass
    c1, c2 = float(first.lever[0]), float(second.lever[0])
    i1, i2 = float(first.inertia[1, 1]), float(second.inertia[1, 1])
    m22 = i2 + m2 * c2 * c2
    m12 = m22 + m2 * l1 * c2 * math.cos(elbow)
    m11 = i1 + m1 * c1 * c1 + m2 * l1 * l1 + 2 * m12 - m22
    return np.array([[m11, m12], [m12, m22]])


@pytest.mark.parametrize("elbow", [-2.4, -1.0, 0.0, 0.7, 2.0])
def test_two_link_modes_equal_the_two_by_two_problem_by_hand(elbow: float) -> None:
    robot = hdselect.load_robot(PLANAR)
    hand = planar_mass(robot, elbow)
    q = np.array([[0.3, elbow]])
    np.testing.assert_allclose(mass_matrices(robot, q, ["shoulder", "elbow"])[0], hand,
                               rtol=1e-9)
    k = (4700.0, 1300.0)
    # det(K - lam M) = 0: det(M) lam^2 - (k1 m22 + k2 m11) lam + k1 k2 = 0, lam = w^2
    a = hand[0, 0] * hand[1, 1] - hand[0, 1] ** 2
    b = -(k[0] * hand[1, 1] + k[1] * hand[0, 0])
    root = math.sqrt(b * b - 4 * a * k[0] * k[1])
    by_hand = sorted(math.sqrt(lam) / (2 * math.pi) for lam in ((-b - root) / (2 * a),
                                                               (-b + root) / (2 * a)))
    frequencies, shapes = arm_modes(hand[None], k)
    np.testing.assert_allclose(frequencies[0], by_hand, rtol=1e-10)
    np.testing.assert_allclose(arm_frequencies(hand[None], k)[0], by_hand, rtol=1e-10)
    for i, f in enumerate(by_hand):  # (K - w^2 M) v = 0, scaled to a largest entry of 1
        v = shapes[0, :, i]
        np.testing.assert_allclose(np.diag(k) @ v, (2 * math.pi * f) ** 2 * hand @ v,
                                   atol=1e-9 * k[0])
        assert np.max(np.abs(v)) == pytest.approx(1.0)


def test_index_table_frequency_by_hand() -> None:
    result = hdselect.size(None, ROOT / "trajectories" / "index_table_indexing.toml",
                           catalog=shg_units())
    (table,) = result.precision.joints
    k1 = table.unit.stiffness.k1
    inertia = 0.0429416 + 4 * (0.00010048 + 0.3768 * 0.11 ** 2)  # the file's derivation
    assert inertia == pytest.approx(0.061581, rel=1e-5)
    by_hand = math.sqrt(k1 / inertia) / (2 * math.pi)
    assert table.lowest_frequency == pytest.approx(by_hand, rel=1e-5)
    np.testing.assert_allclose(table.frequency, by_hand, rtol=1e-5)  # J the same everywhere
    assert result.precision.modes.lowest_frequency == pytest.approx(by_hand, rel=1e-5)
    assert table.resonance_speed == pytest.approx(by_hand * 30.0, rel=1e-12)
    assert table.holding_torsion == 0.0  # gravity along the axis: no torque held


def test_an_arm_sagging_under_gravity_moves_its_tool_down() -> None:
    robot = hdselect.load_robot(PLANAR)
    unit = shg_units()[0]
    held = np.array([[0.0, 0.0]])  # stretched out horizontally: both joints hold it up
    torque = gravity_torques(robot, held)[0]
    rotations = {name: unit_rotation(unit, torque[k:k + 1])[0]
                 for k, name in enumerate(robot.joint_names)}
    translation, rotation = tool_deflection(robot, held, "tool", rotations)
    assert translation[0, 2] < -1e-6  # down
    assert abs(translation[0, 2]) > 100 * abs(translation[0, 1])
    assert abs(rotation[0, 1]) > 0.0 and not rotation[0, [0, 2]].any()  # in its plane


def test_sizing_reports_the_holding_sag_downward_and_names_its_frame() -> None:
    result = hdselect.size(None, ROOT / "trajectories" / "planar2_pick_place.toml",
                           catalog=shg_units())
    tool = result.precision.tool
    assert tool.frame == "tool"
    worst = tool.holding_translation[tool.worst_holding]
    assert worst[2] < 0.0 and tool.max_holding == pytest.approx(np.linalg.norm(worst))
    assert result.precision.not_rated == () and result.precision.rigid == ()
    assert tool.bearing_tilt == ("shoulder", "elbow")  # SHG-2UH rates K_B
    for joint in result.precision.joints:
        assert joint.rated and joint.max_torsion > 0.0
        assert joint.max_torsion == pytest.approx(np.abs(joint.torsion).max())


def test_no_precision_and_units_without_k1() -> None:
    motion = ROOT / "trajectories" / "planar2_pick_place.toml"
    assert hdselect.size(None, motion, catalog=shg_units(), precision=False).precision is None
    psa = hdselect.size(None, motion)  # the built-in PSA-G page rates no stiffness
    assert psa.precision.tool is None and psa.precision.modes is None
    assert psa.precision.not_rated == ("shoulder", "elbow")
    assert all(not j.rated and j.torsion is None for j in psa.precision.joints)


def test_k1_only_unit_twists_linearly_and_the_curve_bends_above_t1() -> None:
    unit = shg_units()[0]
    linear = replace(unit, stiffness=Stiffness(k1=unit.stiffness.k1))
    torque = np.array([0.5, -3.0, 10.0])
    rotation, centre = unit_rotation(linear, torque)
    np.testing.assert_allclose(rotation[:, 2], -torque / unit.stiffness.k1)
    assert not centre.any() and not rotation[:, :2].any()
    curved, _ = unit_rotation(unit, torque)
    assert curved[0, 2] == pytest.approx(-0.5 / unit.stiffness.k1)  # below T1: K1
    assert abs(curved[2, 2]) < 10.0 / unit.stiffness.k1  # stiffer above T1


def test_a_ceiling_mounted_arm_sags_down_in_the_world_too() -> None:
    motion = hdselect.load_motion(ROOT / "trajectories" / "planar2_pick_place.toml")
    shg = {u.id: u for u in shg_units()}
    units = {"shoulder": shg["SHG-17-100-2UH"], "elbow": shg["SHG-14-100-2UH"]}
    held = {}
    for mounting in ("floor", "ceiling"):
        robot = hdselect.load_robot(PLANAR).with_payload(motion.payload).with_mounting(mounting)
        trajectory = hdselect.plan(robot, motion)
        held[mounting] = hdselect.check_units(robot, trajectory, units).precision.tool
    floor, ceiling = held["floor"], held["ceiling"]
    # upside down, gravity flips in the base: the base-frame sag flips and the base's turn
    # (x kept, y and z reversed) brings it back down in the world, x mirrored
    common, at_floor, at_ceiling = np.intersect1d(floor.samples, ceiling.samples,
                                                  return_indices=True)
    assert len(common) >= 1000  # the spread poses; each joint's worst torque may differ
    np.testing.assert_allclose(ceiling.holding_translation[at_ceiling],
                               floor.holding_translation[at_floor] * np.array([-1.0, 1.0, 1.0]),
                               rtol=1e-9, atol=1e-15)
    assert ceiling.holding_translation[ceiling.worst_holding][2] < 0.0


@pytest.mark.parametrize("build", ["gripper", "finger_arm"])
def test_mass_matrix_of_mimic_followers_equals_rnea_columns(tmp_path: Path, build: str) -> None:
    robot = hdselect.load_robot(gripper(tmp_path) if build == "gripper" else finger_arm(tmp_path))
    q = np.random.default_rng(4).uniform(-0.4, 0.4, (25, robot.dof))
    still = np.zeros_like(q)
    gravity = inverse_dynamics(robot, q, still, still)
    columns = []
    for j in range(robot.dof):  # column j of M(q): RNEA(q, 0, e_j) - RNEA(q, 0, 0)
        unit = still.copy()
        unit[:, j] = 1.0
        columns.append(inverse_dynamics(robot, q, still, unit) - gravity)
    np.testing.assert_allclose(mass_matrices(robot, q, list(robot.joint_names)),
                               np.stack(columns, axis=2), rtol=1e-10, atol=1e-14)


def test_the_base_bearing_tilts_a_stretched_arm_down_under_its_weight() -> None:
    robot = hdselect.load_robot(BENCHTOP)
    stretched = np.zeros((1, robot.dof))  # the arm reaches out horizontally (tool0 at x 0.45)
    unit = next(u for u in shg_units() if u.id == "SHG-20-100-2UH")
    wrench = axis_wrenches(robot, stretched, stretched, stretched, ["shoulder_pan"])[0]
    rotation, centre = unit_rotation(unit, wrench[5], wrench, 0.0)
    assert rotation[0, 2] == 0.0 and np.linalg.norm(rotation[0, :2]) > 0.0  # a tilt alone
    k_b = unit.bearing.moment_stiffness
    moment = math.hypot(wrench[3, 0] + centre[0] * wrench[1, 0],
                        wrench[4, 0] - centre[0] * wrench[0, 0])
    assert np.linalg.norm(rotation[0, :2]) == pytest.approx(moment / k_b)
    translation, _ = tool_deflection(robot, stretched, "tool0", {"shoulder_pan": rotation},
                                     {"shoulder_pan": centre})
    assert translation[0, 2] < 0.0 and abs(translation[0, 2]) > 10 * abs(translation[0, 1])
