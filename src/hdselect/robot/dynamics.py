"""Joint torques along a trajectory: the only place that calls Pinocchio's inverse dynamics."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.robot.model import Robot
from hdselect.robot.mounting import STANDARD_GRAVITY

_SAMPLES_PER_THREAD = 2048
"""Below this many samples per thread, starting a thread costs more than it saves."""
CHUNK = 1 << 16
"""Samples per batched call: bounds the temporaries of a long trajectory (a few MB) while
keeping the per-call overhead negligible."""
_CORES = os.cpu_count() or 1
"""Cores of this machine (asking the system costs ~0.1 ms a call)."""
NOISE_FLOOR = 1e-9
"""Torques below this fraction of the robot's torque scale (`torque_floor`) are the noise
of the recursion's floating point (about 1e-16 of the terms it sums; this leaves seven
orders of margin) and count as exactly zero where a joint is sized
(`hdselect.sizing.core.select_units`): a joint nothing loads carries no torque, not 2e-10
N m whose cube-law life is 1e37 h."""
_REPEATS_WORTH = 8
"""Repeated states are computed once when more than 1 in this many samples repeat the one
before (dwells): the same inputs give the same torques, bit for bit."""


@dataclass(frozen=True, eq=False)
class CycleTorques:
    """Torques every joint carries along a trajectory, and along an emergency stop.

    Torque is force for prismatic joints [N]. Arrays have shape (n, dof).

    Attributes:
        tau: Joint torque along the motion [N m].
        stop: Joint torque at the start of an emergency stop from each sample, every
            joint decelerating at -qd / stop_time [N m].
        gravity: The gravity part, RNEA(q, 0, 0) [N m]; None unless split.
        coasting: Gravity plus velocity-product part, RNEA(q, qd, 0) [N m]; None unless split.
    """

    tau: np.ndarray
    stop: np.ndarray
    gravity: np.ndarray | None = None
    coasting: np.ndarray | None = None


def cycle_torques(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                  stop_time: float, *, split: bool = False, threads: int | None = None,
                  columns: Sequence[int] | None = None) -> CycleTorques:
    """The motion's torques and an emergency stop's, in two batched passes (four if split).

    Args:
        robot: The robot (payload, gearhead masses and gravity included).
        q: Joint positions along the trajectory [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        stop_time: Time in which an emergency stop brings every joint to rest [s].
        split: Also compute the gravity and coasting parts (for time scaling).
        threads: Threads for the batched passes; None chooses from the sample count.
        columns: Keep only these joints' torques (indices in the robot's joint order);
            None keeps every joint.

    Returns:
        The torques, shape (n, dof) or (n, len(columns)).
    """
    n = q.shape[0]
    keep = list(range(robot.dof)) if columns is None else list(columns)
    outputs = [np.empty((n, len(keep))) for _ in range(4 if split else 2)]
    for start in range(0, n, CHUNK):
        rows = slice(start, start + CHUNK)
        cq, cqd = q[rows], qd[rows]
        outputs[0][rows] = inverse_dynamics(robot, cq, cqd, qdd[rows], threads=threads)[:, keep]
        outputs[1][rows] = inverse_dynamics(robot, cq, cqd, cqd * (-1.0 / stop_time),
                                            threads=threads)[:, keep]
        if split:
            still = np.zeros_like(cqd)
            outputs[2][rows] = inverse_dynamics(robot, cq, still, still,
                                                threads=threads)[:, keep]
            outputs[3][rows] = inverse_dynamics(robot, cq, cqd, still, threads=threads)[:, keep]
    for array in outputs:
        array.setflags(write=False)
    if not split:
        return CycleTorques(outputs[0], outputs[1])
    return CycleTorques(*outputs)


def gravity_torques(robot: Robot, q: np.ndarray, *, threads: int | None = None) -> np.ndarray:
    """Torques that hold the robot still at each pose, RNEA(q, 0, 0) [N m], shape (n, dof)."""
    still = np.zeros((q.shape[0], robot.dof))
    return inverse_dynamics(robot, q, still, still, threads=threads)


def joint_inertias(robot: Robot, q: np.ndarray, joints: Sequence[str], *,
                   threads: int | None = None) -> np.ndarray:
    """The diagonal of the joint-space inertia matrix M(q) for the given joints.

    M_jj is the inertia joint j moves with every other joint held still: column j of
    M(q) is RNEA(q, 0, e_j) - RNEA(q, 0, 0), one batched pass per joint plus one.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        joints: Joints whose diagonal entry is wanted.
        threads: Threads for the batched passes; None chooses from the sample count.

    Returns:
        M_jj [kg m^2, or kg for a prismatic joint], shape (n, len(joints)).
    """
    still = np.zeros((q.shape[0], robot.dof))
    gravity = inverse_dynamics(robot, q, still, still, threads=threads)
    out = np.empty((q.shape[0], len(joints)))
    for k, name in enumerate(joints):
        j = robot.joint_index(name)
        unit = still.copy()
        unit[:, j] = 1.0
        out[:, k] = inverse_dynamics(robot, q, still, unit, threads=threads)[:, j] - gravity[:, j]
    return out


def torque_spread(robot: Robot, q: np.ndarray, qdd_spread: np.ndarray, *,
                  threads: int | None = None) -> np.ndarray:
    """How far joint torques may be off when each acceleration may be off by `qdd_spread`.

    Torque is linear in acceleration: an error e in qdd moves tau by M(q) e, so each joint's
    torque is off by at most sum_k |M_jk(q)| |e_k|. Column k of M(q) is RNEA(q, 0, e_k) -
    RNEA(q, 0, 0), one batched pass per joint whose spread is not 0, over the samples
    where some spread is not 0.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        qdd_spread: How far each acceleration may be off [rad/s^2 or m/s^2], shape (n, dof).
        threads: Threads for the batched passes; None chooses from the sample count.

    Returns:
        The bound on each joint's torque error [N m or N], shape (n, dof).
    """
    out = np.zeros((q.shape[0], robot.dof))
    rows = np.flatnonzero(np.any(qdd_spread > 0.0, axis=1))
    if not rows.size:
        return out
    q, spread = q[rows], qdd_spread[rows]
    still = np.zeros((len(rows), robot.dof))
    gravity = inverse_dynamics(robot, q, still, still, threads=threads)
    for k in np.flatnonzero(np.any(spread > 0.0, axis=0)):
        unit = still.copy()
        unit[:, k] = 1.0
        column = inverse_dynamics(robot, q, still, unit, threads=threads) - gravity
        out[rows] += np.abs(column) * spread[:, k:k + 1]
    return out


def inverse_dynamics(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, *,
                     threads: int | None = None) -> np.ndarray:
    """Batched recursive Newton-Euler: one Pinocchio call per `CHUNK` samples.

    A sample that repeats the one before (a dwell) is not computed again.

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        threads: Threads to use; None uses every core once there are enough samples
            to repay the threads. A study running one case per worker passes 1.

    Returns:
        Joint torques [N m or N], shape (n, dof).
    """
    n = q.shape[0]
    distinct = distinct_states(q, qd, qdd)
    if distinct is not None:  # a dwell repeats one state: compute it once
        keep, back = distinct
        return inverse_dynamics(robot, q[keep], qd[keep], qdd[keep], threads=threads)[back]
    if threads is None:
        threads = min(_CORES, max(1, min(n, CHUNK) // _SAMPLES_PER_THREAD))
    pool = pin.ModelPool(robot.model, threads)  # 0.05 ms: cheaper than keeping models alive
    out = np.empty((n, robot.model.nv))
    for start in range(0, n, CHUNK):
        rows = slice(start, start + CHUNK)
        m = len(range(*rows.indices(n)))
        config = robot.configuration(q[rows])
        velocity = np.asfortranarray(qd[rows].T)
        acceleration = np.asfortranarray(qdd[rows].T)
        tau = np.empty((robot.model.nv, m), order="F")
        pin.rneaInParallel(threads, pool, config, velocity, acceleration, tau)
        out[rows] = tau.T
    return out


def torque_floor(robot: Robot) -> np.ndarray:
    """Per joint, the torque [N m] (force [N], prismatic) below which it counts as zero.

    `NOISE_FLOOR` times the robot's scale: its whole mass under standard gravity, at
    the length of every joint offset and centre of mass of the model laid end to end
    for a rotary joint (no pose has a longer lever), at no length for a prismatic one.
    The same for every pose, speed and task of the robot.
    """
    model = robot.model
    mass = sum(inertia.mass for inertia in model.inertias)
    length = (sum(float(np.linalg.norm(p.translation)) for p in model.jointPlacements)
              + sum(float(np.linalg.norm(inertia.lever)) for inertia in model.inertias))
    force = NOISE_FLOOR * STANDARD_GRAVITY * mass
    return np.where(robot.revolute, force * length, force)


def distinct_states(q: np.ndarray, qd: np.ndarray,
                    qdd: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Where enough samples repeat the one before (dwells), the states to compute once.

    Args:
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).

    Returns:
        None when it does not pay (few samples, or at most 1 in `_REPEATS_WORTH`
        repeating); else a mask of the samples to compute and, for every sample, the
        index of its state among them.
    """
    n = q.shape[0]
    if n <= _SAMPLES_PER_THREAD:
        return None
    repeat = (np.all(q[1:] == q[:-1], axis=1) & np.all(qd[1:] == qd[:-1], axis=1)
              & np.all(qdd[1:] == qdd[:-1], axis=1))
    if np.count_nonzero(repeat) * _REPEATS_WORTH <= n:
        return None
    keep = np.r_[True, ~repeat]
    return keep, np.cumsum(keep) - 1


def rnea_function(robot: Robot) -> Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]:
    """Inverse dynamics of one state, tau(q, qd, qdd) [N m], as TOPPRA's torque constraint calls it.

    Positions are in the robot's joint order [rad or m]; continuous joints are
    converted to Pinocchio's (cos, sin) pair.
    """
    data = robot.model.createData()

    def rnea(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        config = robot.configuration(np.asarray(q, dtype=float)[None, :])[:, 0]
        return pin.rnea(robot.model, data, config, np.asarray(qd, dtype=float),
                        np.asarray(qdd, dtype=float))
    return rnea
