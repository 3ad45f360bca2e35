"""The arm as springs: its mass matrix, its modes and the tool's deflection, in batches.

A joint with a unit behind it is a spring: its output turns against the input the
servo holds by the unit's twist (`hdselect.catalog.stiffness`), and its output bearing
tilts under the moment it carries. Here those small rotations become what the tool
does and how the arm rings:

- `mass_matrices`: M(q) restricted to some joints, column j = RNEA(q, 0, e_j) -
  RNEA(q, 0, 0), batched like `hdselect.robot.dynamics.joint_inertias`;
- `arm_modes`: the undamped modes of K v = w^2 M v with K = diag(K1), each joint's
  input held still (its servo) and the joints without a spring rigid;
- `tool_deflection`: each joint's small rotation vector w about a point c on its axis
  moves the tool frame at p by w x (p - c) and turns it by w (first order, dx = J dtheta),
  summed over joints, in the world frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pinocchio as pin

from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.model import Robot
from hdselect.robot.payload import frame_id
from hdselect.robot.wrenches import axis_turns


def mass_matrices(robot: Robot, q: np.ndarray, joints: Sequence[str], *,
                  threads: int | None = None) -> np.ndarray:
    """The joint-space inertia matrix M(q) restricted to some joints, at a batch of poses.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        joints: The joints kept, in the order wanted.
        threads: Threads for the batched passes; None chooses from the sample count.

    Returns:
        M restricted to `joints` [kg m^2, kg for a prismatic joint], shape (n, k, k).
    """
    index = [robot.joint_index(name) for name in joints]
    still = np.zeros((q.shape[0], robot.dof))
    gravity = inverse_dynamics(robot, q, still, still, threads=threads)[:, index]
    out = np.empty((q.shape[0], len(index), len(index)))
    for k, j in enumerate(index):
        unit = still.copy()
        unit[:, j] = 1.0
        out[:, :, k] = inverse_dynamics(robot, q, still, unit, threads=threads)[:, index] - gravity
    return 0.5 * (out + out.transpose(0, 2, 1))  # symmetric to rounding: make it exactly so


def arm_modes(mass: np.ndarray, k1: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """The arm's natural frequencies and mode shapes: K v = w^2 M v, K = diag(k1).

    Solved as the symmetric problem K^-1/2 M K^-1/2 u = u / w^2, v = K^-1/2 u, so every
    frequency is real and a massless direction gives inf.

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
    flexibility, vectors = flexibility[:, ::-1], vectors[:, :, ::-1]
    with np.errstate(divide="ignore"):
        omega = 1.0 / np.sqrt(np.clip(flexibility, 0.0, None))
    shapes = vectors * root[None, :, None]
    peak = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=1)[:, None, :], axis=1)
    return omega / (2.0 * math.pi), shapes / peak


def tool_deflection(robot: Robot, q: np.ndarray, frame: str,
                    rotations: Mapping[str, np.ndarray],
                    centres: Mapping[str, np.ndarray | float] | None = None
                    ) -> tuple[np.ndarray, np.ndarray]:
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
            axes are cases evaluated at the same poses (one forward kinematics).
        centres: Per joint, the point on its axis the rotation is about, from the joint
            origin along the axis [m], a number or (..., n); default 0 (the joint origin).

    Returns:
        The frame origin's translation [m] and the frame's rotation vector [rad], each
        (..., n, 3), in the world (the robot's base pose applied; the base frame where the
        robot was mounted by a gravity vector alone).
    """
    model, data = robot.model, robot.model.createData()
    names = list(rotations)
    ids = [model.getJointId(name) for name in names]
    target = frame_id(model, frame)
    config = robot.configuration(q)
    n = q.shape[0]
    turns = np.empty((n, len(ids), 3, 3))
    origins = np.empty((n, len(ids), 3))
    point = np.empty((n, 3))
    for i in range(n):
        pin.forwardKinematics(model, data, config[:, i])
        point[i] = pin.updateFramePlacement(model, data, target).translation
        for k, joint in enumerate(ids):
            turns[i, k] = data.oMi[joint].rotation
            origins[i, k] = data.oMi[joint].translation
    turns = turns @ axis_turns(robot, names)[None]  # each joint's axis frame in the base
    local = np.stack(np.broadcast_arrays(*(np.asarray(rotations[name], dtype=float)
                                           for name in names)), axis=-2)  # (..., n, k, 3)
    spin = np.einsum("nkab,...nkb->...nka", turns, local)
    along = np.stack([np.broadcast_to(np.asarray((centres or {}).get(name, 0.0), dtype=float),
                                      local.shape[:-2]) for name in names], axis=-1)
    centre = origins + turns[..., 2] * along[..., None]
    translation = np.cross(spin, point[:, None, :] - centre).sum(axis=-2)
    rotation = spin.sum(axis=-2)
    if robot.base_pose is not None:
        world = robot.base_pose.matrix
        translation, rotation = translation @ world.T, rotation @ world.T
    return translation, rotation
