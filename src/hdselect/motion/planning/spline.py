"""The geometric path through a motion's waypoints that TOPPRA times.

The path is split where the arm dwells: each piece runs from rest to rest. A piece passes
through its waypoints and, on a straight line, through the line's joint samples
(`Motion.lines`); repeated consecutive points are dropped. It is a clamped cubic spline
over a path position s from 0 to 1 (`SplinePath`), with knots at the cumulative chord
length (the TOPPRA planner's) or at the cumulative time each step takes at given joint
speeds (co-design's knots for a ruckig motion).

The TOPPRA planner (`hdselect.motion.planning.toppra.path_pieces`) and the check of
straight lines (`hdselect.motion.planning.solve`) build the same spline from here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hdselect.motion.motionfile import Motion

LIMIT_CHECK_POINTS = 200
"""Points per knot at which a spline is checked against the position limits."""


@dataclass(frozen=True, eq=False)
class PieceGeometry:
    """The points one piece of the path passes through, and where.

    Attributes:
        first: The waypoint it starts from.
        last: The waypoint it ends at (the next with a dwell, or the last).
        points: The joint positions passed through, in order [rad or m], shape (n, dof).
        knots: The path position s of each point, from 0 to 1 [-], shape (n,); empty
            when the piece has zero length.
        waypoints: The waypoints passed through, in order (repeats dropped).
        waypoint_knots: The path position of each of those, shape (len(waypoints),).
        line_knots: For each line of the piece (by the waypoint it ends at), the path
            position of its start, its samples and its end.
        line_samples: Line samples among the points (neither a waypoint).
    """

    first: int
    last: int
    points: np.ndarray
    knots: np.ndarray
    waypoints: tuple[int, ...]
    waypoint_knots: np.ndarray
    line_knots: Mapping[int, np.ndarray]
    line_samples: int


def piece_bounds(motion: Motion) -> list[tuple[int, int]]:
    """The first and last waypoint of every piece: split at each interior dwell."""
    splits = [0, *np.flatnonzero(motion.dwells[1:-1] > 0.0) + 1, len(motion.waypoints) - 1]
    return list(zip(splits[:-1], splits[1:], strict=True))


def piece_geometry(motion: Motion, first: int, last: int,
                   speeds: np.ndarray | None = None) -> PieceGeometry:
    """The points of the piece from waypoint `first` to `last` and their knots.

    Args:
        motion: The motion (solved: no NaN waypoint).
        first: The piece's first waypoint.
        last: Its last waypoint.
        speeds: Joint speeds that set the knots [rad/s or m/s], shape (dof,); None for
            chord length.
    """
    lines = {line.last: line for line in motion.lines}
    points: list[np.ndarray] = []
    owner: list[tuple[int, int]] = []  # (waypoint, -1) or (line's last waypoint, sample)
    for i in range(first, last + 1):
        if i > first and i in lines:
            for k, q in enumerate(lines[i].interior):
                points.append(q)
                owner.append((i, k))
        points.append(motion.waypoints[i])
        owner.append((i, -1))
    stacked = np.array(points)
    keep = np.r_[True, np.any(np.diff(stacked, axis=0) != 0.0, axis=1)]
    stacked = stacked[keep]
    owner = [o for o, kept in zip(owner, keep, strict=True) if kept]
    waypoints = tuple(i for i, k in owner if k < 0)
    if len(stacked) < 2:
        return PieceGeometry(first, last, stacked, np.zeros(0), waypoints, np.zeros(0), {}, 0)
    steps = np.diff(stacked, axis=0)
    lengths = (np.linalg.norm(steps, axis=1) if speeds is None
               else np.max(np.abs(steps) / speeds, axis=1))
    chord = np.r_[0.0, np.cumsum(lengths)]
    knots = chord / chord[-1]
    at_waypoint = {i: knots[n] for n, (i, k) in enumerate(owner) if k < 0}
    line_knots = {}
    for end in (i for i in range(first + 1, last + 1) if i in lines):
        inner = [knots[n] for n, (i, k) in enumerate(owner) if i == end and k >= 0]
        if end - 1 in at_waypoint and end in at_waypoint:
            line_knots[end] = np.array([at_waypoint[end - 1], *inner, at_waypoint[end]])
    return PieceGeometry(first, last, stacked, knots, waypoints,
                         np.array([at_waypoint[i] for i in waypoints]), line_knots,
                         sum(1 for _, k in owner if k >= 0))


class SplinePath:
    """A path through points, as TOPPRA evaluates it: q(s) and its derivatives.

    Each joint follows the clamped cubic spline through its points unless that spline
    leaves the joint's position limits; then it follows a monotone piecewise cubic
    (PCHIP's slopes inside, zero slope at both ends), which stays between neighbouring
    points.

    Args:
        ss: Path position of each point, increasing from 0 to 1 [-].
        points: The points [rad or m], shape (n, dof).
        lower: Lower position limits [rad or m], shape (dof,).
        upper: Upper position limits [rad or m], shape (dof,).
    """

    def __init__(self, ss: np.ndarray, points: np.ndarray, lower: np.ndarray,
                 upper: np.ndarray):
        from scipy.interpolate import CubicHermiteSpline, CubicSpline, PchipInterpolator

        spline = CubicSpline(ss, points, bc_type="clamped")
        dense = spline(np.linspace(ss[0], ss[-1], LIMIT_CHECK_POINTS * len(ss) + 1))
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
        """Path parameters and positions of the points."""
        return self._ss, self._points
