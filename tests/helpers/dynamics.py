"""Dynamics oracles written out by hand: Pinocchio configurations and a per-sample
RNEA loop, the closed-form two-link arm and index table, point masses added to a model
or a URDF, and the shipped motions planned once per session.
"""

from __future__ import annotations

import functools
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.motion.loading import load_case
from hdselect.motion.planning import Trajectory, plan
from helpers import REPO


def with_point_masses(model: pin.Model, masses: dict[str, float]) -> pin.Model:
    """A copy of `model` with a point mass m_k at joint k's origin, on its parent body."""
    model = pin.Model(model)
    for name, mass in masses.items():
        k = model.getJointId(name)
        model.appendBodyToJoint(model.parents[k], pin.Inertia(mass, np.zeros(3),
                                                              np.zeros((3, 3))),
                                model.jointPlacements[k])
    return model


def with_body(model: pin.Model, body, frame: str) -> pin.Model:
    """A copy of `model` with a rigid body (a Payload: mass, com, inertia) fixed at `frame`."""
    model = pin.Model(model)
    placed = model.frames[model.getFrameId(frame)]
    model.appendBodyToJoint(placed.parentJoint, pin.Inertia(
        body.mass, np.array(body.com), np.array(body.inertia)), placed.placement)
    return model


def part_rows(motion, trajectory: Trajectory) -> np.ndarray:
    """Where a motion's one part attached and released once rides (bool, per sample), by
    the documented rule: from the arrival at the attach waypoint to the end of the release
    waypoint's dwell, boundaries included (the attach before the release here)."""
    (attach,) = [event.waypoint for event in motion.events if event.attach]
    (release,) = [event.waypoint for event in motion.events if not event.attach]
    assert attach < release
    t = np.minimum(trajectory.t, trajectory.duration)
    start = trajectory.waypoint_times[attach]
    end = trajectory.waypoint_times[release] + motion.dwells[release]
    return (t >= start - 1e-9) & (t <= end + 1e-9)


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


ROBOTS = sorted((REPO / "robots").glob("*.urdf"))


MOTIONS = sorted((REPO / "trajectories").glob("*.toml"))


G = 9.80665  # standard gravity [m/s^2], written out (not taken from the code under test)


@functools.cache
def planned(motion_path: Path):
    """(robot, motion, trajectory) of a shipped motion file, planned once per test session."""
    robot, motion = load_case(motion_path)
    return robot, motion, plan(robot, motion)


def pin_config(model: pin.Model, q: np.ndarray) -> np.ndarray:
    """Pinocchio configuration of one joint-position vector, built by hand.

    A one-coordinate joint takes the angle (or slide) as is; a continuous
    (unbounded revolute) joint takes (cos q, sin q).
    """
    config = np.zeros(model.nq)
    for joint in list(model.joints)[1:]:
        value = q[joint.idx_v]
        if joint.nq == 1:
            config[joint.idx_q] = value
        else:
            config[joint.idx_q], config[joint.idx_q + 1] = math.cos(value), math.sin(value)
    return config


def rnea_loop(model: pin.Model, q, qd, qdd) -> np.ndarray:
    """Oracle: one `pinocchio.rnea` call per sample, shape (n, nv)."""
    data = model.createData()
    return np.array([pin.rnea(model, data, pin_config(model, q[k]), qd[k], qdd[k]).copy()
                     for k in range(len(q))])


def noise_zeroed(tau: np.ndarray, floor: np.ndarray | float) -> np.ndarray:
    """The oracle's torques with those below the noise floor [N m] as zero, as the sizing
    counts them (`hdselect.robot.dynamics.torque_floor`, checked by hand in test_life_cap)."""
    return np.where(np.abs(tau) < floor, 0.0, tau)


def random_states(robot, n: int, seed: int, *, speed: float = 2.0, accel: float = 10.0):
    """Random (q, qd, qdd) within the joint limits (continuous joints: -pi..pi)."""
    rng = np.random.default_rng(seed)
    lower = np.where(np.isfinite(robot.lower), robot.lower, -math.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, math.pi)
    q = rng.uniform(lower, upper, size=(n, robot.dof))
    qd = rng.uniform(-speed, speed, size=(n, robot.dof))
    qdd = rng.uniform(-accel, accel, size=(n, robot.dof))
    return q, qd, qdd


def thinned(trajectory: Trajectory, n: int = 300) -> np.ndarray:
    """Indices of about n samples spread over a trajectory."""
    return np.unique(np.linspace(0, len(trajectory.t) - 1, n).astype(int))


# From robots/index_table.urdf: disk izz + four blocks (izz about their centre plus
# the parallel-axis term m r^2, r = 0.11 m): J = 0.0429416 + 4 (0.00010048 + 0.3768 0.11^2)
J_TABLE = 0.0429416 + 4 * (0.00010048 + 0.3768 * 0.11**2)


# From robots/planar2.urdf (axes -y: positive angles raise the arm; both links along +x at
# zero; gravity along -z): link lengths, masses, centre-of-mass distances and the inertias
# about the centre of mass, about the joint axes (iyy).
L1, M1, LC1, I1 = 0.3, 0.243, 0.15, 0.00184072


L2, M2, LC2, I2 = 0.25, 0.16875, 0.125, 0.000887695


def two_link(q, qd, qdd, *, m2=M2, lc2=LC2, i2=I2, g=G):
    """Textbook vertical two-link equations of motion, per sample; returns (n, 2).

    tau1 = M11 qdd1 + M12 qdd2 - h (2 qd1 qd2 + qd2^2) + g1
    tau2 = M12 qdd1 + M22 qdd2 + h qd1^2 + g2
    M11 = I1 + I2 + m1 lc1^2 + m2 (l1^2 + lc2^2 + 2 l1 lc2 cos q2)
    M12 = I2 + m2 (lc2^2 + l1 lc2 cos q2),  M22 = I2 + m2 lc2^2,  h = m2 l1 lc2 sin q2
    g1 = (m1 lc1 + m2 l1) g cos q1 + m2 lc2 g cos(q1 + q2),  g2 = m2 lc2 g cos(q1 + q2)
    """
    q1, q2 = q[:, 0], q[:, 1]
    d1, d2 = qd[:, 0], qd[:, 1]
    a1, a2 = qdd[:, 0], qdd[:, 1]
    c2, s2 = np.cos(q2), np.sin(q2)
    m11 = I1 + i2 + M1 * LC1**2 + m2 * (L1**2 + lc2**2 + 2 * L1 * lc2 * c2)
    m12 = i2 + m2 * (lc2**2 + L1 * lc2 * c2)
    m22 = i2 + m2 * lc2**2
    h = m2 * L1 * lc2 * s2
    g1 = (M1 * LC1 + m2 * L1) * g * np.cos(q1) + m2 * lc2 * g * np.cos(q1 + q2)
    g2 = m2 * lc2 * g * np.cos(q1 + q2)
    tau1 = m11 * a1 + m12 * a2 - h * (2 * d1 * d2 + d2**2) + g1
    tau2 = m12 * a1 + m22 * a2 + h * d1**2 + g2
    return np.column_stack([tau1, tau2])


def composite_link2(mass: float, distance: float):
    """Link 2 with a point payload on its axis at `distance` from the elbow.

    m = m2 + mp, lc = (m2 lc2 + mp d) / m, I about the new centre of mass by the
    parallel-axis theorem: I2 + m2 (lc2 - lc)^2 + mp (d - lc)^2.
    """
    m = M2 + mass
    lc = (M2 * LC2 + mass * distance) / m
    return m, lc, I2 + M2 * (LC2 - lc) ** 2 + mass * (distance - lc) ** 2
