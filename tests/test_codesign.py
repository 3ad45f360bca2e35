"""`hdselect.codesign` against closed forms, a kinematics-only TOPPRA run and the sizing itself.

The index table (one vertical axis, inertia J, no gravity) has textbook answers for
its fastest move through an angle theta under a torque limit T:

    bang-bang (no speed limit reached)     t = 2 sqrt(theta J / T)
    trapezoid (speed limit v reached)      t = theta / v + v J / T
    mean-torque rule binding (bang-bang)   t = 2 sqrt(theta J / x), x the derated torque:
        x = T_N (1750 / N_av)^0.33 with N_av = N (theta / t) in rpm, so
        x^1.165 = T_N (1750 / ((N rpm/2) sqrt(theta / J)))^0.33
    emergency stop binding                 v = M t_stop / J (stop torque J v / t_stop = M)
    crash binding                          J |qdd| + K |qd| <= M: accelerate with
        qd = (M / K) (1 - exp(-K t / J)) to the middle, then the mirror image

The rules are written out here again, not taken from `hdselect.catalog.rules`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError, PlanningError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.cli.main import main
from hdselect.codesign.fastest_cycle import compare_ratios, fastest
from hdselect.codesign.fastpath import GRID_PER_WAYPOINT, PathModel
from hdselect.codesign.pathbounds import PathInfeasible
from hdselect.motion.loading import load_case
from hdselect.motion.planning import plan
from hdselect.motion.planning.toppra import (
    kinematic_constraints,
    overshoot_scale,
    path_pieces,
    solve_piece,
)
from hdselect.sizing.core import size
from hdselect.sizing.options import Options
from helpers import REPO
from helpers.codesign import index_table, mean_speed_allowing_peak
from helpers.robots import write_motion, write_robot

RPM = 60 / (2 * math.pi)  # rpm per rad/s
RESOLUTION = 3e-3
"""What the TOPPRA grid may cost a cycle against its closed form (measured: at most 0.21 %)."""
FAST_PICK = REPO / "trajectories" / "benchtop6_fast_pick.toml"
UNITS = {unit.id: unit for unit in load_catalog()}


def top_speed(unit) -> float:
    """The unit's top output speed [rad/s]: maximum input speed over the ratio."""
    return unit.max_input_speed / unit.ratio / RPM


# --- the three closed forms, for every catalog unit -----------------------------------------

@pytest.mark.parametrize("unit_id", list(UNITS))
def test_bang_bang_under_the_repeated_peak(tmp_path, unit_id):
    unit = UNITS[unit_id]
    torque, mean = unit.repeated_torque, 0.5 * mean_speed_allowing_peak(unit)
    theta = mean * 1.0  # a 1 s move: theta / t = mean speed, t = 2 sqrt(theta J / T)
    inertia = torque / (4.0 * theta)
    robot, motion = index_table(tmp_path, inertia, theta)
    expected = 2.0 * math.sqrt(theta * inertia / torque)
    assert 2.0 * mean < 0.5 * top_speed(unit)  # the peak speed stays far from the limit
    result = fastest(robot, motion, {"table": unit}, Options(stop_time=10.0))
    assert result.feasible and result.reason is None
    assert result.cycle_time == pytest.approx(expected, rel=RESOLUTION)
    assert result.cycle_time >= expected * (1.0 - 1e-4)  # never faster than physics allows
    (joint,) = result.check.joints
    assert np.abs(joint.torque).max() <= torque
    assert np.abs(joint.torque).max() >= 0.99 * torque


@pytest.mark.parametrize("unit_id", list(UNITS))
def test_trapezoid_at_the_units_top_speed(tmp_path, unit_id):
    unit = UNITS[unit_id]
    torque, speed = unit.repeated_torque, top_speed(unit)
    inertia = torque / (101.0 * speed)  # a 1 s move, 1 % of its travel accelerating
    theta = 100.0 * speed**2 * inertia / torque
    robot, motion = index_table(tmp_path, inertia, theta)
    expected = theta / speed + speed * inertia / torque
    # the mean-torque rule stays clear: T_av^3 = T^3 x (travel accelerating / travel)
    n_av = unit.ratio * RPM * theta / expected
    t_av = torque * (speed**2 * inertia / torque / theta) ** (1.0 / 3.0)
    assert t_av < 0.8 * min((1750.0 / n_av) ** 0.33 * unit.rated_torque, torque)
    result = fastest(robot, motion, {"table": unit}, Options(stop_time=10.0))
    assert result.feasible and result.reason is None
    assert result.cycle_time == pytest.approx(expected, rel=RESOLUTION)
    assert result.cycle_time >= expected * (1.0 - 1e-4)
    assert result.binding_shares()[0][1] == "max input speed"
    assert np.abs(result.trajectory.qd).max() <= speed


@pytest.mark.parametrize("unit_id", list(UNITS))
def test_mean_torque_rule_derates_the_bang_bang(tmp_path, unit_id):
    unit = UNITS[unit_id]
    torque, mean = unit.repeated_torque, 1.5 * mean_speed_allowing_peak(unit)
    theta = mean * 1.0  # at the repeated peak: a 1 s move at 1.5 x that mean speed
    inertia = torque / (4.0 * theta)
    robot, motion = index_table(tmp_path, inertia, theta)
    k = unit.ratio * RPM / 2.0 * math.sqrt(theta / inertia)  # N_av = k sqrt(x) [rpm]
    derated = (unit.rated_torque * (1750.0 / k) ** 0.33) ** (1.0 / 1.165)
    assert derated < 0.95 * torque
    expected = 2.0 * math.sqrt(theta * inertia / derated)
    assert 2.0 * theta / expected < 0.9 * top_speed(unit)  # the peak speed
    result = fastest(robot, motion, {"table": unit}, Options(stop_time=10.0))
    assert result.feasible
    assert result.reason == ("table", "mean")
    assert result.optimum == pytest.approx(2.0 * math.sqrt(theta * inertia / torque),
                                           rel=RESOLUTION)
    assert result.cycle_time == pytest.approx(expected, rel=RESOLUTION)
    (joint,) = result.check.joints
    (candidate,) = joint.candidates
    assert candidate.checks["mean"].utilization > 0.999


def test_emergency_stop_caps_the_speed(tmp_path):
    unit = UNITS["PSA-14-100"]
    inertia, stop_time = 2.0, 0.5
    cap = unit.momentary_torque * stop_time / inertia  # J v / t_stop = M
    assert cap < top_speed(unit)
    theta = 20.0 * cap**2 * inertia / unit.repeated_torque
    robot, motion = index_table(tmp_path, inertia, theta, stop_time=stop_time)
    result = fastest(robot, motion, {"table": unit}, Options(stop_time=stop_time))
    expected = theta / cap + cap * inertia / unit.repeated_torque
    assert result.feasible
    assert result.cycle_time == pytest.approx(expected, rel=RESOLUTION)
    assert result.binding_shares()[0][1] == "emergency stop"


def test_crash_bound_move_against_its_ode(tmp_path):
    from scipy.optimize import brentq

    unit = UNITS["PSA-08-100"]  # momentary = repeated peak: the crash binds while moving
    rotor, stop_time = 2e-5, 0.1
    gain = (unit.input_inertia + rotor) * unit.ratio**2 / stop_time  # K [N m s]
    limit, inertia = unit.momentary_torque, 0.05
    theta = 0.8
    # accelerating with J qdd = M - K qd: qd = (M/K)(1 - exp(-K t / J))
    travelled = lambda t: limit / gain * (t - inertia / gain * (1 - math.exp(-gain * t / inertia)))  # noqa: E731
    half = brentq(lambda t: travelled(t) - theta / 2.0, 1e-6, 100.0)
    expected = 2.0 * half
    assert limit / gain * (1 - math.exp(-gain * half / inertia)) < top_speed(unit)
    robot, motion = index_table(tmp_path, inertia, theta, stop_time=stop_time)
    options = Options(stop_time=stop_time, rotor_inertia=rotor)
    result = fastest(robot, motion, {"table": unit}, options)
    assert result.feasible
    assert result.cycle_time == pytest.approx(expected, rel=RESOLUTION)
    assert result.cycle_time >= expected * (1.0 - 1e-4)
    assert result.binding_shares()[0][1] == "crash"


# --- against TOPPRA alone, and against the sizing -------------------------------------------

SLACK = dataclasses.replace(
    UNITS["PSA-14-100"], id="SLACK-1", repeated_torque=1e6, momentary_torque=1e6,
    static_torque=1e6, rated_torque=1e6, max_input_speed=1e12, input_inertia=0.0, flags=())


@pytest.mark.slow
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_fastest_is_no_longer_than_the_plan_that_passes_with_its_units(mounting):
    """Issue 27: the pick-and-place of tool poses, planned, passes every rule with the
    units `size` selects; `fastest` ran the same path with the same units 0.8 % slower
    (4.566 s for 4.530 s on the floor), each piece slowed down uniformly for TOPPRA's
    overshoot between the gridpoints of a grid without the lines' samples."""
    robot, motion = load_case(REPO / "trajectories" / "benchtop6_pick_place_poses.toml",
                              mounting=mounting)
    sized = size(robot, motion, mounting=mounting)
    assert sized.feasible
    units = {joint.name: joint.selected.unit for joint in sized.joints}
    result = fastest(robot, motion, units, sized.options)
    assert result.feasible and result.slowdown == 1.0
    assert result.cycle_time <= sized.cycle_time * (1.0 + 1e-9)
    assert result.cycle_time == pytest.approx(sized.cycle_time, rel=1e-3)


@pytest.mark.slow
def test_fastest_reports_a_slow_down_beyond_the_tolerance(monkeypatch, tmp_path):
    """Forced: the path model on its cosine grid alone (no knots, no refinement), as
    before issue 27, slows every piece of the pick-and-place down by more than 0.1 %:
    each is named, with its joint and factor, in the result's warnings and the JSON."""
    import hdselect.codesign.fastpath as fastpath

    monkeypatch.setattr(fastpath, "_resolved", lambda piece, motion: piece)
    robot, motion = load_case(REPO / "trajectories" / "benchtop6_pick_place_poses.toml")
    result = fastest(robot, motion)
    noted = [w for w in result.warnings if w.startswith("cycle: toppra slowed the path")]
    assert [w.split(" down ")[0].split("path ")[1] for w in noted] == [
        "from waypoint[0] to waypoint[2]", "from waypoint[2] to waypoint[5]",
        "from waypoint[5] to waypoint[7]"]
    for line in noted:
        factor = float(line.split(" down ")[1].split(" times")[0])
        assert 1.001 < factor < 1.1 and "joint '" in line
    assert main(["fastest", str(REPO / "trajectories" / "benchtop6_pick_place_poses.toml"),
                 "--json", str(tmp_path / "fastest.json")]) == 0
    document = json.loads((tmp_path / "fastest.json").read_text())
    assert [w for w in document["warnings"] if w.startswith("cycle: toppra")] == noted


@pytest.mark.parametrize("planner", ["toppra", "ruckig"])
def test_slack_units_give_the_kinematic_toppra_run(tmp_path, planner):
    write_robot(tmp_path, 3)
    points = [[0.0, 0.5, -0.8], [1.2, -0.3, 0.2], [0.4, 0.9, 0.6], [-0.5, 0.2, -0.4]]
    lines = ['robot = "arm.urdf"', f'planner = "{planner}"', 'angle_unit = "rad"', "dt = 0.001",
             "[limits]", "velocity = [1.0, 1.5, 2.0]", "acceleration = [4.0, 6.0, 5.0]"]
    lines += ["jerk = 100.0"] if planner == "ruckig" else []
    for i, q in enumerate(points):
        lines += ["[[waypoint]]", f"q = {q}", f"dwell = {0.4 if i == 2 else 0.0}"]
    robot, motion = load_case(write_motion(tmp_path, "\n".join(lines) + "\n"))
    options = Options(mass_coupling=False)
    result = fastest(robot, motion, dict.fromkeys(robot.joint_names, SLACK), options)
    expected = float(np.sum(motion.dwells))
    for piece in PathModel.build(robot, motion, robot.sized_joints).pieces:  # its own grid
        constraints = kinematic_constraints(motion.velocity_limit, motion.acceleration_limit)
        profile = solve_piece(piece, constraints, where="test")
        expected += profile.duration * overshoot_scale(profile, motion.velocity_limit,
                                                       motion.acceleration_limit)
    assert result.cycle_time == pytest.approx(expected, abs=2 * motion.dt)
    assert result.optimum == pytest.approx(expected, rel=1e-9)
    assert result.reason is None and result.slowdown == pytest.approx(1.0)
    if planner == "toppra":  # the planner's own run, on its four times finer grid
        assert result.cycle_time == pytest.approx(plan(robot, motion).duration, rel=RESOLUTION)


@pytest.mark.parametrize("planner", ["toppra", "ruckig"])
def test_fastest_follows_plans_path_rule_at_a_position_limit(tmp_path, planner):
    # waypoint[1] and [3] lie on j1's +pi limit, passed with a slope: the clamped spline
    # through them leaves the limit, so j1 alone follows the shape-preserving cubic, as in
    # `plan` (test_plan.test_toppra_stays_inside_limits_its_spline_would_leave)
    write_robot(tmp_path, 2)
    points = [[0.0, 0.0], [math.pi, 0.5], [2.0, 1.0], [math.pi, 2.0]]
    lines = ['robot = "arm.urdf"', f'planner = "{planner}"', 'angle_unit = "rad"', "dt = 0.002",
             "[limits]", "velocity = [1.0, 1.5]", "acceleration = [4.0, 6.0]"]
    lines += ["jerk = 100.0"] if planner == "ruckig" else []
    for q in points:
        lines += ["[[waypoint]]", f"q = {q!r}"]
    robot, motion = load_case(write_motion(tmp_path, "\n".join(lines) + "\n"))
    speeds = motion.velocity_limit if planner == "ruckig" else None
    (piece,) = path_pieces(robot, motion, GRID_PER_WAYPOINT, speeds=speeds)
    assert piece.path.shape_preserving == (0,)
    result = fastest(robot, motion, dict.fromkeys(robot.joint_names, SLACK),
                     Options(mass_coupling=False))
    j1 = result.trajectory.q[:, 0]
    assert j1.max() <= math.pi + 1e-12 and j1.min() >= -1e-12
    assert j1.max() == pytest.approx(math.pi, abs=1e-9)  # it does reach the waypoints
    if planner == "toppra":  # plan's path: the same curve, run at other speeds
        (planned,) = path_pieces(robot, motion)
        s = np.linspace(0.0, 1.0, 101)
        np.testing.assert_array_equal(piece.path(s), planned.path(s))
        assert plan(robot, motion).q[:, 0].max() <= math.pi + 1e-12


def test_fastest_leaving_a_limit_is_refused_as_plan_refuses_it(tmp_path, monkeypatch):
    import hdselect.codesign.fastest_cycle as codesign

    write_robot(tmp_path, 2)
    robot, motion = load_case(write_motion(tmp_path, f"""\
        robot = "arm.urdf"
        planner = "toppra"
        angle_unit = "deg"
        dt = 0.002
        [limits]
        velocity = 60
        acceleration = 200
        [[waypoint]]
        q = [0.0, 0.0]
        [[waypoint]]
        q = [{math.degrees(math.pi)!r}, 20.0]
        [[waypoint]]
        q = [90.0, 40.0]
    """))
    verified = codesign.verified

    def bumped(*args, **kwargs):  # a path 0.6 deg past the stop, near waypoint[1]
        trajectory, *rest = verified(*args, **kwargs)
        bump = np.exp(-((trajectory.t - trajectory.t[np.argmax(trajectory.q[:, 0])]) / 0.05) ** 2)
        q = trajectory.q + np.column_stack([math.radians(0.6) * bump, 0.0 * bump])
        return (dataclasses.replace(trajectory, q=q), *rest)

    monkeypatch.setattr(codesign, "verified", bumped)
    with pytest.raises(PlanningError) as info:
        fastest(robot, motion, dict.fromkeys(robot.joint_names, SLACK))
    message = str(info.value)
    assert "the fastest trajectory takes joint 'j1' 0.6 deg past its upper limit 180 deg" \
        in message
    assert "near waypoint[1], which lies on that limit" in message
    assert "move waypoint[1].j1 at least 0.6 deg further inside" in message


def test_path_keeps_the_dwells_and_stops_only_there(tmp_path):
    robot, motion = load_case(FAST_PICK)
    result = fastest(robot, motion)
    trajectory = result.trajectory
    still = np.all(trajectory.qd == 0.0, axis=1)
    for i, point in enumerate(motion.waypoints):
        near = np.all(np.abs(trajectory.q - point) <= 1e-9, axis=1)
        held = near & still
        if motion.dwells[i] > 0.0:
            assert held.sum() * motion.dt == pytest.approx(motion.dwells[i] + motion.dt,
                                                           abs=2 * motion.dt)
        elif 0 < i < len(motion.waypoints) - 1:
            assert not held.any()  # passed through without stopping
        step = np.abs(trajectory.qd).max(axis=0) * motion.dt + 1e-9
        assert np.any(np.all(np.abs(trajectory.q - point) <= step, axis=1))


def write_log_motion(directory: Path, csv: Path, source: Path) -> Path:
    """A samples motion replaying a written trajectory, with the source's robot and payload."""
    with source.open("rb") as stream:
        doc = tomllib.load(stream)
    payload = doc["payload"]
    return write_motion(directory, f"""\
        robot = "{(source.parent / doc['robot']).resolve()}"
        planner = "samples"
        angle_unit = "rad"
        dt = {doc['dt']}
        [payload]
        mass = {payload['mass']}
        com = {payload['com']}
        inertia = {payload['inertia']}
        frame = "{payload['frame']}"
        [samples]
        file = "{csv.name}"
    """, name="log.toml")


@pytest.mark.slow
@pytest.mark.parametrize("coupled", [True, False])
def test_written_trajectory_passes_size_as_a_log(tmp_path, coupled):
    csv = tmp_path / "fastest.csv"
    units = ["PSA-14-100"] if coupled else []
    args = ["fastest", str(FAST_PICK), "--out", str(csv)]
    args += [f"--units={joint}=PSA-14-100" for joint in ("shoulder_pan", "shoulder_lift",
             "elbow", "wrist_1", "wrist_2", "wrist_3")] if coupled else ["--no-mass-coupling"]
    assert main(args) == 0
    robot, motion = load_case(FAST_PICK)
    options = Options(stop_time=0.15, life_hours=20000, mass_coupling=coupled)
    chosen = fastest(robot, motion, dict.fromkeys(robot.joint_names, UNITS["PSA-14-100"])
                     if coupled else None, options).units
    log = write_log_motion(tmp_path, csv, FAST_PICK)
    result = size(None, log, catalog=[UNITS[u] for u in units] or None, stop_time=0.15,
                  life_hours=20000, mass_coupling=coupled)
    for joint in result.joints:
        (candidate,) = [c for c in joint.candidates if c.unit.id == chosen[joint.name].id]
        assert candidate.feasible, (joint.name, candidate.binding)
    if coupled:
        assert all(joint.selected.unit.id == "PSA-14-100" for joint in result.joints)


def stronger(unit, factor=1.2):
    """The unit with every limit `factor` times higher: torques and maximum input speed."""
    return dataclasses.replace(
        unit, id=unit.id + "+", repeated_torque=unit.repeated_torque * factor,
        momentary_torque=unit.momentary_torque * factor,
        static_torque=unit.static_torque * factor, rated_torque=unit.rated_torque * factor,
        max_input_speed=unit.max_input_speed * factor)


FAST_PICK_UNITS = {"shoulder_pan": "PSA-14-80", "shoulder_lift": "PSA-14-100",
                   "elbow": "PSA-14-100", "wrist_1": "PSA-08-80", "wrist_2": "PSA-08-100",
                   "wrist_3": "PSA-08-80"}


@pytest.mark.slow
def test_stronger_unit_never_gives_a_longer_cycle(tmp_path):
    # the arm: shoulder_pan crash-bound (PSA-08-80) or torque-bound (PSA-10-50)
    robot, motion = load_case(FAST_PICK)
    options = Options(stop_time=0.15, life_hours=20000)
    for joint, weak in (("shoulder_pan", "PSA-08-80"), ("shoulder_pan", "PSA-10-50")):
        units = {name: UNITS[unit] for name, unit in {**FAST_PICK_UNITS, joint: weak}.items()}
        slow = fastest(robot, motion, units, options)
        quick = fastest(robot, motion, {**units, joint: stronger(units[joint])}, options)
        assert quick.cycle_time <= slow.cycle_time * (1.0 + 1e-6), joint
        assert quick.cycle_time < slow.cycle_time * 0.999, joint  # and it binds
    # the index table where the mean-torque rule binds, derated
    unit = UNITS["PSA-10-50"]
    theta = 1.5 * mean_speed_allowing_peak(unit)
    robot, motion = index_table(tmp_path, unit.repeated_torque / (4.0 * theta), theta)
    options = Options(stop_time=10.0)
    slow = fastest(robot, motion, {"table": unit}, options)
    quick = fastest(robot, motion, {"table": stronger(unit)}, options)
    assert slow.reason == ("table", "mean")
    assert quick.cycle_time < slow.cycle_time


@pytest.mark.slow
def test_compare_ratios_equals_fastest_unit_by_unit(tmp_path):
    unit = UNITS["PSA-14-100"]
    # the units are chosen on the plan at the motion's own limits (about 1 ms long)
    robot, motion = index_table(tmp_path, 0.5, 3.0, stop_time=0.2, dt=2e-5)
    options = Options(stop_time=0.2, life_hours=20000)
    comparison = compare_ratios(robot, motion, {"table": unit}, options)
    (joint,) = comparison.joints
    assert [row.unit.id for row in joint.rows] == list(UNITS)
    for row in joint.rows:
        try:
            single = fastest(robot, motion, {"table": row.unit}, options).cycle_time
        except PathInfeasible:
            single = None
        assert row.cycle_time == (pytest.approx(single, rel=1e-12) if single else None)
    assert comparison.base.units["table"] is unit


# --- bad input -------------------------------------------------------------------------------

def test_unknown_joint_or_unit(capsys):
    for pair, message in (("elbo=PSA-14-100", "unknown joint 'elbo'; sized joints are: "
                                              "shoulder_pan"),
                          ("elbow=PSA-99-1", "unknown unit 'PSA-99-1' for joint 'elbow'; units "
                                             "are: PSA-08-80"),
                          ("elbow", "expected JOINT=UNIT, got 'elbow'")):
        assert main(["fastest", str(FAST_PICK), "--units", pair]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"hdselect: error: --units: {message}")
        assert err.count("\n") == 1


@pytest.mark.parametrize("command", ["compare", "fastest"])
def test_a_known_joint_not_sized_is_not_called_unknown(capsys, command):
    assert main([command, str(FAST_PICK), "--joints", "elbow", "--joint", "wrist_1",
                 *(["--compare-ratios"] if command == "fastest" else [])]) == 2
    assert capsys.readouterr().err.startswith(
        "hdselect: error: --joint: 'wrist_1' is not a sized joint; sized joints are: elbow\n")


def test_a_log_has_no_path(capsys):
    log = REPO / "trajectories" / "pan_tilt_logged.toml"
    assert main(["fastest", str(log)]) == 2
    err = capsys.readouterr().err
    assert err == (f"hdselect: error: {log}: planner: a logged trajectory ('samples') has no "
                   "path to run faster; give a motion with waypoints\n")


@pytest.mark.slow
def test_a_joint_no_unit_can_run_is_named_with_what_to_do(capsys):
    """No catalog unit holds the shoulder: a result (exit 1) saying why and what works."""
    motion = REPO / "trajectories" / "benchtop6_pick_place.toml"
    assert main(["fastest", str(motion), "--payload", "30"]) == 1
    out = " ".join(capsys.readouterr().out.split())
    assert out.startswith(f"{motion}: no unit of the catalog can run joint 'shoulder_lift' on "
                          "this motion at any speed. ")
    assert "gravity alone needs" in out and "--units" not in out
    assert "--exclude shoulder_pan,shoulder_lift,elbow" in out
    assert main(["fastest", str(motion), "--payload", "30", "--exclude",
                 "shoulder_lift,elbow"]) == 0


def test_unit_that_cannot_hold_gravity(capsys, tmp_path):
    """A unit given that cannot hold the gravity load: a result (exit 1), no file written."""
    out = tmp_path / "never.csv"
    assert main(["fastest", str(FAST_PICK), "--units", "shoulder_lift=PSA-08-80",
                 "--out", str(out)]) == 1
    printed = capsys.readouterr()
    text = " ".join(printed.out.split())
    assert printed.err == ""
    assert "joint 'shoulder_lift' cannot hold its gravity load at any speed" in text
    assert "beyond its repeated-peak limit 2.6 N m" in text
    assert not out.exists()


def test_infeasible_limit_named_with_joint_and_place(tmp_path):
    # a bar on a horizontal axis, 1 kg at 0.5 m: gravity 4.9 N m where it is horizontal
    (tmp_path / "arm.urdf").write_text(
        '<robot name="p"><link name="base"/><link name="bar"><inertial><origin xyz="0.5 0 0"/>'
        '<mass value="1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/>'
        '</inertial></link><joint name="swing" type="revolute"><parent link="base"/>'
        '<child link="bar"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="50" '
        'velocity="10"/></joint></robot>')
    robot, motion = load_case(write_motion(tmp_path, """\
        robot = "arm.urdf"
        planner = "toppra"
        angle_unit = "deg"
        [limits]
        velocity = 500
        acceleration = 5000
        [[waypoint]]
        q = [-80]
        [[waypoint]]
        q = [80]
    """))
    # hanging straight down at the ends (gravity ~0.85 N m), horizontal in the middle
    # (4.9 N m): PSA-10-50 (3.4 N m) holds the ends but not the middle
    with pytest.raises(PathInfeasible, match=r"joint 'swing' cannot hold its gravity load at "
                       r"any speed: 4\.9\d? N m between waypoint\[0\] and waypoint\[1\]") as info:
        fastest(robot, motion, {"swing": UNITS["PSA-10-50"]})
    assert info.value.gravity and info.value.joint == "swing"
    assert isinstance(info.value, PlanningError)


def test_options_and_joint_flags(capsys):
    assert main(["fastest", str(FAST_PICK), "--joint", "elbow"]) == 2
    assert capsys.readouterr().err == ("hdselect: error: --joint: only with --compare-ratios\n")
    assert main(["fastest", str(FAST_PICK), "--compare-ratios", "--joint", "elbo"]) == 2
    assert capsys.readouterr().err.startswith("hdselect: error: --joint: unknown joint 'elbo'")
    with pytest.raises(InputError, match="units: unknown joint"):
        robot, motion = load_case(FAST_PICK)
        fastest(robot, motion, {"nope": "PSA-14-100"})


# --- the command line ------------------------------------------------------------------------

@pytest.mark.slow
def test_json_csv_and_plot_of_fastest(tmp_path, capsys):
    out, plot = tmp_path / "fast.csv", tmp_path / "fast.png"
    assert main(["fastest", str(FAST_PICK), "--json", "-", "--out", str(out), "--plot",
                 str(plot)]) == 0
    captured = capsys.readouterr()
    document = json.loads(captured.out)
    assert f"wrote {out}: t, then q_" in " ".join(captured.err.split())
    assert f"wrote {plot}: speed and torque" in " ".join(captured.err.split())
    assert set(document) == {"robot", "motion", "cycle_time_s", "moving_time_s", "dwell_time_s",
                             "optimum_s", "slowdown", "lengthened_by", "grid_per_waypoint",
                             "samples", "feasible", "assumptions", "joints", "binding",
                             "root_link", "payload", "warnings", "notes"}
    assert document["warnings"] == [] and document["payload"]["frame"] == "tool0"
    assert document["feasible"] and document["grid_per_waypoint"] == GRID_PER_WAYPOINT
    assert document["cycle_time_s"] == pytest.approx(document["moving_time_s"] + 6.0)
    joint = document["joints"][0]
    assert joint["name"] == "shoulder_pan" and joint["candidate"]["unit"] == joint["unit"]
    assert joint["velocity_limit_source"] in ("motion", "robot", "unit")
    assert {b["joint"] for b in document["binding"]} <= set(FAST_PICK_UNITS)
    header = out.read_text().splitlines()[0].split(",")
    assert header[0] == "t" and header[1:5] == ["q_shoulder_pan", "qd_shoulder_pan",
                                                "qdd_shoulder_pan", "tau_shoulder_pan"]
    assert len(header) == 1 + 4 * 6
    assert plot.stat().st_size > 0


@pytest.mark.slow
def test_json_of_compare_ratios(capsys):
    assert main(["fastest", str(FAST_PICK), "--compare-ratios", "--joint", "elbow",
                 "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    (joint,) = document["joints"]
    assert joint["name"] == "elbow" and joint["selected"] == "PSA-14-100"
    rows = {row["unit"]: row for row in joint["units"]}
    assert list(rows) == list(UNITS)
    assert rows["PSA-08-80"]["cycle_time_s"] is None and rows["PSA-08-80"]["gravity"]
    assert rows["PSA-14-100"]["cycle_time_s"] == pytest.approx(document["cycle_time_s"])


@pytest.mark.slow
def test_motor_data_of_the_motion_file_is_taken_not_left_out(tmp_path):
    """fastest and max-payload run the motion file's [motor] (they refused it before)."""
    from hdselect import max_payload

    source = (REPO / "trajectories" / "planar2_pick_place.toml").read_text()
    motion = tmp_path / "motors.toml"
    robot_file = (REPO / "robots" / "planar2.urdf").as_posix()
    motors = (REPO / "motors" / "example_motors.toml").as_posix()
    source = source.replace('robot = "../robots/planar2.urdf"', f'robot = "{robot_file}"')
    motion.write_text(source + f'\n[motor]\ncatalog = "{motors}"\n')
    robot, loaded = load_case(motion)
    assert set(fastest(robot, loaded).motors) == set(robot.sized_joints)
    selection = max_payload(robot, loaded).selection
    assert selection is not None and set(selection.motors) == set(robot.sized_joints)


MOVE = """\
robot = "{robot}"
planner = "ruckig"
angle_unit = "{angle}"
dt = 0.002
[limits]
velocity = {v}
acceleration = {a}
jerk = {j}
[[waypoint]]
q = {{shoulder = {q0}, elbow = {q1}}}
dwell = 0.2
[[waypoint]]
q = {{shoulder = {q2}, elbow = {q3}}}
dwell = 0.2
"""
"""planar2's one move and back, its angles in `angle`."""


@pytest.mark.parametrize("angle", ["deg", "rad"])
def test_fastest_shows_speed_limits_in_the_motion_files_angle_unit(capsys, tmp_path, angle):
    """Issue 27: the table speaks the file's unit; its numbers are the JSON's (rad/s) in it."""
    per_deg = 1.0 if angle == "deg" else math.pi / 180
    motion = tmp_path / "move.toml"
    motion.write_text(MOVE.format(robot=REPO / "robots" / "planar2.urdf", angle=angle,
                                  v=100 * per_deg, a=900 * per_deg, j=9000 * per_deg,
                                  q0=40 * per_deg, q1=-80 * per_deg, q2=-30 * per_deg,
                                  q3=20 * per_deg))
    assert main(["fastest", str(motion), "--json", str(tmp_path / "f.json")]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert f"speed limit [{angle}/s, the motion file's angle unit]" in text
    document = json.loads((tmp_path / "f.json").read_text())
    for joint in document["joints"]:
        shown = joint["velocity_limit"] * (180 / math.pi if angle == "deg" else 1.0)
        assert f"{shown:.3g} {joint['velocity_limit_source']}" in text, joint
    assert "100 motion" in text if angle == "deg" else "1.75 motion" in text  # the file's own


@pytest.mark.slow
def test_compare_says_nothing_is_selected_when_no_unit_passes(capsys, tmp_path):
    assert main(["compare", str(FAST_PICK), "--joint", "elbow", "--efficiency", "0.5",
                 "--life-hours", "1e9"]) == 1
    text = " ".join(capsys.readouterr().out.split())
    assert "Nothing is selected: no unit passes every rule." in text
    assert "▶ selected" not in text and "▶" not in text
