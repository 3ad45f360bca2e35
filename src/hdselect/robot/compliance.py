"""The arm as springs: its mass matrix, its modes and the tool's deflection, in batches.

A joint with a unit behind it is a spring: its output turns against the input the
servo holds by the unit's twist (`hdselect.catalog.stiffness`), and its output bearing
tilts under the moment it carries. Here those small rotations become what the tool
does and how the arm rings, over a whole batch of poses in numpy:

- `placements`: forward kinematics of every pose at once (Pinocchio's
  oMi = oMi(parent) jointPlacement M_joint(q));
- `mass_matrices`: M(q) restricted to some joints, what RNEA(q, 0, e_j) - RNEA(q, 0, 0)
  gives column by column, summed body by body from the placements;
- `arm_modes` (`arm_frequencies` for the frequencies alone): the undamped modes of
  K v = w^2 M v with K = diag(K1), each joint's input held still (its servo) and the
  joints without a spring rigid;
- `unit_rotation`: a unit's twist -phi(tau) and its bearing's tilt -M / K_B;
- `tool_deflection`: each joint's small rotation vector w about a point c on its axis
  moves the tool frame at p by w x (p - c) and turns it by w (first order, dx = J dtheta),
  summed over joints, in the world frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.catalog.stiffness import torsion
from hdselect.catalog.units import Unit
from hdselect.robot.dynamics import NOISE_FLOOR
from hdselect.robot.joint_motions import JointMotion, joint_motions
from hdselect.robot.model import Robot
from hdselect.robot.payload import frame_id
from hdselect.robot.wrenches import axis_turns


@dataclass(frozen=True, eq=False)
class Placements:
    """Every joint frame of a robot at a batch of poses, in the base frame.

    Attributes:
        robot: The robot.
        motions: Its joints' motions, in the model's order (`joint_motions`).
        rotation: Per joint (the universe first), its frame's axes, (n, 3, 3) each.
        origin: Per joint (the universe first), its frame's origin [m], (n, 3) each.
    """

    robot: Robot
    motions: tuple[JointMotion, ...]
    rotation: list[np.ndarray]
    origin: list[np.ndarray]

    def frame_origin(self, frame: str) -> np.ndarray:
        """The origin of a frame of the robot at every pose [m], (n, 3)."""
        model = self.robot.model
        placed = model.frames[frame_id(model, frame)]
        parent = int(placed.parentJoint)
        offset = np.asarray(placed.placement.translation)
        return self.origin[parent] + self.rotation[parent] @ offset


def placements(robot: Robot, q: np.ndarray) -> Placements:
    """Forward kinematics of a batch of poses: every joint frame, in the base frame.

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n, dof).
    """
    model = robot.model
    motions = joint_motions(model, robot.path)
    config = robot.configuration(q)
    n = q.shape[0]
    rotation = [np.broadcast_to(np.eye(3), (n, 3, 3))]
    origin = [np.zeros((n, 3))]
    for i, joint in enumerate(motions, start=1):
        parent = int(model.parents[i])
        placement = model.jointPlacements[i]
        turn = (rotation[parent].reshape(-1, 3) @ placement.rotation).reshape(n, 3, 3)
        start = origin[parent] + rotation[parent] @ np.asarray(placement.translation)
        coordinate = joint.coordinate(config)
        if joint.revolute:  # Rodrigues: R = turn (I + sin K + (1 - cos) K^2)
            skew = pin.skew(joint.axis)
            flat = turn.reshape(-1, 3)
            sin = np.sin(coordinate)[:, None, None]
            versine = (1.0 - np.cos(coordinate))[:, None, None]
            rotation.append(turn + sin * (flat @ skew).reshape(n, 3, 3)
                            + versine * (flat @ (skew @ skew)).reshape(n, 3, 3))
            origin.append(start)
        else:
            rotation.append(turn)
            origin.append(start + coordinate[:, None] * (turn @ joint.axis))
    return Placements(robot, motions, rotation, origin)


def mass_matrices(robot: Robot, q: np.ndarray, joints: Sequence[str], *,
                  placed: Placements | None = None) -> np.ndarray:
    """The joint-space inertia matrix M(q) restricted to some joints, at a batch of poses.

    M = sum over bodies b of m_b Jv_b^T Jv_b + Jw_b^T I_b Jw_b, with Jv_b the velocity of
    its centre of mass and Jw_b its angular velocity per unit joint speed (a mimic
    follower's scaled into its leader's column), the other joints held still.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        joints: The joints kept, in the order wanted.
        placed: These poses' `placements`, when already computed.

    Returns:
        M restricted to `joints` [kg m^2, kg for a prismatic joint], shape (n, k, k).
    """
    placed = placed if placed is not None else placements(robot, q)
    model, motions = robot.model, placed.motions
    column = {motions[model.getJointId(name) - 1].v_index: k for k, name in enumerate(joints)}
    n, size = q.shape[0], len(joints)
    # each body's spatial Jacobian about the base origin, (v_O; w) per column, built from
    # its parent's: a turn about axis a through o adds (o x a; a), a slide along a (a; 0)
    jacobians: list[tuple[np.ndarray, np.ndarray]] = [(np.zeros((n, 3, size)),) * 2]
    rows = []  # per body, its rows G_b of M = sum G_b^T G_b: sqrt(m) Jv and F Jw, I = F^T F
    for i, joint in enumerate(motions, start=1):
        linear, angular = jacobians[int(model.parents[i])]
        if joint.v_index in column:
            k = column[joint.v_index]
            axis = placed.rotation[i] @ joint.axis * joint.scaling
            linear, angular = linear.copy(), angular.copy()
            if joint.revolute:
                linear[:, :, k] += _cross(placed.origin[i], axis)
                angular[:, :, k] += axis
            else:
                linear[:, :, k] += axis
        jacobians.append((linear, angular))
        body = model.inertias[i]
        if body.mass == 0.0 and not np.any(body.inertia):
            continue
        centre = placed.origin[i] + placed.rotation[i] @ np.asarray(body.lever)
        values, vectors = np.linalg.eigh(np.asarray(body.inertia))
        factor = np.sqrt(np.clip(values, 0.0, None))[:, None] * vectors.T
        rows += [math.sqrt(body.mass) * (linear + _cross(angular, centre[:, :, None])),
                 factor @ (placed.rotation[i].transpose(0, 2, 1) @ angular)]  # body axes
    if not rows:
        return np.zeros((n, size, size))
    stacked = np.concatenate(rows, axis=1)
    out: np.ndarray = stacked.transpose(0, 2, 1) @ stacked
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The cross product a x b along axis 1 of (n, 3, ...) arrays, or -1 of (n, 3) ones."""
    axis = 1 if a.ndim > 2 or b.ndim > 2 else -1
    a0, a1, a2 = np.moveaxis(a, axis, 0)
    b0, b1, b2 = np.moveaxis(b, axis, 0)
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=axis)


def arm_frequencies(mass: np.ndarray, k1: Sequence[float]) -> np.ndarray:
    """The arm's natural frequencies alone, as `arm_modes` gives them [Hz], (n, k) ascending."""
    root = 1.0 / np.sqrt(np.asarray(k1, dtype=float))
    flexibility = np.linalg.eigvalsh(mass * root[None, :, None] * root[None, None, :])
    return _frequencies(flexibility[:, ::-1])


def _frequencies(flexibility: np.ndarray) -> np.ndarray:
    """Frequencies w / 2 pi [Hz] from flexibilities 1 / w^2 [s^2], per pose, (n, k).

    A flexibility below `NOISE_FLOOR` of its pose's largest is the recursion's noise: a
    direction that moves no mass, inf.
    """
    floor = NOISE_FLOOR * np.max(flexibility, axis=-1, keepdims=True)
    with np.errstate(divide="ignore"):
        result: np.ndarray = 1.0 / np.sqrt(np.where(flexibility > floor, flexibility, 0.0))
    return result / (2 * math.pi)


def arm_modes(mass: np.ndarray, k1: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """The arm's natural frequencies and mode shapes: K v = w^2 M v, K = diag(k1).

    Solved as the symmetric problem K^-1/2 M K^-1/2 u = u / w^2, v = K^-1/2 u, so every
    frequency is real and a direction that moves no mass gives inf.

    Args:
        mass: M(q) of the joints with a spring (`mass_matrices`) [kg m^2], (n, k, k).
        k1: Each joint's stiffness, in the same order [N m/rad], all above 0.

    Returns:
        The frequencies [Hz], (n, k), ascending at each pose; and the mode shapes, (n, k, k),
        column i of a pose's matrix the shape of its frequency i, largest |entry| 1.
    """
    root = 1.0 / np.sqrt(np.asarray(k1, dtype=float))
    scaled = mass * root[None, :, None] * root[None, None, :]
    flexibility, vectors = np.linalg.eigh(scaled)  # ascending 1 / w^2: descending w
    shapes = vectors[:, :, ::-1] * root[None, :, None]
    peak = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=1)[:, None, :], axis=1)
    return _frequencies(flexibility[:, ::-1]), shapes / peak


def unit_rotation(unit: Unit, torque: np.ndarray, wrench: np.ndarray | None = None,
                  offset: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """How a unit's output turns under its load, in its joint's axis frame, about what point.

    Its twist about the axis is -phi(tau) (`hdselect.catalog.stiffness.torsion`: the load
    pushes the output back from where the servo holds the input); where the unit rates its
    bearing's moment stiffness K_B and the wrench is given, its tilt about x and y is
    -M / K_B, M the moment about the bearing centre: the flange `offset` along the axis,
    moved by the unit's flange-to-centre distance to whichever side tilts more (as
    `hdselect.robot.wrenches.bearing_loads` takes it).

    Args:
        unit: The unit; its K1 must be rated (`hdselect.catalog.stiffness.rates_torsion`).
        torque: The joint torque [N m], (..., n).
        wrench: The joint's wrench in its axis frame (`axis_wrenches` rows) [N, N m],
            (..., 5 or 6, n); None: no tilt.
        offset: The output flange along the axis from the joint origin [m].

    Returns:
        The rotation vector [rad], (..., n, 3), and the point on the axis it is about, from
        the joint origin [m], (..., n) (for `tool_deflection`).
    """
    if unit.stiffness is None:
        raise ValueError(f"{unit.id} rates no torsional stiffness")
    torque = np.asarray(torque, dtype=float)
    rotation = np.zeros((*torque.shape, 3))
    rotation[..., 2] = -torsion(unit.stiffness, torque)
    centre = np.zeros(torque.shape)
    bearing = unit.bearing
    if wrench is None or bearing is None or bearing.moment_stiffness is None:
        return rotation, centre
    fx, fy, mx, my = (wrench[..., row, :] for row in (0, 1, 3, 4))
    sides = (offset + bearing.offset, offset - bearing.offset)
    moments = [np.stack((mx + h * fy, my - h * fx), axis=-1) for h in sides]
    far = np.linalg.norm(moments[1], axis=-1) > np.linalg.norm(moments[0], axis=-1)
    rotation[..., :2] = -np.where(far[..., None], moments[1], moments[0]) / bearing.moment_stiffness
    return rotation, np.where(far, sides[1], sides[0])


def tool_deflection(robot: Robot, q: np.ndarray, frame: str,
                    rotations: Mapping[str, np.ndarray],
                    centres: Mapping[str, np.ndarray | float] | None = None, *,
                    placed: Placements | None = None) -> tuple[np.ndarray, np.ndarray]:
    """How far a frame moves when joints turn by small rotations, at a batch of poses.

    Each joint's rotation is given in its axis frame (`hdselect.robot.wrenches.axis_turns`:
    z along the joint axis, x and y turning with the child link), about a point on its
    axis: its twist about z, and a tilt about x and y. Its rotation vector w, turned into
    the world, moves the frame's origin p by w x (p - c) and turns the frame by w; the
    joints' parts are summed (first order in the rotations).

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n, dof): the commanded poses.
        frame: The frame whose motion is wanted (e.g. the tool's).
        rotations: Per joint, its rotation in its axis frame [rad], (..., n, 3): any leading
            axes are cases evaluated at the same poses.
        centres: Per joint, the point on its axis the rotation is about, from the joint
            origin along the axis [m], a number or (..., n); default 0 (the joint origin).
        placed: These poses' `placements`, when already computed.

    Returns:
        The frame origin's translation [m] and the frame's rotation vector [rad], each
        (..., n, 3), in the world (the robot's base pose applied; the base frame where the
        robot was mounted by a gravity vector alone).
    """
    placed = placed if placed is not None else placements(robot, q)
    names = list(rotations)
    point = placed.frame_origin(frame)
    translation = np.zeros(np.broadcast_shapes(*(np.shape(rotations[name]) for name in names)))
    rotation = np.zeros_like(translation)
    for name, turn in zip(names, axis_turns(robot, names, placed.motions),
                          strict=True):
        i = robot.model.getJointId(name)
        axes = placed.rotation[i] @ turn  # the joint's axis frame in the base, (n, 3, 3)
        spin = np.einsum("nab,...nb->...na", axes, rotations[name])
        along = np.asarray((centres or {}).get(name, 0.0), dtype=float)[..., None]
        centre = placed.origin[i] + axes[:, :, 2] * along
        translation += np.cross(spin, point - centre)
        rotation += spin
    if robot.base_pose is not None:
        world = robot.base_pose.matrix
        translation, rotation = translation @ world.T, rotation @ world.T
    return translation, rotation
