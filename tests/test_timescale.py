"""Time scaling against oracles: Pinocchio at the scaled speeds, hand algebra, brute force.

A path run s times slower (docs/rules.md, "When no unit fits"), per sample, with
g = RNEA(q, 0, 0), v = RNEA(q, qd, 0) - g, i = RNEA(q, qd, qdd) - RNEA(q, qd, 0) and
e = RNEA(q, qd, -qd / t_stop) - RNEA(q, qd, 0):
    speed qd / s, acceleration qdd / s^2, times t s
    tau(s)  = g + (v + i) / s^2            stop(s) = g + v / s^2 + e / s
    crash   = |tau(s)| + (J_in + J_m) N^2 |qd| / (s t_stop)
The scaled cycle is written out again below (`full_check`) and judged by the real
`cycle_load`, `reflect` and `check_unit`, as the sizing judges a cycle at s = 1.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import check_unit, cycle_load
from hdselect.catalog.units import Unit
from hdselect.robot.model import load_robot
from hdselect.sizing.intervals import intersect
from hdselect.sizing.reflect import reflect
from hdselect.sizing.timescale import (
    JointScales,
    ScalableCycle,
    Slowdown,
    check_at,
    exact_scales,
    feasible_scales,
    find_slowdown,
    joint_scales,
)
from helpers import REPO

RPM = 60 / (2 * math.pi)  # rpm per rad/s
J_TABLE = 0.0429416 + 4 * (0.00010048 + 0.3768 * 0.11**2)  # index table, from its URDF
TABLE_TORQUE = J_TABLE * 8 * math.pi  # J A, A = 4 (pi / 2) / 0.5^2 [N m]
TABLE_SPEED_BOUND = 8 * math.pi * (0.25 - 0.00125) * 100 * RPM / 6000  # 0.995


# --- factories -------------------------------------------------------------------------------

def unit(unit_id: str = "PSA-14-100", **changes: float) -> Unit:
    """A catalog unit with some of its figures changed (N m, rpm)."""
    found = next(u for u in load_catalog() if u.id == unit_id)
    return dataclasses.replace(found, **changes)


def generous(unit_id: str = "PSA-14-100", **changes: float) -> Unit:
    """A catalog unit with no limit but those `changes` set (a huge rated torque)."""
    limits = dict(rated_torque=1e4, repeated_torque=math.inf, momentary_torque=math.inf,
                  static_torque=math.inf, max_input_speed=math.inf)
    return unit(unit_id, **{**limits, **changes})


def cycle(g, v=0.0, i=0.0, e=0.0, *, qd=0.1, qdd=0.0, at_rest=False, n: int = 40,
          dt: float = 0.01, stop_time: float = 0.1) -> ScalableCycle:
    """A synthetic cycle of n samples; scalars are broadcast [N m, rad/s, rad/s^2, s]."""
    return ScalableCycle(t=np.arange(n) * dt, dt=dt, duration=n * dt, qd=qd, qdd=qdd,
                         at_rest=at_rest, gravity=g, velocity=v, inertial=i, stop_inertial=e,
                         stop_time=stop_time)


def full_check(c: ScalableCycle, psa: Unit, s: float, *, life_hours: float | None = None,
               rotor_inertia: float = 0.0) -> bool:
    """Oracle: every rule on the cycle run s times slower, the scaling written out again."""
    torque = c.gravity + (c.velocity + c.inertial) / s**2
    stop = c.gravity + c.velocity / s**2 + c.stop_inertial / s
    load = cycle_load(torque, c.qd / s, c.dt * s, c.at_rest)
    (r,) = reflect([psa], c.t * s, torque, c.qd / s, c.qdd / s**2, stop,
                   stop_time=c.stop_time, rotor_inertia=rotor_inertia)
    return check_unit(load, psa, momentary=r.momentary, life_hours=life_hours).feasible


def rnea(model: pin.Model, config: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Oracle: one `pinocchio.rnea` call per sample, shape (n, nv)."""
    data = model.createData()
    return np.array([pin.rnea(model, data, config[:, k], qd[k], qdd[k]).copy()
                     for k in range(len(qd))])


# --- the scaled cycle is the dynamics of the slowed motion -----------------------------------

@pytest.mark.parametrize("s", [0.5, 2.0, 3.7])
def test_scaled_cycle_equals_pinocchio_at_scaled_speeds(s):
    robot = load_robot(REPO / "robots" / "planar2.urdf")
    rng = np.random.default_rng(7)
    n, stop_time = 60, 0.08
    q = rng.uniform(robot.lower, robot.upper, size=(n, 2))
    qd, qdd = rng.uniform(-3, 3, size=(n, 2)), rng.uniform(-20, 20, size=(n, 2))
    config, still = robot.configuration(q), np.zeros((n, 2))
    gravity, coast = rnea(robot.model, config, still, still), rnea(robot.model, config, qd, still)
    tau, stop = rnea(robot.model, config, qd, qdd), rnea(robot.model, config, qd, -qd / stop_time)
    slow_tau = rnea(robot.model, config, qd / s, qdd / s**2)
    slow_stop = rnea(robot.model, config, qd / s, -qd / (s * stop_time))
    for j in range(2):
        c = ScalableCycle.split(np.arange(n) * 0.01, 0.01, n * 0.01, qd[:, j], qdd[:, j],
                                np.zeros(n, bool), torque=tau[:, j], stop_torque=stop[:, j],
                                gravity=gravity[:, j], coast=coast[:, j], stop_time=stop_time)
        at = c.at(s)
        size = np.abs(slow_tau[:, j]).max() + np.abs(slow_stop[:, j]).max()
        np.testing.assert_allclose(at.torque, slow_tau[:, j], rtol=1e-9, atol=1e-12 * size)
        np.testing.assert_allclose(at.stop_torque, slow_stop[:, j], rtol=1e-9, atol=1e-12 * size)
        np.testing.assert_allclose(at.qd, qd[:, j] / s, rtol=1e-15)
        np.testing.assert_allclose(at.qdd, qdd[:, j] / s**2, rtol=1e-15)
        np.testing.assert_allclose(at.t, np.arange(n) * 0.01 * s, rtol=1e-15)
        assert at.dt == pytest.approx(0.01 * s, rel=1e-15) and at.duration == n * 0.01 * s
        assert not at.torque.flags.writeable and not c.gravity.flags.writeable


# --- gravity and dynamics opposed: feasibility is not monotone in s --------------------------

def opposed() -> ScalableCycle:
    """Gravity 10 N m, inertial part -30 N m on every moving sample: tau = 10 - 30 x,
    x = 1/s^2. |tau| <= 9 for x in [1/30, 19/30], s in [sqrt(30/19), sqrt(30)]."""
    return cycle(10.0, i=-30.0)


def test_opposed_gravity_feasible_between_two_scales():
    psa = generous(repeated_torque=9.0)
    lo, hi = math.sqrt(30 / 19), math.sqrt(30)  # 1.2566, 5.4772
    (found,) = feasible_scales(opposed(), psa)
    assert found == pytest.approx((lo, hi), rel=1e-9)
    assert found == pytest.approx((1.2566, 5.4772), abs=1e-4)
    for s in (lo * (1 + 1e-6), math.sqrt(lo * hi), hi * (1 - 1e-6)):
        assert full_check(opposed(), psa, s)
        assert check_at(opposed(), psa, s).feasible
    for s in (1.0, lo * (1 - 1e-6), hi * (1 + 1e-6), 1e3):  # 1e3: "gravity alone too much"
        assert not full_check(opposed(), psa, s)
    # the old bisection tried s = 1000 first and said no slow-down helps
    slowdown = find_slowdown(opposed(), [psa])
    assert slowdown.factor == pytest.approx(lo, rel=1e-9) and slowdown.unit == "PSA-14-100"
    assert slowdown.cycle_time == pytest.approx(lo * 0.4, rel=1e-12)


def test_every_unit_gets_its_intervals_and_the_slowdown_takes_the_smallest():
    weak, strong = generous("PSA-14-80", repeated_torque=9.0), generous(repeated_torque=15.0)
    scales = joint_scales(opposed(), [weak, strong])
    # |10 - 30 x| <= 15: x <= 25/30, s >= sqrt(30/25) = 1.0954, no upper end
    (weak_fit,), (strong_fit,) = scales.fits["PSA-14-80"], scales.fits["PSA-14-100"]
    assert weak_fit == pytest.approx((math.sqrt(30 / 19), math.sqrt(30)), rel=1e-9)
    assert strong_fit == pytest.approx((math.sqrt(1.2), math.inf), rel=1e-9)
    assert scales.slowdown().factor == pytest.approx(math.sqrt(1.2), rel=1e-9)
    assert scales.slowdown().unit == "PSA-14-100"
    assert scales.smallest(2.0) == (2.0, "PSA-14-80")  # both fit at 2: catalog order wins
    assert scales.smallest(6.0) == (6.0, "PSA-14-100")


def test_a_joint_that_passes_only_faster():
    """Gravity -30 N m, dynamics +10 N m: |-30 + 10 x| <= 9 for x in [2.1, 3.9],
    s in [1/sqrt(3.9), 1/sqrt(2.1)] = [0.5064, 0.6901]: only a faster motion passes."""
    scales = joint_scales(cycle(-30.0, i=10.0), [generous(repeated_torque=9.0)])
    lo, hi = 1 / math.sqrt(3.9), 1 / math.sqrt(2.1)
    fastest, fastest_unit = scales.smallest()
    assert fastest == pytest.approx(lo, rel=1e-9) and fastest_unit == "PSA-14-100"
    slowdown = scales.slowdown()  # no s >= 1 fits: the mildest speed-up
    assert slowdown.factor == pytest.approx(hi, rel=1e-9) and slowdown.unit == "PSA-14-100"


# --- closed forms ----------------------------------------------------------------------------

def test_crash_bound():
    """No gravity; qd = 2 rad/s, tau = J qdd = 5 N m (J = 0.5, qdd = 10) on every sample;
    stop inertial part -J qd / t_stop = -10 N m. Crash with K = (J_in + J_m) N^2 / t_stop:
    5 y^2 + 2 K y <= 22.6 (y = 1/s), so y = (-2 K + sqrt(4 K^2 + 4 5 22.6)) / (2 5).
    The stop, 10 y <= 22.6, allows y up to 2.26, far beyond."""
    psa, rotor = unit(), 1e-4
    k = (psa.input_inertia + rotor) * 100**2 / 0.1  # 10.33 N m s/rad
    y = (-2 * k + math.sqrt(4 * k**2 + 4 * 5 * 22.6)) / (2 * 5)
    c = cycle(0.0, i=5.0, e=-10.0, qd=2.0, qdd=10.0)
    assert psa.momentary_torque == 22.6 and psa.ratio == 100
    (found,) = feasible_scales(c, psa, rotor_inertia=rotor)
    assert found == pytest.approx((1 / y, math.inf), rel=1e-9)
    assert 1 / y == pytest.approx(1.1129, abs=1e-4)
    at = check_at(c, psa, 1 / y * (1 + 1e-9), rotor_inertia=rotor)
    assert at.binding == "momentary" and at.checks["momentary"].detail["kind"] == "crash"
    assert at.checks["momentary"].utilization == pytest.approx(1.0, rel=1e-8)


def test_speed_bound():
    """Fastest |qd| 3 rad/s through N = 100: 3 x 100 x 60 / (2 pi) rpm / s <= 6000 rpm,
    s >= 0.47746. The torques are tiny."""
    c = cycle(0.1, i=0.01, qd=np.linspace(-3.0, 2.0, 40))
    (found,) = feasible_scales(c, unit())
    assert found == pytest.approx((300 * RPM / 6000, math.inf), rel=1e-12)
    assert found[0] == pytest.approx(0.47746, abs=1e-5)


def index_table_cycle() -> ScalableCycle:
    """The index table turning theta = pi/2 in T = 0.5 s, accelerating at A = 4 theta / T^2
    to w = 2 theta / T = 2 pi rad/s half-way, then braking: tau = J A = +-1.5476 N m,
    from Pinocchio. 200 samples at the midpoints of dt = T / 200: sum |qd| dt = theta
    exactly, so the mean output speed is theta / T = pi rad/s (3000 rpm through N = 100);
    the fastest sample, A (T / 2 - dt / 2), is 0.995 w (5970 rpm)."""
    robot = load_robot(REPO / "robots" / "index_table.urdf")
    n, period, theta = 200, 0.5, math.pi / 2
    accel, dt = 4 * theta / period**2, period / 200
    t = (np.arange(n) + 0.5) * dt
    first = t < period / 2
    qd = np.where(first, accel * t, accel * (period - t))
    qdd = np.where(first, accel, -accel)
    q = np.where(first, accel * t**2 / 2, theta - accel * (period - t) ** 2 / 2)
    config, still, stop_time = robot.configuration(q[:, None]), np.zeros((n, 1)), 0.1
    torque = rnea(robot.model, config, qd[:, None], qdd[:, None])[:, 0]
    np.testing.assert_allclose(torque, J_TABLE * qdd, rtol=1e-6)
    return ScalableCycle.split(
        t - dt / 2, dt, period, qd, qdd, np.zeros(n, bool), torque=torque,
        stop_torque=rnea(robot.model, config, qd[:, None], -qd[:, None] / stop_time)[:, 0],
        gravity=rnea(robot.model, config, still, still)[:, 0],
        coast=rnea(robot.model, config, qd[:, None], still)[:, 0], stop_time=stop_time)


def test_index_table_mean_torque_bound():
    """T_av = J A / s^2 (|tau| is the same everywhere), mean input speed 3000 / s rpm,
    allowed (1750 s / 3000)^0.33 T_N (below the repeated limit). With T_N = 1 N m the
    rule holds from s^2.33 = J A (3000 / 1750)^0.33 / T_N: s = 1.3019."""
    psa = unit(rated_torque=1.0)
    (found,) = feasible_scales(index_table_cycle(), psa)
    s = (TABLE_TORQUE * (3000 / 1750) ** 0.33 / 1.0) ** (1 / 2.33)
    assert s == pytest.approx(1.3019, abs=1e-4)
    assert found == pytest.approx((s, math.inf), rel=2e-6)
    (exact,) = exact_scales(index_table_cycle(), psa)
    assert exact == pytest.approx((TABLE_SPEED_BOUND, math.inf), rel=1e-12)


def test_index_table_life_bound():
    """L50 = 35000 (1750 s / 3000) (T_N s^2 / (J A))^3 h >= L: s^7 = L / L50(s = 1).
    Without a life requirement the speed binds: peak input speed 6000 x 0.995 rpm / s."""
    c = index_table_cycle()
    life_at_1 = 35000 * 1750 / 3000 * (11.5 / TABLE_TORQUE) ** 3  # 8.38e6 h
    (found,) = feasible_scales(c, unit(), check_options={"life_hours": 3e7})
    assert found == pytest.approx(((3e7 / life_at_1) ** (1 / 7), math.inf), rel=2e-6)
    (found,) = feasible_scales(c, unit())
    assert found == pytest.approx((TABLE_SPEED_BOUND, math.inf), rel=1e-12)


def test_gravity_alone_too_much_for_every_unit():
    """50 N m of gravity on every sample (a quarter at rest), dynamics of the same sign:
    above every catalog unit's repeated, static and momentary limit at any s."""
    rest = np.arange(40) % 4 == 0
    c = cycle(50.0, i=np.where(rest, 0.0, 5.0), qd=np.where(rest, 0.0, 0.5), at_rest=rest)
    units = load_catalog()
    assert all(exact_scales(c, u) == () and feasible_scales(c, u) == () for u in units)
    assert find_slowdown(c, units) == Slowdown(None, None, None)
    assert joint_scales(c, units).smallest() is None


def test_intersection_of_closed_pieces():
    inf = math.inf
    # rows: [0, 2] u [4, 7] | [1, 3] u [5, inf] | [2, 6]: meet at y = 2 and on [5, 6]
    lo = np.array([[0.0, 1.0, 2.0], [4.0, 5.0, inf]])
    hi = np.array([[2.0, 3.0, 6.0], [7.0, inf, -inf]])
    assert intersect(lo, hi) == [(2.0, 2.0), (5.0, 6.0)]
    assert intersect(lo[:, :2], hi[:, :2]) == [(1.0, 2.0), (5.0, 7.0)]
    everywhere = (np.array([[0.0], [inf]]), np.array([[inf], [-inf]]))
    assert intersect(*everywhere) == [(0.0, inf)]
    nowhere = np.array([[inf], [inf]]), np.array([[-inf], [-inf]])
    assert intersect(np.hstack([lo, nowhere[0]]), np.hstack([hi, nowhere[1]])) == []


# --- brute force over seeded random cycles -----------------------------------------------------

def random_case(seed: int) -> tuple[ScalableCycle, Unit, float | None]:
    """A random cycle and unit; seed % 3 picks the shape: 0 anything, 1 gravity above the
    peak limit opposed by inertia (a bounded interval), 2 an emergency stop whose
    inertial part swings the torque through the band (two intervals)."""
    rng = np.random.default_rng(seed)
    n = 60
    psa = [u for u in load_catalog() if u.size >= 10][rng.integers(5)]
    psa = dataclasses.replace(psa, rated_torque=psa.rated_torque * rng.uniform(0.2, 1.0))
    peak, momentary, sign = psa.repeated_torque, psa.momentary_torque, rng.choice([-1.0, 1.0])
    rest = rng.random(n) < 0.2
    qd = rng.uniform(-3.0, 3.0, n) * (0.15 if seed % 3 == 2 else 1.0)
    qdd = rng.uniform(-20.0, 20.0, n)
    jitter = rng.uniform(0.9, 1.1, (4, n))
    if seed % 3 == 0:
        g = rng.uniform(-1, 1, n) * peak
        v, i, e = (rng.uniform(-1, 1, (3, n)).T * [0.3, 2.0, 1.0] * peak).T
    elif seed % 3 == 1:
        g = sign * rng.uniform(1.05, 1.3) * peak * jitter[0]
        v, i, e = sign * peak * np.array([0.1, -rng.uniform(1.0, 3.0), -0.5])[:, None] * jitter[1:]
    else:  # stop(y) = g - 1.8 y + 0.4 y^2 (x momentary): below -1 for y in [0.81, 3.69]
        g, v, e = sign * momentary * np.array([0.2, 0.4, -1.8])[:, None] * jitter[:3] ** 0.3
        i = -v + 0.02 * momentary * rng.uniform(-1.0, 1.0, n)  # tau(s) close to g
    qd, qdd, v, i, e = (np.where(rest, 0.0, x) for x in (qd, qdd, v, i, e))
    c = ScalableCycle(t=np.arange(n) * 0.01, dt=0.01, duration=n * 0.01, qd=qd, qdd=qdd,
                      at_rest=rest, gravity=g, velocity=v, inertial=i, stop_inertial=e,
                      stop_time=0.1)
    return c, psa, [None, 2e4, 1e6][rng.integers(3)]


@pytest.mark.slow
def test_intervals_agree_with_brute_force():
    grid = np.geomspace(1e-2, 1e2, 1200)
    seen = {"bounded": 0, "two or more": 0, "set by a whole-cycle rule": 0, "empty": 0}
    for seed in range(15):
        c, psa, life = random_case(seed)
        found = feasible_scales(c, psa, check_options={"life_hours": life})
        ends = [end for piece in found for end in piece if 0.0 < end < math.inf]
        for s in grid:
            if any(abs(s / end - 1) <= 1e-6 for end in ends):
                continue
            inside = any(lo <= s <= hi for lo, hi in found)
            assert full_check(c, psa, s, life_hours=life) == inside, (seed, s, found)
        exact = {end for piece in exact_scales(c, psa) for end in piece}
        seen["bounded"] += any(hi < math.inf for _, hi in found)
        seen["two or more"] += len(found) >= 2
        seen["set by a whole-cycle rule"] += any(end not in exact for end in ends)
        seen["empty"] += not found
    assert all(seen.values()), seen


def test_joint_scales_record():
    scales = JointScales(2.0, {"A": ((0.5, 0.8),), "B": ((1.5, math.inf),), "C": ()})
    assert scales.smallest() == (0.5, "A") and scales.smallest(1.0) == (1.5, "B")
    assert scales.slowdown().cycle_time == 3.0
