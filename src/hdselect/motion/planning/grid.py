"""The time grid of a trajectory: its size, checked before allocating, and its resolution.

Demands must not depend on how a motion file samples its cycle. A planned cycle is
sampled every dt / k, dt the file's period and k the smallest whole number for which

- every move and path piece spans at least `MIN_MOVE_SAMPLES` samples (a move shorter
  than dt would otherwise be skipped outright),
- every dwell lasts at least one period, so the held pose is sampled at rest,
- the samples find every joint's exact peak acceleration of every move (the
  planner's profile gives it) to within `PEAK_RESOLUTION` of the joint's largest;

the file's own grid points k dt stay sample times. A log is never refined (its
samples are the data), but dt may not be coarser than the log. The grid has at most
``max_samples`` samples (`hdselect.base.bounds.DEFAULT_MAX_SAMPLES`), checked before any
array is allocated.

Each failure is one `InputError` naming the motion file and ``dt``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from decimal import ROUND_FLOOR, Decimal
from pathlib import Path

import numpy as np

from hdselect.base.bounds import bytes_per_sample, check_max_samples
from hdselect.base.errors import InputError

MIN_MOVE_SAMPLES = 50
"""Fewest samples a move (or a TOPPRA path piece) spans [-]: a coarser dt is refined."""
PEAK_RESOLUTION = 0.01
"""How much of a joint's largest peak acceleration [-] the samples may miss of any move's
exact peak before the grid is refined. Accelerations of jerk-limited moves are piecewise
linear (TOPPRA's: piecewise smooth with steps), so a peak between samples is missed by at
most jerk x period / 2: the miss falls in proportion to the period."""
LOG_PERIOD_TOLERANCE = 0.01
"""How much coarser than a log's median sample period dt may be [-]."""


def sample_count(duration: float, dt: float) -> int:
    """Samples on the grid of a cycle of `duration` [s] at period `dt` [s] (finite inputs)."""
    return math.ceil(duration / dt - 1e-9) + 1


def check_size(path: Path, duration: float, dt: float, dof: int, max_samples: int) -> int:
    """The sample count of the grid, if it is within `max_samples`.

    Args:
        path: The motion file, for messages.
        duration: Cycle time T [s].
        dt: Sample period [s].
        dof: Joints of the robot (for the memory estimate).
        max_samples: The limit.

    Returns:
        The number of samples.

    Raises:
        InputError: The grid would have more samples than `max_samples`.
    """
    limit = check_max_samples(max_samples)
    ratio = duration / dt if math.isfinite(duration) else math.inf
    if not ratio < limit:
        samples = "more than 1e308" if not math.isfinite(ratio) else f"{ratio + 1:,.0f}"
        memory = ("" if not math.isfinite(ratio)
                  else f" (about {_gigabytes((ratio + 1) * bytes_per_sample(dof))})")
        cycle = f"{duration:g} s" if math.isfinite(duration) else "longer than 1e308 s"
        raise InputError(f"the cycle lasts {cycle}: at dt = {dt:g} s that is {samples} samples"
                         f"{memory}, more than the limit of {limit:,} (max_samples, "
                         "--max-samples on the command line); use a larger dt, a shorter cycle "
                         "or a higher limit", path=path, field="dt")
    count = sample_count(duration, dt)
    if count > limit:
        raise InputError(f"the cycle needs {count:,} samples, more than the limit of {limit:,} "
                         "(max_samples, --max-samples on the command line)", path=path,
                         field="dt")
    return count


def resolving_factor(dt: float, moves: Sequence[tuple[str, float]],
                     dwells: Sequence[tuple[str, float]]) -> tuple[int, str]:
    """The smallest whole k for which the period dt / k resolves every move and dwell.

    Args:
        dt: The motion file's sample period [s].
        moves: (what, duration [s]) of each move or path piece, e.g.
            ``("the move from waypoint[0] to waypoint[1]", 0.62)``; zero durations
            (no motion) are skipped.
        dwells: (what, duration [s]) of each dwell; zero dwells are skipped.

    Returns:
        k >= 1 such that every move spans at least `MIN_MOVE_SAMPLES` periods and every
        dwell at least one, and what needs it (the shortest such move or dwell; empty
        when k is 1).
    """
    factor, reason = 1, ""
    timed = [(duration, what) for what, duration in moves if duration > 0.0]
    if timed:
        shortest, what = min(timed)
        need = _whole(MIN_MOVE_SAMPLES * dt / shortest)
        if need > factor:
            factor, reason = need, f"{what} ({shortest:.3g} s)"
    held = [(duration, what) for what, duration in dwells if duration > 0.0]
    if held:
        shortest, what = min(held)
        need = _whole(dt / shortest)
        if need > factor:
            factor, reason = need, f"{what} ({shortest:.3g} s)"
    return factor, reason


def _whole(ratio: float) -> int:
    """The smallest whole number at least `ratio` (to rounding), capped where no grid can be."""
    return math.ceil(min(ratio, MAX_FACTOR) * (1.0 - 1e-9))


MAX_FACTOR = 1e15
"""Largest refinement tried: any grid it makes is refused by the sample limit [-]."""


def check_log_period(path: Path, log_path: Path, t: np.ndarray, dt: float) -> None:
    """Check that dt is not coarser than the log's median sample period.

    Raises:
        InputError: It is, so resampling would skip logged samples.
    """
    period = float(np.median(np.diff(t)))
    if dt > period * (1.0 + LOG_PERIOD_TOLERANCE):
        raise InputError(
            f"dt = {dt:g} s is coarser than the log's sample period ({period:.3g} s, the median, "
            f"{log_path.name}): resampling would skip logged samples; use dt <= {_down(period)} s",
            path=path, field="dt")


def _down(value: float) -> str:
    """`value` rounded down to two significant digits, for advice that must hold."""
    exact = Decimal(value)
    step = Decimal(1).scaleb(exact.adjusted() - 1)
    return f"{float((exact / step).to_integral_value(ROUND_FLOOR) * step):.2g}"


def _gigabytes(size: float) -> str:
    if size >= 1e10:
        return f"{size / 1e9:,.0f} GB"
    return f"{size / 1e9:.1f} GB" if size >= 1e8 else f"{size / 1e6:,.0f} MB"
