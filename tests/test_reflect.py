"""Reflecting a joint's demand through a gearhead, against hand arithmetic.

Motor torque (docs/rules.md, "The checks", motor side):
    T = tau / (N eta)   while the motor drives (tau qd > 0)
        tau eta / N     while the load drives back (tau qd < 0)
      + (J_in + J_m) N qdd,
input speed n = N qd 60 / (2 pi) [rpm]; crash torque |tau| + (J_in + J_m) N^2 |qd| / t_stop.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.sizing.reflect import DEFAULT_EFFICIENCY, reflect, reflect_motors, weighted_demand


def unit(unit_id: str, extra=()):
    return {u.id: u for u in load_catalog(extra)}[unit_id]


def motor_demand(psa, tau, qd, qdd, **options):
    """The motor side of `reflect` for one unit: (summary, torque per sample)."""
    zero = np.zeros_like(tau)
    (r,) = reflect([psa], np.arange(len(tau)) * 1e-3, tau, qd, qdd, zero, stop_time=1.0,
                   **options)
    return r.motor, r.motor_torque


def worst_momentary(psa, t, tau, qd, stop_tau, stop_time, **options):
    """The momentary side of `reflect` for one unit."""
    zero = np.zeros_like(tau)
    (r,) = reflect([psa], t, tau, qd, zero, stop_tau, stop_time=stop_time, **options)
    return r.momentary


def test_reflect_handles_many_units_at_once_like_one_at_a_time():
    units = load_catalog()
    rng = np.random.default_rng(5)
    t = np.arange(300) * 1e-3
    tau, qd, qdd, stop = (rng.normal(0, s, 300) for s in (3.0, 1.0, 20.0, 4.0))
    together = reflect(units, t, tau, qd, qdd, stop, stop_time=0.08, rotor_inertia=1e-6)
    for u, r in zip(units, together, strict=True):
        (alone,) = reflect([u], t, tau, qd, qdd, stop, stop_time=0.08, rotor_inertia=1e-6)
        assert r.unit is u and r.motor == alone.motor and r.momentary == alone.momentary
        np.testing.assert_array_equal(r.motor_torque, alone.motor_torque)


def test_several_motors_at_once_like_one_rotor_inertia_at_a_time():
    """`reflect_motors` shares the gear side; each motor's figures equal `reflect`'s with its
    rotor inertia, to the last bit, and the RMS input speed is sqrt(mean(n^2))."""
    units = load_catalog()
    rng = np.random.default_rng(6)
    t = np.arange(400) * 1e-3
    tau, qd, qdd, stop = (rng.normal(0, s, 400) for s in (3.0, 1.0, 20.0, 4.0))
    inertias = [0.0, 2e-6, 5e-5]
    behind = reflect_motors(units, inertias, t, tau, qd, qdd, stop, stop_time=0.08)
    for rotor_inertia, rows in zip(inertias, behind, strict=True):
        alone = reflect(units, t, tau, qd, qdd, stop, stop_time=0.08,
                        rotor_inertia=rotor_inertia)
        for r, a in zip(rows, alone, strict=True):
            assert r.unit is a.unit and r.motor == a.motor and r.momentary == a.momentary
            np.testing.assert_array_equal(r.motor_torque, a.motor_torque)
            n = a.unit.ratio * np.abs(qd) * 60 / (2 * math.pi)
            assert r.motor.rms_speed == pytest.approx(math.sqrt(np.mean(n**2)), rel=1e-12)
    # a heavier rotor: more motor torque where the joint accelerates, a harder crash
    light, heavy = behind[0][-1], behind[2][-1]
    assert heavy.momentary.torque >= light.momentary.torque
    assert not np.array_equal(light.motor_torque, heavy.motor_torque)


def test_psa_14_100_catalog_values_used_here():
    psa = unit("PSA-14-100")
    assert psa.ratio == 100
    assert psa.input_inertia == pytest.approx(0.033e-4, rel=1e-12)  # 0.033 kg cm^2


# --- motor_demand by hand ----------------------------------------------------------------

def test_one_sample_driving_by_hand():
    psa = unit("PSA-14-100")
    # tau = 8 N m, qd = 2 rad/s, qdd = 10 rad/s^2, eta = 0.8, J_m = 2e-6 kg m^2
    # T = 8 / (100 * 0.8) + (3.3e-6 + 2e-6) * 100 * 10 = 0.1 + 0.0053 = 0.1053 N m
    # n = 100 * 2 * 60 / (2 pi) = 1909.859 rpm
    summary, torque = motor_demand(psa, np.array([8.0]), np.array([2.0]), np.array([10.0]),
                                   efficiency=0.8, rotor_inertia=2e-6)
    assert torque[0] == pytest.approx(0.1053, rel=1e-12)
    assert summary.peak_torque == pytest.approx(0.1053, rel=1e-12)
    assert summary.rms_torque == pytest.approx(0.1053, rel=1e-12)
    assert summary.max_speed == pytest.approx(6000 / math.pi, rel=1e-12)
    assert summary.max_speed == pytest.approx(1909.859, abs=1e-3)
    assert summary.efficiency == 0.8


def test_two_samples_driving_then_back_driven_by_hand():
    psa = unit("PSA-14-100")
    # sample 1: tau = 2, qd = 1 (driving):      T = 2 / (100 * 0.7) + 3.3e-6 * 100 * 5
    #                                              = 0.0285714286 + 0.00165 = 0.0302214286
    # sample 2: tau = -3, qd = 1.5 (back-driven): T = -3 * 0.7 / 100 + 3.3e-6 * 100 * (-4)
    #                                              = -0.021 - 0.00132 = -0.02232
    tau, qd, qdd = np.array([2.0, -3.0]), np.array([1.0, 1.5]), np.array([5.0, -4.0])
    summary, torque = motor_demand(psa, tau, qd, qdd, efficiency=0.7)
    t1 = 2 / 70 + 0.00165
    t2 = -0.021 - 0.00132
    np.testing.assert_allclose(torque, [t1, t2], rtol=1e-12)
    assert summary.peak_torque == pytest.approx(t1, rel=1e-12)
    assert summary.rms_torque == pytest.approx(math.sqrt((t1**2 + t2**2) / 2), rel=1e-12)
    # max speed at 1.5 rad/s: 150 rad/s at the input = 1432.394 rpm
    assert summary.max_speed == pytest.approx(150 * 60 / (2 * math.pi), rel=1e-12)


def test_back_driving_with_negative_speed_and_positive_torque():
    psa = unit("PSA-14-100")
    # tau qd = 4 * (-1) < 0: the load drives back; T = 4 * 0.7 / 100 = 0.028
    _, torque = motor_demand(psa, np.array([4.0]), np.array([-1.0]), np.array([0.0]))
    assert torque[0] == pytest.approx(4 * DEFAULT_EFFICIENCY / 100, rel=1e-12)
    assert DEFAULT_EFFICIENCY == 0.70
    # and driving with both negative: T = -4 / (100 * 0.7)
    _, torque = motor_demand(psa, np.array([-4.0]), np.array([-1.0]), np.array([0.0]))
    assert torque[0] == pytest.approx(-4 / 70, rel=1e-12)


def test_back_driven_motor_torque_is_never_above_the_driving_one():
    """For eta <= 1, |tau eta / N| <= |tau / (N eta)|: the load helps when it drives back."""
    rng = np.random.default_rng(1)
    psa = unit("PSA-14-50")
    tau = rng.normal(0, 5, 500)
    qd = rng.uniform(0.1, 2, 500)  # moving: none at rest, where the motor holds (driving)
    _, forward = motor_demand(psa, tau, np.abs(qd) * np.sign(tau), np.zeros(500))
    _, backward = motor_demand(psa, tau, -np.abs(qd) * np.sign(tau), np.zeros(500))
    assert np.all(np.abs(backward) <= np.abs(forward))
    np.testing.assert_allclose(backward, forward * DEFAULT_EFFICIENCY**2, rtol=1e-12)


def test_reflected_inertia_scales_with_the_ratio_squared():
    """At zero load torque the motor's acceleration torque is (J_in + J_m) N qdd at the motor;
    the inertia seen at the output, T_motor N / qdd = (J_in + J_m) N^2."""
    rng = np.random.default_rng(7)
    qdd = rng.uniform(-50, 50, 100)
    zero = np.zeros(100)
    for unit_id in ("PSA-14-50", "PSA-14-80", "PSA-14-100"):
        psa = unit(unit_id)
        _, torque = motor_demand(psa, zero, zero, qdd, rotor_inertia=1e-5)
        np.testing.assert_allclose(torque * psa.ratio, (3.3e-6 + 1e-5) * psa.ratio**2 * qdd,
                                   rtol=1e-12)


# --- worst_momentary: e-stop or crash ----------------------------------------------------

def test_crash_torque_by_hand_for_psa_14_100():
    """Crash at qd = 2 rad/s within 0.1 s: (J_in + J_m) N^2 |qd| / t_stop
    = (3.3e-6 + 1e-5) * 100^2 * 2 / 0.1 = 2.66 N m, on top of |tau| = 1 N m."""
    psa = unit("PSA-14-100")
    t = np.array([0.0, 0.5, 1.0])
    tau = np.array([0.0, -1.0, 0.0])
    qd = np.array([0.0, 2.0, 0.0])
    stop_tau = np.array([0.0, 0.5, 0.0])
    event = worst_momentary(psa, t, tau, qd, stop_tau, 0.1, rotor_inertia=1e-5)
    assert event.kind == "crash"
    assert event.torque == pytest.approx(1.0 + 2.66, rel=1e-12)
    assert event.time == 0.5 and event.speed == 2.0 and event.duration == 0.1


def test_emergency_stop_wins_when_it_is_worse():
    psa = unit("PSA-14-100")
    t = np.array([0.0, 0.1, 0.2, 0.3])
    tau = np.array([1.0, 1.0, 1.0, 1.0])
    qd = np.array([0.5, 1.0, 3.0, 0.0])
    stop_tau = np.array([0.2, -9.0, 4.0, 0.0])
    # crash: 1 + 3.3e-6 * 1e4 * |qd| / 0.05 = 1 + 0.66 |qd|: at most 1 + 1.98 = 2.98 N m
    # e-stop: |stop_tau| at most 9 N m at t = 0.1 s, speed 1 rad/s
    event = worst_momentary(psa, t, tau, qd, stop_tau, 0.05)
    assert event.kind == "emergency stop"
    assert event.torque == 9.0 and event.time == 0.1 and event.speed == 1.0
    assert event.duration == 0.05


def test_crash_term_scales_with_ratio_squared_over_stop_time():
    rng = np.random.default_rng(3)
    qd = rng.uniform(0.1, 3.0, 50)
    zero = np.zeros(50)
    t = np.arange(50) * 0.01
    for stop_time in (0.05, 0.2):
        crash = {}
        for unit_id in ("PSA-14-50", "PSA-14-80", "PSA-14-100"):
            psa = unit(unit_id)
            event = worst_momentary(psa, t, zero, qd, zero, stop_time)
            assert event.kind == "crash"
            crash[psa.ratio] = event.torque
            assert event.torque == pytest.approx(3.3e-6 * psa.ratio**2 * qd.max() / stop_time,
                                                 rel=1e-12)
        assert crash[100] / crash[50] == pytest.approx(4.0, rel=1e-12)
        assert crash[80] / crash[50] == pytest.approx(80**2 / 50**2, rel=1e-12)


# --- a unit with its own efficiency table --------------------------------------------------

TABLE_CATALOG = """\
series = "TST"
source = "test catalog with an efficiency table"

[[unit]]
size = 14
ratio = 100
rated_torque_nm = 10.0
repeated_torque_nm = 20.0
momentary_torque_nm = 30.0
static_torque_nm = 30.0
max_input_speed_rpm = 6000
input_inertia_kg_cm2 = 0.05
mass_kg = 0.6

[unit.efficiency]
input_speed_rpm = [500, 3000]
torque_percent = [0, 100]
value = [[0.5, 0.8], [0.4, 0.7]]
"""


def table_unit(tmp_path):
    path = tmp_path / "tst.toml"
    path.write_text(TABLE_CATALOG)
    return unit("TST-14-100", [path])


def test_efficiency_table_is_interpolated_by_hand(tmp_path):
    tst = table_unit(tmp_path)
    assert tst.input_inertia == pytest.approx(5e-6, rel=1e-12)
    # sample 1: input 1750 rpm (qd = 1750 2 pi / 60 / 100 rad/s), tau = 5 N m = 50 % rated:
    #   eta(500 rpm, 50 %) = 0.65, eta(3000 rpm, 50 %) = 0.55; 1750 is half way: eta = 0.60
    #   driving: T = 5 / (100 * 0.60)
    # sample 2: input 250 rpm (clamped to the 500 rpm row), tau = -2.5 N m = 25 %,
    #   qd > 0 so back-driven: eta = 0.5 + 0.25 * 0.3 = 0.575, T = -2.5 * 0.575 / 100
    # sample 3: input 6000 rpm (clamped to 3000), tau = 30 N m = 300 % (clamped to 100 %):
    #   eta = 0.7, driving with qdd = 20: T = 30 / 70 + 5e-6 * 100 * 20
    rpm = 2 * math.pi / 60 / 100
    qd = np.array([1750 * rpm, 250 * rpm, 6000 * rpm])
    tau = np.array([5.0, -2.5, 30.0])
    qdd = np.array([0.0, 0.0, 20.0])
    summary, torque = motor_demand(tst, tau, qd, qdd, efficiency=0.99)
    expected = [5 / 60, -2.5 * 0.575 / 100, 30 / 70 + 0.01]
    np.testing.assert_allclose(torque, expected, rtol=1e-12)
    assert summary.efficiency == "table"
    assert summary.max_speed == pytest.approx(6000, rel=1e-12)


def test_efficiency_table_reaches_size(tmp_path):
    """`size` uses the table for that unit and the default for the others."""
    from hdselect.sizing.core import size
    from helpers import REPO

    path = tmp_path / "tst.toml"
    path.write_text(TABLE_CATALOG)
    result = size(None, REPO / "trajectories" / "index_table_indexing.toml", catalog=[path])
    (joint,) = result.joints
    motors = {c.unit.id: c.motor for c in joint.candidates}
    assert motors["TST-14-100"].efficiency == "table"
    assert motors["PSA-14-100"].efficiency == DEFAULT_EFFICIENCY


def test_weighted_demand_equals_the_demand_of_the_samples_repeated():
    """A run of identical samples kept once with its length gives the whole cycle's RMS."""
    psa = unit("PSA-14-80")
    rng = np.random.default_rng(7)
    tau, qd, qdd = rng.normal(size=(3, 40))
    weight = rng.integers(1, 6, size=40)
    (kept,) = reflect([psa], np.arange(40) * 1e-3, tau, qd, qdd, tau, stop_time=0.1)
    whole = [np.repeat(x, weight) for x in (tau, qd, qdd)]
    (full,) = reflect([psa], np.arange(weight.sum()) * 1e-3, *whole, whole[0], stop_time=0.1)
    weighted = weighted_demand(kept.motor, kept.motor_torque, qd, psa.ratio, weight * 1e-3)
    assert weighted.rms_torque == pytest.approx(full.motor.rms_torque, rel=1e-12)
    assert weighted.rms_speed == pytest.approx(full.motor.rms_speed, rel=1e-12)
    assert weighted.peak_torque == full.motor.peak_torque
    assert weighted.max_speed == full.motor.max_speed
    assert kept.motor.rms_torque != pytest.approx(full.motor.rms_torque, rel=1e-3)
