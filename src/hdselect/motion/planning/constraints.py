"""TOPPRA constraints whose coefficients are computed for every gridpoint at once.

TOPPRA's own `JointTorqueConstraint` calls an inverse-dynamics function three
times per gridpoint. Along a path q = p(s), with u = s'' and x = s'^2,

    tau = M(q) p' u + (M(q) p'' + C(q, p') p') x + g(q) = a(s) u + b(s) x + c(s),

so three batched passes give every coefficient: c = RNEA(p, 0, 0),
a = RNEA(p, 0, p') - c, b = RNEA(p, p', p'') - c (`path_torque_coefficients`).
`SecondOrderBounds` hands such arrays to TOPPRA in its interpolation
discretization; `SpeedBound` bounds the path speed s' gridpoint by gridpoint.

This module imports toppra: import it only where TOPPRA runs.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from toppra.constraint import DiscretizationType, LinearConstraint
from toppra.constraint.linear_constraint import canlinear_colloc_to_interpolate

from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.model import Robot

MAX_PATH_SPEED_SQUARED = 1e16
"""Bound on x = s'^2 where nothing else bounds it; TOPPRA's own velocity constraint uses
the same value [1/s^2]."""


def path_torque_coefficients(robot: Robot, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, *,
                             threads: int | None = None) -> tuple[np.ndarray, ...]:
    """The joint torque along a path as a(s) s'' + b(s) s'^2 + c(s), in three batched passes.

    Args:
        robot: The robot (payload and gearhead masses as they are carried).
        q: Path positions p(s) at the gridpoints [rad or m], shape (m, dof).
        dq: First derivatives p'(s) [rad or m per unit of s], shape (m, dof).
        ddq: Second derivatives p''(s), shape (m, dof).
        threads: Threads of the batched dynamics (None: chosen from the size).

    Returns:
        a, b, c [N m per unit of s'', of s'^2, N m], each of shape (m, dof).
    """
    zero = np.zeros_like(dq)
    c = inverse_dynamics(robot, q, zero, zero, threads=threads)
    a = inverse_dynamics(robot, q, zero, dq, threads=threads) - c
    b = inverse_dynamics(robot, q, dq, ddq, threads=threads) - c
    return a, b, c


def torque_excess(robot: Robot, profile: Any, limit: np.ndarray) -> np.ndarray:
    """Per step of a TOPPRA profile, how far the torque at its middle goes past `limit` [-].

    TOPPRA bounds the torque at the gridpoints; between them the path's coefficients
    change. At the middle s_m of each step, x = s'^2 is the mean of its ends' and s''
    the step's own, so tau = a(s_m) s'' + b(s_m) x + c(s_m) (three batched passes).

    Args:
        robot: The robot the limits apply to.
        profile: A `hdselect.motion.planning.toppra.Profile`.
        limit: Joint torque limits, |tau| <= limit [N m], shape (dof,).

    Returns:
        max_j |tau_j| / limit_j - 1 at each step's middle, shape (m - 1,).
    """
    piece = profile.piece
    grid = piece.gridpoints
    middle = 0.5 * (grid[:-1] + grid[1:])
    path = piece.path
    a, b, c = path_torque_coefficients(robot, path(middle), path(middle, 1), path(middle, 2))
    x = 0.5 * (profile.sd[:-1] ** 2 + profile.sd[1:] ** 2)
    tau = a * profile.sdd[:, None] + b * x[:, None] + c
    return np.max(np.abs(tau) / limit, axis=1) - 1.0


class SecondOrderBounds(LinearConstraint):
    """F v <= g with v = a(s) s'' + b(s) s'^2 + c(s), given at every gridpoint.

    Discretized by interpolation, as the planner's other constraints: the bound is
    imposed at each gridpoint and, for the step leaving it, at the next one.

    Args:
        gridpoints: Path positions the arrays belong to, shape (m,).
        a: Coefficient of s'', shape (m, k).
        b: Coefficient of s'^2, shape (m, k).
        c: Constant part, shape (m, k).
        F: Constraint matrix, shape (r, k), the same at every gridpoint.
        g: Right-hand side, shape (r,).
    """

    def __init__(self, gridpoints: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
                 F: np.ndarray, g: np.ndarray) -> None:  # noqa: N803 (TOPPRA's names)
        super().__init__()
        self.set_discretization_type(DiscretizationType.Interpolation)
        self.identical = True
        self.gridpoints = np.asarray(gridpoints, dtype=float)
        self.a, self.b, self.c = (np.asarray(x, dtype=float) for x in (a, b, c))
        self.F, self.g = np.asarray(F, dtype=float), np.asarray(g, dtype=float)
        self.dof = self.a.shape[1]

    @classmethod
    def two_sided(cls, gridpoints: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
                  lower: np.ndarray, upper: np.ndarray) -> SecondOrderBounds:
        """Bounds on both sides, lower <= a s'' + b s'^2 + c <= upper (TOPPRA's torque form)."""
        k = np.shape(a)[1]
        eye = np.eye(k)
        return cls(gridpoints, a, b, c, np.vstack([eye, -eye]),
                   np.concatenate([np.asarray(upper, dtype=float),
                                   -np.asarray(lower, dtype=float)]))

    def get_dof(self) -> int:
        """Rows of v [-]."""
        return self.dof

    def compute_constraint_params(self, path, gridpoints):
        """TOPPRA's coefficients, converted to the interpolation discretization."""
        if not np.array_equal(np.asarray(gridpoints), self.gridpoints):
            raise ValueError("the constraint was built for other gridpoints")
        return canlinear_colloc_to_interpolate(self.a, self.b, self.c, self.F, self.g, None,
                                               None, self.gridpoints, identical=True)


class SpeedBound(LinearConstraint):
    """s' <= bound(s) at every gridpoint, as TOPPRA's velocity constraints bound it.

    Args:
        gridpoints: Path positions, shape (m,).
        bound: Largest path speed s' at each [1/s], shape (m,); inf for none.
    """

    def __init__(self, gridpoints: np.ndarray, bound: np.ndarray) -> None:
        super().__init__()
        self.gridpoints = np.asarray(gridpoints, dtype=float)
        squared = np.minimum(np.square(np.asarray(bound, dtype=float)), MAX_PATH_SPEED_SQUARED)
        self.xbound = np.column_stack([np.zeros_like(squared), squared])
        self.dof = 0

    def compute_constraint_params(self, path, gridpoints):
        """Only the bound on x = s'^2 at each gridpoint."""
        if not np.array_equal(np.asarray(gridpoints), self.gridpoints):
            raise ValueError("the constraint was built for other gridpoints")
        return None, None, None, None, None, None, self.xbound
