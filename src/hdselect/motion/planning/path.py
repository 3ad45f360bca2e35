"""The path a TOPPRA motion follows: a cubic spline through the waypoints, in pieces.

The path is a clamped cubic spline through the waypoints (chord-length
parametrised, or by the time each segment takes at given speeds), split where the
arm dwells, so that each piece starts and ends at rest. A joint whose spline would
leave its position limits follows a shape-preserving cubic instead (`_Path`). A
`PathPiece` holds the path and its derivatives at TOPPRA's gridpoints.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.errors import PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.robot.model import Robot

GRID_PER_WAYPOINT = 200
"""Points per waypoint at which a spline is checked against the position limits (`_Path`),
and the default TOPPRA gridpoints per waypoint of `path_pieces` [-]."""


@dataclass(frozen=True, eq=False)
class PathPiece:
    """One piece of the path, from rest to rest, between two waypoints.

    Attributes:
        first: Index of the waypoint it starts from.
        last: Index of the waypoint it ends at (the next one with a dwell, or the last).
        path: The path over s in [0, 1] (`_Path`, toppra's path interface), or None when
            the piece has zero length.
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


@contextmanager
def quiet() -> Iterator[None]:
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


def path_pieces(robot: Robot, motion: Motion, grid_per_waypoint: int = GRID_PER_WAYPOINT, *,
                speeds: np.ndarray | None = None) -> list[PathPiece]:
    """The motion's path split where it dwells: a clamped cubic spline per piece.

    Repeated consecutive waypoints are dropped; a piece whose waypoints all coincide
    has no path (zero length). A joint whose spline would leave the robot's position
    limits follows a shape-preserving cubic instead (`_Path`). The knots are at the
    cumulative chord length (the TOPPRA planner's path) or, given `speeds`, at the
    cumulative time each segment takes at those speeds, max_j |dq_j| / speed_j, which
    weighs joints in different units (rad, m) alike. Each piece gets
    ``grid_per_waypoint`` cosine-spaced gridpoints per waypoint.

    Args:
        robot: The robot (position limits).
        motion: The motion (waypoints and dwells).
        grid_per_waypoint: Gridpoints per waypoint of a piece.
        speeds: Joint speeds that set the knots [rad/s or m/s], shape (dof,); None for
            chord length.

    Returns:
        The pieces, in order.
    """
    splits = [0, *np.flatnonzero(motion.dwells[1:-1] > 0.0) + 1, len(motion.waypoints) - 1]
    pieces: list[PathPiece] = []
    for first, last in zip(splits[:-1], splits[1:], strict=True):
        points = motion.waypoints[first:last + 1]
        keep = np.r_[True, np.any(np.diff(points, axis=0) != 0.0, axis=1)]
        points = points[keep]
        indices = tuple(int(i) for i in first + np.flatnonzero(keep))
        if len(points) < 2:
            nothing = frozen(np.zeros((0, len(motion.joint_names))))
            pieces.append(PathPiece(first, last, None, frozen(np.zeros(0)), nothing, nothing,
                                    nothing, indices))
            continue
        steps = np.diff(points, axis=0)
        lengths = (np.linalg.norm(steps, axis=1) if speeds is None
                   else np.max(np.abs(steps) / speeds, axis=1))
        chord = np.r_[0.0, np.cumsum(lengths)]
        grid = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, grid_per_waypoint * len(points) + 1))
        with quiet():
            try:
                path = _Path(chord / chord[-1], points, robot.lower, robot.upper)
            except (ValueError, ArithmeticError) as err:
                raise PlanningError(f"{motion.path}: toppra: no spline through waypoint[{first}]"
                                    f" to waypoint[{last}]: {err}") from err
            q, dq, ddq = path(grid), path(grid, 1), path(grid, 2)
        pieces.append(PathPiece(first, last, path, frozen(grid), frozen(q), frozen(dq),
                                frozen(ddq), indices, frozen(chord / chord[-1])))
    return pieces


def with_gridpoints(piece: PathPiece, gridpoints: np.ndarray) -> PathPiece:
    """The same piece of path on other TOPPRA gridpoints s [-], shape (m,)."""
    path = piece.path
    with quiet():
        q, dq, ddq = path(gridpoints), path(gridpoints, 1), path(gridpoints, 2)
    return replace(piece, gridpoints=frozen(gridpoints), q=frozen(q), dq=frozen(dq),
                   ddq=frozen(ddq))


class _Path:
    """A geometric path through waypoints, as TOPPRA evaluates it: q(s) and its derivatives.

    Each joint follows the clamped cubic spline through its waypoints unless that
    spline leaves the joint's position limits; then it follows a monotone piecewise
    cubic (PCHIP's slopes inside, zero slope at both ends), which stays between
    neighbouring waypoints.

    Args:
        ss: Path parameter at each waypoint, increasing from 0 to 1 [-].
        points: Waypoints [rad or m], shape (k, dof).
        lower: Lower position limits [rad or m], shape (dof,).
        upper: Upper position limits [rad or m], shape (dof,).
    """

    def __init__(self, ss: np.ndarray, points: np.ndarray, lower: np.ndarray,
                 upper: np.ndarray):
        from scipy.interpolate import CubicHermiteSpline, CubicSpline, PchipInterpolator

        spline = CubicSpline(ss, points, bc_type="clamped")
        dense = spline(np.linspace(ss[0], ss[-1], GRID_PER_WAYPOINT * len(ss) + 1))
        leaves = np.any((dense < lower - 1e-12) | (dense > upper + 1e-12), axis=0)
        self.shape_preserving = tuple(int(j) for j in np.flatnonzero(leaves))
        if self.shape_preserving:
            slopes = PchipInterpolator(ss, points, axis=0).derivative()(ss)
            slopes[[0, -1]] = 0.0
            monotone = CubicHermiteSpline(ss, points, slopes, axis=0)
            spline.c[:, :, leaves] = monotone.c[:, :, leaves]
        self._splines = (spline, spline.derivative(), spline.derivative(2))
        self._ss, self._points = ss, points

    def __call__(self, path_positions, order: int = 0):
        """Positions (order 0) or their first or second derivative along the path."""
        return self._splines[order](path_positions)

    def eval(self, ss):  # noqa: D102  (TOPPRA's path interface)
        return self(ss, 0)

    def evald(self, ss):  # noqa: D102
        return self(ss, 1)

    def evaldd(self, ss):  # noqa: D102
        return self(ss, 2)

    @property
    def dof(self) -> int:
        """Degrees of freedom."""
        return int(self._points.shape[1])

    @property
    def path_interval(self) -> np.ndarray:
        """First and last path parameter."""
        return np.array([self._ss[0], self._ss[-1]])

    @property
    def waypoints(self):
        """Path parameters and positions of the waypoints."""
        return self._ss, self._points
