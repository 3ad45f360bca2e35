"""How a robot is mounted: the direction of gravity in its base frame."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError

STANDARD_GRAVITY = 9.80665
"""Standard gravity [m/s^2]."""


MOUNTINGS = {
    "floor": (0.0, 0.0, -STANDARD_GRAVITY),
    "ceiling": (0.0, 0.0, STANDARD_GRAVITY),
    "wall": (-STANDARD_GRAVITY, 0.0, 0.0),
}
"""Gravity in the base frame [m/s^2] for each named mounting. On a wall the base z
axis is horizontal and gravity points along the base's -x axis."""


def gravity_of(mounting: str | Sequence[float]) -> np.ndarray:
    """Gravity in the base frame [m/s^2] for a named mounting or a gravity vector.

    Raises:
        InputError: The mounting is neither a known name nor three finite numbers.
    """
    if isinstance(mounting, str):
        if mounting not in MOUNTINGS:
            raise InputError(f"unknown mounting '{mounting}'; choose one of: "
                             f"{', '.join(MOUNTINGS)} or a gravity vector", field="mounting")
        return np.array(MOUNTINGS[mounting])
    if isinstance(mounting, bytes) or (
            isinstance(mounting, Sequence) and any(isinstance(g, bool | str | bytes)
                                                   for g in mounting)):
        raise InputError("gravity must be three finite numbers [m/s^2]", field="mounting")
    try:
        gravity = np.asarray(mounting, dtype=float)
    except (TypeError, ValueError, OverflowError) as err:
        raise InputError("gravity must be three finite numbers [m/s^2]",
                         field="mounting") from err
    if gravity.shape != (3,) or not np.all(np.isfinite(gravity)):
        raise InputError("gravity must be three finite numbers [m/s^2]", field="mounting")
    for i, value in enumerate(gravity):
        bounds.GRAVITY.check(float(value), field=f"mounting[{i}]")
    return gravity
