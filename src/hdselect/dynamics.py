"""Joint torques along a trajectory: batched inverse dynamics with Pinocchio."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from hdselect.arrays import frozen
from hdselect.robot import Robot

if TYPE_CHECKING:
    from hdselect.plan import Trajectory

_SAMPLES_PER_THREAD = 2048
"""Below this many samples per thread, starting a thread costs more than it saves."""


@dataclass(frozen=True, eq=False)
class JointTorques:
    """Torques every joint must carry along a trajectory.

    Attributes:
        tau: Joint torque (force for prismatic joints) [N m or N], shape (n, dof).
        gravity: The gravity-only part, tau at the same positions at rest
            [N m or N], shape (n, dof).
    """

    tau: np.ndarray
    gravity: np.ndarray


def joint_torques(robot: Robot, trajectory: Trajectory) -> JointTorques:
    """Inverse dynamics along a trajectory, and its gravity-only part.

    Args:
        robot: The robot (payload and gravity included).
        trajectory: Sampled positions, velocities and accelerations.

    Returns:
        Torques for every sample.
    """
    tau = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
    still = np.zeros_like(trajectory.qd)
    gravity = inverse_dynamics(robot, trajectory.q, still, still)
    return JointTorques(frozen(tau), frozen(gravity))


def inverse_dynamics(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Batched recursive Newton-Euler: one Pinocchio call over all samples, on every core.

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).

    Returns:
        Joint torques [N m or N], shape (n, dof).
    """
    n = q.shape[0]
    config = robot.configuration(q)
    velocity = np.asfortranarray(qd.T)
    acceleration = np.asfortranarray(qdd.T)
    tau = np.empty((robot.model.nv, n), order="F")
    threads = min(os.cpu_count() or 1, max(1, n // _SAMPLES_PER_THREAD))
    pool = pin.ModelPool(robot.model, threads)  # 0.05 ms: cheaper than keeping models alive
    pin.rneaInParallel(threads, pool, config, velocity, acceleration, tau)
    return tau.T
