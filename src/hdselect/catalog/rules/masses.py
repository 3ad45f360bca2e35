"""Intervals of payload mass: the arithmetic of the rules' payload form.

With the torques affine in the payload mass x, tau = tau0 + x tau1 per sample, a limit
on |tau| at every sample holds on one closed interval of x (`masses_within`); a rule's
form gives its masses as sorted disjoint intervals (`Rule.payload_masses`), and a unit's
masses are where every rule's meet (`meet`, `meet_all`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hdselect.catalog.rules.forms import Interval

EVERY_MASS: tuple[Interval, ...] = ((-math.inf, math.inf),)
"""A rule that holds at every mass (or is absent for the case) [kg]."""


def masses_within(c0: np.ndarray, c1: np.ndarray,
                  limit: np.ndarray | float) -> Interval | None:
    """Where |c0 + x c1| <= limit at every sample: an interval of x, or None.

    Args:
        c0: The value at x = 0 per sample [N m], (n,).
        c1: Its change per unit of x [N m], (n,).
        limit: The limit [N m], a number or (n,).
    """
    limit = np.broadcast_to(np.asarray(limit, dtype=float), np.shape(c0))
    if np.shape(c0)[0] == 0:
        return (-math.inf, math.inf)
    if np.any(limit < 0.0):
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (-limit - c0) / c1, (limit - c0) / c1
    flat = c1 == 0.0
    if np.any(flat & (np.abs(c0) > limit)):
        return None
    lo = np.where(flat, -np.inf, np.minimum(a, b))
    hi = np.where(flat, np.inf, np.maximum(a, b))
    low, high = float(lo.max()), float(hi.min())
    return (low, high) if low <= high else None


def meet(a: Interval | None, b: Interval | None) -> Interval | None:
    """The intersection of two closed intervals, or None where they do not overlap."""
    if a is None or b is None:
        return None
    lo, hi = max(a[0], b[0]), min(a[1], b[1])
    return (lo, hi) if lo <= hi else None


def spans(found: Interval | None) -> tuple[Interval, ...]:
    """One interval (or None: no mass) as a form's sorted disjoint intervals."""
    return () if found is None else (found,)


def meet_all(a: Sequence[Interval], b: Sequence[Interval]) -> tuple[Interval, ...]:
    """The intersection of two sorted lists of disjoint closed intervals."""
    return tuple(sorted(span for x in a for y in b for span in [meet(x, y)]
                        if span is not None))
