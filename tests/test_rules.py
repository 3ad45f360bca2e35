"""The catalog's rules, and the selection among candidates, against hand arithmetic."""

from __future__ import annotations

import ast
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import (
    BEARING_CHECKS,
    CHECKS,
    MOTOR_CHECKS,
    PAIR_CHECKS,
    Candidate,
    Check,
    CycleLoad,
    Momentary,
    allowable_mean_torque,
    allowed_momentary_events,
    check_unit,
    cycle_load,
    l50_life_hours,
)
from hdselect.catalog.select import PREFERENCES, select
from hdselect.catalog.units import Flag, Unit
from helpers.motions import PSA_RULES, RPM, make_load, make_unit

# ----------------------------------------------------------------------------- cycle_load


def trapezoid() -> CycleLoad:
    # accelerate, run, decelerate, dwell; torque [N m], speed [rad/s], time [s].
    # Signs are ignored (decelerating torque and a reverse run given negative).
    return cycle_load(torque=np.array([6.0, 2.0, -4.0, 1.5]),
                      speed=np.array([5.0, -10.0, 5.0, 0.0]),
                      duration=np.array([0.1, 0.3, 0.1, 0.5]),
                      at_rest=np.array([False, False, False, True]))


def test_cycle_load_mean_torque_by_hand() -> None:
    load = trapezoid()
    # n_i t_i: 5 x 0.1 = 0.5, 10 x 0.3 = 3.0, 5 x 0.1 = 0.5; sum 4.0 (the dwell has n = 0)
    # n_i t_i T_i^3: 0.5 x 216 = 108, 3.0 x 8 = 24, 0.5 x 64 = 32; sum 164
    # T_av = cbrt(164 / 4.0) = cbrt(41) = 3.4482172...
    assert load.mean_torque == pytest.approx(41.0 ** (1.0 / 3.0), rel=1e-12)
    assert load.mean_torque == pytest.approx(3.4482172, abs=1e-7)


def test_cycle_load_mean_speed_excludes_the_dwell() -> None:
    load = trapezoid()
    # sum n_i t_i / sum t_i over the moving phases: 4.0 / (0.1 + 0.3 + 0.1) = 8 rad/s
    # (with the 0.5 s dwell it would be 4.0 / 1.0 = 4 rad/s: the seed excludes it)
    assert load.mean_speed == pytest.approx(8.0, rel=1e-12)
    assert load.moving_time == pytest.approx(0.5, rel=1e-12)
    assert load.max_speed == 10.0


def test_cycle_load_peak_and_static() -> None:
    load = trapezoid()
    assert load.peak_torque == 6.0  # moving phases only
    assert load.static_torque == 1.5  # the dwell's torque, input locked
    with_static = cycle_load(np.array([6.0, 1.5]), np.array([5.0, 0.0]), np.array([0.1, 0.5]),
                             np.array([False, True]), static_torque=-2.5)
    assert with_static.static_torque == 2.5  # the larger of the dwell and the given load
    no_rest = cycle_load(np.array([6.0]), np.array([5.0]), 0.1, np.array([False]))
    assert no_rest.static_torque is None


def test_cycle_load_of_a_still_joint() -> None:
    load = cycle_load(np.array([3.0]), np.array([0.0]), 1.0, np.array([True]))
    assert load.mean_torque is None
    assert load.mean_speed == 0.0
    assert load.peak_torque == 0.0
    assert load.static_torque == 3.0


def test_cycle_load_samples_generalise_phases() -> None:
    # One phase of 0.3 s at constant torque and speed, split into three samples of 0.1 s:
    # the same sums, so the same summary.
    phase = cycle_load(np.array([5.0]), np.array([2.0]), 0.3, np.array([False]))
    samples = cycle_load(np.full(3, 5.0), np.full(3, 2.0), 0.1, np.zeros(3, dtype=bool))
    assert samples.mean_torque == pytest.approx(phase.mean_torque, rel=1e-12)
    assert samples.mean_speed == pytest.approx(phase.mean_speed, rel=1e-12)
    assert samples.mean_torque == pytest.approx(5.0, rel=1e-12)


# ----------------------------------------------------------------------------- formulas


def test_allowable_mean_torque_by_the_rule() -> None:
    unit = make_unit()
    allowed, capped = allowable_mean_torque(unit, 875.0)
    # (1750 / 875)^0.33 x 10 = 2^0.33 x 10 = exp(0.33 ln 2) x 10 = exp(0.228739) x 10 = 12.5701
    assert allowed == pytest.approx(2.0 ** 0.33 * 10.0, rel=1e-12)
    assert allowed == pytest.approx(12.5701, abs=1e-4)
    assert capped is False
    allowed, capped = allowable_mean_torque(unit, 1750.0)
    assert allowed == pytest.approx(10.0, rel=1e-12) and capped is False  # T_N at 1750 rpm
    # Faster than rated: (1750 / 3500)^0.33 x 10 = 0.5^0.33 x 10 = 10 / 1.25701 = 7.9554
    assert allowable_mean_torque(unit, 3500.0)[0] == pytest.approx(7.9554, abs=1e-4)


def test_allowable_mean_torque_capped_at_low_speed() -> None:
    unit = make_unit()
    # 10 rpm: (1750 / 10)^0.33 x 10 = 175^0.33 x 10 = exp(0.33 x 5.1648) x 10 = 54.98 N m,
    # above the repeated-peak limit of 20 N m: the cap binds.
    assert 175.0 ** 0.33 * 10.0 > 20.0
    assert allowable_mean_torque(unit, 10.0) == (20.0, True)
    # The cap starts where (1750 / N)^0.33 x 10 = 20:
    # N = 1750 / 2^(1/0.33) = 1750 / 8.1698 = 214.2 rpm
    threshold = 1750.0 / 2.0 ** (1.0 / 0.33)
    assert threshold == pytest.approx(214.2, abs=0.1)
    assert allowable_mean_torque(unit, threshold * 1.01)[1] is False
    assert allowable_mean_torque(unit, threshold * 0.99) == (20.0, True)
    assert allowable_mean_torque(unit, 0.0) == (20.0, True)


def test_l50_life_by_hand() -> None:
    unit = make_unit()
    # 35000 x (1750 / 875) x (10 / 5)^3 = 35000 x 2 x 8 = 560000 h
    assert l50_life_hours(unit, 5.0, 875.0) == pytest.approx(560000.0, rel=1e-12)
    # at T_N and 1750 rpm: the rating itself, 35000 h
    assert l50_life_hours(unit, 10.0, 1750.0) == pytest.approx(35000.0, rel=1e-12)
    assert l50_life_hours(unit, 0.0, 875.0) is None
    assert l50_life_hours(unit, 5.0, 0.0) is None


def test_allowed_momentary_events_by_hand() -> None:
    # 1200 rpm for 0.05 s: 2 x (1200 / 60) x 0.05 = 2 revolutions -> 1e4 / 2 = 5000 events
    assert allowed_momentary_events(1200.0, 0.05) == pytest.approx(5000.0, rel=1e-12)
    # 3000 rpm for 0.1 s: 2 x 50 x 0.1 = 10 -> 1000 events
    assert allowed_momentary_events(3000.0, 0.1) == pytest.approx(1000.0, rel=1e-12)
    assert allowed_momentary_events(0.0, 0.1) is None


# ----------------------------------------------------------------------------- check_unit


def test_check_unit_by_hand() -> None:
    unit = make_unit()
    # 35 output rpm x ratio 50 = 1750 input rpm: the allowable mean torque is T_N = 10 N m
    load = make_load(peak=8.0, mean=8.0, mean_speed=35 * RPM, max_speed=60 * RPM, static=6.0)
    candidate = check_unit(load, unit)
    checks = candidate.checks
    assert list(checks) == ["peak", "mean", "speed", "average_speed", "momentary", "static"]
    assert checks["peak"].utilization == pytest.approx(8.0 / 20.0)  # 0.4
    assert checks["mean"].limit == pytest.approx(10.0)
    assert checks["mean"].utilization == pytest.approx(0.8)  # 8 / 10
    assert checks["mean"].detail["mean_input_speed_rpm"] == pytest.approx(1750.0)
    assert checks["speed"].value == pytest.approx(3000.0)  # 60 rpm x 50, input rpm
    assert checks["speed"].utilization == pytest.approx(0.5)  # 3000 / 6000
    assert checks["static"].utilization == pytest.approx(0.2)  # 6 / 30
    # 35000 x (1750 / 1750) x (10 / 8)^3 = 35000 x 1.953125 = 68359.375 h
    assert candidate.life_hours == pytest.approx(68359.375, rel=1e-9)
    assert candidate.feasible
    assert candidate.binding == "mean"
    assert candidate.margin == pytest.approx(0.2)


def test_only_the_required_life_fails() -> None:
    unit = make_unit()
    load = make_load(peak=8.0, mean=8.0, mean_speed=35 * RPM)
    candidate = check_unit(load, unit, life_hours=100000.0)
    life = candidate.checks["life"]
    assert life.value == pytest.approx(68359.375, rel=1e-9)  # as above
    assert life.limit == 100000.0
    # required over expected: 100000 / 68359.375 = 1.46286
    assert life.utilization == pytest.approx(1.46286, abs=1e-5)
    assert not life.ok
    assert [name for name, c in candidate.checks.items() if not c.ok] == ["life"]
    assert not candidate.feasible
    assert candidate.binding == "life"
    assert candidate.margin == pytest.approx(1.0 - 1.46286, abs=1e-5)
    # 60000 h required is within 68359 h
    assert check_unit(load, unit, life_hours=60000.0).feasible


def test_limit_reached_exactly_is_ok() -> None:
    candidate = check_unit(make_load(peak=20.0, mean=1.0), make_unit())
    assert candidate.checks["peak"].utilization == 1.0
    assert candidate.checks["peak"].ok
    assert candidate.feasible
    assert candidate.margin == 0.0
    over = check_unit(make_load(peak=20.5, mean=1.0), make_unit())
    assert not over.checks["peak"].ok and not over.feasible
    assert over.margin == pytest.approx(1.0 - 20.5 / 20.0)


def test_checks_that_do_not_apply() -> None:
    load = make_load(mean=None, static=None)
    candidate = check_unit(load, make_unit(), life_hours=1000.0, max_torsion=1e-3,
                           min_frequency=10.0, load_inertia=0.1)  # no stiffness: not rated
    for name in ("mean", "momentary", "static", "life", "torsion", "natural_frequency"):
        check = candidate.checks[name]
        assert check.value is None, name
        assert check.ok, name
        assert check.utilization == 0.0, name
    assert candidate.life_hours is None
    assert list(candidate.checks) == [name for name in CHECKS
                                      if name not in MOTOR_CHECKS + BEARING_CHECKS + PAIR_CHECKS]


def test_momentary_check_and_events() -> None:
    unit = make_unit()
    event = Momentary(torque=-24.0, kind="given", speed=20 * RPM, duration=0.05, time=1.5)
    check = check_unit(make_load(), unit, momentary=event).checks["momentary"]
    assert check.value == 24.0
    assert check.utilization == pytest.approx(0.8)  # 24 / 30
    assert check.detail["kind"] == "given"
    assert check.detail["time_s"] == 1.5
    # 20 output rpm x 50 = 1000 input rpm; 2 x (1000 / 60) x 0.05 = 1.6667 rev; 1e4 / that
    assert check.detail["allowed_events"] == pytest.approx(6000.0, rel=1e-9)


def psa08() -> Unit:
    return {u.id: u for u in load_catalog()}["PSA-08-80"]


def test_psa08_flags_only_for_checked_fallbacks() -> None:
    unit = psa08()
    moving = make_load(peak=1.0, mean=1.0, static=None)
    assert check_unit(moving, unit).flags == ()
    with_momentary = check_unit(moving, unit, momentary=Momentary(2.0, "given"))
    assert [f.code for f in with_momentary.flags] == ["momentary_torque:fallback"]
    held = make_load(peak=1.0, mean=1.0, static=0.5)
    assert [f.code for f in check_unit(held, unit).flags] == ["static_torque:fallback"]
    both = check_unit(held, unit, momentary=Momentary(2.0, "given"))
    assert sorted(f.code for f in both.flags) == ["momentary_torque:fallback",
                                                  "static_torque:fallback"]
    # The input inertia stand-in matters only where the motor side is computed.
    motor = check_unit(moving, unit, motor=object())
    assert [f.code for f in motor.flags] == ["input_inertia:fallback"]


# ----------------------------------------------------------------------------- series rules

# Harmonic Drive's rules for CSF (L10 = 7000 h at T_N and 2000 rpm input), as stated in a
# catalog file's [rules] table; the numbers are test values, not read from any catalog here.
CSF_RULES = dataclasses.replace(PSA_RULES, rated_input_speed=2000.0, rated_life_hours=7000.0,
                                life_basis="L10", mean_torque_limit="tabulated",
                                mean_speed="whole-cycle")


def csf_unit(**overrides: object) -> Unit:
    """make_unit under the CSF rules, with a limit for average torque of 9 N m."""
    return make_unit(**{"rules": CSF_RULES, "average_torque": 9.0, **overrides})


def dwelling_load() -> CycleLoad:
    # 35 output rpm over the 0.8 s moving part of a 1.0 s cycle: 28 rpm over the whole cycle
    return CycleLoad(peak_torque=8.0, mean_torque=8.0, mean_speed=35 * RPM, max_speed=60 * RPM,
                     moving_time=0.8, cycle_time=1.0, static_torque=None)


def test_cycle_load_whole_cycle_mean_speed() -> None:
    load = trapezoid()
    # travel 4.0 rad over the whole 1.0 s cycle (dwell 0.5 s included): 4.0 rad/s
    assert load.cycle_time == pytest.approx(1.0, rel=1e-12)
    assert load.cycle_mean_speed == pytest.approx(4.0, rel=1e-12)
    assert load.mean_speed_under(CSF_RULES) == pytest.approx(4.0, rel=1e-12)
    assert load.mean_speed_under(PSA_RULES) == pytest.approx(8.0, rel=1e-12)  # moving part


def test_tabulated_mean_torque_limit() -> None:
    unit = csf_unit()
    # the tabulated limit holds at every speed; no speed rule, no cap
    assert allowable_mean_torque(unit, 875.0) == (9.0, False)
    assert allowable_mean_torque(unit, 5000.0) == (9.0, False)


def test_l10_rated_life_is_converted_to_l50() -> None:
    unit = csf_unit()
    # L50 = 5 x 7000 h x (2000 / 1000) x (10 / 5)^3 = 35000 x 2 x 8 = 560000 h
    assert l50_life_hours(unit, 5.0, 1000.0) == pytest.approx(560000.0, rel=1e-12)
    # at T_N and 2000 rpm: the rating itself, 7000 h L10 = 35000 h L50
    assert l50_life_hours(unit, 10.0, 2000.0) == pytest.approx(35000.0, rel=1e-12)


def test_check_unit_under_csf_rules() -> None:
    unit = csf_unit(max_average_input_speed=1200.0)
    candidate = check_unit(dwelling_load(), unit, life_hours=20000.0, life_basis="L10")
    checks = candidate.checks
    # whole-cycle mean output speed 28 rpm x ratio 50 = 1400 rpm input
    n_in = 35.0 * 0.8 / 1.0 * 50
    assert n_in == pytest.approx(1400.0)
    assert checks["mean"].detail["mean_input_speed_rpm"] == pytest.approx(n_in, rel=1e-12)
    assert checks["mean"].limit == 9.0
    assert checks["mean"].utilization == pytest.approx(8.0 / 9.0, rel=1e-12)
    # 1400 rpm over the 1200 rpm limit for average input speed: 116.7 %
    assert checks["average_speed"].value == pytest.approx(n_in, rel=1e-12)
    assert checks["average_speed"].utilization == pytest.approx(n_in / 1200.0, rel=1e-12)
    assert not checks["average_speed"].ok
    # L10 = 7000 x (2000 / 1400) x (10 / 8)^3 = 7000 x 1.428571 x 1.953125 = 19531.25 h
    l10 = 7000.0 * (2000.0 / n_in) * (10.0 / 8.0) ** 3
    assert l10 == pytest.approx(19531.25, rel=1e-12)
    assert candidate.life_hours == pytest.approx(5 * l10, rel=1e-12)  # always L50
    assert candidate.l10_hours == pytest.approx(l10, rel=1e-12)
    life = checks["life"]
    assert life.value == pytest.approx(l10, rel=1e-12) and life.detail == {"basis": "L10"}
    assert life.utilization == pytest.approx(20000.0 / l10, rel=1e-12)  # 1.024: fails
    assert not life.ok
    # 20000 h required as L50 is well within 97656 h L50
    on_l50 = check_unit(dwelling_load(), unit, life_hours=20000.0).checks["life"]
    assert on_l50.ok and on_l50.value == pytest.approx(5 * l10, rel=1e-12)
    assert on_l50.detail == {"basis": "L50"}


def test_life_basis_is_validated() -> None:
    with pytest.raises(InputError) as info:
        check_unit(make_load(), make_unit(), life_hours=1000.0, life_basis="L90")
    assert "'L90'" in str(info.value) and "L10, L50" in str(info.value)
    assert info.value.field == "life_basis"


def test_average_speed_check_without_a_limit() -> None:
    check = check_unit(make_load(), make_unit()).checks["average_speed"]
    assert check.value is None and check.ok and check.utilization == 0.0
    assert check.limit == math.inf


def test_momentary_events_are_capped_by_the_rules() -> None:
    # 1 output rpm x 50 = 50 input rpm for 0.01 s: 2 x (50 / 60) x 0.01 = 0.016667 rev,
    # 1e4 / 0.016667 = 600,000 events by the formula; the rules allow at most 1e4.
    assert allowed_momentary_events(50.0, 0.01) == pytest.approx(600000.0, rel=1e-12)
    assert allowed_momentary_events(50.0, 0.01, cap=1e4) == 1e4
    assert allowed_momentary_events(1200.0, 0.05, cap=1e4) == pytest.approx(5000.0)  # below
    assert allowed_momentary_events(0.0, 0.1, cap=1e4) == 1e4  # no revolution: the cap
    event = Momentary(torque=5.0, kind="given", speed=1 * RPM, duration=0.01)
    check = check_unit(make_load(), make_unit(), momentary=event).checks["momentary"]
    assert check.detail["allowed_events"] == 1e4


def test_assumed_rules_are_flagged_on_every_result() -> None:
    flag = Flag("rules", "assumed", "the catalog file states no [rules]")
    unit = make_unit(rules=dataclasses.replace(PSA_RULES, flag=flag))
    assert check_unit(make_load(), unit).flags == (flag,)
    assert check_unit(make_load(mean=None), unit).flags == (flag,)


def test_rules_does_not_import_reflect() -> None:
    import hdselect.catalog.rules
    import hdselect.sizing.reflect

    package = Path(hdselect.catalog.rules.__file__).parent  # every module of the package
    for path in package.glob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imported = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
        imported |= {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import)
                     for alias in node.names}
        assert "hdselect.sizing.reflect" not in imported, path.name
    assert hdselect.sizing.reflect.MotorDemand is hdselect.catalog.rules.MotorDemand


# ----------------------------------------------------------------------------- select


def candidate(size: int, ratio: int, utilization: float) -> Candidate:
    unit = make_unit(id=f"T-{size:02d}-{ratio}", size=size, ratio=ratio)
    check = Check(value=utilization, limit=1.0, ok=utilization <= 1.0, utilization=utilization)
    return Candidate(unit, {"peak": check}, None, ())


def test_smallest_size_wins() -> None:
    small = candidate(10, 50, 0.9)  # margin 0.1
    large = candidate(14, 50, 0.2)  # margin 0.8
    assert select([large, small]) is small
    assert select([large, small], prefer="margin") is large


def test_within_a_size_the_larger_margin_wins() -> None:
    tight = candidate(14, 50, 0.9)
    loose = candidate(14, 100, 0.4)
    infeasible_small = candidate(10, 50, 1.2)
    assert select([tight, loose, infeasible_small]) is loose


def test_nothing_fits() -> None:
    assert select([candidate(10, 50, 1.01), candidate(14, 80, 3.0)]) is None
    assert select([]) is None


def test_unknown_order_lists_the_choices() -> None:
    with pytest.raises(InputError) as info:
        select([candidate(10, 50, 0.5)], prefer="cheapest")
    message = str(info.value)
    assert "'cheapest'" in message
    for name in PREFERENCES:
        assert name in message
    assert info.value.field == "prefer"


def random_load(rng: np.random.Generator) -> tuple[CycleLoad, Momentary | None]:
    phases = int(rng.integers(1, 5))
    torque = rng.uniform(0.0, 25.0, phases)
    speed = rng.uniform(0.0, 80.0, phases) * RPM  # output rpm up to 80
    duration = rng.uniform(0.01, 1.0, phases)
    at_rest = rng.random(phases) < 0.25
    speed[at_rest] = 0.0
    at_rest[0] = False  # the joint moves at least once
    speed[0] = max(speed[0], 1.0 * RPM)
    load = cycle_load(torque, speed, duration, at_rest,
                      static_torque=float(rng.uniform(0, 30)) if rng.random() < 0.3 else None)
    momentary = (Momentary(float(rng.uniform(0, 40)), "given", float(rng.uniform(0, 80) * RPM),
                           float(rng.uniform(0.01, 0.2))) if rng.random() < 0.5 else None)
    return load, momentary


def test_a_stronger_unit_is_never_less_feasible() -> None:
    rng = np.random.default_rng(20240611)
    outcomes = {(True, True): 0, (False, True): 0, (False, False): 0}
    for _ in range(400):
        rated = float(rng.uniform(1.0, 15.0))
        weak = make_unit(ratio=int(rng.choice([50, 80, 100])), rated_torque=rated,
                         repeated_torque=rated * float(rng.uniform(1.0, 2.0)),
                         momentary_torque=rated * float(rng.uniform(1.0, 3.0)),
                         static_torque=rated * float(rng.uniform(1.0, 3.0)),
                         max_input_speed=float(rng.uniform(1000.0, 7000.0)))
        scale = rng.uniform(1.0, 1.5, 5)
        strong_rated = weak.rated_torque * scale[0]
        strong = dataclasses.replace(
            weak, id="T-stronger", rated_torque=strong_rated,
            repeated_torque=max(weak.repeated_torque * scale[1], strong_rated),
            momentary_torque=weak.momentary_torque * scale[2],
            static_torque=weak.static_torque * scale[3],
            max_input_speed=weak.max_input_speed * scale[4])
        load, momentary = random_load(rng)
        life = float(rng.uniform(1e3, 1e6)) if rng.random() < 0.5 else None
        a = check_unit(load, weak, momentary=momentary, life_hours=life)
        b = check_unit(load, strong, momentary=momentary, life_hours=life)
        for name in a.checks:  # each rule, not only the verdict
            assert b.checks[name].utilization <= a.checks[name].utilization * (1 + 1e-12), name
        assert (a.feasible, b.feasible) in outcomes  # (True, False) never happens
        outcomes[(a.feasible, b.feasible)] += 1
        if a.feasible:
            assert select([a, b], prefer="margin") is b or b.margin == a.margin
    # The samples exercise every outcome, so the invariant was really tested.
    assert all(count > 0 for count in outcomes.values()), outcomes


# --- the motor's rules -----------------------------------------------------------------------

def test_motor_rules_by_hand():
    """Three samples at 0, 3000 and 6000 rpm under a curve 0.3 -> 0.3 -> 0 N m: the last
    sample's 0.01 N m at 6000 rpm exceeds a zero limit; zero torque at zero limit is fine."""
    from hdselect.catalog.motors import Motor
    from hdselect.catalog.rules import MotorDemand, check_motor, inertia_ratio

    motor = Motor("M", rated_torque=0.1, peak_torque=0.3, max_speed=6000.0, rated_speed=3000.0,
                  rotor_inertia=4e-6, mass=0.3, torque_constant=0.05, resistance=2.0,
                  curve=[(0, 0.3), (3000, 0.3), (6000, 0.0)])
    speed = np.array([0.0, 4500.0, 6000.0])
    torque = np.array([-0.2, 0.12, 0.0])
    rms = math.sqrt((0.2**2 + 0.12**2) / 3)
    demand = MotorDemand(0.2, rms, 6000.0, 0.7)
    checks = check_motor(motor, torque, speed, demand)
    assert list(checks) == list(MOTOR_CHECKS)
    # 4500 rpm: the curve gives 0.15 N m; 0.12 / 0.15 = 80 % beats 0.2 / 0.3 = 67 %
    peak = checks["motor_peak"]
    assert (peak.value, peak.limit) == (0.12, pytest.approx(0.15))
    assert peak.utilization == pytest.approx(0.8) and peak.ok
    assert peak.detail["speed_rpm"] == 4500.0 and peak.detail["current_a"] == pytest.approx(4.0)
    assert checks["motor_rms"].utilization == pytest.approx(rms / 0.1)
    assert checks["motor_rms"].detail["copper_loss_w"] == pytest.approx(2.0 * (rms / 0.05)**2)
    assert checks["motor_speed"].utilization == pytest.approx(1.0) and checks["motor_speed"].ok
    stalled = check_motor(motor, np.array([0.0, 0.01]), np.array([0.0, 6000.0]), demand)
    assert stalled["motor_peak"].utilization == math.inf and not stalled["motor_peak"].ok
    unit = make_unit(ratio=100, input_inertia=3e-6)
    assert inertia_ratio(0.05, unit, motor) == pytest.approx((0.05 / 1e4 + 3e-6) / 4e-6)
    assert inertia_ratio(0.05, unit, dataclasses.replace(motor, rotor_inertia=0.0)) is None
