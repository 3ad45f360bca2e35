"""Choose one gearhead among the candidates checked for a joint."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from hdselect.base.errors import InputError
from hdselect.catalog.rules import Candidate


def _mass(candidate: Candidate) -> float:
    """The pair's mass, gearhead and motor [kg] (the gearhead's without a motor)."""
    motor = candidate.motor_unit
    return candidate.unit.mass + (motor.mass if motor is not None else 0.0)


def _motor_mass(candidate: Candidate) -> float:
    """The paired motor's mass [kg]; 0 without one (a tie-break among motors)."""
    return candidate.motor_unit.mass if candidate.motor_unit is not None else 0.0


def _motor(name: str) -> Callable[[Candidate], float]:
    def key(candidate: Candidate) -> float:
        return float(getattr(candidate.motor, name)) if candidate.motor is not None else 0.0
    return key


DEFAULT_INERTIA_TARGET = 1.0
"""Load-to-rotor inertia ratio ``prefer = "inertia"`` aims at by default [-]: 1, the
matched load of the classic power-transfer optimum. Designers often accept 3 to 10;
give yours with ``--inertia-target``."""


def inertia_mismatch(candidate: Candidate, target: float = DEFAULT_INERTIA_TARGET) -> float:
    """How far a pair's load-to-rotor inertia ratio is from a target: |ln(ratio / target)|.

    A factor too high counts as much as the same factor too low (8 and 0.125 are equally
    far from 1). Infinite for a candidate without a ratio (no motor, or no load inertia).
    """
    ratio = candidate.inertia_ratio
    if ratio is None or ratio <= 0.0:
        return math.inf
    return abs(math.log(ratio / target))


def _inertia_key(target: float) -> Callable[[Candidate], tuple[float, ...]]:
    return lambda c: (round(inertia_mismatch(c, target), 9), c.unit.size,
                      -round(c.margin, 9), c.unit.ratio, _motor_mass(c))


PREFERENCES: dict[str, tuple[str, Callable[[Candidate], tuple[float, ...]]]] = {
    "size": ("smallest size; within a size, the largest worst-case margin (ties: the lower "
             "ratio, which reflects less inertia, then the lighter motor)",
             lambda c: (c.unit.size, -round(c.margin, 9), c.unit.ratio, _motor_mass(c))),
    "margin": ("largest worst-case margin, whatever the size",
               lambda c: (-round(c.margin, 9), c.unit.size, c.unit.ratio, _motor_mass(c))),
    "motor-rms": ("lowest motor RMS torque; ties go to the smaller size",
                  lambda c: (_motor("rms_torque")(c), c.unit.size, _motor_mass(c))),
    "motor-peak": ("lowest motor peak torque; ties go to the smaller size",
                   lambda c: (_motor("peak_torque")(c), c.unit.size, _motor_mass(c))),
    "mass": ("lightest gearhead and motor together (the default where motors are given); "
             "ties go to the smaller size, then the largest worst-case margin",
             lambda c: (round(_mass(c), 9), c.unit.size, -round(c.margin, 9), c.unit.ratio)),
    "inertia": ("load-to-rotor inertia ratio closest to the target (--inertia-target, "
                f"default {DEFAULT_INERTIA_TARGET:g}) by factor; ties go to the smaller size, "
                "then the largest worst-case margin; a joint without motor data as size",
                _inertia_key(DEFAULT_INERTIA_TARGET)),
}
"""Selection orders by name: (description, sort key; the first candidate wins)."""
DEFAULT_PREFER = "size"
"""The selection order where no motors are given."""
DEFAULT_PREFER_WITH_MOTORS = "mass"
"""The selection order where motors are given: the lightest feasible pair."""


def select(candidates: Sequence[Candidate], prefer: str = "size", *,
           inertia_target: float = DEFAULT_INERTIA_TARGET) -> Candidate | None:
    """The preferred feasible candidate.

    Args:
        candidates: Every unit checked against one joint.
        prefer: A key of `PREFERENCES`.
        inertia_target: The load-to-rotor inertia ratio ``"inertia"`` aims at [-].

    Returns:
        The chosen candidate, or None when no unit is feasible.

    Raises:
        InputError: `prefer` is not a known order.
    """
    if not isinstance(prefer, str) or prefer not in PREFERENCES:
        raise InputError(f"unknown order '{prefer}'; choose one of: {', '.join(PREFERENCES)}",
                         field="prefer")
    feasible = [c for c in candidates if c.feasible]
    key = _inertia_key(inertia_target) if prefer == "inertia" else PREFERENCES[prefer][1]
    return min(feasible, key=key) if feasible else None
