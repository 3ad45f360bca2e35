"""The cubic mean's interval from sorted sums, against bisection on the samples themselves.

Oracle: F(m) = sum w |c0 + m c1|^3 evaluated directly, its interval's ends found by
plain bisection (F is convex: the minimum by ternary search, each end by bisection).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdselect.codesign.cubicmean import CubicMean


def direct(c0, c1, w, most):
    """The interval where (sum w |c0 + m c1|^3 / sum w)^(1/3) <= most, by bisection."""
    w = w / w.sum()

    def f(m):
        return float(np.dot(w, np.abs(c0 + m * c1) ** 3))

    lo, hi = -1e4, 1e4
    for _ in range(300):  # ternary search of the convex minimum
        a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        lo, hi = (lo, b) if f(a) <= f(b) else (a, hi)
    centre = 0.5 * (lo + hi)
    if f(centre) > most**3:
        return None

    def end(inside, outside):
        for _ in range(300):
            middle = 0.5 * (inside + outside)
            inside, outside = (middle, outside) if f(middle) <= most**3 else (inside, middle)
        return inside

    far = 1.0
    while f(centre + far) <= most**3 or f(centre - far) <= most**3:
        far *= 2.0
    return end(centre, centre - far), end(centre, centre + far)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(12))
def test_the_interval_equals_bisection_on_the_samples(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 400))
    c0 = rng.normal(0.0, 5.0, n)
    c1 = rng.normal(0.0, 2.0, n) * (rng.random(n) > 0.2)  # some samples do not depend on m
    w = rng.random(n) * (rng.random(n) > 0.3)
    if seed % 3 == 0:  # dwells: runs of identical samples
        c0, c1, w = np.repeat(c0, 7), np.repeat(c1, 7), np.repeat(w, 7)
    w[0] = max(w[0], 0.1)
    cubic = CubicMean(c0, c1, w)
    total = w / w.sum()
    minimum = min(float(np.dot(total, np.abs(c0 + m * c1) ** 3))
                  for m in np.linspace(-50, 50, 20001)) ** (1 / 3)
    for most in (0.5 * minimum, 1.0001 * minimum, 1.5 * minimum, 4.0 * minimum):
        found, expected = cubic.at_most(most), direct(c0, c1, w, most)
        if expected is None:
            assert found is None or found[1] - found[0] < 1e-6 * max(1.0, abs(found[0]))
            continue
        assert found is not None
        for got, want in zip(found, expected, strict=True):
            assert got == pytest.approx(want, rel=1e-9, abs=1e-9)
        for end in found:  # each end inside on the samples themselves (to their rounding)
            assert float(np.dot(total, np.abs(c0 + end * c1) ** 3)) <= most**3 * (1 + 1e-12)


def test_no_dependence_on_the_mass():
    c0 = np.array([1.0, -2.0, 3.0])
    cubic = CubicMean(c0, np.zeros(3), np.ones(3))
    mean = (np.mean(np.abs(c0) ** 3)) ** (1 / 3)
    assert cubic.at_most(mean * 1.01) == (-math.inf, math.inf)
    assert cubic.at_most(mean * 0.99) is None


def test_one_sample_is_the_peak():
    """One moving sample: |c0 + m c1| <= most, the interval by hand."""
    cubic = CubicMean(np.array([2.0]), np.array([0.5]), np.array([1.0]))
    lo, hi = cubic.at_most(3.0)  # -3 <= 2 + 0.5 m <= 3
    assert lo == pytest.approx(-10.0, rel=1e-12) and hi == pytest.approx(2.0, rel=1e-12)
