"""A joint's output-bearing loads from its wrench along the cycle, at any time scale.

The core's torque model gives each sized joint's whole force and moment per sample
(`hdselect.robot.wrenches.axis_wrenches`); here they become the bearing's loads
over the cycle (`hdselect.catalog.bearing_rules.BearingLoad`) about the output
flange, or about a unit's own bearing centre. Run s times slower, the wrench of a
fixed path is W + (F - W) / s^2 (W at rest, F along the motion): what the time-scale
search checks a rated bearing on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdselect.catalog.bearing_rules import (
    BearingLoad,
    travel_weights,
    weighted_bearing_load,
)
from hdselect.robot.wrenches import bearing_loads


@dataclass(frozen=True, eq=False)
class SampledWrench:
    """A joint's wrench along the samples, each distinct state's stored once.

    In the joint's axis frame about its origin (rows as `axis_wrenches`): a dwell repeats
    one state, so its row is kept once and `index` points every sample at its row.

    Attributes:
        rows: The wrench of each distinct state [N, N m], shape (5 or 6, m), read-only.
        index: Each sample's row, shape (n,); None when every sample has its own.
    """

    rows: np.ndarray
    index: np.ndarray | None = None

    def full(self) -> np.ndarray:
        """The wrench of every sample [N, N m], shape (5 or 6, n)."""
        return self.rows if self.index is None else self.rows[:, self.index]

    def loads(self, offset: float = 0.0, spread: float = 0.0, *,
              per_row: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """F_a [N], F_r [N] and M [N m] about a centre on the axis (`bearing_loads`).

        Per sample; with `per_row`, per distinct state (a row of `rows`).
        """
        loads = bearing_loads(self.rows, offset, spread)
        if self.index is None or per_row:
            return loads
        axial, radial, moment = (np.take(load, self.index) for load in loads)
        return axial, radial, moment


def cycle_bearing(wrench: SampledWrench, offset: float, spread: float, speed: np.ndarray,
                  duration: np.ndarray | float, at_rest: np.ndarray) -> BearingLoad:
    """The bearing's loads over a cycle from the joint's wrench per sample.

    Args:
        wrench: The joint's wrench along the samples.
        offset: The output flange along the axis from the joint origin [m].
        spread: The unit's distance from its flange to its bearing centre, side unknown
            (the larger moment of both sides per sample) [m].
        speed: Output speed per sample [rad/s], (n,).
        duration: What each sample stands for [s].
        at_rest: Where the joint is held still (in the maxima, not the means), (n,).

    Returns:
        The loads: maxima, and 10/3-power means weighted by |n| t.
    """
    axial, radial, moment = wrench.loads(offset, spread, per_row=True)
    weight = travel_weights(speed, duration, at_rest)
    if wrench.index is not None:  # the weights of the samples sharing a row, summed
        weight = np.bincount(wrench.index, weight, minlength=wrench.rows.shape[1])
    return weighted_bearing_load(axial, radial, moment, weight, offset=offset, spread=spread)


@dataclass(frozen=True, eq=False)
class ScalableWrench:
    """A joint's wrench along a fixed path, split by how it scales with time.

    Attributes:
        gravity: W, the wrench holding each pose still [N, N m], shape (5, n).
        motion: F, the wrench along the motion at s = 1 [N, N m], shape (5, n).
        offset: The output flange along the axis from the joint origin [m].
    """

    gravity: np.ndarray
    motion: np.ndarray
    offset: float = 0.0

    def at(self, s: float) -> np.ndarray:
        """The wrench run s times slower [N, N m], (5, n): W + (F - W) / s^2."""
        return self.gravity + (self.motion[:5] - self.gravity) / (s * s)

    def load(self, s: float, speed: np.ndarray, duration: np.ndarray | float,
             at_rest: np.ndarray, spread: float = 0.0) -> BearingLoad:
        """The bearing's loads run s times slower; `speed` [rad/s] and `duration` [s] at s."""
        return cycle_bearing(SampledWrench(self.at(s)), self.offset, spread, speed, duration,
                             at_rest)
