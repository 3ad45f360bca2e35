"""TOPPRA: a time-optimal traversal of a spline path through the waypoints.

The path is a clamped cubic spline through the waypoints (chord-length
parametrised); a waypoint with a dwell splits the path into pieces that each
start and end at rest. A cubic spline overshoots its waypoints: where that would
take a joint past its position limit (a waypoint on or near the limit, such as a
home pose on a stop), that joint alone follows a shape-preserving cubic instead
(PCHIP slopes, zero at the ends), which never leaves the range of its neighbouring
waypoints. TOPPRA's answer is the path speed s' at every gridpoint,
with constant path acceleration between them (`Profile`, which samples it with
numpy exactly as toppra's ``ParametrizeConstAccel`` does).

TOPPRA's cost grows with its gridpoints (three small LPs on each, in Python), so a
piece is solved on a coarse grid, 50 cosine-spaced gridpoints per waypoint
(`hdselect.motion.planning.path.first_grid`), or on the dense one (200 per waypoint and 8
per line sample) where a shape-preserving joint or a straight line's close samples bend
the path, with every knot of the spline a gridpoint: p'' is linear between knots, and the
sharp turn where a free move meets a line would otherwise fall between gridpoints. Its
trajectory is verified between them: the speed and acceleration at `_DENSE_CHECK` times
in every step, the torque at the middle of every step. Steps that exceed a limit by more
than `REFINE_TOLERANCE` are split and the piece solved again (`solve_refined`), so
gridpoints are added only where the path needs them. What overshoot remains is removed by
slowing the piece down uniformly (plus 1e-4, `overshoot_scale`), which keeps the sampled
velocity and acceleration within ``TOPPRA_TOLERANCE`` of the limits; a slow-down of more
than `SLOWDOWN_NOTED` is reported (`Trajectory.notes`, and a warning of the
``hdselect.motion.planning`` logger) with the piece, the joint and the factor. Cycle
times are within 0.1 % of those on the dense grid (tests/test_plan.py,
tests/test_toolposes.py). Torque limits hold within ``TOPPRA_TORQUE_TOLERANCE``.

Co-design (`hdselect.codesign`) solves the same pieces, built by the same
`path_pieces` (so under the same rule at the position limits), under more
constraints with `solve_piece`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.path import (
    GRID_PER_LINE_SAMPLE,
    PathPiece,
    bends_sharply,
    first_grid,
    path_pieces,
    quiet,
    with_gridpoints,
)
from hdselect.motion.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot.model import Robot

__all__ = ["GRID_PER_LINE_SAMPLE", "PathPiece", "Profile", "kinematic_constraints",
           "overshoot_scale", "path_pieces", "plan_toppra", "solve_piece", "solve_refined",
           "step_excess", "with_gridpoints"]

TOPPRA_TOLERANCE = 1e-6
"""Relative amount by which a TOPPRA trajectory may exceed its velocity and
acceleration limits [-]."""

TOPPRA_TORQUE_TOLERANCE = 1e-3
"""Relative amount by which a TOPPRA trajectory may exceed its torque limits [-]."""

REFINE_TOLERANCE = 2e-4
"""Relative excess over a limit between gridpoints above which a step is halved [-]."""

REFINE_ROUNDS = 3
"""Most TOPPRA solves of a piece while its grid is refined."""

_SPLIT_MARGIN = 1.25
"""Parts a step is split into, over the square root of its excess over the tolerance [-]."""


SLOWDOWN_NOTED = 1e-3
"""Uniform slow-down of a piece [-] beyond which the planner says so: the cycle is then
no longer within 0.1 % of TOPPRA's on the dense grid (docs/rules.md)."""

_DENSE_CHECK = 10
"""Check points per TOPPRA gridpoint when measuring its overshoot."""

_MARGIN = 1e-4
"""Extra time scaling of a TOPPRA piece for peaks between the check points [-]."""


@dataclass(frozen=True, eq=False)
class Profile:
    """TOPPRA's time parametrisation of one piece: s' at each gridpoint, constant s'' between.

    Attributes:
        piece: The piece it parametrises.
        sd: Path speed s' at each gridpoint [1/s], shape (m,).
        t: Time at each gridpoint [s], shape (m,).
        sdd: Path acceleration s'' over each step [1/s^2], shape (m - 1,).
    """

    piece: PathPiece
    sd: np.ndarray
    t: np.ndarray
    sdd: np.ndarray

    @classmethod
    def from_speeds(cls, piece: PathPiece, sd: np.ndarray) -> Profile:
        """The profile of path speeds [1/s], with toppra's ``ParametrizeConstAccel`` formulas."""
        ss, sd = piece.gridpoints, np.asarray(sd, dtype=float)
        steps = np.diff(ss)
        sdd = 0.5 * np.diff(sd**2) / steps
        t = np.concatenate([[0.0], np.cumsum(2.0 * steps / (sd[:-1] + sd[1:]))])
        return cls(piece, frozen(sd), frozen(t), frozen(sdd))

    @property
    def duration(self) -> float:
        """Time to traverse the piece [s]."""
        return float(self.t[-1])

    @property
    def time_step(self) -> float:
        """The median time between gridpoints [s]: the acceleration steps this often."""
        return float(np.median(np.diff(self.t))) if len(self.t) > 1 else 0.0

    def peak_accelerations(self, scale: float = 1.0) -> np.ndarray:
        """Each joint's largest |acceleration| along the piece run `scale` times slower.

        The acceleration p'' s'^2 + p' s'' steps at every gridpoint (s'' is constant
        between them); its extremes are taken from both sides of each gridpoint.

        Returns:
            Peak |acceleration| per joint [rad/s^2 or m/s^2], shape (dof,).
        """
        piece, x = self.piece, np.square(self.sd)[:, None]
        before = np.r_[self.sdd[:1], self.sdd][:, None]
        after = np.r_[self.sdd, self.sdd[-1:]][:, None]
        sides = [piece.ddq * x + piece.dq * u for u in (before, after)]
        return np.max(np.abs(np.concatenate(sides)), axis=0) / scale**2

    def path_state(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """s, s' and s'' at times from the start of the piece [s], each shape (n,)."""
        index = np.searchsorted(self.t, times, side="right") - 1
        index = np.where(index == len(self.sdd), index - 1, index)
        step = times - self.t[index]
        u = self.sdd[index]
        s = self.piece.gridpoints[index] + step * self.sd[index] + 0.5 * step**2 * u
        return s, self.sd[index] + step * u, u

    def time_at(self, positions: np.ndarray) -> np.ndarray:
        """The time [s] from the start at which the piece reaches path positions s [-]."""
        s = np.asarray(positions, dtype=float)
        index = np.clip(np.searchsorted(self.piece.gridpoints, s, side="right") - 1, 0,
                        len(self.sdd) - 1)
        ahead = s - self.piece.gridpoints[index]
        speed, u = self.sd[index], self.sdd[index]
        # s_i + speed tau + u tau^2 / 2 = s, in the form that stays exact as u -> 0
        root = np.sqrt(np.maximum(speed**2 + 2.0 * u * ahead, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            tau = np.where(speed + root > 0.0, 2.0 * ahead / (speed + root), 0.0)
        return self.t[index] + tau

    def sample(self, times: np.ndarray,
               scale: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions, velocities and accelerations along the piece run `scale` times slower.

        Args:
            times: Times from the start of the piece [s], shape (n,).
            scale: Time scale [-]; the piece takes `scale` x `duration`.

        Returns:
            q [rad or m], qd [per s], qdd [per s^2], each of shape (n, dof).
        """
        with quiet():
            s, sd, u = self.path_state(np.asarray(times, dtype=float) / scale)
            path = self.piece.path
            q, dq, ddq = path(s), path(s, 1), path(s, 2)
        return q, dq * sd[:, None] / scale, (ddq * sd[:, None] ** 2 + dq * u[:, None]) / scale**2


def plan_toppra(robot: Robot, motion: Motion, *,
                max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Plan the motion's path time-optimally and sample it every ``motion.dt``.

    Raises:
        InputError: The grid does not resolve a path piece or exceeds `max_samples`.
        PlanningError: The limits make a piece of the path infeasible (the message
            names the constraint set at fault) or TOPPRA fails.
    """
    notes: list[str] = []
    moves = _toppra_pieces(robot, motion, notes)
    return assemble(motion, moves, max_samples=max_samples, notes=tuple(notes))


def slowdown_note(first: int, last: int, joint: str, limit: str, scale: float) -> str:
    """The line that says a piece was slowed down uniformly by `scale` [-], and why."""
    return (f"toppra slowed the path from waypoint[{first}] to waypoint[{last}] down "
            f"{scale:.4g} times: joint '{joint}' broke its {limit} limit between gridpoints "
            "after refining the grid; the cycle is longer than the time-optimal one")


def kinematic_constraints(velocity: np.ndarray, acceleration: np.ndarray) -> list[Any]:
    """TOPPRA's joint velocity [rad/s or m/s] and acceleration [per s^2] constraints."""
    with quiet():
        import toppra.constraint as constraint
    return [
        constraint.JointVelocityConstraint(np.column_stack([-velocity, velocity])),
        constraint.JointAccelerationConstraint(
            np.column_stack([-acceleration, acceleration]),
            discretization_scheme=constraint.DiscretizationType.Interpolation),
    ]


def solve_piece(piece: PathPiece, constraints: Sequence[Any], *, where: str) -> Profile | None:
    """TOPPRA's time-optimal profile of a piece from rest to rest, or None if infeasible.

    Args:
        piece: A piece with a path.
        constraints: toppra constraints built for the piece's gridpoints.
        where: The file, for the error message.

    Raises:
        PlanningError: TOPPRA itself fails (not mere infeasibility).
    """
    with quiet():
        import toppra.algorithm as algorithm
        try:
            instance = algorithm.TOPPRA(list(constraints), piece.path,
                                        parametrizer="ParametrizeConstAccel",
                                        gridpoints=piece.gridpoints)
            instance.compute_parameterization(0.0, 0.0)
        except Exception as err:  # toppra raises assorted solver errors
            raise PlanningError(f"{where}: toppra failed on the path from waypoint"
                                f"[{piece.first}] to waypoint[{piece.last}]: {err}") from err
        data = instance.problem_data
        if data.return_code != algorithm.ParameterizationReturnCode.Ok:
            return None
        return Profile.from_speeds(piece, data.sd_vec)


def overshoot_scale(profile: Profile, velocity: np.ndarray, acceleration: np.ndarray) -> float:
    """The uniform slow-down r >= 1 [-] that brings a profile within its kinematic limits.

    TOPPRA's constant-acceleration parametrisation exceeds the limits slightly
    between gridpoints; the overshoot found on a dense time grid sets the scale
    (q(t / r)), plus a margin for peaks between the check points.

    Args:
        profile: The piece's profile.
        velocity: Joint speed limits [rad/s or m/s], shape (dof,).
        acceleration: Joint acceleration limits [per s^2], shape (dof,).
    """
    return overshoot(profile, velocity, acceleration)[0]


def overshoot(profile: Profile, velocity: np.ndarray,
              acceleration: np.ndarray) -> tuple[float, int, str]:
    """`overshoot_scale`, with the joint (index) and the limit that set it.

    Returns:
        The scale [-], the joint's index and ``"velocity"`` or ``"acceleration"``.
    """
    dense = np.linspace(0.0, profile.duration, _DENSE_CHECK * len(profile.sd) + 1)
    _, qd, qdd = profile.sample(dense)
    speed = np.max(np.abs(qd) / velocity, axis=0)
    accel = np.sqrt(np.max(np.abs(qdd) / acceleration, axis=0))
    fast, hard = int(np.argmax(speed)), int(np.argmax(accel))
    joint, limit, ratio = ((fast, "velocity", speed[fast]) if speed[fast] >= accel[hard]
                           else (hard, "acceleration", accel[hard]))
    return max(1.0, float(ratio)) * (1.0 + _MARGIN), joint, limit


def step_excess(profile: Profile, velocity: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """Per step between gridpoints, how far the profile goes past its kinematic limits [-].

    Each step is checked at `_DENSE_CHECK` evenly spaced times (its start included).

    Returns:
        max(|qd| / v, sqrt(|qdd| / a)) - 1 over the step's check times, shape (m - 1,);
        negative where the step stays within the limits.
    """
    steps = np.diff(profile.t)
    times = profile.t[:-1, None] + steps[:, None] * (np.arange(_DENSE_CHECK) / _DENSE_CHECK)
    _, qd, qdd = profile.sample(times.ravel())
    ratio = np.maximum(np.max(np.abs(qd) / velocity, axis=1),
                       np.sqrt(np.max(np.abs(qdd) / acceleration, axis=1)))
    return ratio.reshape(len(steps), _DENSE_CHECK).max(axis=1) - 1.0


def solve_refined(piece: PathPiece, constraints: Callable[[PathPiece], Sequence[Any]],
                  excess: Callable[[Profile], np.ndarray], *,
                  where: str) -> tuple[PathPiece, Profile | None]:
    """TOPPRA's profile of a piece, its grid refined where the profile breaks a limit.

    The piece is solved on its gridpoints; every step whose `excess` is above
    `REFINE_TOLERANCE` is split (into more parts the more it exceeds) and the piece
    solved again, at most `REFINE_ROUNDS` times.

    Args:
        piece: A piece with a path, on its first gridpoints.
        constraints: The toppra constraints of a piece on its gridpoints.
        excess: Per step of a profile, its relative excess over the limits [-], (m - 1,).
        where: The file, for the error message.

    Returns:
        The piece on its last gridpoints, and its profile (None if infeasible).
    """
    for round_ in range(REFINE_ROUNDS):
        found = solve_piece(piece, constraints(piece), where=where)
        if found is None or round_ == REFINE_ROUNDS - 1:
            return piece, found
        over = excess(found)
        steps = np.flatnonzero(over > REFINE_TOLERANCE)
        if not len(steps):
            return piece, found
        # the excess between gridpoints falls as the square of the step: split each
        # step into as many parts as bring it within the tolerance
        parts = np.ceil(np.sqrt(over[steps] / REFINE_TOLERANCE) * _SPLIT_MARGIN).astype(int)
        grid = piece.gridpoints
        inserted = np.concatenate([grid[k] + (grid[k + 1] - grid[k]) * np.arange(1, n) / n
                                   for k, n in zip(steps, parts, strict=True)])
        piece = with_gridpoints(piece, np.sort(np.concatenate([grid, inserted])))
    raise AssertionError("unreachable")


def refined_profile(dense: PathPiece, constraints: Callable[[PathPiece], Sequence[Any]],
                    excess: Callable[[Profile], np.ndarray], *,
                    where: str) -> tuple[PathPiece, Profile | None]:
    """`solve_refined` from the piece's `first_grid`, or from the other grid if that fails.

    A piece with a shape-preserving joint or a straight line's samples starts from the
    dense grid (their knots are close together, and p'' steps at a shape-preserving
    joint's knots), any other from the coarse grid. toppra's seidel LPs can fail on one
    grid near the rest ends, where p' -> 0 (toppra issues #14 and #17): a piece is
    infeasible only if the other grid fails too.

    Arguments and returns as `solve_refined`, `dense` on the dense grid of `path_pieces`.
    """
    full = bends_sharply(dense)
    piece, found = solve_refined(first_grid(dense, full=full), constraints, excess,
                                 where=where)
    if found is None:
        piece, found = solve_refined(first_grid(dense, full=not full), constraints, excess,
                                     where=where)
    return piece, found


def _toppra_pieces(robot: Robot, motion: Motion, notes: list[str]) -> list[Move]:
    """Time-optimal pieces of the spline path, split at waypoints with a dwell.

    A piece slowed down by more than `SLOWDOWN_NOTED` gets a line in `notes`.
    """
    from hdselect.motion.planning.constraints import (
        SecondOrderBounds,
        path_torque_coefficients,
        torque_excess,
    )

    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    if velocity is None or acceleration is None:
        raise InputError("the toppra planner needs velocity and acceleration limits",
                         path=motion.path, field="limits")
    kinematic = kinematic_constraints(velocity, acceleration)
    torque = motion.torque_limit
    where = str(motion.path)

    def constraints(piece: PathPiece) -> list[Any]:
        if torque is None:
            return kinematic
        a, b, c = path_torque_coefficients(robot, piece.q, piece.dq, piece.ddq)
        return [*kinematic, SecondOrderBounds.two_sided(piece.gridpoints, a, b, c, -torque,
                                                        torque)]

    def excess(profile: Profile) -> np.ndarray:
        over = step_excess(profile, velocity, acceleration)
        if torque is not None:
            over = np.maximum(over, torque_excess(robot, profile, torque))
        return over

    moves: list[Move] = []
    for dense in path_pieces(robot, motion):
        first, last = dense.first, dense.last
        if dense.path is None:
            moves.append(Move(first, last, 0.0, None))
            continue
        piece, found = refined_profile(dense, constraints, excess, where=where)
        if found is None and torque is not None:
            if solve_piece(piece, kinematic, where=where) is not None:
                raise PlanningError(
                    f"{motion.path}: toppra: the torque limits (limits.torque) make the path "
                    f"from waypoint[{first}] to waypoint[{last}] infeasible; it is feasible "
                    "with the velocity and acceleration limits alone")
        if found is None:
            raise PlanningError(
                f"{motion.path}: toppra: the velocity and acceleration limits (limits.velocity, "
                f"limits.acceleration) make the path from waypoint[{first}] to "
                f"waypoint[{last}] infeasible")
        try:
            scale, joint, limit = overshoot(found, velocity, acceleration)
            duration = found.duration * scale
            if not (math.isfinite(duration) and duration > 0.0 and np.all(np.isfinite(found.sd))):
                raise ArithmeticError(f"duration {duration!r} s")
        except (ValueError, ArithmeticError) as err:
            raise PlanningError(f"{motion.path}: toppra: the path from waypoint[{first}] to "
                                f"waypoint[{last}] cannot be timed with these limits "
                                f"({type(err).__name__}: {err})") from err
        if scale > 1.0 + SLOWDOWN_NOTED:
            notes.append(slowdown_note(first, last, motion.joint_names[joint], limit, scale))
        if piece.knots is None:
            raise RuntimeError("a path piece without its knots")
        reached = found.time_at(piece.knots) * scale
        passes = tuple(float(reached[max(k for k, w in enumerate(piece.waypoints) if w <= i)])
                       for i in range(first, last + 1))
        # sampled at least as finely as the median step of the dense grid (200 gridpoints
        # per waypoint), on which the 1 % promise of the sampled demands was measured
        finer = min(1.0, len(piece.gridpoints) / len(dense.gridpoints))
        moves.append(Move(first, last, duration, partial(found.sample, scale=scale),
                          found.peak_accelerations(scale), found.time_step * scale * finer,
                          passes=passes))
    return moves


