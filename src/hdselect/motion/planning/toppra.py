"""TOPPRA: a time-optimal traversal of a spline path through the waypoints.

The path is a clamped cubic spline through the waypoints (chord-length
parametrised), with 200 cosine-spaced TOPPRA gridpoints per waypoint of a piece
(`path_pieces`). A waypoint with a dwell splits the path into pieces that each
start and end at rest. A cubic spline overshoots its waypoints: where that would
take a joint past its position limit (a waypoint on or near the limit, such as a
home pose on a stop), that joint alone follows a shape-preserving cubic instead
(PCHIP slopes, zero at the ends), which never leaves the range of its neighbouring
waypoints. TOPPRA's answer is the path speed s' at every gridpoint,
with constant path acceleration between them (`Profile`, which samples it with
numpy exactly as toppra's ``ParametrizeConstAccel`` does). That parametrisation
overshoots the limits between gridpoints (measured up to 2.5e-3 relative); each
piece is therefore slowed down uniformly by its overshoot (plus 1e-4,
`overshoot_scale`), which keeps the sampled velocity and acceleration within
``TOPPRA_TOLERANCE`` of the limits (measured: never above them on 30 random 6-DOF
paths) for a cycle at most that much longer than TOPPRA's. Torque limits hold
within ``TOPPRA_TORQUE_TOLERANCE`` (measured up to 6e-5 relative).

Co-design (`hdselect.codesign`) solves the same pieces, built by the same
`path_pieces` (so under the same rule at the position limits), under more
constraints with `solve_piece`.
"""

from __future__ import annotations

import logging
import math
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.motion.paths import SplinePath, piece_bounds, piece_geometry
from hdselect.motion.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot.model import Robot

TOPPRA_TOLERANCE = 1e-6
"""Relative amount by which a TOPPRA trajectory may exceed its velocity and
acceleration limits [-]."""

TOPPRA_TORQUE_TOLERANCE = 1e-3
"""Relative amount by which a TOPPRA trajectory may exceed its torque limits [-]."""

_GRID_PER_SEGMENT = 200
"""TOPPRA gridpoints per waypoint of a piece (cosine-spaced, dense near the rest ends)."""

GRID_PER_LINE_SAMPLE = 8
"""TOPPRA gridpoints per joint sample of a straight line (its samples are close together)."""

_DENSE_CHECK = 10
"""Check points per TOPPRA gridpoint when measuring its overshoot."""

_MARGIN = 1e-4
"""Extra time scaling of a TOPPRA piece for peaks between the check points [-]."""


@dataclass(frozen=True, eq=False)
class PathPiece:
    """One piece of the path, from rest to rest, between two waypoints.

    Attributes:
        first: Index of the waypoint it starts from.
        last: Index of the waypoint it ends at (the next one with a dwell, or the last).
        path: The path over s in [0, 1] (`hdselect.motion.paths.SplinePath`, toppra's path
            interface), or None when the piece has zero length.
        gridpoints: TOPPRA's gridpoints s, shape (m,).
        q: p(s) at the gridpoints [rad or m], shape (m, dof).
        dq: p'(s) at the gridpoints [rad or m per unit of s], shape (m, dof).
        ddq: p''(s) at the gridpoints, shape (m, dof).
        waypoints: Index of every waypoint the path passes through, in order (repeats
            dropped).
        knots: Path position s of each of those waypoints, shape (len(waypoints),).
    """

    first: int
    last: int
    path: Any
    gridpoints: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    waypoints: tuple[int, ...] = ()
    knots: np.ndarray | None = None

    def segment(self, s: float) -> tuple[int, int]:
        """The waypoints (indices) between which path position s [-] lies."""
        if self.knots is None or len(self.waypoints) < 2:
            return self.first, self.last
        k = int(np.clip(np.searchsorted(self.knots, s, side="right") - 1, 0,
                        len(self.waypoints) - 2))
        return self.waypoints[k], self.waypoints[k + 1]


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
        with _quiet():
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
    return assemble(motion, _toppra_pieces(robot, motion), max_samples=max_samples)


@contextmanager
def _quiet() -> Iterator[None]:
    """Silence TOPPRA's log records and numerical warnings."""
    log = logging.getLogger("toppra")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        log.setLevel(level)


def path_pieces(robot: Robot, motion: Motion, grid_per_waypoint: int = _GRID_PER_SEGMENT, *,
                speeds: np.ndarray | None = None) -> list[PathPiece]:
    """The motion's path split where it dwells: a clamped cubic spline per piece.

    Repeated consecutive waypoints are dropped; a piece whose waypoints all coincide
    has no path (zero length). A straight line's joint samples are points of the path
    too. A joint whose spline would leave the robot's position limits follows a
    shape-preserving cubic instead (`hdselect.motion.paths.SplinePath`). The knots are at
    the cumulative chord length (the TOPPRA planner's path) or, given `speeds`, at the
    cumulative time each segment takes at those speeds, max_j |dq_j| / speed_j, which
    weighs joints in different units (rad, m) alike. Each piece gets
    ``grid_per_waypoint`` cosine-spaced gridpoints per waypoint, and `GRID_PER_LINE_SAMPLE`
    per line sample.

    Args:
        robot: The robot (position limits).
        motion: The motion (waypoints, solved, and dwells).
        grid_per_waypoint: Gridpoints per waypoint of a piece.
        speeds: Joint speeds that set the knots [rad/s or m/s], shape (dof,); None for
            chord length.

    Returns:
        The pieces, in order.
    """
    pieces: list[PathPiece] = []
    for first, last in piece_bounds(motion):
        geometry = piece_geometry(motion, first, last, speeds)
        if len(geometry.knots) < 2:
            nothing = frozen(np.zeros((0, len(motion.joint_names))))
            pieces.append(PathPiece(first, last, None, frozen(np.zeros(0)), nothing, nothing,
                                    nothing, geometry.waypoints))
            continue
        count = (grid_per_waypoint * len(geometry.waypoints)
                 + GRID_PER_LINE_SAMPLE * geometry.line_samples)
        grid = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, count + 1))
        with _quiet():
            try:
                path = SplinePath(geometry.knots, geometry.points, robot.lower, robot.upper)
            except (ValueError, ArithmeticError) as err:
                raise PlanningError(f"{motion.path}: toppra: no spline through waypoint[{first}]"
                                    f" to waypoint[{last}]: {err}") from err
            q, dq, ddq = path(grid), path(grid, 1), path(grid, 2)
        pieces.append(PathPiece(first, last, path, frozen(grid), frozen(q), frozen(dq),
                                frozen(ddq), geometry.waypoints,
                                frozen(geometry.waypoint_knots)))
    return pieces


def kinematic_constraints(velocity: np.ndarray, acceleration: np.ndarray) -> list[Any]:
    """TOPPRA's joint velocity [rad/s or m/s] and acceleration [per s^2] constraints."""
    with _quiet():
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
    with _quiet():
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
    dense = np.linspace(0.0, profile.duration, _DENSE_CHECK * len(profile.sd) + 1)
    _, qd, qdd = profile.sample(dense)
    speed = np.max(np.abs(qd) / velocity)
    accel = np.max(np.abs(qdd) / acceleration)
    return max(1.0, float(speed), math.sqrt(accel)) * (1.0 + _MARGIN)


def _toppra_pieces(robot: Robot, motion: Motion) -> list[Move]:
    """Time-optimal pieces of the spline path, split at waypoints with a dwell."""
    from hdselect.motion.planning.constraints import SecondOrderBounds, path_torque_coefficients

    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    assert velocity is not None and acceleration is not None  # load_motion requires them
    kinematic = kinematic_constraints(velocity, acceleration)
    moves: list[Move] = []
    for piece in path_pieces(robot, motion):
        first, last = piece.first, piece.last
        if piece.path is None:
            moves.append(Move(first, last, 0.0, None))
            continue
        dynamic = []
        if motion.torque_limit is not None:
            a, b, c = path_torque_coefficients(robot, piece.q, piece.dq, piece.ddq)
            dynamic.append(SecondOrderBounds.two_sided(piece.gridpoints, a, b, c,
                                                       -motion.torque_limit, motion.torque_limit))
        found = solve_piece(piece, kinematic + dynamic, where=str(motion.path))
        if found is None and dynamic:
            if solve_piece(piece, kinematic, where=str(motion.path)) is not None:
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
            scale = overshoot_scale(found, velocity, acceleration)
            duration = found.duration * scale
            if not (math.isfinite(duration) and duration > 0.0 and np.all(np.isfinite(found.sd))):
                raise ArithmeticError(f"duration {duration!r} s")
        except (ValueError, ArithmeticError) as err:
            raise PlanningError(f"{motion.path}: toppra: the path from waypoint[{first}] to "
                                f"waypoint[{last}] cannot be timed with these limits "
                                f"({type(err).__name__}: {err})") from err
        assert piece.knots is not None  # every piece with a path has its knots
        reached = found.time_at(piece.knots) * scale
        passes = tuple(float(reached[max(k for k, w in enumerate(piece.waypoints) if w <= i)])
                       for i in range(first, last + 1))
        moves.append(Move(first, last, duration, partial(found.sample, scale=scale),
                          found.peak_accelerations(scale), found.time_step * scale,
                          passes=passes))
    return moves
