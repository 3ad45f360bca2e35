"""The worst states found, as whole states (q, qd, qdd) a motion could pass through.

Per joint, one state for each demand (`hdselect.envelope.demands.KINDS`):

- peak: the search's (q, qd), the joint's own speed at whichever bound (+v or -v) is
  worse (the torque is affine in a joint's own speed: dM_jj/dq_j = 0, so one bound is
  never better than the inside), the worst vertex acceleration, and every speed
  reversed if that makes the motor drive the load (the torque is even in qd). At
  full speed it is also the worst crash: |tau_j| + J N^2 |qd_j| / T is largest there.
- held: the joint at rest (qd_j = qdd_j = 0), the others at the worst vertex;
- stop: the search's (q, qd) coasting (qdd = 0); the stop decelerates from it;
- gravity: the pose at rest.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.envelope.box import LimitBox
from hdselect.envelope.demands import KINDS, joint_demands, worst_accelerations
from hdselect.envelope.search import Worst
from hdselect.robot.model import Robot


@dataclass(frozen=True, eq=False)
class StateRows:
    """Worst states, one row per (joint, demand) searched.

    Attributes:
        q: Positions [rad or m], shape (m, dof).
        qd: Velocities [rad/s or m/s], shape (m, dof).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (m, dof).
        joint: Index of the joint each row was searched for, shape (m,).
        kind: The demand each row was searched for, one of `KINDS` per row.
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    joint: np.ndarray
    kind: tuple[str, ...]

    def __len__(self) -> int:
        return len(self.kind)

    @property
    def rest(self) -> np.ndarray:
        """Where a joint is held in a row: its speed and acceleration exactly 0, (m, dof)."""
        return (self.qd == 0.0) & (self.qdd == 0.0)

    def row(self, joint: int, kind: str) -> int:
        """The row searched for a joint's demand."""
        for i, (j, k) in enumerate(zip(self.joint, self.kind, strict=True)):
            if j == joint and k == kind:
                return i
        raise KeyError((joint, kind))


def state_rows(robot: Robot, box: LimitBox, found: Mapping[tuple[int, str], Worst],
               stop_time: float, *, threads: int | None = None) -> StateRows:
    """Whole states of the worst points found, in the order of `found`.

    Args:
        robot: The robot the search ran with (payload and carried masses).
        box: The limit box.
        found: The search's worst point per (joint index, demand).
        stop_time: The emergency-stop time [s].
        threads: Threads for the batched passes.

    Returns:
        The rows, read-only.
    """
    keys = list(found)
    joint = np.array([j for j, _ in keys], dtype=np.intp)
    kind = np.array([KINDS.index(k) for _, k in keys], dtype=np.intp)
    points = np.array([found[key].point for key in keys])
    q, qd = box.states(points)
    qdd = np.zeros_like(q)
    rows = np.arange(len(keys))
    peak = kind == 0
    if peak.any():
        p = rows[peak]
        qd[p] = _full_speed(robot, box, points[p], joint[p], stop_time, threads)
    inertial = kind <= 1
    if inertial.any():
        r = rows[inertial]
        qdd[r] = worst_accelerations(robot, box, q[r], qd[r], joint[r], kind[r] == 1,
                                     threads=threads)
    if peak.any():
        p = rows[peak]
        # tau_j has the sign of qdd_j (M_jj > 0); reversing every speed keeps tau
        backwards = np.sign(qdd[p, joint[p]]) * qd[p, joint[p]] < 0.0
        qd[p[backwards]] *= -1.0
    qd[kind == 3] = 0.0
    return StateRows(frozen(q), frozen(qd), frozen(qdd), joint,
                     tuple(KINDS[k] for k in kind))


def _full_speed(robot: Robot, box: LimitBox, points: np.ndarray, joint: np.ndarray,
                stop_time: float, threads: int | None) -> np.ndarray:
    """Speeds of the peak points with each joint's own speed at the worse of its bounds."""
    dof, m = box.dof, len(points)
    tries = np.repeat(points, 3, axis=0)
    column = np.repeat(dof + joint, 3)
    tries[np.arange(3 * m), column] = np.tile([np.nan, 1.0, 0.0], m)
    keep = np.isnan(tries[np.arange(3 * m), column])
    tries[keep, column[keep]] = points[np.arange(m), dof + joint]
    values = joint_demands(robot, box, tries, np.repeat(joint, 3), np.zeros(3 * m, np.intp),
                           stop_time, threads=threads).reshape(m, 3)
    # a bound is taken unless the point itself is strictly better (never, in exact arithmetic)
    choice = np.where(values[:, 1:].max(axis=1) >= values[:, 0] * (1.0 - 1e-12),
                      1 + values[:, 1:].argmax(axis=1), 0)
    chosen = tries.reshape(m, 3, -1)[np.arange(m), choice]
    return box.states(chosen)[1]
