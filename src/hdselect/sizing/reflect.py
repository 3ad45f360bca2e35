"""Reflect a joint's demand through a gearhead: input speed, motor torque, crash torque.

The gear teeth carry the load torque tau from inverse dynamics. The motor
behind a unit of ratio N, efficiency eta and input inertia J_in (plus the
rotor inertia J_m) must deliver

    T_motor = tau / (N eta)   while the motor drives the load (tau qd >= 0),
              tau eta / N     while the load drives back (tau qd < 0),
            + (J_in + J_m) N qdd

at the input speed N qd. A joint at rest (`hdselect.catalog.rules.at_rest`: speed and
acceleration negligible, the input held) counts as driven: the motor holds the load
through the gear, tau / (N eta). The direction of the power flow is then no more than
the sign of a speed that is zero but for rounding (a logged position's spline), and
must not decide the holding torque.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from hdselect.catalog.rules import RPM_PER_RAD_S, Momentary, MotorDemand, at_rest
from hdselect.catalog.rules.momentary import crash_gain, crash_torques
from hdselect.catalog.units import Unit
from hdselect.motion.option_specs import DEFAULT_EFFICIENCY

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
    _cycle: tuple[np.ndarray, np.ndarray, np.ndarray, float, float, np.ndarray] = field(
        repr=False)
    _torque: np.ndarray | None = field(default=None, repr=False)
    _expand: np.ndarray | None = field(default=None, repr=False)
    _starts: np.ndarray | None = field(default=None, repr=False)

    @property
    def motor_torque(self) -> np.ndarray:
        """Motor torque per sample [N m], shape (n,).

        Kept from the reflection for a cycle of one `CHUNK` (once per run of identical
        samples); for a longer one computed when asked for (the same floats), so a long
        cycle's reflections stay small.
        """
        if self._torque is not None:
            return self._torque if self._expand is None else self._torque[self._expand]
        tau, qd, qdd, efficiency, rotor_inertia, rest = self._cycle
        return _motor_torques([self.unit], tau, qd, qdd, efficiency, rotor_inertia, rest)[0]

    def distinct_motor_torque(self) -> tuple[np.ndarray, np.ndarray | None]:
        """Motor torque once per run of identical samples [N m], and each run's first sample.

        A run's samples are identical, so a rule of single samples (the motor's peak at
        its speed) judged on these is judged on every sample, first worst sample first.
        Where the reflection keeps no runs: every sample, and None.
        """
        if self._torque is not None and self._starts is not None:
            return self._torque, self._starts
        return self.motor_torque, None


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
    rest: np.ndarray | None = None,
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
        rest: Where the joint is held still, shape (n,); None: `at_rest` of these samples.

    Returns:
        One reflection per unit, in the order given.
    """
    return reflect_motors(units, (rotor_inertia,), t, tau, qd, qdd, stop_tau,
                          stop_time=stop_time, efficiency=efficiency, rest=rest)[0]


def reflect_motors(
    units: Sequence[Unit],
    rotor_inertias: Sequence[float],
    t: np.ndarray,
    tau: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    stop_tau: np.ndarray,
    *,
    stop_time: float,
    efficiency: float = DEFAULT_EFFICIENCY,
    rest: np.ndarray | None = None,
) -> list[list[Reflection]]:
    """Reflect one joint's cycle through every unit, behind each of several motors.

    The gear side (efficiency, ratio) is computed once per `CHUNK` samples; each
    motor's rotor inertia J_m then adds (J_in + J_m) N qdd to the motor torque and
    (J_in + J_m) N^2 |qd| / stop_time to the crash, exactly as `reflect` does for one
    rotor inertia.

    Args:
        units: The gearheads.
        rotor_inertias: Each motor's rotor inertia J_m [kg m^2].
        t: Sample times [s], shape (n,).
        tau: Output (load) torque per sample [N m], shape (n,).
        qd: Output speed per sample [rad/s], shape (n,).
        qdd: Output acceleration per sample [rad/s^2], shape (n,).
        stop_tau: Output torque at the start of an emergency stop from each sample [N m].
        stop_time: Time to bring everything to rest [s].
        efficiency: Gear efficiency [-], for units without a table.
        rest: Where the joint is held still, shape (n,); None: `at_rest` of these samples
            (a robot's pooled tasks give each task's own).

    Returns:
        Per rotor inertia, in the order given, one reflection per unit.
    """
    n = len(t)
    ratio = np.array([unit.ratio for unit in units], dtype=float)
    inertias = [float(j) for j in rotor_inertias]
    inertia = np.add.outer(inertias, [unit.input_inertia for unit in units])  # (motors, units)
    gain = crash_gain(inertia, ratio, stop_time)
    peak = np.zeros(inertia.shape)
    squares = np.zeros(inertia.shape)
    crash_best = np.full(inertia.shape, -np.inf)
    crash_at = np.zeros(inertia.shape, dtype=int)
    rows = np.arange(len(units))
    kept: list[np.ndarray | None] = [None] * len(inertias)  # a one-chunk cycle's torques
    resting = at_rest(qd, qdd) if rest is None else np.asarray(rest, dtype=bool)
    starts, counts = _runs(tau, qd, qdd, resting)
    m = len(starts)
    for first in range(0, m, CHUNK):
        part = starts[first:first + CHUNK]
        count = counts[first:first + CHUNK] if counts is not None else None
        geared = _geared(units, ratio, tau[part], qd[part], efficiency, resting[part])
        speed, held, accel = np.abs(qd[part]), np.abs(tau[part]), qdd[part]
        for k in range(len(inertias)):
            motor = geared + np.multiply.outer(inertia[k] * ratio, accel)
            peak[k] = np.maximum(peak[k], np.maximum(motor.max(axis=1), -motor.min(axis=1)))
            squares[k] += np.einsum("ij,ij->i", motor, motor if count is None else motor * count)
            crash = crash_torques(gain[k], speed, held)
            i = crash.argmax(axis=1)
            better = crash[rows, i] > crash_best[k]  # strictly: the first worst instant wins
            crash_best[k] = np.where(better, crash[rows, i], crash_best[k])
            crash_at[k] = np.where(better, part[i], crash_at[k])
            if m <= CHUNK:
                kept[k] = motor
    expand = None if counts is None else np.repeat(np.arange(m), counts)
    rms = np.sqrt(squares / n)
    max_speed = float(np.abs(qd).max()) * RPM_PER_RAD_S * ratio
    rms_speed = float(np.sqrt(np.einsum("i,i->", qd, qd) / n)) * RPM_PER_RAD_S * ratio
    stop = np.abs(stop_tau)
    i_stop = int(stop.argmax())
    out = []
    for k, rotor_inertia in enumerate(inertias):
        behind = []
        for row, unit in enumerate(units):
            at = int(crash_at[k, row])
            if stop[i_stop] >= crash_best[k, row]:
                event = Momentary(float(stop[i_stop]), "emergency stop",
                                  float(abs(qd[i_stop])), stop_time, float(t[i_stop]))
            else:
                event = Momentary(float(crash_best[k, row]), "crash", float(abs(qd[at])),
                                  stop_time, float(t[at]))
            demand = MotorDemand(float(peak[k, row]), float(rms[k, row]), float(max_speed[row]),
                                 "table" if unit.efficiency is not None else efficiency,
                                 float(rms_speed[row]))
            torque = kept[k]
            behind.append(Reflection(unit, demand, event,
                                     (tau, qd, qdd, efficiency, rotor_inertia, resting),
                                     None if torque is None else torque[row], expand,
                                     None if counts is None else starts))
        out.append(behind)
    return out


def _runs(tau: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
          rest: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """The first sample of each run of identical samples (a dwell), and each run's length.

    Identical samples give identical reflections, so each run is reflected once and its
    squares counted as many times as it repeats. Where few samples repeat, every sample
    is its own run (lengths None).
    """
    n = len(tau)
    if n < 2:
        return np.arange(n), None
    repeat = ((tau[1:] == tau[:-1]) & (qd[1:] == qd[:-1]) & (qdd[1:] == qdd[:-1])
              & (rest[1:] == rest[:-1]))
    if np.count_nonzero(repeat) * _REPEATS_WORTH <= n:
        return np.arange(n), None
    starts = np.flatnonzero(np.r_[True, ~repeat])
    return starts, np.diff(np.append(starts, n))


_REPEATS_WORTH = 8
"""Runs of identical samples are reflected once when more than 1 in this many repeat."""


def _geared(units: Sequence[Unit], ratio: np.ndarray, tau: np.ndarray, qd: np.ndarray,
            efficiency: float, held: np.ndarray) -> np.ndarray:
    """Gear-side torque over the ratio of every unit at every sample given [N m], (units, n).

    tau / eta while the motor drives (tau qd >= 0) or holds (`held`, at rest), tau eta
    while the load drives back.
    """
    driving = (tau * qd >= 0.0) | held
    load = np.empty((len(units), len(tau)))
    load[:] = np.where(driving, tau * (1.0 / efficiency), tau * efficiency)
    for row, unit in enumerate(units):
        if unit.efficiency is not None:
            eta = unit.efficiency(np.abs(qd) * unit.ratio * RPM_PER_RAD_S,
                                  100.0 * np.abs(tau) / unit.rated_torque)
            load[row] = tau * np.where(driving, 1.0 / eta, eta)
    load *= (1.0 / ratio)[:, None]
    return load


def _motor_torques(units: Sequence[Unit], tau: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                   efficiency: float, rotor_inertia: float, rest: np.ndarray) -> np.ndarray:
    """Motor torque of every unit at every sample given [N m], shape (units, n)."""
    ratio = np.array([unit.ratio for unit in units], dtype=float)
    inertia = np.array([unit.input_inertia for unit in units]) + rotor_inertia
    return (_geared(units, ratio, tau, qd, efficiency, rest)
            + np.multiply.outer(inertia * ratio, qdd))


def weighted_demand(demand: MotorDemand, motor_torque: np.ndarray, qd: np.ndarray, ratio: float,
                    weight: np.ndarray) -> MotorDemand:
    """A motor demand with its RMS torque and RMS speed over samples of unequal length.

    `reflect` takes every sample to stand for the same time. Where each stands for
    `weight` of them (a study's runs of identical samples, each kept once), the RMS
    values weight each sample's square by it; the peak and largest speed stay.

    Args:
        demand: The demand `reflect` found on these samples.
        motor_torque: Motor torque per sample [N m], shape (n,).
        qd: Output speed per sample [rad/s], shape (n,).
        ratio: The gearhead's ratio [-].
        weight: What each sample stands for (any positive scale, e.g. its duration), (n,).

    Returns:
        The demand with `rms_torque` [N m] and `rms_speed` [rpm] weighted.
    """
    total = float(weight.sum())
    # einsum, not np.dot: a threaded BLAS dot of one long vector can cost milliseconds
    rms = float(np.sqrt(np.einsum("i,i,i->", weight, motor_torque, motor_torque) / total))
    rms_speed = float(np.sqrt(np.einsum("i,i,i->", weight, qd, qd) / total)) \
        * RPM_PER_RAD_S * ratio
    return replace(demand, rms_torque=rms, rms_speed=rms_speed)
