"""``momentary``: the worst emergency stop or crash within the unit's momentary torque.

An emergency stop brings every joint to rest within the stop time from any instant; a
crash stops the output dead while the input still spins, adding the input inertia's
(J_in + J_m) N^2 |qd| / t_stop to the torque already carried (`hdselect.sizing.reflect`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules.base import Gear, RuleInput, UnitLimit, within
from hdselect.catalog.rules.forms import (
    Interval,
    PathBound,
    PathCase,
    PathKind,
    PayloadCase,
    Rows,
    ScaleTerms,
    UnitBatch,
)
from hdselect.catalog.rules.load import RPM_PER_RAD_S, Momentary, allowed_momentary_events
from hdselect.catalog.rules.masses import EVERY_MASS, masses_within, meet, spans
from hdselect.catalog.units import Unit


class MomentaryTorque(UnitLimit):
    """The worst momentary event's |T| at most the momentary torque T_M.

    Its detail: the event's kind, the events the unit survives (with its speed and
    duration) and when it happens. Value None where no event is given.
    """

    name = "momentary"
    label = "mom."
    words = "momentary torque"
    unit = "N m"
    limit = "momentary_torque"

    def largest(self, case: RuleInput, gear: Gear) -> tuple[float | None, dict[str, object]]:
        """See `UnitLimit.largest`: the worst event's |T| [N m]."""
        unit, event = gear[0], case.momentary
        if event is None:
            return None, {}
        detail: dict[str, object] = {"kind": event.kind}
        if event.speed is not None and event.duration is not None:
            event_rpm = abs(event.speed) * RPM_PER_RAD_S * unit.ratio
            detail["allowed_events"] = allowed_momentary_events(
                event_rpm, event.duration, cap=unit.rules.max_momentary_events)
        if event.time is not None:
            detail["time_s"] = event.time
        return abs(event.torque), detail

    def scale_rows(self, terms: ScaleTerms, unit: Unit, margin: float) -> Sequence[Rows]:
        """Emergency stop |g + v y^2 + e y| <= T_M; crash |g + (v + i) y^2| + K |qd| y <= T_M."""
        if not self.rated(unit):
            return []
        limit = self.allowed(unit, margin)
        gain = (unit.input_inertia + terms.rotor_inertia) * unit.ratio**2 / terms.stop_time
        g, v = terms.gravity, terms.velocity
        a = v + terms.inertial
        crash = gain * np.abs(terms.qd)
        return (*within(v, terms.stop_inertial, g, limit),
                (a, crash, g - limit),  # tau + K |qd| y <= limit
                (-a, crash, -g - limit))  # -tau + K |qd| y <= limit

    def prefilter(self, batch: UnitBatch) -> np.ndarray | None:
        """See `Rule.prefilter`."""
        if batch.rotor_inertia is None:
            return None  # each motor's rotor inertia changes the crash
        worst = worst_events(batch)
        return self.utilizations(np.maximum(worst.stop_torque, worst.crash_torque),
                                 batch.units)

    def payload_masses(self, case: PayloadCase) -> tuple[Interval, ...]:
        """Emergency stop |stop0 + x stop1| <= T_M; crash |tau0 + x tau1| + K |qd| <= T_M."""
        if not self.rated(case.unit):
            return EVERY_MASS
        limit = self.allowed(case.unit, case.margin)
        gain = _gain(case.unit, case.rotor_inertia, case.stop_time)
        return spans(meet(masses_within(case.stop0, case.stop1, limit),
                          masses_within(case.tau0, case.tau1, limit - gain * np.abs(case.qd))))

    def path_rows(self, case: PathCase) -> list[Any]:
        """The emergency stop's and the crash's |tau| (+ K |qd|) <= T_M; none where not rated."""
        if not self.rated(case.unit):
            return []
        return [PathBound(PathKind.MOMENTARY, self.allowed(case.unit, case.margin),
                          gain=_gain(case.unit, case.rotor_inertia, case.stop_time))]


class WorstEvents:
    """Every unit's worst emergency stop and crash over a batch's samples.

    Attributes:
        stop_at: The sample of the worst emergency stop (the same for every unit).
        stop_torque: Its |torque| [N m].
        crash_at: Each unit's sample of its worst crash, (units,).
        crash_torque: Each unit's worst crash torque [N m], (units,).
    """

    def __init__(self, batch: UnitBatch) -> None:
        if batch.rotor_inertia is None:
            raise ValueError("a crash needs the rotor inertia")
        self._batch = batch
        inertia = np.array([unit.input_inertia for unit in batch.units]) + batch.rotor_inertia
        self.speed, stopping = np.abs(batch.qd), np.abs(batch.stop)
        self.stop_at = int(stopping.argmax())
        self.stop_torque = float(stopping[self.stop_at])
        crash = crash_torques(crash_gain(inertia, batch.ratio, batch.stop_time), self.speed,
                              np.abs(batch.torque))
        self.crash_at = crash.argmax(axis=1)
        self.crash_torque = crash[np.arange(len(batch.units)), self.crash_at]

    def event(self, k: int) -> Momentary:
        """Unit k's worst momentary event, as `hdselect.sizing.reflect` reports it."""
        t, stop_time = self._batch.t, self._batch.stop_time
        if self.stop_torque >= self.crash_torque[k]:
            return Momentary(self.stop_torque, "emergency stop", float(self.speed[self.stop_at]),
                             stop_time, float(t[self.stop_at]))
        i = int(self.crash_at[k])
        return Momentary(float(self.crash_torque[k]), "crash", float(self.speed[i]), stop_time,
                         float(t[i]))


def crash_gain(inertia: np.ndarray, ratio: np.ndarray, stop_time: float) -> np.ndarray:
    """K = (J_in + J_m) N^2 / t_stop of each unit [N m s], from its input-side inertia [kg m^2]."""
    gain: np.ndarray = inertia * ratio**2 / stop_time
    return gain


def crash_torques(gain: np.ndarray, speed: np.ndarray, held: np.ndarray) -> np.ndarray:
    """A crash's torque K |qd| + |T| of each unit at each sample [N m], (units, n).

    Args:
        gain: Each unit's K (`crash_gain`) [N m s], (units,).
        speed: |qd| per sample [rad/s], (n,).
        held: |T| per sample, the torque already carried [N m], (n,).
    """
    crash = np.multiply.outer(gain, speed)
    crash += held
    return crash


def worst_events(batch: UnitBatch) -> WorstEvents:
    """The batch's `WorstEvents`, found once and kept in its memo."""
    if "momentary" not in batch.memo:
        batch.memo["momentary"] = WorstEvents(batch)
    found: WorstEvents = batch.memo["momentary"]
    return found


MOMENTARY = MomentaryTorque()


def _gain(unit: Unit, rotor_inertia: float, stop_time: float) -> float:
    """One unit's crash gain K (`crash_gain`) behind a rotor of `rotor_inertia` [N m s]."""
    return float(crash_gain(np.array(unit.input_inertia + rotor_inertia),
                            np.array(float(unit.ratio)), stop_time))
