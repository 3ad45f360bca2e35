"""Every registered rule of a gearhead (and its output bearing) or of a motor, in order.

Both front ends use `check_unit`: `hdselect duty` builds the cycle from the catalog
page's phases, `hdselect size` from the sampled dynamics. Every rule reads the unit's
series rules (`hdselect.catalog.units.SeriesRules`); no series' numbers live here.
"""

from __future__ import annotations

import numpy as np

from hdselect.base.errors import InputError
from hdselect.catalog.bearing_rules import BearingLoad, bearing_figures
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.base import DEFAULT_MARGIN, Check, Part, Rule, RuleInput
from hdselect.catalog.rules.candidate import Candidate
from hdselect.catalog.rules.load import CycleLoad, Momentary, MotorDemand
from hdselect.catalog.rules.registry import rules_of
from hdselect.catalog.units import LIFE_BASES, NOT_RATED, WHOLE_UNIT, Flag, Unit

UNRATED_STIFFNESS = Flag("stiffness", "not-rated", f"torsional stiffness K1 {NOT_RATED}: "
                         "the joint's torsion and natural frequency targets are not checked")
"""The note on a unit judged against a precision target that its source rates no K1 for."""


def check_unit(
    load: CycleLoad,
    unit: Unit,
    *,
    momentary: Momentary | None = None,
    life_hours: float | None = None,
    life_basis: str = "L50",
    motor: MotorDemand | None = None,
    bearing: BearingLoad | None = None,
    margin: float = DEFAULT_MARGIN,
    max_torsion: float | None = None,
    min_frequency: float | None = None,
    load_inertia: float | None = None,
) -> Candidate:
    """Apply every registered rule of the gearhead and its output bearing to one unit.

    Args:
        load: The joint's cycle on the output side.
        unit: The gearhead.
        momentary: The worst momentary (T4) event for this unit, if any.
        life_hours: Required life [h] on `life_basis`; adds the ``life`` check.
        life_basis: ``"L10"`` or ``"L50"``: the basis of `life_hours`, and of the
            ``life`` check's value.
        motor: The motor-side demand, carried into the result as is.
        bearing: The loads on the unit's output bearing, about its centre: checked where
            the unit's catalog rates the bearing (`hdselect.catalog.rules.bearing`).
        margin: Design margin [-], in [0, 1): every rule must hold at (1 - margin) of
            its limit (`Rule.judge`), the output bearing's too; utilization stays
            demand / limit.
        max_torsion: The joint's largest twist allowed [rad]; adds the ``torsion`` check.
        min_frequency: The joint's lowest natural frequency asked for [Hz]; adds the
            ``natural_frequency`` check.
        load_inertia: The joint's load inertia J [kg m^2], the largest over the cycle's
            poses: the natural frequency's.

    Returns:
        The candidate with every check (in registry order), life and the flags it
        depends on.

    Raises:
        InputError: `life_basis` is not one of ``L10``, ``L50``.
    """
    if life_basis not in LIFE_BASES:
        raise InputError(f"unknown life basis {life_basis!r}; choices are: "
                         f"{', '.join(LIFE_BASES)}", field="life_basis")
    rules = unit.rules
    figures = None
    if unit.bearing is not None and bearing is not None:
        figures = bearing_figures(bearing, unit.bearing, rules, load.mean_speed_under(rules))
    case = RuleInput(unit, load, margin, momentary, life_hours, life_basis, figures, motor,
                     load_inertia=load_inertia, max_torsion=max_torsion,
                     min_frequency=min_frequency)
    applied = _applied((Part.GEARHEAD, Part.BEARING) if figures is not None
                       else (Part.GEARHEAD,), case)  # a bearing rule needs its figures
    checks = {found.name: check for found, check in applied}
    fields = [field for found, check in applied if check.value is not None
              for field in found.fields(unit)]
    life = case.l50_hours
    if life is not None:
        fields.append("rated_torque")
    if motor is not None:
        fields.append("input_inertia")
    flags = unit.flags_for(*fields, WHOLE_UNIT) + ((rules.flag,) if rules.flag is not None else ())
    if any("stiffness" in found.fields(unit) and "not_rated" in check.detail
           for found, check in applied):  # a target asked for, and nothing to judge it by
        flags += (UNRATED_STIFFNESS,)
    return Candidate(unit, checks, life, flags, motor, required_margin=margin, bearing=figures)


def check_motor(motor: Motor, torque: np.ndarray, speed_rpm: np.ndarray,
                demand: MotorDemand, *, margin: float = DEFAULT_MARGIN) -> dict[str, Check]:
    """Every registered rule of the motor on what it must deliver behind one gearhead.

    Args:
        motor: The motor.
        torque: Motor torque per sample [N m], shape (n,).
        speed_rpm: Input speed per sample [rpm], shape (n,).
        demand: The cycle's peak and RMS motor torque and largest input speed.
        margin: Design margin [-]: each rule must hold at (1 - margin) of its limit.

    Returns:
        The checks by name, in the order of `MOTOR_CHECKS` (`hdselect.catalog.rules.motor`).
    """
    case = RuleInput(None, None, margin, demand=demand, motor=motor, motor_torque=torque,
                     motor_speed=speed_rpm)
    return apply_rules((Part.MOTOR,), case)


def apply_rules(parts: tuple[Part, ...], case: RuleInput) -> dict[str, Check]:
    """The checks of every registered rule of `parts` on one case, in registry order.

    A rule absent for the case (its check None) is left out.
    """
    return {found.name: check for found, check in _applied(parts, case)}


def _applied(parts: tuple[Part, ...], case: RuleInput) -> list[tuple[Rule, Check]]:
    """Each registered rule of `parts` with its check on the case, where present."""
    return [(found, check) for part in parts for found in rules_of(part)
            if (check := found.check(case)) is not None]
