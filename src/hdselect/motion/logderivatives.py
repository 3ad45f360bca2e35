"""Velocities and accelerations of a log that gives positions only, and how sure they are.

A joint rests where its logged position repeats (`REST_RUN` equal values in a row):
velocity and acceleration are exactly 0 there. Where it moves, between two rests, the
cubic spline through the samples with zero velocity at both ends (it starts and ends at
rest; its acceleration is free there, as a planner's may step at a start) gives them.
A spline through the whole log instead rings into the rests (a speed at rest that is
not zero, which flips the efficiency rule) and overshoots where an acceleration steps.

Positions do not fix accelerations that step (TOPPRA's) or bend between samples; how
far they are known is estimated by deriving them again from every other sample
(`acceleration_uncertainty`), and a motion file reading such a log says so.
"""

from __future__ import annotations

import numpy as np

CHUNK = 1 << 16
"""Grid points evaluated from one spline at a time [-]."""
MARGIN = 64
"""Log samples on either side of a chunk that its spline passes through [-]."""
UNCERTAIN = 0.01
"""Estimated acceleration error, as a fraction of a joint's peak, above which a motion file
reading the log warns and asks for the log's own qd and qdd columns [-]."""


def from_positions(t: np.ndarray, q: np.ndarray, at: np.ndarray,
                   inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocities and accelerations of a log of positions only, at the grid times `at`.

    Each joint's log is split into stretches where it rests (`REST_RUN` or more equal
    positions in a row: velocity and acceleration exactly 0 there) and stretches where
    it moves. A moving stretch between two rests is the cubic spline through its
    samples with zero velocity at both ends (it starts and ends at rest; its
    acceleration is free there, as a planner's may step at a start); a stretch at the
    log's start or end is not-a-knot on that side. A spline through the whole log
    instead rings into the rests (a speed at rest that is not zero) and overshoots
    where the acceleration steps at a start.

    Args:
        t: The log's times from its start [s], shape (m,).
        q: The logged positions [rad or m], shape (m, dof).
        at: Grid times [s], shape (n,), clipped to the log's end.
        inside: Grid times within the log, shape (n,); beyond it, at rest.

    Returns:
        qd and qdd [per s, per s^2], each shape (n, dof).
    """
    qd, qdd = np.zeros((len(at), q.shape[1])), np.zeros((len(at), q.shape[1]))
    for j in range(q.shape[1]):
        stretches, rest = _moving_stretches(q[:, j])
        for first, last in stretches:
            lo, hi = np.searchsorted(at, [t[first], t[last]], side="left")
            hi = int(np.searchsorted(at, t[last], side="right"))
            if hi <= lo:
                continue
            clamped = (bool(rest[first]), bool(rest[last]))  # a rest on that side
            part = slice(first, last + 1)
            for order, out in ((1, qd), (2, qdd)):
                out[lo:hi, j] = spline_values(t[part], q[part, j], at[lo:hi], order,
                                              clamped=clamped)
    qd[~inside] = 0.0
    qdd[~inside] = 0.0
    return qd, qdd


REST_RUN = 3
"""Equal positions in a row that make a joint at rest in a positions-only log [-]."""


def _moving_stretches(q: np.ndarray) -> tuple[list[tuple[int, int]], np.ndarray]:
    """(first, last) log index of each stretch where a joint moves, and which samples rest.

    A sample rests when it is one of a run of at least `REST_RUN` equal positions. The
    interval between two samples is still when both rest at the same position, else
    moving; a stretch is a run of moving intervals, from its first sample to its last.
    """
    equal = q[1:] == q[:-1]
    rest = np.zeros(len(q), dtype=bool)
    edges = np.diff(np.r_[0, equal.astype(np.int8), 0])
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        if b - a + 1 >= REST_RUN:  # intervals a .. b-1 equal: samples a .. b
            rest[a:b + 1] = True
    moving = ~(equal & rest[:-1] & rest[1:])
    edges = np.diff(np.r_[0, moving.astype(np.int8), 0])
    return [(int(a), int(b)) for a, b in zip(np.flatnonzero(edges == 1),
                                             np.flatnonzero(edges == -1), strict=True)], rest


def spline_values(t: np.ndarray, values: np.ndarray, at: np.ndarray, order: int, *,
                  clamped: tuple[bool, bool] = (False, False)) -> np.ndarray:
    """The cubic spline through (t, values), or a derivative, evaluated at `at`.

    Not-a-knot at each end, or zero first derivative at an end that is `clamped`.
    Evaluated `CHUNK` points at a time, each from a spline through the log samples
    that chunk spans plus `MARGIN` on either side: a cubic spline's dependence on a
    distant sample decays by 2 - sqrt(3) = 0.27 per knot, so beyond 64 knots it is
    below 1e-36 of the values and the result equals the spline through the whole log
    to rounding, in memory bounded by the chunk.
    """
    from scipy.interpolate import CubicSpline

    out = np.empty((len(at),) + values.shape[1:])
    for start in range(0, len(at), CHUNK):
        part = slice(start, start + CHUNK)
        first, last = np.searchsorted(t, [at[part][0], at[part][-1]])
        lo, hi = max(0, int(first) - MARGIN), min(len(t), int(last) + MARGIN + 1)
        ends = tuple((1, 0.0) if rest and edge else "not-a-knot"
                     for rest, edge in zip(clamped, (lo == 0, hi == len(t)), strict=True))
        if hi - lo < 4 and "not-a-knot" in ends and ends != ("not-a-knot", "not-a-knot"):
            ends = tuple("natural" if end == "not-a-knot" else end for end in ends)
        with np.errstate(all="ignore"):  # `plan` refuses a result that is not finite
            out[part] = CubicSpline(t[lo:hi], values[lo:hi], axis=0, bc_type=ends)(at[part],
                                                                                  order)
    return out


def acceleration_uncertainty(t: np.ndarray, q: np.ndarray) -> np.ndarray:
    """How far each joint's acceleration derived from positions may be off [-].

    The accelerations at the log's samples derived from every sample and from every
    other sample differ by about three times the error of the first where the motion
    is smooth between samples (the spline's error falls as the period squared), and
    by the step itself where the acceleration steps: a third of the largest
    difference, as a fraction of the joint's peak acceleration, estimates the error.

    Args:
        t: The log's times [s], shape (m,).
        q: The logged positions [rad or m], shape (m, dof).

    Returns:
        Per joint, the estimated largest error over its peak |acceleration| [-]; 0 for a
        joint that does not move.
    """
    inside = np.ones(len(t), dtype=bool)
    _, full = from_positions(t, q, t, inside)
    _, half = from_positions(t[::2], q[::2], t, inside & (t <= t[::2][-1]))
    peak = np.abs(full).max(axis=0)
    covered = t <= t[::2][-1]
    gap = np.abs(full - half)[covered].max(axis=0) / 3.0 if covered.any() else 0.0 * peak
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(peak > 0.0, gap / peak, 0.0)
