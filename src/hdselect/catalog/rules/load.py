"""What the rules read of one joint's cycle: its load, momentary event and motor demand.

Both front ends build these: `hdselect duty` from the catalog page's phases, `hdselect
size` from the sampled dynamics. A phase is simply a sample whose duration is the phase
time. The catalog page's formulas that several rules share (the allowable mean torque,
the L50 life, the momentary events allowed) are here too; no series' numbers live here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hdselect.catalog.units import SeriesRules, Unit

RPM_PER_RAD_S = 60.0 / (2.0 * np.pi)
"""Revolutions per minute in one radian per second."""


ALLOWABLE_TORQUE_EXPONENT = 0.33
"""Exponent of the speed-adjusted mean-torque rule, T = (n_rated / N_av)^0.33 T_N."""


MOMENTARY_EVENTS_FACTOR = 1.0e4
"""Harmonic Drive's momentary-overload rule: allowed events = 1e4 / (2 (n/60) t)."""


REST_FRACTION = 1e-3
"""A joint is at rest (input held) where both its speed and its acceleration are below
this fraction of their largest values in the cycle [-]."""
_CHUNK = 1 << 16
"""Samples summed at a time by `cycle_load` (with `numpy.einsum`: a BLAS dot of one long
vector may hand it to threads that, on a loaded machine, cost milliseconds per call)."""


@dataclass(frozen=True)
class CycleLoad:
    """The output-side load of one joint over one cycle; the same for every gearhead.

    Attributes:
        peak_torque: Largest |T| while moving (the catalog's T1..T3) [N m].
        mean_torque: The mean torque T_av over the moving part [N m]; None when the
            joint never moves.
        mean_speed: Mean output speed over the moving part (dwells excluded) [rad/s].
        max_speed: Largest output speed [rad/s].
        moving_time: Time spent moving [s].
        cycle_time: Time of the whole cycle, dwells included [s].
        static_torque: Largest |T| held at rest, input locked [N m]; None if never at rest.
    """

    peak_torque: float
    mean_torque: float | None
    mean_speed: float
    max_speed: float
    moving_time: float
    cycle_time: float
    static_torque: float | None

    @property
    def cycle_mean_speed(self) -> float:
        """Mean output speed over the whole cycle, dwells included [rad/s]."""
        if self.cycle_time <= 0.0:
            return 0.0
        return self.mean_speed * self.moving_time / self.cycle_time

    def mean_speed_under(self, rules: SeriesRules) -> float:
        """Mean output speed N_av as a series' rules define it [rad/s].

        `MeanSpeed.MOVING`: over the moving part (`mean_speed`); `MeanSpeed.WHOLE_CYCLE`:
        over the whole cycle, dwells included (`cycle_mean_speed`).
        """
        return rules.mean_speed.of(self.mean_speed, self.cycle_mean_speed)


@dataclass(frozen=True)
class Momentary:
    """The worst momentary (T4) event of a cycle for one gearhead.

    Attributes:
        torque: Output torque of the event [N m].
        kind: What it was: ``"given"``, ``"emergency stop"`` or ``"crash"``.
        speed: Output speed when it happens [rad/s], if known.
        duration: How long it lasts [s], if known.
        time: When in the cycle it happens [s], if known.
    """

    torque: float
    kind: str
    speed: float | None = None
    duration: float | None = None
    time: float | None = None


@dataclass(frozen=True)
class MotorDemand:
    """What the motor behind one gearhead must deliver over the cycle.

    Attributes:
        peak_torque: Largest |T_motor| [N m].
        rms_torque: Root mean square of T_motor over the whole cycle [N m].
        max_speed: Largest input speed [rpm].
        efficiency: The efficiency used: a number, or ``"table"`` for the unit's own table.
        rms_speed: Root mean square of the input speed over the whole cycle [rpm]: with
            `rms_torque`, the cycle's RMS point on the motor's torque-speed plane.
    """

    peak_torque: float
    rms_torque: float
    max_speed: float
    efficiency: float | str
    rms_speed: float | None = None


def cycle_load(
    torque: np.ndarray,
    speed: np.ndarray,
    duration: np.ndarray | float,
    at_rest: np.ndarray,
    *,
    static_torque: float | None = None,
    idle: float = 0.0,
) -> CycleLoad:
    """Summarise one joint's cycle with the catalog page's formulas.

    Args:
        torque: Output torque of each sample or phase [N m]; sign ignored.
        speed: Output speed of each sample or phase [rad/s]; sign ignored.
        duration: Duration of each sample or phase [s].
        at_rest: True where the joint is held still (input locked): these count
            towards the static check, not towards the peak, mean torque or the
            moving-part mean speed.
        static_torque: An extra torque held at rest [N m], if any.
        idle: Time at rest that no sample stands for [s], in the samples' time: the
            idle part of a robot's hour. A pause, it counts in the cycle time (the
            whole-cycle mean speed) and in nothing else.

    Returns:
        The summary. `CycleLoad.mean_speed` averages over the moving part; a series
        whose rules average over the whole cycle reads `CycleLoad.mean_speed_under`.
    """
    torque = np.asarray(torque, dtype=float)
    speed = np.asarray(speed, dtype=float)
    duration = np.broadcast_to(np.asarray(duration, dtype=float), torque.shape)
    at_rest = np.broadcast_to(np.asarray(at_rest, dtype=bool), torque.shape)
    moving_time = travel = cubes = cycle_time = 0.0
    peak = max_speed = 0.0
    held: list[float] = [] if static_torque is None else [abs(static_torque)]
    for start in range(0, len(torque), _CHUNK):  # a long cycle in pieces of bounded memory
        part = slice(start, start + _CHUNK)
        tau, moving, step = np.abs(torque[part]), ~at_rest[part], duration[part]
        weight = np.abs(speed[part]) * step * moving
        moving_time += float(step[moving].sum())
        travel += float(weight.sum())
        cubes += float(np.einsum("i,i->", weight, tau**3))  # no threaded BLAS dot: see below
        cycle_time += float(step.sum())
        peak = max(peak, float(tau[moving].max(initial=0.0)))
        max_speed = max(max_speed, float(np.abs(speed[part]).max(initial=0.0)))
        if not moving.all():
            held.append(float(tau[~moving].max()))
    return CycleLoad(
        peak_torque=peak,
        mean_torque=float(np.cbrt(cubes / travel)) if travel > 0.0 else None,
        mean_speed=travel / moving_time if moving_time > 0.0 else 0.0,
        max_speed=max_speed,
        moving_time=moving_time,
        cycle_time=cycle_time + idle,
        static_torque=max(held) if held else None,
    )


def allowable_mean_torque(unit: Unit, mean_input_speed_rpm: float) -> tuple[float, bool]:
    """The limit for the mean output torque under the unit's series rules.

    ``"tabulated"``: the unit's own limit for average torque. ``"speed-adjusted"``:
    (rated input speed / N_av)^0.33 x T_N, never above the repeated-peak limit.

    Args:
        unit: The gearhead.
        mean_input_speed_rpm: Mean input speed N_av [rpm].

    Returns:
        The allowable mean output torque [N m] and whether the repeated-peak cap bound it.
    """
    rules = unit.rules
    if rules.mean_torque_limit == "tabulated":
        if unit.average_torque is None:  # the catalog reader requires it for this rule
            raise TypeError(f"{unit.id}: a tabulated mean-torque limit needs the unit's "
                            "average torque")
        return unit.average_torque, False
    if mean_input_speed_rpm <= 0.0:
        return unit.repeated_torque, True
    rule = (rules.rated_input_speed / mean_input_speed_rpm) ** ALLOWABLE_TORQUE_EXPONENT
    allowed = rule * unit.rated_torque
    return min(allowed, unit.repeated_torque), allowed >= unit.repeated_torque


def l50_life_hours(unit: Unit, mean_torque: float, mean_input_speed_rpm: float) -> float | None:
    """L50 = L50_rated x (n_rated / N_av) x (T_N / T_av)^3 [h]; None when unlimited.

    L50_rated is the series' rated life on the L50 basis (5 x a rated L10). A life too
    long for a float (a torque or speed vanishingly small) is unlimited too.
    """
    if mean_torque <= 0.0 or mean_input_speed_rpm <= 0.0:
        return None
    rules = unit.rules
    try:
        life = (rules.rated_l50_hours * (rules.rated_input_speed / mean_input_speed_rpm)
                * (unit.rated_torque / mean_torque) ** 3)
    except OverflowError:
        return None
    return life if math.isfinite(life) else None


def allowed_momentary_events(input_speed_rpm: float, duration: float, *,
                             cap: float | None = None) -> float | None:
    """Momentary overloads a unit survives: 1e4 / (2 (n_in/60) t), at most `cap`.

    Args:
        input_speed_rpm: Input speed during the event [rpm].
        duration: Duration of the event [s].
        cap: Most events ever allowed [-], the series' rules; None for no cap.

    Returns:
        The count [-]; None when unlimited (no revolution and no cap).
    """
    revolutions = 2.0 * (input_speed_rpm / 60.0) * duration
    allowed = MOMENTARY_EVENTS_FACTOR / revolutions if revolutions > 0.0 else math.inf
    if cap is not None:
        allowed = min(allowed, cap)
    return allowed if math.isfinite(allowed) else None


def at_rest(qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Samples where a joint is held still: speed and acceleration both negligible.

    Args:
        qd: The joint's speed [rad/s], shape (n,).
        qdd: The joint's acceleration [rad/s^2], shape (n,).

    Returns:
        True where both are at most `REST_FRACTION` of their largest values.
    """
    speed, acceleration = np.abs(qd), np.abs(qdd)
    return ((speed <= REST_FRACTION * speed.max())
            & (acceleration <= REST_FRACTION * acceleration.max()))
