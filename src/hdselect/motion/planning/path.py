"""The path a TOPPRA motion follows, in pieces from rest to rest, at TOPPRA's gridpoints.

The path itself (a clamped cubic spline through the waypoints and a straight line's
joint samples, shape-preserving where a joint's spline would leave its limits) is
`hdselect.motion.planning.spline.SplinePath`; it is split where the arm dwells (`path_pieces`). A
`PathPiece` holds the path and its derivatives at TOPPRA's gridpoints, which
`with_gridpoints` changes.
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
from hdselect.motion.planning.spline import SplinePath, piece_bounds, piece_geometry
from hdselect.robot.model import Robot

GRID_PER_WAYPOINT = 200
"""TOPPRA gridpoints per waypoint of a piece by default (cosine-spaced, dense near the rest
ends) [-]."""

GRID_PER_LINE_SAMPLE = 8
"""TOPPRA gridpoints per joint sample of a straight line (its samples are close together)."""

SOLVE_GRID = 50
"""TOPPRA gridpoints per waypoint of a piece the planner solves first (cosine-spaced,
dense near the rest ends), before refining the steps that need it."""

MIN_SOLVE_GRIDPOINTS = 400
"""Fewest gridpoints a piece is first solved on (a short piece's cycle converges slower)."""


@dataclass(frozen=True, eq=False)
class PathPiece:
    """One piece of the path, from rest to rest, between two waypoints.

    Attributes:
        first: Index of the waypoint it starts from.
        last: Index of the waypoint it ends at (the next one with a dwell, or the last).
        path: The path over s in [0, 1] (`hdselect.motion.planning.spline.SplinePath`, toppra's path
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
    has no path (zero length). A straight line's joint samples are points of the path
    too. A joint whose spline would leave the robot's position limits follows a
    shape-preserving cubic instead (`hdselect.motion.planning.spline.SplinePath`). The knots are at
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
        grid = cosine_grid(count)
        with quiet():
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


def with_gridpoints(piece: PathPiece, gridpoints: np.ndarray) -> PathPiece:
    """The same piece of path on other TOPPRA gridpoints s [-], shape (m,)."""
    path = piece.path
    with quiet():
        q, dq, ddq = path(gridpoints), path(gridpoints, 1), path(gridpoints, 2)
    return replace(piece, gridpoints=frozen(gridpoints), q=frozen(q), dq=frozen(dq),
                   ddq=frozen(ddq))


def bends_sharply(piece: PathPiece) -> bool:
    """Whether TOPPRA needs the dense grid to time a piece's path.

    It does where the path has a shape-preserving joint (p'' steps at its knots) or a
    straight line's joint samples (close together).
    """
    knots, _ = piece.path.waypoints
    return bool(piece.path.shape_preserving) or len(knots) > len(piece.waypoints)


def dense_grid(piece: PathPiece) -> np.ndarray:
    """The planner's dense grid of a piece [-], as `path_pieces` lays it.

    `GRID_PER_WAYPOINT` cosine-spaced gridpoints per waypoint and `GRID_PER_LINE_SAMPLE`
    per line sample.
    """
    knots, _ = piece.path.waypoints
    waypoints = len(piece.waypoints)
    return cosine_grid(GRID_PER_WAYPOINT * waypoints
                       + GRID_PER_LINE_SAMPLE * (len(knots) - waypoints))


def first_grid(dense: PathPiece, *, full: bool = False) -> PathPiece:
    """The piece on the gridpoints TOPPRA solves it on first: coarse, and at every knot.

    The coarse grid has `SOLVE_GRID` cosine-spaced gridpoints per waypoint (a quarter of
    the dense grid's, line samples included; at least `MIN_SOLVE_GRIDPOINTS`). Every knot
    of the spline (waypoints and line samples) is a gridpoint too: p'' is linear between
    knots (and steps at a shape-preserving joint's knots), so a limit broken between
    gridpoints is broken by a margin that splitting the step removes. Without them, the
    sharp turn where a free move meets a line's close samples falls between gridpoints.

    Args:
        dense: A piece with a path, on the dense grid of `path_pieces`.
        full: Keep the dense grid's gridpoints (and add the knots) rather than a quarter.
    """
    steps = len(dense.gridpoints) - 1
    coarse = max(MIN_SOLVE_GRIDPOINTS, steps * SOLVE_GRID // GRID_PER_WAYPOINT)
    knots, _ = dense.path.waypoints
    grid = cosine_grid(steps if full else min(coarse, steps))
    return with_gridpoints(dense, np.union1d(grid, knots))


def cosine_grid(steps: int) -> np.ndarray:
    """`steps` + 1 cosine-spaced path positions from 0 to 1 [-] (as `path_pieces` spaces them)."""
    return 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, steps + 1))
