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
        for first, last in _moving_stretches(q[:, j]):
            lo, hi = np.searchsorted(at, [t[first], t[last]], side="left")
            hi = int(np.searchsorted(at, t[last], side="right"))
            if hi <= lo:
                continue
            clamped = (first > 0, last < len(t) - 1)  # a rest on that side
            spline = _stretch_spline(t[first:last + 1], q[first:last + 1, j], clamped)
            with np.errstate(all="ignore"):  # `plan` refuses a result that is not finite
                qd[lo:hi, j] = spline(at[lo:hi], 1)
                qdd[lo:hi, j] = spline(at[lo:hi], 2)
    qd[~inside] = 0.0
    qdd[~inside] = 0.0
    return qd, qdd


REST_RUN = 3
"""Equal positions in a row that make a joint at rest in a positions-only log [-]."""


def _moving_stretches(q: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) log index of each stretch where a joint moves, bounding rests included.

    A sample is at rest when it begins or continues a run of at least `REST_RUN` equal
    positions; a moving stretch runs from the last rest sample before it to the first
    after it (or the log's ends).
    """
    same = np.r_[False, q[1:] == q[:-1]]  # equal to the sample before
    starts = np.flatnonzero(np.diff(np.r_[0, same.astype(np.int8), 0]) == 1)  # run of equals
    ends = np.flatnonzero(np.diff(np.r_[0, same.astype(np.int8), 0]) == -1)
    rest = np.zeros(len(q), dtype=bool)
    for a, b in zip(starts, ends, strict=True):  # samples a-1 .. b-1 are equal
        if b - a + 1 >= REST_RUN:
            rest[a - 1:b] = True
    moving = np.flatnonzero(~rest)
    if not moving.size:
        return []
    breaks = np.flatnonzero(np.diff(moving) > 1)
    out = []
    for first, last in zip(np.r_[moving[0], moving[breaks + 1]],
                           np.r_[moving[breaks], moving[-1]], strict=True):
        out.append((max(int(first) - 1, 0), min(int(last) + 1, len(q) - 1)))
    return out


def _stretch_spline(t: np.ndarray, q: np.ndarray, clamped: tuple[bool, bool]):
    """The cubic spline of one moving stretch: zero velocity at an end that meets a rest."""
    from scipy.interpolate import CubicSpline

    if len(t) < 4 and not all(clamped):
        return CubicSpline(t, q, bc_type="natural")
    ends = tuple((1, 0.0) if rest else "not-a-knot" for rest in clamped)
    return CubicSpline(t, q, bc_type=ends)


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
