"""Reflect a joint's demand through a gearhead: input speed, motor torque, crash torque.

The gear teeth carry the load torque tau from inverse dynamics. The motor
behind a unit of ratio N, efficiency eta and input inertia J_in (plus the
rotor inertia J_m) must deliver

    T_motor = tau / (N eta)   while the motor drives the load (tau qd >= 0),
              tau eta / N     while the load drives back (tau qd < 0),
            + (J_in + J_m) N qdd

at the input speed N qd.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdselect.catalog import Unit
from hdselect.rules import RPM_PER_RAD_S, Momentary

DEFAULT_EFFICIENCY = 0.70
"""Gear efficiency used where a catalog gives no table [-]. The PSA-G page shows
efficiency curves but no numbers; 70 % is a mid-range reading for small
Harmonic Drive units near rated torque, and lower at light load."""


@dataclass(frozen=True)
class MotorDemand:
    """What the motor behind one gearhead must deliver over the cycle.

    Attributes:
        peak_torque: Largest |T_motor| [N m].
        rms_torque: Root mean square of T_motor over the whole cycle [N m].
        max_speed: Largest input speed [rpm].
        efficiency: The efficiency used: a number, or ``"table"`` for the unit's own table.
    """

    peak_torque: float
    rms_torque: float
    max_speed: float
    efficiency: float | str


def motor_demand(
    unit: Unit,
    tau: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    *,
    efficiency: float = DEFAULT_EFFICIENCY,
    rotor_inertia: float = 0.0,
) -> tuple[MotorDemand, np.ndarray]:
    """The motor torque along the cycle for one gearhead.

    Args:
        unit: The gearhead.
        tau: Output (load) torque per sample [N m], shape (n,).
        qd: Output speed per sample [rad/s], shape (n,).
        qdd: Output acceleration per sample [rad/s^2], shape (n,).
        efficiency: Gear efficiency [-], used when the unit has no table.
        rotor_inertia: Motor rotor inertia J_m [kg m^2].

    Returns:
        The summary, and the motor torque per sample [N m], shape (n,).
    """
    ratio = unit.ratio
    eta: float | np.ndarray
    if unit.efficiency is not None:
        eta = unit.efficiency(np.abs(qd) * ratio * RPM_PER_RAD_S,
                              100.0 * np.abs(tau) / unit.rated_torque)
        used: float | str = "table"
    else:
        eta = efficiency
        used = efficiency
    driving = tau * qd >= 0.0
    torque = np.where(driving, tau / (ratio * eta), tau * eta / ratio)
    torque = torque + (unit.input_inertia + rotor_inertia) * ratio * qdd
    summary = MotorDemand(
        peak_torque=float(np.abs(torque).max()),
        rms_torque=float(np.sqrt(np.mean(torque * torque))),
        max_speed=float(np.abs(qd).max() * ratio * RPM_PER_RAD_S),
        efficiency=used,
    )
    return summary, torque


def worst_momentary(
    unit: Unit,
    t: np.ndarray,
    tau: np.ndarray,
    qd: np.ndarray,
    stop_tau: np.ndarray,
    stop_time: float,
    *,
    rotor_inertia: float = 0.0,
) -> Momentary:
    """The worse of an emergency stop and a crash, at the worst instant of the cycle.

    Emergency stop: at any instant every joint is brought to rest within
    `stop_time`; `stop_tau` is the output torque at the start of that stop.
    Crash: the output stops dead while the input still spins; the input
    inertia (J_in + J_m) is brought to rest through the gear within `stop_time`,
    adding (J_in + J_m) N^2 |qd| / stop_time to the torque already carried.

    Args:
        unit: The gearhead.
        t: Sample times [s], shape (n,).
        tau: Output torque along the cycle [N m], shape (n,).
        qd: Output speed along the cycle [rad/s], shape (n,).
        stop_tau: Output torque at the start of an emergency stop from each sample [N m].
        stop_time: Time to bring everything to rest [s].
        rotor_inertia: Motor rotor inertia J_m [kg m^2].

    Returns:
        The worse event, with its speed and duration (for the allowed-event count).
    """
    stop = np.abs(stop_tau)
    reflected = (unit.input_inertia + rotor_inertia) * unit.ratio**2
    crash = np.abs(tau) + reflected * np.abs(qd) / stop_time
    i_stop, i_crash = int(stop.argmax()), int(crash.argmax())
    if stop[i_stop] >= crash[i_crash]:
        return Momentary(float(stop[i_stop]), "emergency stop", float(abs(qd[i_stop])),
                         stop_time, float(t[i_stop]))
    return Momentary(float(crash[i_crash]), "crash", float(abs(qd[i_crash])), stop_time,
                     float(t[i_crash]))
