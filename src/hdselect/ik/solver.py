"""Inverse kinematics of one tool pose: damped least squares within the joint limits.

`solve_pose` moves a robot frame onto a pose given in the base frame, starting from a
seed. It is Pinocchio's damped least squares ("inverse kinematics (clik)" of its
examples) on the pose error e = log6(T_frame^-1 T_target), made robust:

- damping (mu |e|^2 + 1e-6) (Sugihara 2011): Gauss-Newton near the solution, a gradient
  step far from it or near a singularity; a step that does not lower |e|^2 is rejected
  and mu multiplied by 10, an accepted one divides it by 3 (never below 1);
- joint limits by an active set: a joint at a limit whose step points outward is held
  there and the step solved again without it (4 rounds), then every joint is clipped;
- no joint moves more than `MAX_STEP` in one iteration, so that a nearby pose is found
  on the seed's branch;
- an attempt that stalls (10 iterations gaining less than 10 %) with a joint of a full
  turn of range pressed against a limit moves that joint 2 pi, to the same angle inside
  its range, and goes on (once per joint);
- optional restarts from seeded random configurations when the seed's attempt fails.

The iteration goes on until both errors are below a tenth of their tolerance. Nothing
raises for an unreachable pose: the result says how far off the best attempt stayed and
which joint limits it is pressed against.

Why not pin-pink: for one frame task within box limits, pink's ``FrameTask`` is the same
Levenberg-Marquardt step built as a QP and handed to a QP solver every iteration. Measured
on UR5, Panda and benchtop6 (docs/tool-poses.md), it reached the same poses to the same
accuracy from the same seeds, 1.4 to 2 times slower, and needs ``pin-pink``, ``qpsolvers``
and a QP backend; the 2 pi move above (which pink lacks) doubles the success from far
seeds on arms whose joints turn a full circle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.ik.poses import Tolerance, pose_error
from hdselect.ik.targets import Goal, Target
from hdselect.robot.kinematics import AT_BOUND, FrameKinematics, LimitContact

MAX_ITERATIONS = 200
"""Jacobian evaluations per attempt [-]."""
MAX_STEP = 0.5
"""Largest change of a joint in one iteration [rad or m]."""
DEFAULT_TOLERANCE = Tolerance()
"""0.1 mm and 0.01 deg."""
_DAMPING_FLOOR = 1e-6
"""Constant part of the damping: keeps the step finite at a singularity."""
_INNER = 0.1
"""The iteration goes on until the errors are below this fraction of the tolerance."""
_WINDOW, _PROGRESS = 10, 0.9
"""An attempt has stalled when `_WINDOW` iterations lowered |e|^2 by less than 10 %."""


@dataclass(frozen=True)
class PoseSolution:
    """The outcome of solving one pose.

    Attributes:
        q: The joint positions reached, within the limits [rad or m], shape (dof,),
            read-only.
        position_error: Distance of the frame's origin from the pose's [m].
        orientation_error: Angle between the frame's orientation and the pose's [rad].
        converged: Both errors are within the tolerance.
        iterations: Jacobian evaluations spent, over every attempt.
        blocking: The joint limits the best attempt is pressed against with the error
            still falling outward: the limits in the way (empty when converged, and for
            a pose outside the arm's reach).
        restart: 0 when solved from the seed, k from the k-th random restart.
    """

    q: np.ndarray
    position_error: float
    orientation_error: float
    converged: bool
    iterations: int
    blocking: tuple[LimitContact, ...]
    restart: int = 0


def solve_pose(kin: FrameKinematics, target: Goal, seed: np.ndarray, *,
               tolerance: Tolerance = DEFAULT_TOLERANCE, restarts: int = 0, wrap: bool = True,
               rng_seed: int = 0) -> PoseSolution:
    """Place the frame of `kin` at `target` (base frame), starting from `seed`.

    Args:
        kin: The frame and the joint limits.
        target: The pose wanted, in the base frame: a full pose, or a `Target` that
            fixes less (its free coordinates are then settled by `settle`).
        seed: Joint positions to start from [rad or m], shape (dof,); clipped first.
        tolerance: How close the frame must come.
        restarts: Further attempts from random joint positions within the limits
            (unbounded joints in [-pi, pi]) when the seed's fails; their solution is
            usually on another branch than the seed.
        wrap: Allow the 2 pi move of a full-turn joint (along a line it would be a jump).
        rng_seed: Seed of the restarts' draws (the result is deterministic).

    Returns:
        The best attempt: the one that converged, else the one closest to the pose.
    """
    residual = _Residual(kin, target)
    best: tuple[float, np.ndarray, float, float, int] | None = None
    spent = 0
    rng = np.random.default_rng(rng_seed)
    for attempt in range(restarts + 1):
        start = kin.clip(seed) if attempt == 0 else _random(kin, rng)
        q, position, orientation, iterations = _descend(kin, residual, start, tolerance, wrap)
        spent += iterations
        score = position / tolerance.position + orientation / tolerance.orientation
        if best is None or score < best[0]:
            best = (score, q, position, orientation, attempt)
        if tolerance.holds(position, orientation):
            break
    if best is None:
        raise RuntimeError("inverse kinematics made no attempt")
    _, q, position, orientation, attempt = best
    converged = tolerance.holds(position, orientation)
    if converged and isinstance(target, Target):
        q, position, orientation, settling = settle(kin, residual, q, kin.clip(seed),
                                                    tolerance, wrap)
        spent += settling
    q = q.copy()
    q.setflags(write=False)
    return PoseSolution(q, position, orientation, converged, spent,
                        () if converged else blocking_limits(kin, target, q), attempt)


class _Residual:
    """The error of the frame's pose against a goal, and its Jacobian.

    A full pose uses the log6 error and Pinocchio's Jlog6 (the frame's own axes); a
    `Target` its own rows (`Target.residual`, the base frame's axes).
    """

    def __init__(self, kin: FrameKinematics, target: Goal) -> None:
        self.kin, self.target = kin, target
        self.full = not isinstance(target, Target)

    def at(self, q: np.ndarray) -> tuple[pin.SE3, np.ndarray]:
        """The frame's pose at `q` and the residual there."""
        current = self.kin.placement(q)
        target = self.target
        if isinstance(target, Target):
            return current, target.value(current)
        return current, pin.log6(current.actInv(target)).vector

    def jacobian(self, q: np.ndarray, current: pin.SE3) -> np.ndarray:
        """d(residual)/dq at `q`, shape (rows, dof)."""
        target = self.target
        if isinstance(target, Target):
            return target.residual(current, self.kin.jacobian(q, aligned=True))[1]
        return -pin.Jlog6(target.actInv(current)) @ self.kin.jacobian(q)

    def errors(self, current: pin.SE3, error: np.ndarray) -> tuple[float, float]:
        """The position [m] and orientation [rad] errors of `current`."""
        target = self.target
        if isinstance(target, Target):
            return target.errors(current)
        # log6's angular part is the rotation between the two orientations
        return (float(np.linalg.norm(target.translation - current.translation)),
                float(np.linalg.norm(error[3:])))

    def final(self, current: pin.SE3) -> tuple[float, float]:
        """The errors reported for the pose reached."""
        target = self.target
        return target.errors(current) if isinstance(target, Target) else \
            pose_error(current, target)


def _descend(kin: FrameKinematics, residual: _Residual, q: np.ndarray, tolerance: Tolerance,
             wrap: bool) -> tuple[np.ndarray, float, float, int]:
    """One attempt of damped least squares from `q`: (q, position, orientation, iterations)."""
    goal = tolerance.scaled(_INNER)
    current, error = residual.at(q)
    cost = float(error @ error)
    mu, stalled, iterations = 1.0, 0, 0
    history = [cost]
    wrapped = ~kin.full_turn if wrap else np.ones(kin.dof, dtype=bool)
    held = np.zeros(kin.dof, dtype=bool)
    identity = np.eye(kin.dof)
    while iterations < MAX_ITERATIONS:
        if goal.holds(*residual.errors(current, error)):
            break
        iterations += 1
        jacobian = residual.jacobian(q, current)
        gradient = jacobian.T @ error
        hessian = jacobian.T @ jacobian + (mu * cost + _DAMPING_FLOOR) * identity
        step, held = _step_within_limits(kin, q, hessian, gradient)
        biggest = float(np.abs(step).max(initial=0.0))
        if biggest > MAX_STEP:
            step *= MAX_STEP / biggest
        trial_q = kin.clip(q + step)
        trial, trial_error = residual.at(trial_q)
        trial_cost = float(trial_error @ trial_error)
        if trial_cost < cost:
            stalled = stalled + 1 if cost - trial_cost < 1e-14 + 1e-10 * cost else 0
            q, current, error, cost = trial_q, trial, trial_error, trial_cost
            mu = max(mu * 0.3, 1.0)
        else:
            stalled += 1
            mu *= 10.0
        history.append(cost)
        if stalled >= 8 or mu > 1e12 or (
                len(history) > _WINDOW and cost > _PROGRESS * history[-1 - _WINDOW]):
            turn = ~wrapped & held
            if not turn.any():
                break
            q = kin.clip(np.where(turn, q - np.sign(q - kin.middle) * 2.0 * np.pi, q))
            wrapped |= turn
            current, error = residual.at(q)
            cost = float(error @ error)
            mu, stalled, history = 1.0, 0, [cost]
    return (q, *residual.final(current), iterations)


SETTLE_ROUNDS = 40
"""Steps along the free coordinates at most [-]."""
SETTLE_STEP = 0.1
"""Largest joint move of one step along the free coordinates [rad or m]."""
LIMIT_MARGIN = 0.8
"""The part of each joint's half-range beyond which `preference` pushes back [-]."""
LIMIT_WEIGHT, SINGULAR_WEIGHT, SINGULAR_NEAR = 10.0, 1.0, 0.05
"""Weights of the limit and singularity terms of `preference` [-], and the arm's scaled
smallest singular value below which the singularity term acts [rad/rad]."""


def preference(kin: FrameKinematics, q: np.ndarray, reference: np.ndarray) -> float:
    """What `settle` lowers along the free coordinates [-].

    Half the squared joint distance from `reference` (the waypoint before, or the seed)
    [rad^2]; plus `LIMIT_WEIGHT` times the square of how far each bounded joint is beyond
    `LIMIT_MARGIN` of its half-range from the middle (as a fraction of the half-range);
    plus `SINGULAR_WEIGHT` times the square of how far the arm's scaled smallest
    singular value (`FrameKinematics.sigma_min`, the measure of
    `hdselect.ik.branches`) is below `SINGULAR_NEAR` (as a fraction of it).
    """
    value = 0.5 * float((q - reference) @ (q - reference))
    bounded = np.isfinite(kin.lower) & np.isfinite(kin.upper)
    half = np.where(bounded, 0.5 * (kin.upper - kin.lower), 1.0)
    beyond = np.maximum(np.abs(q - kin.middle) / half - LIMIT_MARGIN, 0.0)
    value += LIMIT_WEIGHT * float(np.where(bounded, beyond, 0.0) @ np.where(bounded, beyond, 0.0))
    sigma = kin.sigma_min(q)
    return value + SINGULAR_WEIGHT * max(0.0, 1.0 - sigma / SINGULAR_NEAR) ** 2


def settle(kin: FrameKinematics, residual: _Residual, q: np.ndarray, reference: np.ndarray,
           tolerance: Tolerance, wrap: bool) -> tuple[np.ndarray, float, float, int]:
    """Use the freedom a `Target` leaves: lower `preference` while holding what it fixes.

    A projected-gradient (null-space) step: the gradient of `preference` (central
    differences) projected on the null space of the fixed rows' Jacobian, at most
    `SETTLE_STEP` per joint, within the limits; the fixed coordinates are then restored by
    `_descend`. A step is taken only when the result holds the tolerance and lowers the
    preference; the step halves when it does not. An arm with no freedom left (as many
    fixed rows as joints) is returned as it is.

    Returns:
        (q, position error [m], orientation error [rad], Jacobian evaluations).
    """
    current = residual.at(q)[0]
    position, orientation = residual.final(current)
    spent, size = 0, SETTLE_STEP
    here = preference(kin, q, reference)
    for _ in range(SETTLE_ROUNDS):
        jacobian = residual.jacobian(q, current)
        _, singular, rows = np.linalg.svd(jacobian)
        rank = int(np.sum(singular > 1e-9 * max(float(singular[0]), 1.0)))
        null = rows[rank:]
        if not len(null) or size < 1e-6:
            break
        gradient = np.array([
            (preference(kin, q + d, reference)
             - preference(kin, q - d, reference)) / 2e-7
            for d in 1e-7 * np.eye(kin.dof)])
        step = -(null.T @ (null @ gradient))
        biggest = float(np.abs(step).max(initial=0.0))
        if biggest < 1e-9:
            break
        trial = kin.clip(q + step * min(size / biggest, 1.0))
        trial, p, o, iterations = _descend(kin, residual, trial, tolerance, wrap)
        spent += iterations + 1
        lower = preference(kin, trial, reference)
        if tolerance.holds(p, o) and lower < here - 1e-12:
            q, here, position, orientation = trial, lower, p, o
            current = residual.at(q)[0]
        else:
            size *= 0.5
    return q, position, orientation, spent


def _step_within_limits(kin: FrameKinematics, q: np.ndarray, hessian: np.ndarray,
                        gradient: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The damped step with joints at a limit that would push past it held (active set)."""
    held = np.zeros(kin.dof, dtype=bool)
    step = np.zeros(kin.dof)
    at_lower, at_upper = q <= kin.lower + AT_BOUND, q >= kin.upper - AT_BOUND
    for _ in range(4):
        free = ~held
        step = np.zeros(kin.dof)
        step[free] = -np.linalg.solve(hessian[np.ix_(free, free)], gradient[free])
        pushing = ((at_lower & (step < 0.0)) | (at_upper & (step > 0.0))) & ~held
        if not pushing.any():
            break
        held |= pushing
    return step, held


def blocking_limits(kin: FrameKinematics, target: Goal,
                    q: np.ndarray) -> tuple[LimitContact, ...]:
    """The limits `q` sits at with the pose error still falling outward: the limits in the way.

    The steepest descent of |e|^2 at `q`, -J^T e, is compared joint by joint with the
    side of the limit the joint sits at.
    """
    contacts = kin.contacts(q)
    if not contacts:
        return ()
    residual = _Residual(kin, target)
    current, error = residual.at(q)
    descent = -residual.jacobian(q, current).T @ error
    scale = float(np.abs(descent).max(initial=0.0)) or 1.0
    return tuple(contact for j, contact in contacts
                 if (descent[j] if contact.side == "upper" else -descent[j]) > 1e-6 * scale)


def _random(kin: FrameKinematics, rng: np.random.Generator) -> np.ndarray:
    """Joint positions drawn uniformly within the limits (unbounded: [-pi, pi])."""
    lower = np.where(np.isfinite(kin.lower), kin.lower, -np.pi)
    upper = np.where(np.isfinite(kin.upper), kin.upper, np.pi)
    return rng.uniform(lower, upper)
