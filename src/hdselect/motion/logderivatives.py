"""Velocities and accelerations of a log that gives positions only, and how sure they are.

A joint rests where its logged position repeats (`REST_RUN` equal values in a row, and
in a quantised log for long enough: `REST_SHARE`): velocity and acceleration are 0
there. Where it moves, between two rests, the cubic spline with zero velocity at both
ends (it starts and ends at rest; its acceleration is free there, as a planner's may
step at a start) gives them.
A spline through the whole log instead rings into the rests (a speed at rest that is
not zero, which flips the efficiency rule) and overshoots where an acceleration steps.

Positions do not fix accelerations that step (TOPPRA's) or bend between samples, and
an encoder's quantisation (or any noise) is amplified as 1 / period^2. Each joint's
spline passes through every k-th sample of each moving stretch, k = 1, 2, 4, ...,
whichever k states the smallest uncertainty there (`derivatives`): the difference
from the spline through every 2k-th sample (three times the error where the motion is
smooth, the error itself at a kink or a step), plus the most the log's noise can move
the spline (`NOISE_GAIN`, the noise measured from the log's sixth differences). The
sizing turns that into an uncertainty of each joint's peak torque and states it where
it exceeds 1 %.
"""

from __future__ import annotations

import math

import numpy as np

CHUNK = 1 << 16
"""Grid points evaluated from one spline at a time [-]."""
MARGIN = 64
"""Log samples on either side of a chunk that its spline passes through [-]."""
MAX_STEP = 64
"""Largest k: the spline passes through at least every 64th sample [-]."""
NOISE_GAIN = 18.0
"""Most a cubic spline's second derivative moves, anywhere, per unit of every sample's
error on a grid of period 1: the largest sum of |weights| (12 between the ends of a
not-a-knot spline, 17.9 at an end) [-]."""
NOISE_FACTOR = math.sqrt(3.0)
"""Largest error of a sample per standard deviation of the log's noise: a quantisation
step's half over its standard deviation [-]."""
MEDIAN_NORMAL = 0.6745
"""Median of |N(0, 1)|: the deviation of normal noise from a median of absolute values [-]."""


def derivatives(t: np.ndarray, q: np.ndarray, at: np.ndarray,
                inside: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocities, accelerations and how far the accelerations may be off, at `at`.

    Each joint's log is split into stretches where it rests (`REST_RUN` or more equal
    positions in a row: velocity and acceleration exactly 0 there) and stretches where
    it moves. A moving stretch between two rests is the cubic spline through every k-th
    of its samples (its first and last always) with zero velocity at both ends; a
    stretch at the log's start or end is not-a-knot on that side. Per stretch, k is the
    one of 1, 2, 4, ... `MAX_STEP` that states the smallest uncertainty of its peak
    |acceleration| (module docstring). A stretch too short to check (fewer than 4
    samples through every 2k-th) is uncertain by its whole acceleration; a rest of
    duration D by the 8 x quantisation step / D^2 an acceleration could hide in it.

    Args:
        t: The log's times from its start [s], shape (m,).
        q: The logged positions [rad or m], shape (m, dof).
        at: Grid times [s], shape (n,), clipped to the log's end.
        inside: Grid times within the log, shape (n,); beyond it, at rest.

    Returns:
        qd, qdd and the uncertainty of qdd [per s, per s^2, per s^2], each (n, dof).
    """
    qd, qdd, spread = (np.zeros((len(at), q.shape[1])) for _ in range(3))
    for j in range(q.shape[1]):
        split = _moving_stretches(q[:, j], t)
        noise = noise_level(q[:, j], split[0], t)
        split = _steps_at_rest(split, q[:, j], noise)
        done: dict[tuple[int, int, bool, bool], tuple[np.ndarray, ...]] = {}
        for _ in range(REST_ROUNDS):
            qd[:, j], qdd[:, j], spread[:, j] = _joint(t, q[:, j], at, split, noise, done)
            peak = max((float(np.abs(qdd[slice(*_grid(at, t, first, last)), j]).max(initial=0.0))
                        for first, last in split[0] if last - first >= 6), default=0.0)
            if noise == 0.0 or peak == 0.0:
                break
            shortest = math.sqrt(16.0 * NOISE_FACTOR * noise / (REST_SHARE * peak))
            again = _steps_at_rest(_moving_stretches(q[:, j], t, shortest), q[:, j], noise)
            if again[2] == split[2]:
                break
            split = again
    for array in (qd, qdd, spread):
        array[~inside] = 0.0
    return qd, qdd, spread


REST_SHARE = 0.01
"""Largest acceleration, as a fraction of the joint's peak (over the stretches long enough
to check), that a rest may hide within one quantisation step of a noisy log [-]: a
shorter run of equal positions is a crawl, part of the stretch around it."""
REST_ROUNDS = 8
"""Times the rests of a noisy log are judged again against the peak they yield [-]."""

Split = tuple[list[tuple[int, int]], np.ndarray, list[tuple[int, int]]]
"""A joint's moving stretches, which samples rest, and the rests: (first, last) indices."""


def _joint(t: np.ndarray, q: np.ndarray, at: np.ndarray, split: Split, noise: float,
           done: dict[tuple[int, int, bool, bool], tuple[np.ndarray, ...]],
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One joint's qd, qdd and qdd's uncertainty at `at` [per s, per s^2, per s^2].

    `done` keeps each stretch's result for the next round of rests: most stay the same.
    """
    stretches, rest, runs = split
    qd, qdd, spread = np.zeros(len(at)), np.zeros(len(at)), _rest_spread(t, at, runs, noise)
    for first, last in stretches:
        lo, hi = _grid(at, t, first, last)
        if hi > lo:
            part, key = slice(lo, hi), (first, last, bool(rest[first]), bool(rest[last]))
            if key not in done:
                done[key] = _stretch(t, q, at[part], first, last, key[2:], noise)
            qd[part], qdd[part], error = done[key]
            spread[part] = np.maximum(spread[part], error)
    return qd, qdd, spread


def _stretch(t: np.ndarray, q: np.ndarray, at: np.ndarray, first: int, last: int,
             clamped: tuple[bool, bool],
             noise: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One moving stretch's qd, qdd and qdd's uncertainty at `at`, through every k-th sample.

    k is the one of 1, 2, 4, ... `MAX_STEP` that states the smallest uncertainty of the
    stretch's peak |acceleration|: the difference from the spline through every 2k-th
    sample, plus the most the noise moves it (`NOISE_GAIN` over its sample spacing
    squared); where every 2k-th sample leaves fewer than 4, its whole acceleration and
    at least 4 |change| / duration^2, the least that moves it from rest to rest.
    """
    def spline(step: int) -> list[np.ndarray]:
        kept = _kept(first, last, step)
        return spline_derivatives(t[kept], q[kept], at, (1, 2), clamped=clamped)

    best, step, fine = None, 1, spline(1)
    unchecked = 4.0 * abs(q[last] - q[first]) / (t[last] - t[first]) ** 2
    while True:
        kept = _kept(first, last, step)
        moved = NOISE_FACTOR * noise * NOISE_GAIN / float(np.diff(t[kept]).min()) ** 2
        checked = len(_kept(first, last, 2 * step)) >= 4
        coarse = spline(2 * step) if checked else fine
        if checked:
            error = _envelope(np.abs(fine[1] - coarse[1]), at, t[kept]) + moved
        else:  # its whole acceleration, at least what moving rest to rest would take
            error = np.maximum(np.abs(fine[1]), unchecked) + moved
        bound = peak_uncertainty(fine[1], error)
        if best is not None and bound >= best[0]:
            break  # past the smallest: the motion's own error grows from here
        best = (bound, fine, error)
        if not checked or 2 * step > MAX_STEP:
            break
        step, fine = 2 * step, coarse
    _, (velocity, acceleration), error = best
    return velocity, acceleration, error


def peak_uncertainty(values: np.ndarray, spread: np.ndarray) -> float:
    """How far the largest |value| may be off when each sample may be off by `spread`.

    The true peak is at least the estimated peak's sample less its spread, and at most
    the largest |value| + spread of any sample: the larger distance from the estimate.

    Args:
        values: One joint's samples (an acceleration, a torque), shape (n,).
        spread: How far each may be off, in the same unit, shape (n,).

    Returns:
        The uncertainty of max |values|, in their unit; 0 for no samples.
    """
    if not len(values):
        return 0.0
    size = np.abs(values)
    peak = int(np.argmax(size))
    return max(float(np.max(size + spread) - size[peak]), float(spread[peak]))


def noise_level(q: np.ndarray, stretches: list[tuple[int, int]],
                t: np.ndarray | None = None) -> float:
    """Standard deviation of a joint's logged positions' noise [rad or m].

    The larger of two estimates over the moving stretches. The median |sixth divided
    difference| of seven samples in a row, over its deviation for noise of deviation 1
    (its weights' root sum of squares): the motion's own part is (period x its rate of change)^6
    small; a step of the acceleration lifts only the few spanning it. And a
    quantisation's: where every change between two samples is a whole number of the
    smallest one (within `QUANTUM_TOLERANCE`), that smallest change is the step, whose
    rounding errors spread as step / sqrt(12) (the sixth differences of a motion
    crawling through steps are mostly 0 and miss them). 0 for a log with no seven
    samples in a row moving.

    Args:
        q: One joint's logged positions [rad or m], shape (m,).
        stretches: Its moving stretches, (first, last) log indices.
        t: The log's times [s], shape (m,); None for evenly spaced samples.
    """
    starts = np.concatenate([np.arange(first, last - 5) for first, last in stretches]
                            + [np.empty(0, dtype=int)]).astype(int)
    if not len(starts):
        return 0.0
    starts = starts[np.linspace(0, len(starts) - 1, min(len(starts), NOISE_WINDOWS)).astype(int)]
    window = starts[:, None] + np.arange(7)
    if t is None:
        weights = np.array([1.0, -6.0, 15.0, -20.0, 15.0, -6.0, 1.0])[None, :]
    else:
        times = t[window]
        gaps = times[:, :, None] - times[:, None, :]
        gaps[:, np.arange(7), np.arange(7)] = 1.0
        weights = 1.0 / np.prod(gaps, axis=2)  # the sixth divided difference's
    sixth = np.abs(np.sum(weights * q[window], axis=1)) / np.sqrt(np.sum(weights**2, axis=1))
    changes = np.abs(np.diff(q[window[:, :2]], axis=1)[:, 0])
    changes = changes[changes > 0.0]
    level = float(np.median(sixth)) / MEDIAN_NORMAL
    if not len(changes):
        return level
    ratio = changes / changes.min()
    quantised = bool(np.all(np.abs(ratio - np.round(ratio)) <= QUANTUM_TOLERANCE))
    return max(level, float(changes.min()) / math.sqrt(12.0) if quantised else 0.0)


NOISE_WINDOWS = 1 << 17
"""Most windows of seven samples the noise is estimated from, evenly spread [-]."""
QUANTUM_TOLERANCE = 1e-3
"""How far from a whole number of the smallest step a quantised log's changes may be, in
steps: the rounding of a unit's conversion (degrees to radians) [-]."""


def _kept(first: int, last: int, step: int) -> np.ndarray:
    """About every step-th log index of a stretch, evenly from its first to its last.

    No interval is shorter than `step` samples: a short one would amplify noise the more.
    """
    count = max(1, (last - first) // step)  # at most one interval per sample: no repeats
    return np.round(np.linspace(first, last, count + 1)).astype(int)


def _envelope(values: np.ndarray, at: np.ndarray, knots: np.ndarray) -> np.ndarray:
    """The largest of `values` within two knot intervals of each grid time.

    Two estimates may cross where both are off: their difference then vanishes at a
    sample but not over the intervals around it.
    """
    if len(knots) < 2 or len(at) < 2:
        return values
    from scipy.ndimage import maximum_filter1d

    width = 2.0 * float(np.diff(knots).max()) / max(float(np.median(np.diff(at))), 1e-300)
    return maximum_filter1d(values, size=2 * min(int(math.ceil(width)), len(at)) + 1,
                            mode="nearest")


def _steps_at_rest(split: Split, q: np.ndarray, noise: float) -> Split:
    """A stretch between two rests that stays within one quantisation step is at rest too.

    A joint creeping the last step into a rest (or out of it) changes by one step
    between two runs of equal positions; the spline through those few samples with
    zero end velocities would show a spike of 6 x step / period^2 that is not there.
    """
    stretches, rest, runs = split
    band = 2.0 * NOISE_FACTOR * noise * (1.0 + QUANTUM_TOLERANCE)
    steps = [(first, last) for first, last in stretches if noise > 0.0 and rest[first]
             and rest[last] and np.ptp(q[first:last + 1]) <= band]
    if not steps:
        return split
    rest = rest.copy()
    spans: list[tuple[int, int]] = []
    for first, last in sorted(runs + steps):
        rest[first:last + 1] = True
        if spans and first <= spans[-1][1]:
            spans[-1] = (spans[-1][0], max(last, spans[-1][1]))
        else:
            spans.append((first, last))
    return [s for s in stretches if s not in steps], rest, spans


def _rest_spread(t: np.ndarray, at: np.ndarray, runs: list[tuple[int, int]],
                 noise: float) -> np.ndarray:
    """How far the acceleration 0 of each rest may be off, at `at` [per s^2].

    A joint whose position stays within one quantisation step (2 `NOISE_FACTOR` x the
    noise) for a time D may accelerate by up to 8 x step / D^2 unseen.
    """
    out = np.zeros(len(at))
    if noise == 0.0:
        return out
    for first, last in runs:
        lo, hi = _grid(at, t, first, last)
        out[lo:hi] = 16.0 * NOISE_FACTOR * noise / (t[last] - t[first]) ** 2
    return out


def _grid(at: np.ndarray, t: np.ndarray, first: int, last: int) -> tuple[int, int]:
    """The slice of grid times from log sample `first` to `last`, both included."""
    return (int(np.searchsorted(at, t[first], side="left")),
            int(np.searchsorted(at, t[last], side="right")))


REST_RUN = 3
"""Equal positions in a row that make a joint at rest in a positions-only log [-]."""


def _moving_stretches(q: np.ndarray, t: np.ndarray, shortest: float = 0.0) -> Split:
    """Where a joint moves and where it rests (`Split`).

    A sample rests when it is one of a run of at least `REST_RUN` equal positions
    lasting at least `shortest` [s]. The interval between two samples is still when
    both rest at the same position, else moving; a stretch is a run of moving
    intervals, from its first sample to its last.
    """
    equal = q[1:] == q[:-1]
    rest = np.zeros(len(q), dtype=bool)
    runs = []
    edges = np.diff(np.r_[0, equal.astype(np.int8), 0])
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        if b - a + 1 >= REST_RUN and t[b] - t[a] >= shortest:  # samples a .. b equal
            rest[a:b + 1] = True
            runs.append((int(a), int(b)))
    moving = ~(equal & rest[:-1] & rest[1:])
    edges = np.diff(np.r_[0, moving.astype(np.int8), 0])
    return [(int(a), int(b)) for a, b in zip(np.flatnonzero(edges == 1),
                                             np.flatnonzero(edges == -1), strict=True)], rest, runs


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
    (out,) = spline_derivatives(t, values, at, (order,), clamped=clamped)
    return out


def spline_derivatives(t: np.ndarray, values: np.ndarray, at: np.ndarray,
                       orders: tuple[int, ...], *,
                       clamped: tuple[bool, bool] = (False, False)) -> list[np.ndarray]:
    """`spline_values` of several orders from the same splines, one array per order."""
    from scipy.interpolate import CubicSpline

    out = [np.empty((len(at),) + values.shape[1:]) for _ in orders]
    for start in range(0, len(at), CHUNK):
        part = slice(start, start + CHUNK)
        first, last = np.searchsorted(t, [at[part][0], at[part][-1]])
        lo, hi = max(0, int(first) - MARGIN), min(len(t), int(last) + MARGIN + 1)
        ends = tuple((1, 0.0) if rest and edge else "not-a-knot"
                     for rest, edge in zip(clamped, (lo == 0, hi == len(t)), strict=True))
        if hi - lo < 4 and "not-a-knot" in ends and ends != ("not-a-knot", "not-a-knot"):
            ends = tuple("natural" if end == "not-a-knot" else end for end in ends)
        with np.errstate(all="ignore"):  # `plan` refuses a result that is not finite
            spline = CubicSpline(t[lo:hi], values[lo:hi], axis=0, bc_type=ends)
            for array, order in zip(out, orders, strict=True):
                array[part] = spline(at[part], order)
    return out
