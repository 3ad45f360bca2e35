"""A motor's rules behind a gearhead: peak and RMS torque, speed, inertia ratio."""

from __future__ import annotations

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    DEFAULT_MARGIN,
    Candidate,
    Check,
    MotorDemand,
    holds,
    limit_check,
)
from hdselect.catalog.units import Unit


def check_motor(motor: Motor, torque: np.ndarray, speed_rpm: np.ndarray,
                demand: MotorDemand, *, margin: float = DEFAULT_MARGIN) -> dict[str, Check]:
    """The motor's rules on what it must deliver behind one gearhead.

    ``motor_peak``: every sample's |T_motor| under the motor's peak torque at that
    sample's input speed (its curve, or its flat peak torque); the value and limit are
    those of the worst sample. ``motor_rms``: the RMS torque over the whole cycle, dwells
    included, at most the rated torque. This is the thermal rule of one cycle repeated
    back to back, with no thermal model: the motor's thermal time constant is taken as
    long against the cycle, and the rated torque as the datasheet rates it (its ambient
    and mounting). ``motor_speed``: the largest input speed at most the motor's maximum.
    Torque and speed count by magnitude: the motor is taken as symmetric in all four
    quadrants. With a torque constant the checks carry the currents (I = T / k_t), and
    with a resistance too the copper loss R I_rms^2.

    Args:
        motor: The motor.
        torque: Motor torque per sample [N m], shape (n,).
        speed_rpm: Input speed per sample [rpm], shape (n,).
        demand: The cycle's peak and RMS motor torque and largest input speed.
        margin: Design margin [-]: each rule must hold at (1 - margin) of its limit.

    Returns:
        The three checks by name, in the order of `MOTOR_CHECKS`.
    """
    magnitude = np.abs(torque)
    allowed = motor.peak_torque_at(speed_rpm)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(magnitude > 0.0, magnitude / allowed, 0.0)
    k = int(share.argmax()) if share.size else 0
    peak_detail: dict[str, object] = {"speed_rpm": float(abs(speed_rpm[k])) if share.size
                                      else 0.0}
    rms_detail: dict[str, object] = {}
    if motor.torque_constant is not None:
        peak_detail["current_a"] = demand.peak_torque / motor.torque_constant
        rms_current = demand.rms_torque / motor.torque_constant
        rms_detail["current_a"] = rms_current
        if motor.resistance is not None:
            rms_detail["copper_loss_w"] = motor.resistance * rms_current**2
    peak = (Check(float(magnitude[k]), float(allowed[k]), holds(float(share[k]), margin),
                  float(share[k]), peak_detail) if share.size
            else limit_check(0.0, motor.peak_torque, margin=margin))
    return {"motor_peak": peak,
            "motor_rms": limit_check(demand.rms_torque, motor.rated_torque, margin=margin,
                                     **rms_detail),
            "motor_speed": limit_check(demand.max_speed, motor.max_speed, margin=margin)}


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
        raise TypeError(f"{candidate.unit.id}: a motor pair needs the candidate's motor demand "
                        "(reflect it with a motor)")
    margin = candidate.required_margin if margin is None else margin
    checks = {**candidate.checks, **check_motor(motor, torque, speed_rpm, candidate.motor,
                                                 margin=margin)}
    ratio = None if load_inertia is None else inertia_ratio(load_inertia, candidate.unit, motor)
    largest = max_inertia_ratio if max_inertia_ratio is not None else motor.max_inertia_ratio
    if largest is not None and load_inertia is not None:
        checks["inertia_ratio"] = inertia_check(ratio, largest)
    return Candidate(candidate.unit, checks, candidate.life_hours, candidate.flags,
                     candidate.motor, motor, ratio, margin, candidate.bearing)


def inertia_check(ratio: float | None, largest: float) -> Check:
    """The ``inertia_ratio`` check: the pair's load-to-rotor ratio at most `largest` [-].

    A motor without rotor inertia (ratio None) cannot be matched, so fails. No margin.
    """
    if ratio is None:
        return Check(None, largest, False, float("inf"), {"reason": "no rotor inertia"})
    return limit_check(ratio, largest)


def inertia_ratio(load_inertia: float, unit: Unit, motor: Motor) -> float | None:
    """Load inertia at the motor shaft over the rotor inertia [-].

    The load at the motor shaft is the joint's output inertia through the ratio plus
    the gearhead's own input inertia, J_load / N^2 + J_in.

    Args:
        load_inertia: The joint's output-side inertia J_load [kg m^2].
        unit: The gearhead.
        motor: The motor.

    Returns:
        (J_load / N^2 + J_in) / J_m; None when the rotor inertia is zero.
    """
    if motor.rotor_inertia <= 0.0:
        return None
    return (load_inertia / unit.ratio**2 + unit.input_inertia) / motor.rotor_inertia
