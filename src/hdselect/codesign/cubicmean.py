"""Where a cubic mean of affine torques stays under a bound: exactly, from sorted sums.

Along a fixed trajectory a joint's torque is affine in the payload mass m,
tau_i(m) = c0_i + m c1_i, and the catalog's mean torque is the cubic mean
T_av(m) = (sum_i w_i |tau_i(m)|^3 / sum_i w_i)^(1/3). Each sample with c1_i != 0
vanishes at b_i = -c0_i / c1_i, and |tau_i(m)|^3 = |c1_i|^3 |m - b_i|^3, so

    F(m) = sum_i w_i |tau_i(m)|^3 = K + sum_i W_i |m - b_i|^3,   W_i = w_i |c1_i|^3,

K the samples that do not depend on m. Between two consecutive b_i every sign is
fixed and F is a cubic, whose coefficients are prefix sums of W b^p (p = 0..3) over
the sorted b: one sort per joint (`CubicMean`), after which the interval where
T_av(m) <= T for any bound T (each unit's allowance, its life torque) costs a binary
search and a cubic's root (`CubicMean.at_most`), not a pass over the samples per
bisection step. F is convex, so that set is an interval. Runs of identical samples
are merged first (their weights added). Each end found is checked on the samples
themselves and moved inward by rounding steps where it is just outside.
"""

from __future__ import annotations

import math

import numpy as np

Interval = tuple[float, float]
"""A closed interval of payload masses (lo, hi) [kg]."""

_NUDGES = 64
"""Most rounding steps an end is moved inward to lie inside on the samples themselves."""


class CubicMean:
    """sum_i w_i |c0_i + m c1_i|^3 as a piecewise cubic in m, ready for any bound.

    Args:
        c0: Torque without payload per sample [N m], shape (n,).
        c1: Torque per kg of payload per sample [N m/kg], shape (n,).
        weight: Weight w of each sample (|qd| dt over moving samples; 0 elsewhere), (n,).
    """

    def __init__(self, c0: np.ndarray, c1: np.ndarray, weight: np.ndarray) -> None:
        keep = weight > 0.0
        total = float(weight.sum())
        c0, c1, w = c0[keep], c1[keep], weight[keep] / total if total > 0.0 else weight[keep]
        if len(c0) > 1:  # a run of identical samples counts once, with its weights added
            start = np.r_[True, (c0[1:] != c0[:-1]) | (c1[1:] != c1[:-1])]
            if np.count_nonzero(~start) * 8 > len(c0):
                runs = np.flatnonzero(start)
                c0, c1, w = c0[runs], c1[runs], np.add.reduceat(w, runs)
        self._c0, self._c1, self._w = c0, c1, w
        flat = c1 == 0.0
        self.constant = float(np.einsum("i,i->", w[flat], np.abs(c0[flat]) ** 3))
        self.depends = bool(np.any(~flat))
        b = -c0[~flat] / c1[~flat]
        order = np.argsort(b, kind="stable")
        self.b = b[order]
        weights = (w[~flat] * np.abs(c1[~flat]) ** 3)[order]
        # prefix sums S_p[k] = sum_{i<k} W_i b_i^p, p = 0..3, and the signed sums P_p of
        # segment k (the samples below it counted +, those above -): P_p = 2 S_p[k] - T_p
        powers = np.vstack([weights * self.b**p for p in range(4)])
        prefix = np.concatenate([np.zeros((4, 1)), np.cumsum(powers, axis=1)], axis=1)
        self._p = 2.0 * prefix - prefix[:, -1:]
        # F at every b_k (segment k + 1 holds b_k at its lower end)
        self._f_at_b = self._cubic(np.arange(1, len(self.b) + 1), self.b)

    def value(self, m: float) -> float:
        """F(m) on the samples themselves [N^3 m^3]."""
        torque = self._c1 * m
        torque += self._c0
        np.abs(torque, out=torque)
        # einsum, not np.dot: a threaded BLAS dot waits for a busy core (27x slower here)
        return float(np.einsum("i,i->", self._w, torque * torque * torque))

    def at_most(self, bound: float) -> Interval | None:
        """The masses m where the cubic mean is at most `bound` [N m]: an interval, or None."""
        level = bound**3
        if not self.depends:
            return (-math.inf, math.inf) if self.value(0.0) <= level else None
        k, centre = self._minimum()
        if self._cubic(k, centre) > level and self.value(centre) > level:
            return None
        right = self._root(level, centre, rising=True)
        left = self._root(level, centre, rising=False)
        return (self._inside(left, level, +1.0), self._inside(right, level, -1.0))

    def _cubic(self, k: np.ndarray | int, m: np.ndarray | float) -> np.ndarray | float:
        """F(m) by segment k's cubic (the b below it counted +)."""
        p0, p1, p2, p3 = self._p[:, k]
        return self.constant + ((p0 * m - 3.0 * p1) * m + 3.0 * p2) * m - p3

    def _slope(self, k: int, m: float) -> float:
        """F'(m) / 3 by segment k's quadratic."""
        p0, p1, p2, _ = self._p[:, k]
        return float((p0 * m - 2.0 * p1) * m + p2)

    def _minimum(self) -> tuple[int, float]:
        """The segment of F's minimum and the mass m at it (F' = 0)."""
        p = self._p
        b = self.b
        slopes = (p[0, 1:] * b - 2.0 * p[1, 1:]) * b + p[2, 1:]  # F'/3 at every b_k
        k = int(np.searchsorted(slopes, 0.0))  # F' rises: the first b_k with F' >= 0
        lo = b[k - 1] if k > 0 else -math.inf
        hi = b[k] if k < len(b) else math.inf
        return k, self._solve(lambda m: self._slope(k, m), lo, hi, 0.0)

    def _root(self, level: float, centre: float, *, rising: bool) -> float:
        """Where F crosses `level` on the rising (right) or falling (left) side of `centre`."""
        b, f = self.b, self._f_at_b
        if rising:
            above = np.flatnonzero((b > centre) & (f > level))
            k = int(above[0]) if len(above) else len(b)  # the root lies in segment k
            lo = max(centre, b[k - 1]) if k > 0 else centre
            hi = b[k] if k < len(b) else math.inf
        else:
            above = np.flatnonzero((b < centre) & (f > level))
            k = int(above[-1]) + 1 if len(above) else 0
            lo = b[k - 1] if k > 0 else -math.inf
            hi = min(centre, b[k]) if k < len(b) else centre
        return self._solve(lambda m: float(self._cubic(k, m)), lo, hi, level,
                           falling=not rising)

    @staticmethod
    def _solve(function, lo: float, hi: float, target: float, *, falling: bool = False) -> float:
        """Where a monotone `function` meets `target` in [lo, hi] (ends may be infinite).

        Rising (or, with `falling`, falling) in m; the end returned, to machine
        precision, is the one where ``function <= target`` (for the slope of a minimum,
        the last m before it rises).
        """
        def above(m: float) -> bool:
            return (function(m) > target) != falling

        if not math.isfinite(hi):  # grow a finite bracket
            step = max(1.0, abs(lo) if math.isfinite(lo) else 1.0)
            hi = (lo if math.isfinite(lo) else 0.0) + step
            while not above(hi):
                step *= 2.0
                hi += step
        if not math.isfinite(lo):
            step = max(1.0, abs(hi))
            lo = hi - step
            while above(lo):
                step *= 2.0
                lo -= step
        for _ in range(200):
            middle = 0.5 * (lo + hi)
            if middle in (lo, hi):
                break
            if above(middle):
                hi = middle
            else:
                lo = middle
        return hi if falling else lo

    def _inside(self, m: float, level: float, direction: float) -> float:
        """`m`, or the nearest float inward (to `direction`) where F <= level on the samples.

        The cubic's root is off by the rounding of its sums (a few parts in 1e16 of the
        largest term): it is first moved inward by what that rounding can shift it, then
        checked on the samples, the step doubling while it is not inside.
        """
        k = int(np.searchsorted(self.b, m))
        slope = 3.0 * abs(self._slope(k, m))
        terms = float(np.sum(np.abs(self._p[:, k]) * np.abs(m) ** np.arange(3, -1, -1)))
        step = max(abs(m) * 1e-15, 1e-300, 64.0 * np.finfo(float).eps * (
            terms + self.constant) / slope if slope > 0.0 else 0.0)
        m += direction * step
        for _ in range(_NUDGES):
            if self.value(m) <= level:
                return m
            m += direction * step
            step *= 2.0
        return m
