"""Choose one gearhead among the candidates checked for a joint."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from hdselect.errors import InputError
from hdselect.rules import Candidate


def _motor(name: str) -> Callable[[Candidate], float]:
    def key(candidate: Candidate) -> float:
        return float(getattr(candidate.motor, name)) if candidate.motor is not None else 0.0
    return key


PREFERENCES: dict[str, tuple[str, Callable[[Candidate], tuple[float, ...]]]] = {
    "size": ("smallest size; within a size, the largest worst-case margin (ties: the lower "
             "ratio, which reflects less inertia)",
             lambda c: (c.unit.size, -round(c.margin, 9), c.unit.ratio)),
    "margin": ("largest worst-case margin, whatever the size",
               lambda c: (-round(c.margin, 9), c.unit.size, c.unit.ratio)),
    "motor-rms": ("lowest motor RMS torque; ties go to the smaller size",
                  lambda c: (_motor("rms_torque")(c), c.unit.size)),
    "motor-peak": ("lowest motor peak torque; ties go to the smaller size",
                   lambda c: (_motor("peak_torque")(c), c.unit.size)),
}
"""Selection orders by name: (description, sort key; the first candidate wins)."""


def select(candidates: Sequence[Candidate], prefer: str = "size") -> Candidate | None:
    """The preferred feasible candidate.

    Args:
        candidates: Every unit checked against one joint.
        prefer: A key of `PREFERENCES`.

    Returns:
        The chosen candidate, or None when no unit is feasible.

    Raises:
        InputError: `prefer` is not a known order.
    """
    if not isinstance(prefer, str) or prefer not in PREFERENCES:
        raise InputError(f"unknown order '{prefer}'; choose one of: {', '.join(PREFERENCES)}",
                         field="prefer")
    feasible = [c for c in candidates if c.feasible]
    return min(feasible, key=PREFERENCES[prefer][1]) if feasible else None
