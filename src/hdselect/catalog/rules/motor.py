"""The motor's three rules behind a gearhead: peak torque at speed, RMS torque, speed.

``motor_peak``: every sample's |T_motor| under the motor's peak torque at that sample's
input speed (its curve, or its flat peak torque); the value and limit are those of the
worst sample. ``motor_rms``: the RMS torque over the whole cycle, dwells included, at
most the rated torque. This is the thermal rule of one cycle repeated back to back, with
no thermal model: the motor's thermal time constant is taken as long against the cycle,
and the rated torque as the datasheet rates it (its ambient and mounting).
``motor_speed``: the largest input speed at most the motor's maximum. Torque and speed
count by magnitude: the motor is taken as symmetric in all four quadrants. With a torque
constant the checks carry the currents (I = T / k_t), and with a resistance too the
copper loss R I_rms^2.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules.base import Check, Part, Rule, RuleInput, Scope
from hdselect.catalog.rules.forms import PathBound, PathCase, PathKind, Rows, ScaleTerms
from hdselect.catalog.rules.load import RPM_PER_RAD_S
from hdselect.catalog.rules.speed import speed_row
from hdselect.catalog.units import Unit


class MotorPeak(Rule):
    """Every sample's |T_motor| within the motor's peak torque at its input speed."""

    name = "motor_peak"
    label = "m.peak"
    words = "motor peak torque"
    part = Part.MOTOR
    scope = Scope.SAMPLE
    unit = "N m"
    share_of = "peak at that speed"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        motor, torque, speed_rpm = case.motor, case.motor_torque, case.motor_speed
        if motor is None or torque is None or speed_rpm is None or case.demand is None:
            return None
        magnitude = np.abs(torque)
        allowed = motor.peak_torque_at(speed_rpm)
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.where(magnitude > 0.0, magnitude / allowed, 0.0)
        if not share.size:
            return self.judge(0.0, motor.peak_torque, case.margin)
        k = int(share.argmax())
        detail: dict[str, object] = {"speed_rpm": float(abs(speed_rpm[k]))}
        if motor.torque_constant is not None:
            detail["current_a"] = case.demand.peak_torque / motor.torque_constant
        return self.verdict(float(magnitude[k]), float(allowed[k]), float(share[k]),
                            case.margin, detail)

    def path_rows(self, case: PathCase) -> list[Any]:
        """|k tau + (J_in + J_m) N qdd| <= the motor's flat peak torque, for both gear factors.

        k = 1 / (N eta_low) while the motor drives and eta_high / N while the load drives
        back (`efficiency_range`: the direction is not known before the solve). The curve
        below the flat peak at speed is checked on the result (the forward check). None
        bound without a motor.
        """
        unit, motor = case.unit, case.motor
        if motor is None:
            return []
        low, high = efficiency_range(unit, case.efficiency)
        return [PathBound(PathKind.MOTOR_TORQUE, self.derate(motor.peak_torque, case.margin),
                          factors=(1.0 / (unit.ratio * low), high / unit.ratio),
                          inertia=(unit.input_inertia + case.rotor_inertia) * unit.ratio)]


class MotorRms(Rule):
    """The RMS motor torque over the whole cycle at most the rated torque."""

    name = "motor_rms"
    label = "m.rms"
    words = "motor RMS torque"
    part = Part.MOTOR
    scope = Scope.CYCLE
    unit = "N m"
    share_of = "rated"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        motor, demand = case.motor, case.demand
        if motor is None or demand is None:
            return None
        detail: dict[str, object] = {}
        if motor.torque_constant is not None:
            rms_current = demand.rms_torque / motor.torque_constant
            detail["current_a"] = rms_current
            if motor.resistance is not None:
                detail["copper_loss_w"] = motor.resistance * rms_current**2
        return self.judge(demand.rms_torque, motor.rated_torque, case.margin, **detail)


class MotorSpeed(Rule):
    """The largest input speed at most the motor's maximum speed [rpm]."""

    name = "motor_speed"
    label = "m.speed"
    words = "motor speed"
    part = Part.MOTOR
    scope = Scope.SAMPLE
    unit = "rpm"
    share_of = "maximum"

    def check(self, case: RuleInput) -> Check | None:
        """See `Rule.check`."""
        if case.motor is None or case.demand is None:
            return None
        return self.judge(case.demand.max_speed, case.motor.max_speed, case.margin)

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """The largest |qd| N y at most the motor's maximum speed [rpm]; none without a motor."""
        if terms.motor is None:
            return ()
        return (speed_row(terms, unit, self.derate(terms.motor.max_speed, margin)),)

    def path_rows(self, case: PathCase) -> list[Any]:
        """|qd| <= the motor's maximum speed over the ratio [rad/s]; none without a motor."""
        if case.motor is None:
            return []
        return [PathBound(PathKind.SPEED, self.derate(case.motor.max_speed, case.margin)
                          / case.unit.ratio / RPM_PER_RAD_S, "motor")]


MOTOR_RULES = (MotorPeak(), MotorRms(), MotorSpeed())
"""The motor's rules, in the order of `hdselect.catalog.rules.MOTOR_CHECKS`."""


def efficiency_range(unit: Unit, default: float) -> tuple[float, float]:
    """The unit's lowest and highest efficiency [-]: its table's, else `default` twice.

    The motor torque bound takes the lowest while the motor drives and the highest while
    the load drives back, the larger motor torque each way, for the whole path (the
    table's speed and load are not known before the solve); the check of the result
    uses the table itself.
    """
    if unit.efficiency is None:
        return default, default
    values = np.asarray(unit.efficiency.value, dtype=float)
    return float(values.min()), float(values.max())
