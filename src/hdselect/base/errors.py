"""The exceptions hdselect raises: one base class and a few specific kinds."""

from __future__ import annotations

import warnings
from pathlib import Path


class HdselectError(Exception):
    """Base class of every error hdselect raises on purpose."""


class InputError(HdselectError):
    """A file or option given by the user is missing, malformed or inconsistent.

    Attributes:
        path: The file at fault, or None for a command-line option.
        field: The key, column or option at fault (dotted for nested TOML keys).
    """

    def __init__(self, message: str, *, path: str | Path | None = None, field: str | None = None):
        self.path = None if path is None else Path(path)
        self.field = field
        self.reason = message
        where = ": ".join(str(part) for part in (path, field) if part is not None)
        super().__init__(f"{where}: {message}" if where else message)


class PlanningError(HdselectError):
    """The planner could not produce a trajectory for a valid motion file."""


def deprecated(old: str, new: str, *, depth: int = 1) -> None:
    """Warn that `old` is spelled `new` now (a DeprecationWarning, one line).

    Args:
        old: The old spelling.
        new: The new one.
        depth: Calls between the caller's code and this one (1: the caller called the
            function that calls this).
    """
    warnings.warn(f"{old} is deprecated; use {new}", DeprecationWarning, stacklevel=2 + depth)
