"""Read-only numpy arrays, for the immutable records passed down the data flow."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def frozen(array: ArrayLike) -> np.ndarray:
    """A read-only, C-ordered float copy of `array`."""
    out = np.array(array, dtype=float, order="C")
    out.setflags(write=False)
    return out


def readonly(array: np.ndarray) -> np.ndarray:
    """`array` itself if it is already read-only (a view costs no copy), else a frozen copy."""
    return array if not array.flags.writeable else frozen(array)
