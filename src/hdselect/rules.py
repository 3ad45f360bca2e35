"""The catalog's rules: one joint's cycle against one gearhead's limits.

Both front ends use this module: `hdselect duty` builds the cycle from the
catalog page's phases, `hdselect size` from the sampled dynamics. A phase is
simply a sample whose duration is the phase time.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from hdselect.catalog import RATED_INPUT_SPEED_RPM, RATED_LIFE_HOURS, Flag, Unit

if TYPE_CHECKING:
    from hdselect.reflect import MotorDemand

RPM_PER_RAD_S = 60.0 / (2.0 * np.pi)
"""Revolutions per minute in one radian per second."""
ALLOWABLE_TORQUE_EXPONENT = 0.33
"""Exponent of the catalog's continuous-torque rule, T = (1750 / N)^0.33 T_N."""
L50_PER_L10 = 5.0
"""Harmonic Drive's ratio of average (L50) to 90 %-survival (L10) wave generator life."""
MOMENTARY_EVENTS_FACTOR = 1.0e4
"""Harmonic Drive's momentary-overload rule: allowed events = 1e4 / (2 (n/60) t)."""
CHECKS = ("peak", "mean", "speed", "momentary", "static", "life")


@dataclass(frozen=True)
class CycleLoad:
    """The output-side load of one joint over one cycle; the same for every gearhead.

    Attributes:
        peak_torque: Largest |T| while moving (the catalog's T1..T3) [N m].
        mean_torque: The seed's mean torque T_av over the moving part [N m];
            None when the joint never moves.
        mean_speed: Mean output speed over the moving part (dwells excluded) [rad/s].
        max_speed: Largest output speed [rad/s].
        moving_time: Time spent moving [s].
        static_torque: Largest |T| held at rest, input locked [N m]; None if never at rest.
    """

    peak_torque: float
    mean_torque: float | None
    mean_speed: float
    max_speed: float
    moving_time: float
    static_torque: float | None


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
class Check:
    """One rule applied to one gearhead.

    Attributes:
        value: The demand ([N m], input speed [rpm] or life [h]); None if the rule
            does not apply to this cycle.
        limit: What the gearhead allows (for ``life``: what the user requires).
        ok: The rule holds.
        utilization: Demand over allowance [-] (life: required over expected); 0 if
            the rule does not apply, above 1 when it fails.
        detail: Extra figures for reports, e.g. ``{"kind": "crash"}``.
    """

    value: float | None
    limit: float
    ok: bool
    utilization: float
    detail: dict[str, object] = field(default_factory=dict)


@dataclass(frozen=True)
class Candidate:
    """One gearhead against one joint's cycle.

    Attributes:
        unit: The gearhead.
        checks: Each rule by name, in the order of `CHECKS`.
        life_hours: L50 life [h]; None when unlimited (no load while moving).
        flags: Catalog stand-ins and corrections this result depends on.
        motor: What the motor behind it must deliver, when computed (hdselect size).
    """

    unit: Unit
    checks: dict[str, Check]
    life_hours: float | None
    flags: tuple[Flag, ...]
    motor: MotorDemand | None = None

    @property
    def feasible(self) -> bool:
        """Every rule holds."""
        return all(check.ok for check in self.checks.values())

    @property
    def binding(self) -> str:
        """Name of the rule with the highest utilization."""
        return max(self.checks, key=lambda name: self.checks[name].utilization)

    @property
    def l10_hours(self) -> float | None:
        """L10 life, L50 / 5 [h]; None when unlimited."""
        return None if self.life_hours is None else self.life_hours / L50_PER_L10

    @property
    def margin(self) -> float:
        """Worst-case margin, 1 minus the highest utilization [-]."""
        return 1.0 - self.checks[self.binding].utilization


def cycle_load(
    torque: np.ndarray,
    speed: np.ndarray,
    duration: np.ndarray | float,
    at_rest: np.ndarray,
    *,
    static_torque: float | None = None,
) -> CycleLoad:
    """Summarise one joint's cycle with the catalog page's formulas.

    Args:
        torque: Output torque of each sample or phase [N m]; sign ignored.
        speed: Output speed of each sample or phase [rad/s]; sign ignored.
        duration: Duration of each sample or phase [s].
        at_rest: True where the joint is held still (input locked): these count
            towards the static check, not towards the peak, mean torque or mean speed.
        static_torque: An extra torque held at rest [N m], if any.

    Returns:
        The summary. The mean speed averages over the moving part only, as the
        catalog page writes it; dwells do not dilute it (the conservative reading).
    """
    torque = np.abs(np.asarray(torque, dtype=float))
    speed = np.abs(np.asarray(speed, dtype=float))
    duration = np.broadcast_to(np.asarray(duration, dtype=float), torque.shape)
    moving = ~np.asarray(at_rest, dtype=bool)
    weight = speed * duration * moving
    moving_time = float(duration[moving].sum())
    travel = float(weight.sum())
    mean_torque = (float(np.cbrt(np.dot(weight, torque**3) / travel)) if travel > 0.0 else None)
    held = [float(torque[~moving].max())] if (~moving).any() else []
    if static_torque is not None:
        held.append(abs(static_torque))
    return CycleLoad(
        peak_torque=float(torque[moving].max()) if moving.any() else 0.0,
        mean_torque=mean_torque,
        mean_speed=travel / moving_time if moving_time > 0.0 else 0.0,
        max_speed=float(speed.max()) if speed.size else 0.0,
        moving_time=moving_time,
        static_torque=max(held) if held else None,
    )


def allowable_mean_torque(unit: Unit, mean_input_speed_rpm: float) -> tuple[float, bool]:
    """The catalog's continuous-torque rule, capped by the repeated-peak limit.

    Args:
        unit: The gearhead.
        mean_input_speed_rpm: Mean input speed N_av [rpm].

    Returns:
        The allowable mean output torque [N m] and whether the cap bound it.
    """
    if mean_input_speed_rpm <= 0.0:
        return unit.repeated_torque, True
    rule = (RATED_INPUT_SPEED_RPM / mean_input_speed_rpm) ** ALLOWABLE_TORQUE_EXPONENT
    allowed = rule * unit.rated_torque
    return min(allowed, unit.repeated_torque), allowed >= unit.repeated_torque


def l50_life_hours(unit: Unit, mean_torque: float, mean_input_speed_rpm: float) -> float | None:
    """L50 = 35000 h x (1750 / N_av) x (T_N / T_av)^3; None when unlimited."""
    if mean_torque <= 0.0 or mean_input_speed_rpm <= 0.0:
        return None
    return (RATED_LIFE_HOURS * (RATED_INPUT_SPEED_RPM / mean_input_speed_rpm)
            * (unit.rated_torque / mean_torque) ** 3)


def allowed_momentary_events(input_speed_rpm: float, duration: float) -> float | None:
    """Number of momentary overloads a unit survives: 1e4 / (2 (n_in/60) t); None if unlimited."""
    revolutions = 2.0 * (input_speed_rpm / 60.0) * duration
    return MOMENTARY_EVENTS_FACTOR / revolutions if revolutions > 0.0 else None


def check_unit(
    load: CycleLoad,
    unit: Unit,
    *,
    momentary: Momentary | None = None,
    life_hours: float | None = None,
    motor: MotorDemand | None = None,
) -> Candidate:
    """Apply every rule of the catalog to one gearhead.

    Args:
        load: The joint's cycle on the output side.
        unit: The gearhead.
        momentary: The worst momentary (T4) event for this unit, if any.
        life_hours: Required L50 life [h]; adds the ``life`` check.
        motor: The motor-side demand, carried into the result as is.

    Returns:
        The candidate with every check, life and the flags it depends on.
    """
    mean_input_rpm = load.mean_speed * RPM_PER_RAD_S * unit.ratio
    allowed, capped = allowable_mean_torque(unit, mean_input_rpm)
    checks = {
        "peak": _check(load.peak_torque, unit.repeated_torque),
        "mean": _check(load.mean_torque, allowed, mean_input_speed_rpm=mean_input_rpm,
                       capped_by_repeated=capped),
        "speed": _check(load.max_speed * RPM_PER_RAD_S * unit.ratio, unit.max_input_speed),
    }
    if momentary is None:
        checks["momentary"] = _check(None, unit.momentary_torque)
    else:
        detail: dict[str, object] = {"kind": momentary.kind}
        if momentary.speed is not None and momentary.duration is not None:
            event_rpm = abs(momentary.speed) * RPM_PER_RAD_S * unit.ratio
            detail["allowed_events"] = allowed_momentary_events(event_rpm, momentary.duration)
        if momentary.time is not None:
            detail["time_s"] = momentary.time
        checks["momentary"] = _check(abs(momentary.torque), unit.momentary_torque, **detail)
    checks["static"] = _check(load.static_torque, unit.static_torque)
    life = (l50_life_hours(unit, load.mean_torque, mean_input_rpm)
            if load.mean_torque is not None else None)
    if life_hours is not None:
        utilization = 0.0 if life is None else life_hours / life
        checks["life"] = Check(life, life_hours, utilization <= 1.0, utilization)
    used = {"peak": "repeated_torque", "mean": "rated_torque", "momentary": "momentary_torque",
            "static": "static_torque"}
    fields = [used[name] for name, check in checks.items()
              if name in used and check.value is not None]
    if motor is not None:
        fields.append("input_inertia")
    return Candidate(unit, checks, life, unit.flags_for(*fields), motor)


def _check(value: float | None, limit: float, **detail: object) -> Check:
    utilization = 0.0 if value is None else value / limit
    return Check(value, limit, utilization <= 1.0, utilization, dict(detail))
