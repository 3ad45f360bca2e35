"""Gearhead and motor chosen together, against hand calculations and Pinocchio.

The motor behind a unit of ratio N, efficiency eta, input inertia J_in, with rotor
inertia J_m (docs/rules.md, "The checks", motor side), written out again here:

    T_motor = tau / (N eta) + (J_in + J_m) N qdd   while the motor drives (tau qd >= 0)
            = tau eta / N   + (J_in + J_m) N qdd   while the load drives back

The motor's rules: every sample's |T_motor| under its peak torque at that sample's
input speed n = N |qd|; the RMS of T_motor over the whole cycle at most its rated
torque; max n at most its maximum speed. Inertia ratio (M_jj / N^2 + J_in) / J_m.
Nothing below is taken from `hdselect.catalog` or `hdselect.sizing.reflect`.
"""

from __future__ import annotations

import base64
import json
import math
import re

import numpy as np
import pinocchio as pin
import pytest

from hdselect import Options, load_case, plan, size, size_trajectory, summarize
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor, load_motors
from hdselect.catalog.select import PREFERENCES
from hdselect.cli.main import main
from hdselect.robot.model import load_robot
from hdselect.robot.payload import Payload
from hdselect.sizing.records import size_json
from helpers import REPO
from helpers.dynamics import J_TABLE, pin_config, rnea_loop, thinned, urdf_with_masses
from helpers.motions import CYCLE, ETA, MOTOR, T_A, A, V, index_motion

RPM = 60 / (2 * math.pi)  # rpm per rad/s
EXAMPLE = REPO / "motors" / "example_motors.toml"
BENCHTOP = REPO / "trajectories" / "benchtop6_pick_place.toml"


def curve_by_hand(n_rpm):
    """The MOTOR's peak torque [N m] at n [rpm], written out."""
    n = np.abs(n_rpm)
    return np.where(n <= 2000, 0.1, 0.1 - 0.05 * (n - 2000) / 4000)


def motor_torque_by_hand(unit, j_m, tau, qd, qdd):
    driving = tau * qd >= 0
    gear = np.where(driving, tau / (unit.ratio * ETA), tau * ETA / unit.ratio)
    return gear + (unit.input_inertia + j_m) * unit.ratio * qdd


# --- the index table by hand -----------------------------------------------------------------

def test_index_table_motor_figures_by_hand(tmp_path):
    """Per sample, and in closed form for the trapezoid: tau = J a while accelerating
    (driving), -J a while decelerating at positive speed (the load drives back)."""
    result = size(None, index_motion(tmp_path))
    (joint,) = result.joints
    traj = result.trajectory
    qd, qdd = traj.qd[:, 0], traj.qdd[:, 0]
    tau = J_TABLE * qdd
    j_m = 5e-6
    assert joint.load_inertia == pytest.approx(J_TABLE, rel=1e-9)  # M_jj of a lone axis: J
    assert len(joint.candidates) == 7  # one motor, seven gearheads
    for c in joint.candidates:
        unit = c.unit
        assert c.motor_unit is not None and c.motor_unit.id == "T1"
        t_m = motor_torque_by_hand(unit, j_m, tau, qd, qdd)
        n = unit.ratio * np.abs(qd) * RPM
        # per sample, exactly
        assert c.motor.rms_torque == pytest.approx(np.sqrt(np.mean(t_m**2)), rel=1e-9)
        assert c.motor.peak_torque == pytest.approx(np.abs(t_m).max(), rel=1e-9)
        share = np.abs(t_m) / curve_by_hand(n)
        assert c.checks["motor_peak"].utilization == pytest.approx(share.max(), rel=1e-9)
        assert c.checks["motor_rms"].utilization == pytest.approx(
            np.sqrt(np.mean(t_m**2)) / 0.03, rel=1e-9)
        assert c.checks["motor_speed"].value == pytest.approx(n.max(), rel=1e-9)
        assert c.checks["motor_speed"].limit == 6000
        # closed form: T_acc while accelerating, T_dec while braking, zero otherwise
        t_acc = J_TABLE * A / (unit.ratio * ETA) + (unit.input_inertia + j_m) * unit.ratio * A
        t_dec = J_TABLE * A * ETA / unit.ratio + (unit.input_inertia + j_m) * unit.ratio * A
        assert c.motor.peak_torque == pytest.approx(t_acc, rel=1e-6)
        rms = math.sqrt((t_acc**2 + t_dec**2) * T_A / CYCLE)
        assert c.motor.rms_torque == pytest.approx(rms, rel=3e-3)  # sampled every 0.5 ms
        # the worst sample: full torque at full speed, at the end of the acceleration
        # (the last sample before the corner is up to one dt = 0.5 ms short of full speed)
        top = unit.ratio * V * RPM
        assert c.checks["motor_peak"].utilization == pytest.approx(
            t_acc / curve_by_hand(top), rel=1e-3)
        # currents and copper loss with k_t = 0.025 N m/A, R = 1.5 ohm
        assert c.checks["motor_peak"].detail["current_a"] == pytest.approx(
            c.motor.peak_torque / 0.025, rel=1e-12)
        assert c.checks["motor_rms"].detail["copper_loss_w"] == pytest.approx(
            1.5 * (c.motor.rms_torque / 0.025) ** 2, rel=1e-12)
        # inertia ratio: the table through the ratio plus the gearhead's input, over the rotor
        assert joint.inertia_ratio(c) == pytest.approx(
            (J_TABLE / unit.ratio**2 + unit.input_inertia) / j_m, rel=1e-9)
        # the crash carries the rotor too: |tau| + (J_in + J_m) N^2 |qd| / t_stop
        crash = np.max(np.abs(tau) + (unit.input_inertia + j_m) * unit.ratio**2 * np.abs(qd)
                       / 0.1)
        estop = np.max(J_TABLE * np.abs(qd) / 0.1)
        assert c.checks["momentary"].value == pytest.approx(max(crash, estop), rel=1e-9)


def test_index_table_psa_14_100_numbers():
    """The same closed form with numbers, for a reader checking by calculator.

    PSA-14-100: N = 100, J_in = 0.033 kg cm^2 = 3.3e-6 kg m^2. J a = 0.061581 x 12.566 =
    0.77385 N m. T_acc = 0.77385 / 70 + 8.3e-6 x 100 x 12.566 = 0.011055 + 0.010430 =
    0.021485 N m; T_dec = 0.77385 x 0.7 / 100 + 0.010430 = 0.015847 N m. RMS =
    sqrt((0.021485^2 + 0.015847^2) x 0.25 / 2.25) = 0.0089 N m. At 100 x 30 rpm = 3000 rpm
    the curve allows 0.1 - 0.05 x 1000 / 4000 = 0.0875 N m: 24.6 %. Inertia ratio
    (0.061581 / 1e4 + 3.3e-6) / 5e-6 = 1.8916.
    """
    j_in, j_m, n = 3.3e-6, 5e-6, 100
    t_acc = J_TABLE * A / (n * ETA) + (j_in + j_m) * n * A
    t_dec = J_TABLE * A * ETA / n + (j_in + j_m) * n * A
    assert t_acc == pytest.approx(0.021485, abs=1e-6)
    assert t_dec == pytest.approx(0.015847, abs=1e-6)
    assert math.sqrt((t_acc**2 + t_dec**2) * T_A / CYCLE) == pytest.approx(0.0089, abs=1e-4)
    assert t_acc / 0.0875 == pytest.approx(0.2455, abs=1e-4)
    assert (J_TABLE / n**2 + j_in) / j_m == pytest.approx(1.8916, abs=1e-4)


# --- a motor of zero rotor inertia and mass changes nothing ----------------------------------

def null_motor() -> Motor:
    return Motor("null", rated_torque=1e7, peak_torque=1e7, max_speed=1e6, rated_speed=1.0,
                 rotor_inertia=0.0, mass=0.0)


@pytest.mark.parametrize("prefer", ["size", "mass"])
def test_zero_inertia_zero_mass_motor_gives_todays_results_exactly(prefer):
    robot, motion = load_case(BENCHTOP)
    traj = plan(robot, motion)
    units = load_catalog()
    options = Options(stop_time=0.15, life_hours=20000, prefer=prefer)
    today = size_trajectory(robot, traj, units, options)
    paired = size_trajectory(robot, traj, units, options,
                             motors={name: [null_motor()] for name in robot.sized_joints})
    for a, b in zip(today.joints, paired.joints, strict=True):
        assert a.selected is not None and b.selected is not None
        assert b.selected.unit.id == a.selected.unit.id
        assert b.selected.motor_unit.id == "null"
        np.testing.assert_array_equal(a.torque, b.torque)
        np.testing.assert_array_equal(a.stop_torque, b.stop_torque)
        assert a.carried_mass == b.carried_mass
        for ca, cb in zip(a.candidates, b.candidates, strict=True):
            assert ca.unit.id == cb.unit.id
            assert cb.motor == ca.motor  # peak, RMS, speed: the same floats
            assert cb.life_hours == ca.life_hours and cb.flags == ca.flags
            for name, check in ca.checks.items():
                assert cb.checks[name] == check, name
            assert set(cb.checks) - set(ca.checks) == {"motor_peak", "motor_rms",
                                                       "motor_speed"}
            assert all(cb.checks[m].utilization < 1e-2 for m in set(cb.checks) - set(ca.checks))
        # the selected pair's motor torque per sample, kept for the figure
        assert np.abs(b.motor_torque).max() == b.selected.motor.peak_torque


# --- mass coupling with motors against Pinocchio ---------------------------------------------

def test_coupled_pairs_equal_pinocchio_with_gearhead_and_motor_masses_in_the_urdf(tmp_path):
    """The chosen gearhead and motor sit at the joint's origin on the link before it.
    Written into a copy of the URDF as extra links, Pinocchio's full dynamics gives every
    joint's torque; the load inertia is the largest M_jj (pinocchio.crba) over the poses."""
    robot, motion = load_case(BENCHTOP)
    traj = plan(robot, motion)
    motors = load_motors(EXAMPLE)
    result = size_trajectory(robot, traj, load_catalog(), Options(stop_time=0.15),
                             motors={name: motors for name in robot.sized_joints})
    assert result.feasible
    masses = {j.name: j.selected.unit.mass + j.selected.motor_unit.mass for j in result.joints}
    assert any(j.selected.motor_unit.mass > 0.1 for j in result.joints)
    heavy_path = urdf_with_masses(REPO / "robots" / "benchtop6.urdf",
                                  tmp_path / "benchtop6.urdf", masses)
    heavy = load_robot(heavy_path).with_payload(robot.payload)
    keep = thinned(traj, 150)
    q, qd, qdd = traj.q[keep], traj.qd[keep], traj.qdd[keep]
    expected = rnea_loop(heavy.model, q, qd, qdd)
    expected_stop = rnea_loop(heavy.model, q, qd, -qd / 0.15)
    names = list(robot.joint_names)
    for joint in result.joints:
        j = names.index(joint.name)
        np.testing.assert_allclose(joint.torque[keep], expected[:, j], rtol=0, atol=1e-8)
        np.testing.assert_allclose(joint.stop_torque[keep], expected_stop[:, j], rtol=0,
                                   atol=1e-8)
    # carried mass: every pair further out, gearhead and motor
    assert result.joints[0].carried_mass == pytest.approx(sum(list(masses.values())[1:]),
                                                          rel=1e-12)
    # the load inertia: the largest diagonal of M(q) over 400 poses spread over the cycle
    poses = np.unique(np.linspace(0, len(traj.t) - 1, 400).astype(int))
    data = heavy.model.createData()
    diagonal = np.array([np.diag(pin.crba(heavy.model, data, pin_config(heavy.model, traj.q[k])))
                         for k in poses])
    for joint in result.joints:
        j = names.index(joint.name)
        assert joint.load_inertia == pytest.approx(diagonal[:, j].max(), rel=1e-9)


# --- selection of pairs ----------------------------------------------------------------------

def benchtop_with_motors(**options):
    return size(None, BENCHTOP, motors={n: load_motors(EXAMPLE) for n in
                                        ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1",
                                         "wrist_2", "wrist_3")}, **options)


def test_lightest_feasible_pair_by_default_and_prefer_still_applies():
    result = benchtop_with_motors()
    assert result.options.prefer == "mass"
    for joint in result.joints:
        feasible = [c for c in joint.candidates if c.feasible]
        lightest = min(c.unit.mass + c.motor_unit.mass for c in feasible)
        chosen = joint.selected
        assert chosen.unit.mass + chosen.motor_unit.mass == pytest.approx(lightest, abs=1e-12)
        assert len(joint.candidates) == 7 * 6
    by_size = benchtop_with_motors(prefer="size")
    assert by_size.options.prefer == "size"
    for joint in by_size.joints:
        feasible = [c for c in joint.candidates if c.feasible]
        assert joint.selected is min(feasible, key=PREFERENCES["size"][1])
        assert joint.selected.unit.size == min(c.unit.size for c in feasible)


def test_without_motors_the_default_order_is_size():
    result = size(None, REPO / "trajectories" / "index_table_indexing.toml")
    assert result.options.prefer == "size" and result.motors == {}
    assert all(c.motor_unit is None and "motor_peak" not in c.checks
               for c in result.joints[0].candidates)


WEAK_PEAK = MOTOR.replace("peak_torque_nm = 0.1\n", "peak_torque_nm = 0.004\n").replace(
    "rated_torque_nm = 0.03", "rated_torque_nm = 0.002").replace(
    "peak_torque_nm = [0.1, 0.1, 0.05]", "peak_torque_nm = [0.004, 0.004, 0.002]")


@pytest.mark.slow
def test_a_pair_failing_only_on_the_motor_side_is_reported_with_the_motor_rule(tmp_path,
                                                                                capsys):
    """A motor too weak for every gearhead: the gearheads alone all pass except where
    they fail today, and every pair fails on the motor's peak rule."""
    path = index_motion(tmp_path, WEAK_PEAK)
    alone = size(None, index_motion(tmp_path, "", header="", name="alone.toml"))
    result = size(None, path)
    (joint,) = result.joints
    assert joint.selected is None and not result.feasible
    passing = {c.unit.id for c in alone.joints[0].candidates if c.feasible}
    assert passing
    for c in joint.candidates:
        gearhead = [name for name in c.checks if not name.startswith("motor_")]
        if c.unit.id in passing:
            assert all(c.checks[name].ok for name in gearhead)
            assert not c.feasible and c.binding == "motor_peak"
    # the command line: exit 1, the joint shown with the motor's rule
    status = main(["size", str(path)])
    out, _ = capsys.readouterr()
    assert status == 1
    assert re.search(r"table +none +none +motor_peak [\d.]+ > [\d.]+ N m", out)
    assert "table: no pair holds it: motor peak torque" in out and "+ T1" in out
    document = size_json(result)
    (entry,) = document["joints"]
    assert entry["selected"] is None and entry["selected_motor"] is None
    strongest = next(c for c in entry["candidates"] if c["unit"] == joint.strongest.unit.id)
    assert strongest["binding"] == "motor_peak" and strongest["motor"]["id"] == "T1"
    # slowed down, the torque falls as 1/s^2 (no gravity about a vertical axis): the
    # smallest slow-down is the one that brings the weakest pair under 0.004 N m
    slowdown = joint.slowdown
    assert slowdown is not None and slowdown.factor is not None and slowdown.factor > 1
    # by hand: the pair passes once T_acc / s^2 <= 0.004 N m (the curve is flat below
    # 2000 rpm, and N v / s stays below it here), and RMS / s^2 <= 0.002 N m binds later
    for c in joint.candidates:
        s_peak = math.sqrt(c.motor.peak_torque / 0.004)
        assert c.unit.ratio * V * RPM / s_peak < 2000
        assert math.sqrt(c.motor.rms_torque / 0.002) < s_peak
        ((lo, hi),) = joint.scales.fits[c.label]
        assert lo == pytest.approx(s_peak, rel=1e-5) and hi == math.inf
    best = min(math.sqrt(c.motor.peak_torque / 0.004) for c in joint.candidates)
    assert slowdown.factor == math.ceil(best * 1000) / 1000
    rerun = size(None, index_motion(tmp_path, WEAK_PEAK, scale=slowdown.factor,
                                    name="slow.toml"))
    passing_pair = next(c for c in rerun.joints[0].candidates if c.label == slowdown.unit)
    assert passing_pair.feasible, {k: v.utilization for k, v in passing_pair.checks.items()}
    faster = size(None, index_motion(tmp_path, WEAK_PEAK, scale=0.98 * slowdown.factor,
                                     name="faster.toml"))
    assert faster.joints[0].selected is None


@pytest.mark.parametrize(("change", "rule"), [
    (("rated_torque_nm = 0.03", "rated_torque_nm = 0.003"), "motor_rms"),
    (("max_speed_rpm = 6000", "max_speed_rpm = 2500"), "motor_speed"),
])
def test_each_motor_rule_can_bind(tmp_path, change, rule):
    text = MOTOR.replace(*change)
    if rule == "motor_speed":  # the curve must reach the maximum speed
        text = text.replace("rated_speed_rpm = 2000", "rated_speed_rpm = 1000").replace(
            "speed_rpm = [0, 2000, 6000]", "speed_rpm = [0, 2000, 2500]")
    result = size(None, index_motion(tmp_path, text))
    for c in result.joints[0].candidates:
        if c.checks[rule].utilization > 1.0:
            assert not c.feasible
    # with 3000 rpm at N = 100 and 2400 rpm at N = 80, at least the high ratios fail
    assert any(c.binding == rule and not c.feasible for c in result.joints[0].candidates)


def test_motors_and_motor_options_together_are_refused(tmp_path):
    path = index_motion(tmp_path)
    with pytest.raises(Exception, match="rotor inertia and motor mass"):
        size(None, path, rotor_inertia=1e-6)
    with pytest.raises(Exception, match="rotor inertia and motor mass"):
        size(None, path, motor_mass=0.1)
    # nothing given: ignored
    assert size(None, path, rotor_inertia=None, motor_mass=None).joints[0].candidates


# --- reports ---------------------------------------------------------------------------------

def test_json_and_summary_carry_the_pair(tmp_path):
    result = benchtop_with_motors()
    document = json.loads(json.dumps(size_json(result), allow_nan=False))
    summary = summarize(result)
    assert document["assumptions"]["prefer"] == "mass"
    assert document["assumptions"]["motors"]["elbow"] == [m.id for m in load_motors(EXAMPLE)]
    assert {m["id"] for m in document["motors"]} == {m.id for m in load_motors(EXAMPLE)}
    for joint, entry, brief in zip(result.joints, document["joints"], summary.joints,
                                   strict=True):
        chosen = joint.selected
        assert entry["selected"] == chosen.unit.id == brief.unit
        assert entry["selected_motor"] == chosen.motor_unit.id == brief.motor
        assert entry["gearhead_binding"] == chosen.gearhead_binding
        assert entry["motor_binding"] == chosen.motor_binding == brief.motor_binding
        assert entry["inertia_ratio"] == pytest.approx(joint.inertia_ratio(chosen))
        assert brief.inertia_ratio == entry["inertia_ratio"]
        assert entry["load_inertia_kg_m2"] == joint.load_inertia
        assert len(entry["candidates"]) == 42
        for c in entry["candidates"]:
            assert set(c["checks"]) >= {"motor_peak", "motor_rms", "motor_speed"}
            assert c["motor"]["id"] and c["motor"]["inertia_ratio"] > 0


def test_report_without_motor_data_says_inertia_and_mass_not_included(capsys):
    status = main(["size", str(REPO / "trajectories" / "index_table_indexing.toml")])
    out = capsys.readouterr().out
    assert status == 0
    assert "motor: none given: motor rotor inertia and mass not included" in " ".join(
        out.split())


@pytest.mark.slow
def test_html_report_has_a_motor_figure_per_joint(tmp_path, capsys):
    pytest.importorskip("hdselect.report.figures")
    report = tmp_path / "report"
    status = main(["size", str(index_motion(tmp_path)), "--report", str(report)])
    capsys.readouterr()
    assert status == 0
    assert (report / "motor_table.png").stat().st_size > 10_000
    page = (report / "index.html").read_text()
    images = {alt.split()[0]: data for data, alt in re.findall(
        r"src='data:image/png;base64,([A-Za-z0-9+/=]+)' alt='([^']+)'", page)}
    # the joint's profiles, its motor's torque-speed plane, its output bearing's loads
    assert sorted(images) == ["output", "speed", "torque-speed"]
    assert base64.b64decode(images["torque-speed"]) == (report / "motor_table.png").read_bytes()
    assert base64.b64decode(images["output"]) == (report / "bearing_table.png").read_bytes()
    assert "torque-speed plane of the motor T1" in page and "load/rotor inertia" in page
    assert "no thermal model" in page


@pytest.mark.parametrize(("prefer", "margin", "mass"), [
    ("mass", 0.0, None), ("size", 0.3, None), ("motor-rms", 0.1, 2.0), ("mass", 0.2, 8.0)])
def test_the_selection_without_detail_is_the_one_among_every_pair(prefer, margin, mass):
    """A second method: the choice among every (gearhead, motor) pair.

    Without detail (the coarse guess, a study's case) only the pairs whose gearhead
    passes the rules no motor changes are checked; the selection, its figures, and where
    no pair fits the strongest, are those found among every pair, rated bearings and the
    design margin included (the heavier payloads leave joints without a pair).
    """
    from hdselect.sizing.core import select_units
    from hdselect.sizing.tasks import Task, pooled
    from hdselect.sizing.torques import DirectTorques

    robot, motion = load_case(BENCHTOP, payload=None if mass is None else Payload(mass))
    units = load_catalog([REPO / "catalogs" / "example_rated_bearing.toml"])
    assert any(u.bearing is not None for u in units)
    motors = {name: load_motors(EXAMPLE) for name in robot.sized_joints}
    options = Options(prefer=prefer, margin=margin)
    samples = pooled((Task(robot, plan(robot, motion)),))
    model = DirectTorques(samples.tasks, samples, options.stop_time)
    per_joint = {name: units for name in robot.sized_joints}
    every, _ = select_units(model, per_joint, options, motors, slowdowns=False)
    chosen, _ = select_units(model, per_joint, options, motors, detail=False, slowdowns=False)
    none_fits = 0
    for full, pruned in zip(every, chosen, strict=True):
        want = full.selected or full.strongest
        got = pruned.selected or pruned.strongest
        none_fits += full.selected is None
        assert (pruned.selected is None) == (full.selected is None), full.name
        assert (got.unit.id, got.motor_unit.id) == (want.unit.id, want.motor_unit.id)
        assert got.checks == want.checks
        assert np.array_equal(pruned.motor_torque, full.motor_torque)
        assert pruned.bearing == full.bearing
    assert (none_fits > 0) == (mass is not None)  # both branches: a pair found, none found


def test_the_motor_peak_judged_once_per_dwell_is_the_one_of_every_sample():
    """A second method: `check_motor` on every sample against once per run of identical
    samples (`Reflection.distinct_motor_torque`), on the benchtop motion's dwells, for
    every unit and motor (a motor with a speed curve among them)."""
    from hdselect.catalog.rules import check_motor
    from hdselect.robot.dynamics import inverse_dynamics
    from hdselect.sizing.reflect import reflect_motors

    robot, motion = load_case(BENCHTOP)
    trajectory = plan(robot, motion)
    torques = inverse_dynamics(robot, trajectory.q, trajectory.qd, trajectory.qdd)
    units = load_catalog()
    motors = load_motors(EXAMPLE)
    j = robot.joint_index("shoulder_lift")
    qd, qdd = trajectory.qd[:, j], trajectory.qdd[:, j]
    behind = reflect_motors(units, [m.rotor_inertia for m in motors], trajectory.t,
                            torques[:, j], qd, qdd, torques[:, j], stop_time=0.1,
                            efficiency=ETA)
    speed = np.abs(qd) * RPM
    assert any(m.curve is not None for m in motors)
    for m, motor in enumerate(motors):
        for r in behind[m]:
            torque, starts = r.distinct_motor_torque()
            assert starts is not None and len(starts) < len(qd) / 2  # dwells merged
            every = check_motor(motor, r.motor_torque, speed * r.unit.ratio, r.motor)
            once = check_motor(motor, torque, (speed * r.unit.ratio)[starts], r.motor)
            assert once == every
