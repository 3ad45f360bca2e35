"""A gearhead paired with a motor: the motor's rules and the pair's added to its checks.

The rules are in `hdselect.catalog.rules` (`motor`, `inertia_ratio`).
"""

from __future__ import annotations

import warnings

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    Candidate,
    Check,
    Part,
    RuleInput,
    apply_rules,
    inertia_ratio,
)
from hdselect.catalog.rules.inertia_ratio import INERTIA_RATIO


def with_motor(candidate: Candidate, motor: Motor, torque: np.ndarray,
               speed_rpm: np.ndarray, *, load_inertia: float | None = None,
               max_inertia_ratio: float | None = None,
               margin: float | None = None) -> Candidate:
    """A gearhead's candidate paired with a motor: its checks plus the motor's.

    With the joint's load inertia, the pair carries its load-to-rotor inertia ratio
    (`inertia_ratio`); with a largest ratio too (`max_inertia_ratio`, else the motor's
    own `Motor.max_inertia_ratio`), the ``inertia_ratio`` check: a pair above it is not
    feasible. The design margin does not apply to that check (the largest ratio is a
    design choice, not a rating).

    Args:
        candidate: The gearhead checked with this motor's rotor inertia (`check_unit`).
        motor: The motor.
        torque: Motor torque per sample behind this gearhead [N m], shape (n,).
        speed_rpm: Input speed per sample [rpm], shape (n,).
        load_inertia: The joint's output-side load inertia J_load [kg m^2], or None.
        max_inertia_ratio: Largest load-to-rotor inertia ratio allowed [-], overriding
            the motor's; None takes the motor's (None there too: no such check).
        margin: Design margin of the motor's rules [-]; None takes the gearhead's
            (`Candidate.required_margin`).

    Returns:
        The pair, its checks in the order of `CHECKS`.
    """
    if candidate.motor is None:
        raise ValueError("a pair needs the motor demand of its reflection")
    margin = candidate.required_margin if margin is None else margin
    ratio = None if load_inertia is None else inertia_ratio(load_inertia, candidate.unit, motor)
    case = RuleInput(candidate.unit, None, margin, demand=candidate.motor, motor=motor,
                     motor_torque=torque, motor_speed=speed_rpm, load_inertia=load_inertia,
                     max_inertia_ratio=max_inertia_ratio)
    checks = {**candidate.checks, **apply_rules((Part.MOTOR, Part.PAIR), case)}
    return Candidate(candidate.unit, checks, candidate.life_hours, candidate.flags,
                     candidate.motor, motor, ratio, margin, candidate.bearing)


def inertia_check(ratio: float | None, largest: float) -> Check:
    """Deprecated: the ``inertia_ratio`` rule's check, `InertiaRatio.of`."""
    warnings.warn("hdselect.catalog.motor_rules.inertia_check is deprecated; use "
                  "hdselect.catalog.rules.inertia_ratio.INERTIA_RATIO.of", DeprecationWarning,
                  stacklevel=2)
    return INERTIA_RATIO.of(ratio, largest)
