"""The envelope against oracles: closed forms, per-sample Pinocchio, a dense random sample.

The worst states must be real states (their torque re-computed by per-sample
`pinocchio.rnea` on a model built here, not by hdselect), must equal the closed
forms of the index table and the planar arm, must not be beaten by any state of a
dense random sample, and the units chosen must hold for every shipped motion of the
6-axis arm within the same limits.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import minimize

from hdselect.envelope import SearchSettings, envelope
from hdselect.envelope.search import agree
from hdselect.motion.loading import load_case
from hdselect.robot.mounting import STANDARD_GRAVITY
from hdselect.robot.payload import Payload
from hdselect.sizing.core import check_units, size
from helpers import REPO

ROBOTS = REPO / "robots"
MOTIONS = REPO / "trajectories"
G = STANDARD_GRAVITY
DEG = math.pi / 180.0

# planar2.urdf (its comment derives each number): link 1 and link 2
M1, LC1, I1, L1 = 0.243, 0.15, 0.00184072, 0.3
M2, LC2, I2 = 0.16875, 0.125, 0.000887695
K = I2 + M2 * LC2**2  # M22, and the constant part of M12 [kg m^2]
H = M2 * L1 * LC2  # amplitude of the cos q2 part of M12 and of the velocity products
# index_table.urdf: disk and four steel blocks at 0.11 m
J_TABLE = 0.0429416 + 4 * (0.00010048 + 0.3768 * 0.11**2)  # [kg m^2]

PAYLOAD = Payload(0.5, (0.0, 0.0, 0.03), ((2.1e-4, 0, 0), (0, 2.1e-4, 0), (0, 0, 2.1e-4)),
                  "tool0")


def oracle_model(path, payload: Payload | None, masses: dict[str, float]) -> pin.Model:
    """The robot built with Pinocchio alone: payload, point masses at joint origins, gravity."""
    model = pin.buildModelFromUrdf(str(path))
    if payload is not None:
        frame = model.frames[model.getFrameId(payload.frame)]
        model.appendBodyToJoint(frame.parentJoint, pin.Inertia(
            payload.mass, np.array(payload.com), np.array(payload.inertia)), frame.placement)
    for name, mass in masses.items():
        k = model.getJointId(name)
        if model.parents[k] > 0:
            model.appendBodyToJoint(model.parents[k], pin.Inertia(
                mass, np.zeros(3), np.zeros((3, 3))), model.jointPlacements[k])
    model.gravity.linear = np.array([0.0, 0.0, -G])
    return model


# -- closed forms --------------------------------------------------------------------------


def test_index_table_peak_is_inertia_times_acceleration_and_stop_inertia_times_speed():
    """A table about a vertical axis carries no gravity and no velocity product.

    tau = J qdd, so the worst repeated torque is J a; an emergency stop from full speed
    decelerates at v / T: J v / T. Held, it carries nothing (static 0, gravity 0). The
    table's own unit sits on the base, so nothing is carried.
    """
    v, a, stop_time = 270 * DEG, 2000 * DEG, 0.1
    result = envelope(ROBOTS / "index_table.urdf", velocity=v, acceleration=a,
                      stop_time=stop_time)
    (table,) = result.joints
    assert abs(table.worst["peak"].torque) == pytest.approx(J_TABLE * a, rel=1e-9)
    assert abs(table.worst["stop"].torque) == pytest.approx(J_TABLE * v / stop_time, rel=1e-9)
    assert abs(table.worst["static"].torque) < 1e-12
    assert abs(table.gravity.torque) < 1e-12
    assert abs(table.worst["peak"].qd[0]) == pytest.approx(v)  # the crash's full speed
    assert table.convergence.converged and result.converged


@pytest.fixture(scope="module")
def planar():
    v, a, stop_time = 180 * DEG, 900 * DEG, 0.1
    return envelope(ROBOTS / "planar2.urdf", velocity=v, acceleration=a,
                    stop_time=stop_time), v, a, stop_time


def test_planar_elbow_worst_torques_equal_closed_forms(planar):
    """The elbow of the two-link arm in a vertical plane (q measured from the horizontal).

    tau2 = M21 qdd1 + M22 qdd2 + h qd1^2 + G cos(q1 + q2), with G = m2 lc2 g,
    M21 = K + H cos q2, M22 = K, h = H sin q2 (K = I2 + m2 lc2^2, H = m2 l1 lc2).

    Peak: |qdd_k| = a at the vertex whose signs align every term, cos(q1 + q2) = 1 (the
    second link horizontal) and qd1^2 = v^2:
        G + K a + K a + H (a cos q2 + v^2 sin q2)  ->  G + 2 K a + H sqrt(a^2 + v^4)
    at q2 = atan(v^2 / a) (reachable: q1 = -q2 lies in the shoulder's range).
    Static (the elbow held, qd2 = qdd2 = 0, the shoulder moving anywhere):
        G + K a + H sqrt(a^2 + v^4).
    Stop from (q, qd), decelerating at -qd / T:
        G + H sin q2 qd1^2 + ((K + H cos q2) |qd1| + K |qd2|) / T, largest at |qd| = v and
        q2 = atan(v T): G + K (v + v) / T + H v sqrt(v^2 + 1 / T^2).
    Gravity: G at the horizontal. No unit is carried by the elbow (its own sits on link 1).
    """
    result, v, a, stop_time = planar
    elbow = result.joints[1]
    gravity = M2 * LC2 * G
    assert abs(elbow.worst["peak"].torque) == pytest.approx(
        gravity + 2 * K * a + H * math.hypot(a, v * v), rel=1e-9)
    assert abs(elbow.worst["static"].torque) == pytest.approx(
        gravity + K * a + H * math.hypot(a, v * v), rel=1e-9)
    assert abs(elbow.worst["stop"].torque) == pytest.approx(
        gravity + 2 * K * v / stop_time + H * v * math.hypot(v, 1 / stop_time), rel=1e-9)
    assert abs(elbow.gravity.torque) == pytest.approx(gravity, rel=1e-12)


def test_planar_shoulder_gravity_is_worst_at_full_extension(planar):
    """Gravity on the shoulder, the arm stretched horizontally (q1 = q2 = 0, both reachable):

        (m1 lc1 + (m2 + m_e) l1 + m2 lc2) g,

    m_e the elbow unit's mass, carried at the elbow's origin (x = l1 on link 1).
    """
    result, *_ = planar
    carried = result.masses["elbow"]
    expected = (M1 * LC1 + (M2 + carried) * L1 + M2 * LC2) * G
    assert abs(result.joints[0].gravity.torque) == pytest.approx(expected, rel=1e-12)
    assert np.allclose(result.joints[0].gravity.q, 0.0, atol=1e-4)


SHOULDER_RANGE = (np.array([-1.5707963, -2.6179939]), np.array([2.0943951, 2.6179939]))
"""planar2.urdf's joint ranges [rad]: (lower, upper) of (q1, q2)."""


def shoulder_terms(q1, q2, me):
    """The shoulder's row of the planar arm's dynamics, the elbow unit m_e at x = l1 on link 1:

        M11 = I1 + I2 + m1 lc1^2 + m2 (l1^2 + lc2^2 + 2 l1 lc2 cos q2) + m_e l1^2,
        M12 = K + H cos q2,  c1 = -h (2 qd1 qd2 + qd2^2) with h = H sin q2,
        g1 = (m1 lc1 + (m2 + m_e) l1) g cos q1 + m2 lc2 g cos(q1 + q2).

    Returns M11, M12 [kg m^2], h [kg m^2] and g1 [N m].
    """
    m11 = I1 + I2 + M1 * LC1**2 + M2 * (L1**2 + LC2**2 + 2 * L1 * LC2 * np.cos(q2)) \
        + me * L1**2
    m12 = K + H * np.cos(q2)
    g1 = (M1 * LC1 + (M2 + me) * L1) * G * np.cos(q1) + M2 * LC2 * G * np.cos(q1 + q2)
    return m11, m12, H * np.sin(q2), g1


def maximised(worst):
    """The largest value of worst(q1, q2) over the joint ranges: a 1201 x 1201 grid, then
    Nelder-Mead from its best point (never below the grid's best)."""
    lo, hi = SHOULDER_RANGE
    q1, q2 = np.meshgrid(np.linspace(lo[0], hi[0], 1201), np.linspace(lo[1], hi[1], 1201))
    values = worst(q1, q2)
    k = np.unravel_index(np.argmax(values), values.shape)
    best = minimize(lambda x: -worst(*np.clip(x, lo, hi)), [q1[k], q2[k]],
                    method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-14})
    assert -best.fun >= values.max()
    return -best.fun


def test_planar_shoulder_peak_equals_the_closed_form_maximised_independently(planar):
    """The shoulder's peak from its closed form (`shoulder_terms`), maximised by `maximised`.

    tau1 = M11 qdd1 + M12 qdd2 + c1 + g1. The worst vertex gives M11 a + |M12| a; over
    the speed box 2 qd1 qd2 + qd2^2 spans [-v^2, 3 v^2] (bilinear in qd1, then
    quadratic in qd2), so the worst |g1 + c1| is the larger of |g1 + h v^2| and
    |g1 - 3 h v^2|. What is left is a function of (q1, q2) over the joint ranges.
    """
    result, v, a, _ = planar
    me = result.masses["elbow"]

    def peak(q1, q2):
        m11, m12, h, g1 = shoulder_terms(q1, q2, me)
        bias = np.maximum(np.abs(g1 + h * v * v), np.abs(g1 - 3 * h * v * v))
        return bias + m11 * a + np.abs(m12) * a

    assert abs(result.joints[0].worst["peak"].torque) == pytest.approx(maximised(peak),
                                                                       rel=1e-8)


@pytest.mark.slow
def test_planar_shoulder_static_and_stop_equal_their_closed_forms_maximised(planar):
    """The shoulder held, and the shoulder's emergency stop, from `shoulder_terms`.

    Static (qd1 = qdd1 = 0, the elbow anywhere within the spec): tau1 = M12 qdd2 - h qd2^2
    + g1, affine in qdd2 and in qd2^2 in [0, v^2]: max(|g1|, |g1 - h v^2|) + |M12| a.

    Stop from (q, qd), decelerating at -qd / T:
        tau1 = g1 - h (2 qd1 qd2 + qd2^2) - (M11 qd1 + M12 qd2) / T,
    affine in qd1 (so |tau1| is largest at qd1 = +-v) and a parabola in qd2, whose
    largest |value| on [-v, v] is at an end or at its vertex
    qd2 = -(2 h qd1 + M12 / T) / (2 h), clipped to the box.
    """
    result, v, a, stop_time = planar
    me = result.masses["elbow"]

    def static(q1, q2):
        _, m12, h, g1 = shoulder_terms(q1, q2, me)
        return np.maximum(np.abs(g1), np.abs(g1 - h * v * v)) + np.abs(m12) * a

    def stop(q1, q2):
        m11, m12, h, g1 = shoulder_terms(q1, q2, me)
        best = np.zeros_like(np.asarray(q1, dtype=float))
        for qd1 in (-v, v):
            with np.errstate(divide="ignore", invalid="ignore"):
                vertex = np.clip(-(2 * h * qd1 + m12 / stop_time) / (2 * h), -v, v)
            vertex = np.where(np.isfinite(vertex), vertex, v)
            for qd2 in (-v, v, vertex):
                tau = g1 - h * (2 * qd1 * qd2 + qd2**2) - (m11 * qd1 + m12 * qd2) / stop_time
                best = np.maximum(best, np.abs(tau))
        return best

    shoulder = result.joints[0]
    assert abs(shoulder.worst["static"].torque) == pytest.approx(maximised(static), rel=1e-8)
    assert abs(shoulder.worst["stop"].torque) == pytest.approx(maximised(stop), rel=1e-8)


def test_the_worst_states_do_not_leak_into_the_averages(planar):
    """A worst state stands for no time: where the units (so the carried masses) are the
    duty's own, the mean torque, mean speed and motor RMS equal the duty's alone (to the
    rounding of sums that now hold zeros)."""
    result, *_ = planar
    for joint, alone in zip(result.joints, result.duty_sizing.joints, strict=True):
        assert joint.duty is not None and joint.selected is not None
        assert joint.selected.unit == joint.duty.unit
        assert joint.sizing.load.mean_torque == pytest.approx(alone.load.mean_torque, rel=1e-13)
        assert joint.sizing.load.mean_speed == pytest.approx(alone.load.mean_speed, rel=1e-13)
        assert joint.sizing.load.moving_time == pytest.approx(alone.load.moving_time, rel=1e-13)
        assert joint.selected.motor.rms_torque == pytest.approx(alone.selected.motor.rms_torque,
                                                                rel=1e-12)
        assert joint.sizing.load.peak_torque >= alone.load.peak_torque


# -- the 6-axis arm ------------------------------------------------------------------------

SPEC6 = {"velocity": 90 * DEG, "acceleration": 400 * DEG, "stop_time": 0.15}


@pytest.fixture(scope="module")
def arm():
    return envelope(ROBOTS / "benchtop6.urdf", payload=PAYLOAD, **SPEC6)


@pytest.mark.slow
def test_reported_worst_states_give_their_torques_by_per_sample_rnea(arm):
    """Each reported state, put through per-sample `pinocchio.rnea` on a model built here
    (payload and the chosen units' masses appended by hand), gives the reported torque;
    and it lies in the box (static: the joint held)."""
    model = oracle_model(ROBOTS / "benchtop6.urdf", PAYLOAD, arm.masses)
    data = model.createData()
    box, stop_time = arm.spec.box, SPEC6["stop_time"]
    for j, joint in enumerate(arm.joints):
        for figure, state in joint.worst.items():
            qdd = -state.qd / stop_time if figure == "stop" else state.qdd
            tau = pin.rnea(model, data, state.q, state.qd, qdd)[j]
            assert tau == pytest.approx(state.torque, rel=1e-9, abs=1e-12), (joint.name, figure)
            assert np.all((state.q >= box.lower) & (state.q <= box.upper))
            assert np.all(np.abs(state.qd) <= box.velocity * (1 + 1e-12))
            assert np.all(np.abs(state.qdd) <= box.acceleration * (1 + 1e-12))
        assert joint.worst["static"].qd[j] == 0.0 and joint.worst["static"].qdd[j] == 0.0
        assert abs(joint.worst["peak"].qd[j]) == pytest.approx(box.velocity[j])
        gravity = pin.rnea(model, data, joint.gravity.q, np.zeros(6), np.zeros(6))[j]
        assert gravity == pytest.approx(joint.gravity.torque, rel=1e-9, abs=1e-12)
        assert joint.convergence.converged, joint.convergence.note
    assert arm.states >= 100_000
    assert arm.converged


@pytest.mark.slow
def test_no_state_of_a_dense_random_sample_beats_the_worst(arm):
    """10^6 random states of the box through batched Pinocchio (called here, not through
    hdselect): q and qd uniform, qdd at a random vertex; each joint's torque must not beat
    its reported peak, its stop torque the reported stop, and, with one random joint held
    per state, the held joint's torque the reported static, by more than the tolerance.
    10^5 of them also at each joint's exact worst vertex (from per-sample M(q) and b)."""
    model = oracle_model(ROBOTS / "benchtop6.urdf", PAYLOAD, arm.masses)
    box, stop_time = arm.spec.box, SPEC6["stop_time"]
    tolerance = 1.0 + arm.settings.tolerance
    peak = np.array([abs(j.worst["peak"].torque) for j in arm.joints])
    static = np.array([abs(j.worst["static"].torque) for j in arm.joints])
    stop = np.array([abs(j.worst["stop"].torque) for j in arm.joints])
    rng = np.random.default_rng(7)
    pool = pin.ModelPool(model, 2)
    seen = np.zeros((3, 6))
    for _ in range(5):
        n = 200_000
        q = box.lower + rng.random((n, 6)) * (box.upper - box.lower)
        qd = box.velocity * rng.uniform(-1, 1, (n, 6))
        qdd = box.acceleration * rng.choice([-1.0, 1.0], (n, 6))
        held = rng.integers(0, 6, n)
        rows = np.arange(n)
        still_qd, still_qdd = qd.copy(), qdd.copy()
        still_qd[rows, held] = still_qdd[rows, held] = 0.0
        for k, (v, acc) in enumerate(((qd, qdd), (qd, -qd / stop_time),
                                      (still_qd, still_qdd))):
            tau = np.empty((6, n), order="F")
            pin.rneaInParallel(2, pool, np.asfortranarray(q.T), np.asfortranarray(v.T),
                               np.asfortranarray(acc.T), tau)
            if k == 2:
                for j in range(6):
                    seen[2, j] = max(seen[2, j], np.abs(tau[j, held == j]).max())
            else:
                seen[k] = np.maximum(seen[k], np.abs(tau).max(axis=1))
    assert np.all(seen[0] <= peak * tolerance), seen[0] / peak
    assert np.all(seen[1] <= stop * tolerance), seen[1] / stop
    assert np.all(seen[2] <= static * tolerance), seen[2] / static
    data = model.createData()
    exact = np.zeros(6)
    for _ in range(100_000 // 1000):
        q = box.lower + rng.random((1000, 6)) * (box.upper - box.lower)
        qd = box.velocity * rng.uniform(-1, 1, (1000, 6))
        for i in range(1000):
            inertia = pin.crba(model, data, q[i])
            inertia = np.triu(inertia) + np.triu(inertia, 1).T
            bias = pin.rnea(model, data, q[i], qd[i], np.zeros(6))
            exact = np.maximum(exact, np.abs(bias) + np.abs(inertia) @ box.acceleration)
    assert np.all(exact <= peak * tolerance), exact / peak


def test_the_bearings_largest_loads_count_the_worst_states_and_its_means_the_duty_alone(arm):
    """A worst state is a sample of no duration: its whole force and moment count in the
    output bearing's largest loads, never in its means.

    Oracles: the duty alone checked with the envelope's units (`check_units` on the duty's
    trajectory: no worst state in it) gives the means and the duty's largest loads; and
    per-sample `pinocchio.rnea` on the model built here gives, at every reported worst
    state, the wrench through each joint in its own frame (``data.f``): axial force
    f . z, radial force |f - (f . z) z|, tilting moment |m - (m . z) z| about the joint
    origin (z the joint axis).
    """
    units = {joint.name: joint.selected.unit for joint in arm.joints}
    alone = check_units(arm.robot, arm.duty.tasks[0].trajectory, units, arm.sizing.options)
    model = oracle_model(ROBOTS / "benchtop6.urdf", PAYLOAD, arm.masses)
    data = model.createData()
    states = [state for joint in arm.joints for state in (*joint.worst.values(), joint.gravity)]
    assert all(state.source == "search" for state in states)  # so they are the searched rows
    wrenches = []
    for state in states:
        pin.rnea(model, data, state.q, state.qd, state.qdd)  # a stop state coasts (qdd = 0)
        wrenches.append([(data.f[k].linear.copy(), data.f[k].angular.copy(),
                          np.asarray(data.joints[k].S)[3:].ravel())
                         for k in range(1, model.njoints)])
    beyond = 0
    for j, (joint, duty) in enumerate(zip(arm.joints, alone.joints, strict=True)):
        load, own = joint.sizing.bearing, duty.bearing
        axial = max(abs(f @ z) for f, _, z in (w[j] for w in wrenches))
        radial = max(np.linalg.norm(f - (f @ z) * z) for f, _, z in (w[j] for w in wrenches))
        moment = max(np.linalg.norm(m - (m @ z) * z) for _, m, z in (w[j] for w in wrenches))
        assert load.max_axial == pytest.approx(max(own.max_axial, axial), rel=1e-9)
        assert load.max_radial == pytest.approx(max(own.max_radial, radial), rel=1e-9)
        assert load.max_moment == pytest.approx(max(own.max_moment, moment), rel=1e-9)
        for mean in ("mean_axial", "mean_radial", "mean_moment"):
            assert getattr(load, mean) == pytest.approx(getattr(own, mean), rel=1e-9)
        beyond += moment > own.max_moment
    assert beyond >= 3  # the states do load the bearings beyond what the duty does


@pytest.mark.slow
def test_a_rated_bearing_is_judged_at_the_worst_states_too():
    """With the example catalog that rates bearings, the contour duty alone lets the
    shoulder pan take the XB-07-100 (tilting moment below its 6 N m); at the worst
    states of the spec the arm tilts that bearing past 6 N m, so the envelope rejects it
    by its bearing moment, and the value it rejects it by is a worst state's, not the
    duty's."""
    rated = REPO / "catalogs" / "example_rated_bearing.toml"
    result = envelope(MOTIONS / "envelopes" / "benchtop6_dispensing.toml", catalog=[rated])
    pan, duty = result.joints[0], result.duty_sizing.joints[0]
    assert duty.selected.unit.id == "XB-07-100"
    assert duty.selected.checks["bearing_moment"].value < 6.0
    small = next(c for c in pan.sizing.candidates if c.unit.id == "XB-07-100")
    assert not small.feasible and small.binding == "bearing_moment"
    assert small.checks["bearing_moment"].value > 6.0
    assert pan.selected is not None and pan.selected.unit.size > small.unit.size
    assert pan.sizing.bearing.mean_moment == pytest.approx(
        check_units(result.robot, result.duty.tasks[0].trajectory,
                    {j.name: j.selected.unit for j in result.joints},
                    result.sizing.options).joints[0].bearing.mean_moment, rel=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(path.name for path in MOTIONS.glob("benchtop6_*.toml")))
def test_every_unit_picked_holds_for_each_shipped_motion_within_the_same_limits(name):
    """For every shipped motion of the 6-axis arm (each benchtop6_*.toml, tool poses
    solved): with the motion's own limits, payload and stop time (and the default duty for
    the averages), each unit the envelope picks holds for that motion (`check_units`
    passes on its planned trajectory) and is no smaller than the one `size` picks."""
    robot, motion = load_case(MOTIONS / name)
    result = envelope(robot, velocity=motion.velocity_limit,
                      acceleration=motion.acceleration_limit, stop_time=motion.stop_time,
                      life_hours=motion.life_hours)
    sized = size(robot, motion)
    picked = {joint.name: joint.selected.unit for joint in result.joints if joint.selected}
    assert picked, "the envelope picks no unit at these limits"
    units = {joint.name: picked.get(joint.name, joint.sizing.strongest.unit)
             for joint in result.joints}
    checked = check_units(robot, sized.trajectory, units, sized.options)
    for joint, alone in zip(checked.joints, sized.joints, strict=True):
        if joint.name in picked:
            assert joint.selected is not None, (name, joint.name, joint.candidates[0].binding)
            assert alone.selected is not None
            assert picked[joint.name].size >= alone.selected.unit.size


@pytest.mark.slow
def test_search_convergence_is_what_its_rounds_say():
    """With few starts the search reports each round's worst value; the flag is their
    agreement, and the reported value is the largest found."""
    result = envelope(ROBOTS / "benchtop6.urdf", acceleration=300 * DEG, stop_time=0.15,
                      settings=SearchSettings(starts=64, refine=1, rounds=0), moves=3)
    for joint in result.joints:
        for worst in joint.convergence.by_demand.values():
            (n1, first), (n2, second) = worst.by_starts
            assert (n1, n2) == (64, 256) and second >= first
            assert worst.converged == agree(first, second, 0.005)
            assert worst.value >= second
    assert result.converged == (result.settled and all(
        j.convergence.converged for j in result.joints))
