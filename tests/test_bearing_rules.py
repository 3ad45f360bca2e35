"""The output bearing's rules on hand-computed cycles, and its ratings in catalog files.

The example cycle (worked by hand in `test_life_and_static_safety_by_hand`):

    phase   time   output speed   F_r     F_a     M
    1       1 s     30 rpm        200 N   100 N   10 N m
    2       2 s     60 rpm        100 N    50 N    5 N m
    3       1 s      0 (held)     300 N   400 N   20 N m

on a bearing with d_p = 0.05 m, C = 2000 N, C0 = 3000 N, f_w = 1.2.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.catalog.bearing_rules import (
    BearingLoad,
    bearing_figures,
    bearing_load,
)
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import BEARING_CHECKS, CHECK_LABELS, CHECKS, bearing_checks, check_unit
from hdselect.catalog.units import BearingRating
from helpers.motions import PSA_RULES, make_load, make_unit

RPM = 2.0 * math.pi / 60.0  # rad/s in one rpm
RATING = BearingRating(pitch_diameter=0.05, dynamic_rating=2000.0, static_rating=3000.0,
                       max_moment=100.0, max_radial=2000.0, max_axial=3000.0)


def example() -> BearingLoad:
    """The module docstring's cycle, as samples of the phases' durations."""
    return bearing_load(np.array([100.0, -50.0, 400.0]), np.array([200.0, 100.0, 300.0]),
                        np.array([10.0, 5.0, 20.0]), np.array([30.0, -60.0, 0.0]) * RPM,
                        np.array([1.0, 2.0, 1.0]), np.array([False, False, True]))


def test_loads_by_hand():
    """Maxima over every phase, held included; 10/3-power means weighted by |n| t over the
    moving phases: weights 30 and 120, and each load of phase 1 is twice phase 2's, so
    F_av = F_2 ((30 2^(10/3) + 120) / 150)^0.3 = 1.36422 F_2."""
    load = example()
    assert (load.max_radial, load.max_axial, load.max_moment) == (300.0, 400.0, 20.0)
    factor = ((30 * 2 ** (10 / 3) + 120) / 150) ** 0.3
    assert factor == pytest.approx(1.36422, abs=1e-5)
    assert load.mean_radial == pytest.approx(100.0 * factor, rel=1e-12)
    assert load.mean_axial == pytest.approx(50.0 * factor, rel=1e-12)
    assert load.mean_moment == pytest.approx(5.0 * factor, rel=1e-12)


def test_life_and_static_safety_by_hand():
    """F_r,av + 2 M_av / d_p = 1.36422 (100 + 200) = 409.27 N; F_a,av = 68.21 N is below 1.5
    times that, so X = 1, Y = 0.45 and P_c = 1.36422 (300 + 22.5) = 439.96 N. N_av over the
    moving part = (30 + 120) / 3 = 50 rpm. L10 = 10^6 / (60 50) (2000 / (1.2 P_c))^(10/3)
    = 333.3 x 3.7882^(10/3) = 333.3 x 84.75 = 28,250 h. P_0 = 300 + 2 20 / 0.05 + 0.44 400 =
    1276 N, C0 / P_0 = 2.351."""
    figures = bearing_figures(example(), RATING, PSA_RULES, 50.0 * RPM)
    assert figures.factors == (1.0, 0.45)
    assert figures.equivalent_load == pytest.approx(439.96, abs=0.01)
    assert figures.mean_speed == pytest.approx(50.0)
    assert figures.life_hours == pytest.approx(28_250, rel=1e-3)
    assert figures.static_load == pytest.approx(1276.0, rel=1e-12)
    assert figures.static_safety == pytest.approx(3000.0 / 1276.0, rel=1e-12)
    checks = bearing_checks(figures, RATING, PSA_RULES, life_hours=20_000.0)
    assert list(checks) == list(BEARING_CHECKS)
    assert checks["bearing_moment"].utilization == pytest.approx(20.0 / 100.0)
    assert checks["bearing_radial"].utilization == pytest.approx(300.0 / 2000.0)
    assert checks["bearing_axial"].utilization == pytest.approx(400.0 / 3000.0)
    assert checks["bearing_life"].utilization == pytest.approx(20_000 / 28_250, rel=1e-3)
    assert checks["bearing_static"].utilization == pytest.approx(1.5 * 1276.0 / 3000.0)
    assert all(check.ok for check in checks.values())
    longer = bearing_checks(figures, RATING, PSA_RULES, life_hours=30_000.0)
    assert not longer["bearing_life"].ok
    strict = bearing_checks(figures, RATING, PSA_RULES.__class__(
        **{**PSA_RULES.__dict__, "bearing_static_safety": 2.5}), life_hours=None)
    assert "bearing_life" not in strict and not strict["bearing_static"].ok


def test_a_mostly_axial_load_takes_x_and_y_of_067():
    """F_a,av = 2000 N over F_r,av + 2 M_av / d_p = 100 + 2 x 5 / 0.05 = 300 N: a ratio of
    6.7 > 1.5, so P_c = 0.67 (300 + 2000) = 1541 N."""
    steady = bearing_load(np.array([2000.0]), np.array([100.0]), np.array([5.0]),
                          np.array([10.0 * RPM]), 1.0, np.array([False]))
    figures = bearing_figures(steady, RATING, PSA_RULES, 10.0 * RPM)
    assert figures.factors == (0.67, 0.67)
    assert figures.equivalent_load == pytest.approx(0.67 * 2300.0, rel=1e-12)
    life = 1e6 / (60 * 10.0) * (2000.0 / (1.2 * 1541.0)) ** (10 / 3)
    assert figures.life_hours == pytest.approx(life, rel=1e-12)


def test_a_held_pose_has_maxima_and_no_life():
    held = bearing_load(np.array([10.0]), np.array([20.0]), np.array([3.0]), np.array([0.0]),
                        5.0, np.array([True]))
    assert held.mean_radial is None and held.max_moment == 3.0
    figures = bearing_figures(held, RATING, PSA_RULES, 0.0)
    assert figures.life_hours is None and figures.equivalent_load is None
    checks = bearing_checks(figures, RATING, PSA_RULES, life_hours=1000.0)
    assert checks["bearing_life"].value is None and checks["bearing_life"].utilization == 0.0
    assert checks["bearing_static"].value == pytest.approx(3000.0 / (20 + 2 * 3 / 0.05 + 4.4))


def test_check_unit_adds_the_bearing_checks_only_where_rated():
    """The rated unit gets the bearing checks in CHECKS order, its figures and a binding
    rule among them; the unit without ratings gets none and no figures."""
    load = make_load(peak=8.0, mean=8.0, mean_speed=50.0 * RPM)
    rated = check_unit(load, make_unit(bearing=RATING), life_hours=30_000.0, bearing=example())
    order = [name for name in CHECKS if name in rated.checks]
    assert list(rated.checks) == order and set(BEARING_CHECKS) <= set(order)
    assert rated.bearing is not None and rated.bearing.life_hours == pytest.approx(28_250,
                                                                                  rel=1e-3)
    assert rated.binding == "bearing_life" and not rated.feasible
    plain = check_unit(load, make_unit(), life_hours=30_000.0, bearing=example())
    assert plain.bearing is None and not set(BEARING_CHECKS) & set(plain.checks)
    assert all(name in CHECK_LABELS for name in CHECKS)


def test_the_design_margin_judges_the_bearing_as_every_rule():
    """The example cycle on a bearing allowing M_max = 24 N m, with 24,000 h required and a
    static safety of 2 (the hand figures of `test_life_and_static_safety_by_hand`):
    moment 20 / 24 = 83.3 %; life 24,000 / 28,248.5 = 84.96 % (required over reached);
    static safety 2 / (3000 / 1276) = 85.07 % (required over reached); radial 300 / 2000
    = 15 %, axial 400 / 3000 = 13.3 %. The gear: T_av 5 N m against (1750 / 2500)^0.33
    x 10 = 8.89 N m (56 %), peak 8 / 20 (40 %), 2500 / 6000 rpm (42 %), L50 196,000 h
    (12 %). Margin 0: every rule holds. Margin 0.2 (80 % of each limit): the three bearing
    checks above 80 % fail, nothing else. Margin 0.15 (85 %): only the static safety
    fails. The utilizations are the same at every margin."""
    rating = replace(RATING, max_moment=24.0)
    rules = replace(PSA_RULES, bearing_static_safety=2.0)
    load = make_load(peak=8.0, mean=5.0, mean_speed=50.0 * RPM)
    unit = make_unit(bearing=rating, rules=rules)
    judged = {margin: check_unit(load, unit, life_hours=24_000.0, bearing=example(),
                                 margin=margin) for margin in (0.0, 0.15, 0.2)}
    plain, edge, kept = judged[0.0], judged[0.15], judged[0.2]
    hand = {"bearing_moment": 20.0 / 24.0, "bearing_radial": 0.15,
            "bearing_axial": 400.0 / 3000.0, "bearing_life": 24_000.0 / 28_248.5,
            "bearing_static": 2.0 * 1276.0 / 3000.0}
    for name, utilization in hand.items():
        for candidate in judged.values():
            assert candidate.checks[name].utilization == pytest.approx(utilization, rel=1e-5)
    assert plain.feasible and all(check.ok for check in plain.checks.values())
    assert {name for name, check in kept.checks.items() if not check.ok} == {
        "bearing_moment", "bearing_life", "bearing_static"}
    assert not kept.feasible and kept.required_margin == 0.2
    assert {name for name, check in edge.checks.items() if not check.ok} == {"bearing_static"}
    assert kept.binding == edge.binding == plain.binding == "bearing_static"


# --- catalog files ------------------------------------------------------------------------------

CATALOG = """series = "EX"
[rules]
rated_input_speed_rpm = 2000
rated_life_hours = 7000
life_basis = "L10"
mean_torque_limit = "speed-adjusted"
mean_speed = "whole-cycle"
max_momentary_events = 10000
{rules}
[[unit]]
size = 20
ratio = 100
rated_torque_nm = 40
repeated_torque_nm = 80
max_input_speed_rpm = 6000
input_inertia_kg_cm2 = 0.2
mass_kg = 1.5
{bearing}
"""


def write(tmp_path: Path, rules: str = "", bearing: str = "") -> Path:
    path = tmp_path / "ex.toml"
    path.write_text(CATALOG.format(rules=rules, bearing=bearing))
    return path


def ex_unit(tmp_path: Path, rules: str = "", bearing: str = ""):
    (unit,) = [u for u in load_catalog([write(tmp_path, rules, bearing)]) if u.series == "EX"]
    return unit


def test_a_catalog_file_rates_the_bearing(tmp_path):
    unit = ex_unit(tmp_path, "bearing_load_factor = 1.5\nbearing_static_safety = 2",
                   "[unit.bearing]\npitch_diameter_m = 0.0645\ndynamic_rating_n = 14_600\n"
                   "static_rating_n = 22_000\nmax_moment_nm = 187\noffset_m = 0.0103")
    assert unit.bearing == BearingRating(0.0645, 14_600.0, 22_000.0, 187.0, None, None, 0.0103)
    assert (unit.rules.bearing_load_factor, unit.rules.bearing_static_safety) == (1.5, 2.0)
    default = ex_unit(tmp_path)
    assert default.bearing is None
    assert (default.rules.bearing_load_factor, default.rules.bearing_static_safety) == (1.2, 1.5)
    assert all(u.bearing is None for u in load_catalog())  # the PSA-G page rates none


@pytest.mark.parametrize(("rules", "bearing", "field", "message"), [
    ("", "[unit.bearing]\npitch_diameter_m = 0.05", "unit[EX-20-100].bearing",
     "gives no rating"),
    ("", "[unit.bearing]\ndynamic_rating_n = 1000", "unit[EX-20-100].bearing.pitch_diameter_m",
     "dynamic_rating_n needs pitch_diameter_m"),
    ("", "[unit.bearing]\nmax_moment_nm = -3", "unit[EX-20-100].bearing.max_moment_nm",
     "must be a torque"),
    ("", "[unit.bearing]\nmax_moment = 3", "unit[EX-20-100].bearing.max_moment",
     "did you mean 'max_moment_nm'"),
    ("bearing_load_factor = 0.5", "", "rules.bearing_load_factor", "must be a load factor"),
])
def test_bad_bearing_ratings_are_refused_by_field(tmp_path, rules, bearing, field, message):
    with pytest.raises(InputError, match=message) as caught:
        load_catalog([write(tmp_path, rules, bearing)])
    assert caught.value.field == field and caught.value.path == tmp_path / "ex.toml"
