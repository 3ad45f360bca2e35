"""The smallest uniform slow-down of a motion that lets a joint pass with some unit.

Run s times slower, speeds scale as 1/s and the velocity- and acceleration-
dependent torques as 1/s^2 while gravity stays. An emergency stop's
deceleration -qd / (s t_stop) scales as 1/s, so its inertial part does too,
while its velocity (Coriolis, centrifugal) part scales as 1/s^2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from hdselect.catalog import Unit
from hdselect.plan import Trajectory
from hdselect.reflect import reflect
from hdselect.rules import check_unit, cycle_load

_GIVE_UP = 1e3
"""Largest slow-down tried; beyond it the motion is as good as standing still [-]."""


@dataclass(frozen=True)
class Slowdown:
    """The smallest uniform slow-down of the motion that lets a joint pass.

    Attributes:
        factor: Time scale s >= 1 (the motion run s times slower), or None when
            no slow-down helps (gravity alone is too much).
        unit: The unit that passes at that factor.
        cycle_time: The slowed cycle time [s].
    """

    factor: float | None
    unit: str | None
    cycle_time: float | None


def find_slowdown(
    units: Sequence[Unit],
    traj: Trajectory,
    qd: np.ndarray,
    qdd: np.ndarray,
    tau: np.ndarray,
    stop_tau: np.ndarray,
    gravity: np.ndarray,
    coast: np.ndarray,
    at_rest: np.ndarray,
    *,
    stop_time: float,
    efficiency: float,
    rotor_inertia: float,
    life_hours: float | None,
) -> Slowdown:
    """The smallest slow-down, over all units, at which one joint passes every rule.

    Args:
        units: The catalog.
        traj: The trajectory at full speed.
        qd: The joint's speed [rad/s], shape (n,).
        qdd: The joint's acceleration [rad/s^2], shape (n,).
        tau: Its torque along the motion [N m], shape (n,).
        stop_tau: Its torque at the start of an emergency stop from each sample [N m].
        gravity: Its gravity torque at each sample [N m].
        coast: Its torque at full speed with no acceleration (gravity plus velocity
            terms) [N m].
        at_rest: Samples where the joint is held still.
        stop_time: Emergency-stop and crash time [s].
        efficiency: Gear efficiency where a unit has no table [-].
        rotor_inertia: Motor rotor inertia [kg m^2].
        life_hours: Required L50 life [h], if any.

    Returns:
        The factor (to 0.1 %) and the unit, or a factor of None when no slow-down helps.
    """

    def passes(unit: Unit, s: float) -> bool:
        torque = gravity + (tau - gravity) / s**2
        stop = gravity + (stop_tau - coast) / s + (coast - gravity) / s**2
        load = cycle_load(torque, qd / s, traj.dt * s, at_rest)
        (reflection,) = reflect([unit], traj.t * s, torque, qd / s, qdd / s**2, stop,
                                stop_time=stop_time, efficiency=efficiency,
                                rotor_inertia=rotor_inertia)
        return check_unit(load, unit, momentary=reflection.momentary,
                          life_hours=life_hours).feasible

    best: tuple[float, str] | None = None
    for unit in units:
        factor = _smallest_factor(lambda s, unit=unit: passes(unit, s))
        if factor is not None and (best is None or factor < best[0]):
            best = (factor, unit.id)
    if best is None:
        return Slowdown(None, None, None)
    return Slowdown(best[0], best[1], best[0] * traj.duration)


def _smallest_factor(passes) -> float | None:
    """Smallest s >= 1 with passes(s), by a geometric scan and bisection to 0.1 %."""
    if not passes(_GIVE_UP):
        return None
    low, high = 1.0, 1.1
    while not passes(high):
        low, high = high, high * 1.1
    while high / low > 1.001:
        middle = (low * high) ** 0.5
        low, high = (low, middle) if passes(middle) else (middle, high)
    return high
