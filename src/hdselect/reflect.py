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

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from hdselect.catalog import Unit
from hdselect.rules import RPM_PER_RAD_S, Momentary, MotorDemand

DEFAULT_EFFICIENCY = 0.70
"""Gear efficiency used where a catalog gives no table [-]. The PSA-G page shows
efficiency curves but no numbers; 70 % is a mid-range reading for small
Harmonic Drive units near rated torque, and lower at light load."""


CHUNK = 1 << 15
"""Samples reflected at a time: the per-unit work of a long cycle stays a few MB."""


@dataclass(frozen=True, eq=False)
class Reflection:
    """One joint's cycle seen through one gearhead.

    Attributes:
        unit: The gearhead.
        motor: What the motor must deliver over the cycle.
        momentary: The worse of an emergency stop and a crash.
    """

    unit: Unit
    motor: MotorDemand
    momentary: Momentary
    _cycle: tuple[np.ndarray, np.ndarray, np.ndarray, float, float] = field(repr=False)

    @property
    def motor_torque(self) -> np.ndarray:
        """Motor torque per sample [N m], shape (n,); computed when asked for."""
        tau, qd, qdd, efficiency, rotor_inertia = self._cycle
        return _motor_torques([self.unit], tau, qd, qdd, efficiency, rotor_inertia)[0]


def reflect(
    units: Sequence[Unit],
    t: np.ndarray,
    tau: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    stop_tau: np.ndarray,
    *,
    stop_time: float,
    efficiency: float = DEFAULT_EFFICIENCY,
    rotor_inertia: float = 0.0,
) -> list[Reflection]:
    """Reflect one joint's cycle through every unit at once, `CHUNK` samples at a time.

    Emergency stop: from any instant every joint is brought to rest within
    `stop_time`; `stop_tau` is the output torque at the start of that stop.
    Crash: the output stops dead while the input still spins; the input
    inertia (J_in + J_m) is brought to rest through the gear within `stop_time`,
    adding (J_in + J_m) N^2 |qd| / stop_time to the torque already carried.

    Args:
        units: The gearheads.
        t: Sample times [s], shape (n,).
        tau: Output (load) torque per sample [N m], shape (n,).
        qd: Output speed per sample [rad/s], shape (n,).
        qdd: Output acceleration per sample [rad/s^2], shape (n,).
        stop_tau: Output torque at the start of an emergency stop from each sample [N m].
        stop_time: Time to bring everything to rest [s].
        efficiency: Gear efficiency [-], for units without a table.
        rotor_inertia: Motor rotor inertia J_m [kg m^2].

    Returns:
        One reflection per unit, in the order given.
    """
    n = len(t)
    ratio = np.array([unit.ratio for unit in units], dtype=float)
    inertia = np.array([unit.input_inertia for unit in units]) + rotor_inertia
    crash_gain = inertia * ratio**2 / stop_time
    peak = np.zeros(len(units))
    squares = np.zeros(len(units))
    crash_best = np.full(len(units), -np.inf)
    crash_at = np.zeros(len(units), dtype=int)
    rows = np.arange(len(units))
    for start in range(0, n, CHUNK):
        part = slice(start, start + CHUNK)
        motor = _motor_torques(units, tau[part], qd[part], qdd[part], efficiency, rotor_inertia)
        peak = np.maximum(peak, np.abs(motor).max(axis=1))
        squares += np.einsum("ij,ij->i", motor, motor)
        crash = np.multiply.outer(crash_gain, np.abs(qd[part]))
        crash += np.abs(tau[part])
        k = crash.argmax(axis=1)
        better = crash[rows, k] > crash_best  # strictly: the first worst instant wins
        crash_best = np.where(better, crash[rows, k], crash_best)
        crash_at = np.where(better, k + start, crash_at)
    rms = np.sqrt(squares / n)
    speed_max = float(np.abs(qd).max())
    max_speed = speed_max * RPM_PER_RAD_S * ratio
    stop = np.abs(stop_tau)
    i_stop = int(stop.argmax())
    out = []
    for row, unit in enumerate(units):
        k = int(crash_at[row])
        if stop[i_stop] >= crash_best[row]:
            event = Momentary(float(stop[i_stop]), "emergency stop", float(abs(qd[i_stop])),
                              stop_time, float(t[i_stop]))
        else:
            event = Momentary(float(crash_best[row]), "crash", float(abs(qd[k])), stop_time,
                              float(t[k]))
        demand = MotorDemand(float(peak[row]), float(rms[row]), float(max_speed[row]),
                             "table" if unit.efficiency is not None else efficiency)
        out.append(Reflection(unit, demand, event, (tau, qd, qdd, efficiency, rotor_inertia)))
    return out


def _motor_torques(units: Sequence[Unit], tau: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                   efficiency: float, rotor_inertia: float) -> np.ndarray:
    """Motor torque of every unit at every sample given [N m], shape (units, n)."""
    ratio = np.array([unit.ratio for unit in units], dtype=float)
    inertia = np.array([unit.input_inertia for unit in units]) + rotor_inertia
    driving = tau * qd >= 0.0
    speed = np.abs(qd)
    # gear side: tau / eta while the motor drives, tau eta while the load drives back
    load = np.empty((len(units), len(tau)))
    load[:] = np.where(driving, tau * (1.0 / efficiency), tau * efficiency)
    for row, unit in enumerate(units):
        if unit.efficiency is not None:
            eta = unit.efficiency(speed * unit.ratio * RPM_PER_RAD_S,
                                  100.0 * np.abs(tau) / unit.rated_torque)
            load[row] = tau * np.where(driving, 1.0 / eta, eta)
    load *= (1.0 / ratio)[:, None]
    load += np.multiply.outer(inertia * ratio, qdd)
    return load
