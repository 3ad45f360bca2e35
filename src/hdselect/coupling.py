"""Torques from gearhead masses carried by the arm, by linearity of the dynamics.

A gearhead (and its motor) is bolted to the link before its joint, on the
joint axis: a point mass at the joint origin that every joint nearer the base
carries. Inverse dynamics is linear in the inertial parameters, so the torque
a mass m adds is m times the torque of a 1 kg point mass there:

    tau_i = m * (z_i x (x - o_i)) . (a_x - g)   for each revolute ancestor i
    tau_i = m * z_i . (a_x - g)                 for each prismatic ancestor i

with x the mount point, a_x its acceleration, o_i and z_i the origin and axis of
joint i. Pinocchio evaluates one configuration per call, so the forward
kinematics these need are evaluated here with numpy over all samples at once;
the tests check the result against Pinocchio with the masses written into the
model.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from hdselect.robot import Robot


def unit_mass_torques(
    robot: Robot,
    joints: list[str],
    q: np.ndarray,
    qd: np.ndarray,
    accelerations: list[np.ndarray],
) -> list[np.ndarray]:
    """Torques on every joint from a 1 kg point mass at each listed joint's mount point.

    Args:
        robot: The robot.
        joints: Joints whose gearhead mass is to be carried.
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        accelerations: One or more sets of joint accelerations [rad/s^2 or m/s^2],
            each (n, dof), e.g. the motion's and an emergency stop's.

    Returns:
        For each acceleration set, an array (len(joints), n, dof) of torques per
        kilogram [N m/kg or N/kg]; zero on the joint itself and on joints that do
        not carry it.
    """
    model = robot.model
    n = q.shape[0]
    kinematics = _Kinematics(model, q.T, qd.T)
    gravity = robot.gravity[:, None]
    out = [np.zeros((len(joints), n, robot.dof)) for _ in accelerations]
    for result, qdd in zip(out, accelerations, strict=True):
        acc = kinematics.accelerations(qdd.T)
        for row, name in enumerate(joints):
            joint_id = model.getJointId(name)
            force = acc[joint_id] - gravity  # per kg, (3, n)
            moment = _cross(kinematics.origin[joint_id], force)  # about the world origin
            ancestor = model.parents[joint_id]
            while ancestor > 0:
                dof = model.joints[ancestor].idx_v
                axis = kinematics.axis[ancestor]
                if kinematics.revolute[ancestor]:
                    # z . ((x - o) x F) = z . (x x F) - F . (z x o)
                    result[row, :, dof] = _dot(axis, moment) - _dot(force,
                                                                    kinematics.sweep[ancestor])
                else:
                    result[row, :, dof] = _dot(axis, force)
                ancestor = model.parents[ancestor]
    return out


class _Kinematics:
    """World-frame origins, axes and angular velocities of every joint, all samples.

    Vectors are stored as (3, n) arrays and rotations as their three columns,
    so every operation is a handful of contiguous length-n numpy operations.
    """

    def __init__(self, model: pin.Model, q: np.ndarray, qd: np.ndarray):
        n = q.shape[1]
        self.model = model
        self.qd = qd
        zero = np.zeros((3, n))
        self.origin: dict[int, np.ndarray] = {0: zero}
        self.axis: dict[int, np.ndarray] = {}
        self.sweep: dict[int, np.ndarray] = {}  # axis x origin, for moments about the axis
        self.revolute: dict[int, bool] = {}
        self.omega: dict[int, np.ndarray] = {0: zero}
        columns: dict[int, list[np.ndarray]] = {
            0: [np.repeat(e[:, None], n, axis=1) for e in np.eye(3)]}
        for joint_id in range(1, model.njoints):
            joint = model.joints[joint_id]
            parent = model.parents[joint_id]
            placement = model.jointPlacements[joint_id]
            local_axis, revolute = _axis(joint)
            angle, rate = q[joint.idx_v], qd[joint.idx_v]
            frame = [_combine(columns[parent], placement.rotation[:, j]) for j in range(3)]
            axis = _combine(frame, local_axis)
            origin = self.origin[parent] + _combine(columns[parent], placement.translation)
            if revolute:
                columns[joint_id] = _rotate(frame, local_axis, axis, angle)
                self.omega[joint_id] = self.omega[parent] + axis * rate
            else:
                columns[joint_id] = frame
                origin = origin + axis * angle
                self.omega[joint_id] = self.omega[parent]
            self.origin[joint_id], self.axis[joint_id] = origin, axis
            self.sweep[joint_id] = _cross(axis, origin)
            self.revolute[joint_id] = revolute

    def accelerations(self, qdd: np.ndarray) -> dict[int, np.ndarray]:
        """Linear acceleration of every joint origin [m/s^2], each (3, n)."""
        model, qd = self.model, self.qd
        zero = np.zeros((3, qdd.shape[1]))
        alpha: dict[int, np.ndarray] = {0: zero}
        linear: dict[int, np.ndarray] = {0: zero}
        for joint_id in range(1, model.njoints):
            parent = model.parents[joint_id]
            v = model.joints[joint_id].idx_v
            axis, omega = self.axis[joint_id], self.omega[parent]
            r = self.origin[joint_id] - self.origin[parent]
            acc = linear[parent] + _cross(alpha[parent], r) + _cross(omega, _cross(omega, r))
            if self.revolute[joint_id]:
                alpha[joint_id] = alpha[parent] + axis * qdd[v] + _cross(omega, axis) * qd[v]
            else:
                alpha[joint_id] = alpha[parent]
                acc = acc + axis * qdd[v] + 2.0 * _cross(omega, axis) * qd[v]
            linear[joint_id] = acc
        return linear


def _axis(joint: pin.JointModel) -> tuple[np.ndarray, bool]:
    kind = joint.shortname().removeprefix("JointModel")
    revolute = kind.startswith("R")
    if kind[-1] in "XYZ" and kind not in ("RevoluteUnaligned", "PrismaticUnaligned"):
        axis = np.zeros(3)
        axis["XYZ".index(kind[-1])] = 1.0
        return axis, revolute
    return np.asarray(joint.extract().axis, dtype=float), revolute


def _combine(columns: list[np.ndarray], weights: np.ndarray) -> np.ndarray:
    """Sum of columns[k] * weights[k]: a rotation (as columns) applied to a vector."""
    out = columns[0] * weights[0]
    for column, weight in zip(columns[1:], weights[1:], strict=True):
        if weight != 0.0:
            out = out + column * weight
    return out


def _rotate(frame: list[np.ndarray], axis: np.ndarray, world_axis: np.ndarray,
            angle: np.ndarray) -> list[np.ndarray]:
    """Columns of frame @ R(axis, angle) (Rodrigues), angle of shape (n,)."""
    c, s = np.cos(angle), np.sin(angle)
    out = []
    for j in range(3):
        unit = np.zeros(3)
        unit[j] = 1.0
        sweep = np.cross(axis, unit)  # R(a, t) e_j = c e_j + s (a x e_j) + (1 - c) a_j a
        column = frame[j] * c + _combine(frame, sweep) * s
        if axis[j] != 0.0:
            column = column + world_axis * ((1.0 - c) * axis[j])
        out.append(column)
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.stack((a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]))


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
