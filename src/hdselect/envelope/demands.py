"""What one state of the limit box demands of each joint: the quantities the search maximises.

With b(q, qd) = RNEA(q, qd, 0) (gravity and velocity products) and M(q) the
joint-space inertia matrix, the torque is affine in the acceleration:
tau = b + M qdd. So over the acceleration box |qdd_k| <= a_k the largest |tau_j| is
reached at a vertex, qdd_k = sign(b_j) sign(M_jk) a_k, and equals exactly

    peak_j    = |b_j(q, qd)| + sum_k |M_jk(q)| a_k.

The other demands of a state:

    held_j    = the same with joint j held (qd_j = qdd_j = 0) while the others move
                anywhere within the spec: |b_j(q, qd)| + sum_(k != j) |M_jk(q)| a_k,
    stop_j    = |RNEA(q, qd, -qd / T)_j| = |b_j - (M qd)_j / T|: the emergency stop from
                (q, qd) within the stop time T,
    gravity_j = |RNEA(q, 0, 0)_j|.

Column k of M is RNEA(q, 0, e_k) - RNEA(q, 0, 0), and M is symmetric, so row j is one
pass: every demand comes from batched passes of inverse dynamics
(`hdselect.robot.dynamics`), never from a loop over states.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from hdselect.envelope.box import LimitBox
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.model import Robot

KINDS = ("peak", "held", "stop", "gravity")
"""The demands of a state, in the order of `all_demands`' last axis."""


def all_demands(robot: Robot, box: LimitBox, x: np.ndarray, joints: Sequence[int],
                stop_time: float, *, threads: int | None = None) -> np.ndarray:
    """Every demand of the given joints at points of the unit cube.

    A joint's ``held`` demand is taken at the point with that joint's speed set to 0
    (its velocity coordinate 0.5); the others at the point itself. Row j of M is its
    column j (M is symmetric), so a joint costs two passes: its column of M and its
    held bias; gravity and bias are shared.

    Args:
        robot: The robot (payload and carried masses included).
        box: The limit box.
        x: Points of the unit cube, shape (n, 2 dof).
        joints: Indices of the joints wanted.
        stop_time: The emergency-stop time T [s].
        threads: Threads for the batched passes; None chooses from the count.

    Returns:
        Demands [N m or N], shape (n, len(joints), len(KINDS)): 2 + 2 len(joints) passes.
    """
    q, qd = box.states(x)
    still = np.zeros_like(q)
    gravity = inverse_dynamics(robot, q, still, still, threads=threads)
    bias = inverse_dynamics(robot, q, qd, still, threads=threads)
    out = np.empty((len(q), len(joints), len(KINDS)))
    for c, j in enumerate(joints):
        unit = still.copy()
        unit[:, j] = 1.0
        row = inverse_dynamics(robot, q, still, unit, threads=threads) - gravity  # M_j.
        spread = np.abs(row) @ box.acceleration  # sum_k |M_jk| a_k
        held = qd.copy()
        held[:, j] = 0.0
        bias_held = inverse_dynamics(robot, q, held, still, threads=threads)[:, j]
        out[:, c, 0] = np.abs(bias[:, j]) + spread
        out[:, c, 1] = np.abs(bias_held) + spread - np.abs(row[:, j]) * box.acceleration[j]
        out[:, c, 2] = np.abs(bias[:, j] - np.einsum("nk,nk->n", row, qd) / stop_time)
        out[:, c, 3] = np.abs(gravity[:, j])
    return out


def joint_demands(robot: Robot, box: LimitBox, x: np.ndarray, joint: np.ndarray,
                  kind: np.ndarray, stop_time: float, *,
                  threads: int | None = None) -> np.ndarray:
    """One demand per point: point i's `kind` of joint `joint[i]`.

    A ``held`` point must have its joint's velocity coordinate at 0.5 (speed 0), a
    ``gravity`` point every velocity coordinate at 0.5.

    Args:
        robot: The robot (payload and carried masses included).
        box: The limit box.
        x: Points of the unit cube, shape (n, 2 dof).
        joint: Index of each point's joint, shape (n,).
        kind: Index into `KINDS` of each point's demand, shape (n,).
        stop_time: The emergency-stop time T [s].
        threads: Threads for the batched passes.

    Returns:
        The demands [N m or N], shape (n,).
    """
    q, qd = box.states(x)
    out = np.empty(len(q))
    still = np.zeros_like(q)
    inertial = np.flatnonzero(kind <= 1)
    if inertial.size:
        r, j = inertial, joint[inertial]
        bias, column = _bias_and_column(robot, q[r], qd[r], j, threads)
        spread = np.abs(column) * box.acceleration
        spread[np.arange(r.size), j] *= (kind[r] == 0)  # held: joint j does not accelerate
        out[r] = np.abs(bias) + spread.sum(axis=1)
    stopping = np.flatnonzero(kind == 2)
    if stopping.size:
        r = stopping
        tau = inverse_dynamics(robot, q[r], qd[r], qd[r] * (-1.0 / stop_time), threads=threads)
        out[r] = np.abs(tau[np.arange(r.size), joint[r]])
    posed = np.flatnonzero(kind == 3)
    if posed.size:
        r = posed
        tau = inverse_dynamics(robot, q[r], still[r], still[r], threads=threads)
        out[r] = np.abs(tau[np.arange(r.size), joint[r]])
    return out


def worst_accelerations(robot: Robot, box: LimitBox, q: np.ndarray, qd: np.ndarray,
                        joint: np.ndarray, held: np.ndarray, *,
                        threads: int | None = None) -> np.ndarray:
    """The vertex of the acceleration box that makes |tau_j| largest at each state.

    qdd_k = sign(b_j) sign(M_jk) a_k (a zero sign counts as +), and qdd_j = 0 where
    the joint is held.

    Args:
        robot: The robot (payload and carried masses included).
        box: The limit box.
        q: Positions [rad or m], shape (n, dof).
        qd: Velocities [rad/s or m/s], shape (n, dof).
        joint: Index of each state's joint, shape (n,).
        held: Where the joint is held, shape (n,).
        threads: Threads for the batched passes.

    Returns:
        Accelerations [rad/s^2 or m/s^2], shape (n, dof).
    """
    bias, column = _bias_and_column(robot, q, qd, joint, threads)
    sign = np.where(bias < 0.0, -1.0, 1.0)[:, None] * np.where(column < 0.0, -1.0, 1.0)
    qdd = sign * box.acceleration
    qdd[np.arange(len(q)), joint] *= ~np.asarray(held, dtype=bool)
    return qdd


def _bias_and_column(robot: Robot, q: np.ndarray, qd: np.ndarray, joint: np.ndarray,
                     threads: int | None) -> tuple[np.ndarray, np.ndarray]:
    """b_j(q, qd) [N m], shape (n,), and row j of M(q), (n, dof): two passes.

    M is symmetric, so row j is column j, RNEA(q, qd, e_j) - RNEA(q, qd, 0) (the torque
    is affine in the acceleration).
    """
    rows = np.arange(len(q))
    still = np.zeros_like(q)
    unit = still.copy()
    unit[rows, joint] = 1.0
    bias = inverse_dynamics(robot, q, qd, still, threads=threads)
    column = inverse_dynamics(robot, q, qd, unit, threads=threads) - bias
    return bias[rows, joint], column
