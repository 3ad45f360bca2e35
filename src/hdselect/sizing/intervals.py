"""Sets of time scales: per-sample quadratic inequalities in y = 1/s, solved and intersected.

Every rule on single samples of a cycle run s times slower is, per sample, a
quadratic inequality c2 y^2 + c1 y + c0 <= 0 in y = 1/s (`hdselect.sizing.timescale`).
Here each is solved exactly for y >= 0 (at most two closed pieces), the pieces of
every sample intersected by counting their ends, and two sorted interval lists
overlapped. Pure arithmetic: no rule, unit or robot.
"""

from __future__ import annotations

import math

import numpy as np

Interval = tuple[float, float]
"""A closed interval of time scales (lo, hi) [-]; hi may be math.inf."""


def solve_quadratics(c2: np.ndarray, c1: np.ndarray,
                     c0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where c2 y^2 + c1 y + c0 <= 0 for y >= 0: lo, hi of shape (2, rows).

    At most two disjoint closed pieces per row; a piece with lo > hi is empty.
    """
    flat, up = c2 == 0.0, c2 > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):  # an infinite limit: every y
        disc = c1 * c1 - 4.0 * c2 * c0
        line = -c0 / c1
        q = -0.5 * (c1 + np.copysign(np.sqrt(np.maximum(disc, 0.0)), c1))
        r1, r2 = q / c2, np.where(q != 0.0, c0 / q, 0.0)  # stable roots
    small, big = np.minimum(r1, r2), np.maximum(r1, r2)
    free = np.isneginf(c0)  # no limit
    cap = ~free & ~flat & ~up & (disc > 0.0) & (small < big)  # outside the roots
    every = free | (flat & (c1 == 0.0) & (c0 <= 0.0)) | (~flat & ~up & ~cap)
    below = flat & (c1 > 0.0)  # y <= -c0 / c1
    above = flat & (c1 < 0.0)  # y >= -c0 / c1
    cup = up & (disc >= 0.0)  # between the roots
    lo = np.stack([np.select([every | below, above, cup, cap], [0.0, line, small, 0.0], np.inf),
                   np.where(cap, big, np.inf)])
    hi = np.stack([np.select([every | above, below, cup, cap], [np.inf, line, big, small],
                             -np.inf), np.where(cap, np.inf, -np.inf)])
    return np.maximum(lo, 0.0), hi


def intersect(lo: np.ndarray, hi: np.ndarray) -> list[Interval]:
    """Where every row covers y, by counting the pieces over the sorted ends."""
    keep = ~((lo[0] <= 0.0) & (hi[0] == np.inf))  # rows that hold everywhere drop out
    lo, hi = lo[:, keep], hi[:, keep]
    rows = lo.shape[1]
    piece = lo <= hi
    if not piece.any(axis=0).all():
        return []  # a row holds nowhere
    if rows == 0:
        return [(0.0, math.inf)]
    where = np.concatenate([lo[piece], hi[piece]])
    step = np.repeat([1, -1], piece.sum())
    order = np.lexsort((-step, where))  # on a tie starts come first: closed ends meet
    where = where[order]
    full = np.flatnonzero(np.cumsum(step[order]) == rows)  # the next end closes each
    return [(float(where[k]), float(where[k + 1])) for k in full]


def overlap(a: list[Interval], b: list[Interval]) -> list[Interval]:
    """The intersection of two sorted lists of disjoint closed intervals."""
    out: list[Interval] = []
    i = j = 0
    while i < len(a) and j < len(b):
        lo, hi = max(a[i][0], b[j][0]), min(a[i][1], b[j][1])
        if lo <= hi:
            out.append((lo, hi))
        if a[i][1] < b[j][1]:
            i += 1
        else:
            j += 1
    return out
