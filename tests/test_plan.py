from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
import ruckig
from scipy.interpolate import CubicSpline

from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.loading import load_case
from hdselect.motion.planning import PLANNERS, plan
from hdselect.motion.planning.ruckig import sample_profiles
from hdselect.motion.planning.toppra import TOPPRA_TOLERANCE, TOPPRA_TORQUE_TOLERANCE
from helpers.motions import dense_toppra_cycle, make_motion, ruckig_move
from helpers.robots import write_chain, write_motion


def sample_at_time(traj: ruckig.Trajectory, times: np.ndarray):
    """Oracle for `sample_profiles`: Ruckig's own ``at_time``, one call per sample (slow)."""
    states = [traj.at_time(float(time)) for time in np.asarray(times, dtype=float)]
    shape = (len(states), traj.degrees_of_freedom)
    return tuple(np.array([s[i] for s in states]).reshape(shape) for i in range(3))


def check_grid(trajectory, motion):
    n = math.ceil(trajectory.duration / motion.dt - 1e-9) + 1
    np.testing.assert_array_equal(trajectory.t, np.arange(n) * motion.dt)
    shape = (n, len(motion.joint_names))
    assert trajectory.q.shape == trajectory.qd.shape == trajectory.qdd.shape == shape
    assert trajectory.joint_names == motion.joint_names
    for array in (trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd):
        assert not array.flags.writeable


def check_waypoints(trajectory, motion):
    """The trajectory starts, ends (at rest) and passes within one sample of each waypoint."""
    np.testing.assert_allclose(trajectory.q[0], motion.waypoints[0], atol=1e-12)
    np.testing.assert_allclose(trajectory.q[-1], motion.waypoints[-1], atol=1e-12)
    np.testing.assert_allclose(trajectory.qd[-1], 0.0, atol=1e-12)
    step = np.abs(trajectory.qd).max(axis=0) * motion.dt + 1e-12
    for point in motion.waypoints:
        assert np.any(np.all(np.abs(trajectory.q - point) <= step, axis=1))


# --- ruckig ----------------------------------------------------------------------------------

def test_ruckig_one_joint_by_hand(tmp_path):
    # 1 rad with v = 1, a = 2, j = 10: jerk phases a/j = 0.2 s, constant acceleration
    # v/a - a/j = 0.3 s, so T = D/v + v/a + a/j = 1.7 s.
    robot, motion = make_motion(tmp_path, "ruckig", [[0.0], [1.0]], dwells=[0.25, 0.5],
                         velocity=1, acceleration=2, jerk=10)
    trajectory = plan(robot, motion)
    assert trajectory.duration == pytest.approx(0.25 + 1.7 + 0.5, abs=1e-12)
    assert trajectory.qd.max() == pytest.approx(1.0, abs=1e-12)
    assert trajectory.qdd.max() == pytest.approx(2.0, abs=1e-12)
    assert trajectory.qdd.min() == pytest.approx(-2.0, abs=1e-12)
    held = trajectory.t <= 0.25
    np.testing.assert_array_equal(trajectory.q[held], 0.0)
    # full speed after 0.2 + 0.3 + 0.2 s, for 1.7 - 2 * 0.7 = 0.3 s
    cruise = (trajectory.t > 0.25 + 0.701) & (trajectory.t < 0.25 + 0.999)
    np.testing.assert_allclose(trajectory.qd[cruise], 1.0, atol=1e-12)
    check_grid(trajectory, motion)


@pytest.mark.parametrize("velocity", [None, [3.0, -2.0, 0.5]])
def test_sample_profiles_equals_at_time(velocity):
    # different distances per joint (one not moving); an initial velocity above the
    # limit makes Ruckig add a brake pre-trajectory.
    traj = ruckig_move([0.0, 0.5, -1.0], [1.3, -0.2, -1.0], [1.0, 1.5, 2.0], [2.0, 3.0, 4.0],
                       [10.0, 20.0, 30.0], velocity)
    if velocity is not None:
        assert any(p.brake.duration > 0.0 for p in traj.profiles[0])
    times = np.r_[np.linspace(0.0, traj.duration * 1.2, 2001), traj.duration]
    for mine, reference in zip(sample_profiles(traj, times), sample_at_time(traj, times),
                               strict=True):
        np.testing.assert_allclose(mine, reference, rtol=0, atol=1e-9)


def test_ruckig_plan_equals_at_time_on_the_grid(tmp_path):
    points = [[0.0, 0.0, 0.0], [1.0, -0.4, 0.1], [1.0, -0.4, 0.1], [-0.5, 0.3, 0.1]]
    dwells = [0.1, 0.0, 0.2, 0.05]
    v, a, j = [1.0, 1.2, 1.4], [2.0, 3.0, 4.0], [20.0, 30.0, 40.0]
    robot, motion = make_motion(tmp_path, "ruckig", points, dwells=dwells, velocity=v,
                         acceleration=a, jerk=j, dt=0.002)
    trajectory = plan(robot, motion)
    reference = np.empty((3, *trajectory.q.shape))
    clock, hold = dwells[0], [(0.0, dwells[0], points[0])]
    for i in range(len(points) - 1):
        traj = ruckig_move(points[i], points[i + 1], v, a, j)
        inside = (trajectory.t >= clock) & (trajectory.t < clock + traj.duration)
        for k, state in enumerate(sample_at_time(traj, trajectory.t[inside] - clock)):
            reference[k][inside] = state
        clock += traj.duration
        hold.append((clock, clock + dwells[i + 1], points[i + 1]))
        clock += dwells[i + 1]
    for begin, end, point in hold:
        inside = (trajectory.t >= begin) & (trajectory.t <= end + 1e-12)
        reference[:, inside] = 0.0
        reference[0, inside] = point
    reference[:, trajectory.t > clock] = 0.0
    reference[0, trajectory.t > clock] = points[-1]
    assert trajectory.duration == pytest.approx(clock, abs=1e-12)
    for mine, expected in zip((trajectory.q, trajectory.qd, trajectory.qdd), reference,
                              strict=True):
        np.testing.assert_allclose(mine, expected, rtol=0, atol=1e-9)


# --- limits and waypoints, both planners -----------------------------------------------------

CASES = {
    1: [[0.0], [1.2], [-0.5]],
    2: [[0.0, 0.0], [1.0, -0.5], [0.2, 0.8]],
    6: [[0.0, 0.5, -0.8, 0.0, 1.0, 0.0], [1.5, 0.0, -0.2, 0.4, -0.6, 1.0],
        [1.5, 0.0, -0.2, 0.4, -0.6, 1.0], [-1.0, 0.9, 0.3, -0.4, 0.2, -1.2]],
}


@pytest.mark.parametrize("planner", ["ruckig", "toppra"])
@pytest.mark.parametrize("dof", [1, 2, 6])
def test_limits_and_waypoints(tmp_path, planner, dof):
    points = CASES[dof]
    v, a, j = np.linspace(1.0, 2.0, dof), np.linspace(3.0, 6.0, dof), np.linspace(30, 60, dof)
    dwells = [0.0] * len(points)
    dwells[1] = 0.3
    robot, motion = make_motion(tmp_path, planner, points, dwells=dwells, velocity=v.tolist(),
                         acceleration=a.tolist(), jerk=j.tolist() if planner == "ruckig" else None)
    trajectory = plan(robot, motion)
    check_grid(trajectory, motion)
    check_waypoints(trajectory, motion)
    tolerance = 1e-12 if planner == "ruckig" else TOPPRA_TOLERANCE
    assert np.all(np.abs(trajectory.qd) <= v * (1 + tolerance))
    assert np.all(np.abs(trajectory.qdd) <= a * (1 + tolerance))
    if planner == "ruckig":
        jerk = np.abs(np.diff(trajectory.qdd, axis=0)) / motion.dt
        assert np.all(jerk <= j * (1 + 1e-6))
    # the dwell: at rest on waypoint 1 for 0.3 s
    at_rest = np.all(trajectory.qd == 0.0, axis=1) & np.all(trajectory.q == points[1], axis=1)
    assert at_rest.sum() * motion.dt == pytest.approx(0.3, abs=1.5 * motion.dt)


# --- toppra ----------------------------------------------------------------------------------

def test_toppra_is_time_optimal_on_one_joint(tmp_path):
    # 1 rad with v = 1, a = 2: trapezoid, T = D/v + v/a = 1.5 s.
    robot, motion = make_motion(tmp_path, "toppra", [[0.0], [1.0]], velocity=1, acceleration=2)
    trajectory = plan(robot, motion)
    assert trajectory.duration == pytest.approx(1.5, rel=2e-3)
    assert trajectory.qd.max() == pytest.approx(1.0, rel=2e-3)


def test_toppra_torque_limits(tmp_path):
    points = [[0.0, -math.pi / 2], [math.pi / 2, math.pi / 2]]
    free = plan(*make_motion(tmp_path, "toppra", points, velocity=6.28, acceleration=50))
    limit = 0.85
    robot, motion = make_motion(tmp_path, "toppra", points, velocity=6.28, acceleration=50,
                         torque=limit)
    trajectory = plan(robot, motion)
    model = robot.model
    data = model.createData()
    config = robot.configuration(trajectory.q)
    torque = np.array([pin.rnea(model, data, config[:, k], trajectory.qd[k], trajectory.qdd[k])
                       for k in range(0, len(trajectory.t), 5)])
    assert np.abs(torque).max() <= limit * (1 + TOPPRA_TORQUE_TOLERANCE)
    assert np.abs(torque).max() > 0.95 * limit
    assert trajectory.duration > free.duration * 1.05
    with pytest.raises(PlanningError, match=r"motion.toml: toppra: the torque limits"):
        plan(*make_motion(tmp_path, "toppra", points, velocity=6.28, acceleration=50, torque=0.5))


def clamped_spline(waypoints):
    """The clamped cubic spline through waypoints, chord-length parametrised (an oracle)."""
    points = np.asarray(waypoints, dtype=float)
    chord = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))]
    return CubicSpline(chord / chord[-1], points, bc_type="clamped")


@pytest.mark.parametrize("waypoints", [
    [[0.0, 0.0], [3.1, 0.0], [3.1, 3.0], [0.0, 3.0]],      # near the +pi limit
    [[0.0, 0.0], [math.pi, 0.5], [2.0, 1.0], [math.pi, 2.0]],  # on it, passed with a slope
    [[-math.pi, 0.0], [-3.1, 2.0], [-2.0, 2.1]],          # starting on the -pi limit
], ids=["near", "on", "start-on"])
def test_toppra_stays_inside_limits_its_spline_would_leave(tmp_path, waypoints):
    spline = clamped_spline(waypoints)(np.linspace(0.0, 1.0, 2001))
    assert np.abs(spline[:, 0]).max() > math.pi + 1e-3  # the plain spline leaves the limits
    robot, motion = make_motion(tmp_path, "toppra", waypoints, velocity=1, acceleration=2,
                                dt=0.005)
    trajectory = plan(robot, motion)
    check_waypoints(trajectory, motion)
    j1 = trajectory.q[:, 0]
    points = np.asarray(waypoints)[:, 0]
    # the shape-preserving path never leaves the range of the waypoints it joins
    assert points.min() - 1e-9 <= j1.min() and j1.max() <= points.max() + 1e-9
    assert np.all(np.abs(trajectory.qd) <= 1.0 * (1 + TOPPRA_TOLERANCE))


def test_toppra_keeps_the_spline_for_joints_inside_their_limits(tmp_path):
    waypoints = [[0.0, 0.0], [1.0, 0.5], [1.0, 1.0], [0.0, 1.5]]
    robot, motion = make_motion(tmp_path, "toppra", waypoints, velocity=1, acceleration=2,
                                dt=0.005)
    trajectory = plan(robot, motion)
    # the clamped spline bulges past 1.0 between the two equal waypoints, inside the limits
    bulge = clamped_spline(waypoints)(np.linspace(0.0, 1.0, 2001))[:, 0].max()
    assert bulge > 1.0 + 1e-3
    assert trajectory.q[:, 0].max() == pytest.approx(bulge, abs=1e-4)


def test_a_trajectory_leaving_a_limit_names_the_waypoint_and_the_overshoot(tmp_path,
                                                                         monkeypatch):
    robot, motion = make_motion(tmp_path, "ruckig", [[0.0, 0.0], [math.pi, 0.5], [1.0, 1.0]],
                                velocity=1, acceleration=2, jerk=10)
    planned = plan(robot, motion)
    bump = np.exp(-((planned.t - planned.t[np.argmax(planned.q[:, 0])]) / 0.05) ** 2)
    bumped = replace(planned, q=planned.q + np.column_stack([0.01 * bump, 0 * bump]))
    monkeypatch.setitem(PLANNERS, "ruckig", lambda robot, motion, **_: bumped)
    with pytest.raises(PlanningError) as info:
        plan(robot, motion)
    message = str(info.value)
    assert "joint 'j1' 0.01 rad past its upper limit 3.14159 rad" in message
    assert "near waypoint[1], which lies on that limit" in message
    assert "move waypoint[1].j1 at least 0.01 rad further inside" in message


def test_identical_waypoints_take_no_time(tmp_path):
    for planner in ("ruckig", "toppra"):
        robot, motion = make_motion(tmp_path, planner, [[0.3, 0.1], [0.3, 0.1]], dwells=[0.0, 0.1],
                             velocity=1, acceleration=2, jerk=10 if planner == "ruckig" else None)
        trajectory = plan(robot, motion)
        assert trajectory.duration == pytest.approx(0.1)
        np.testing.assert_array_equal(trajectory.q, 0.0 * trajectory.q + [0.3, 0.1])


def test_ruckig_failure_is_a_planning_error(tmp_path, monkeypatch):
    class Broken:
        def __init__(self, dof):
            pass

        def calculate(self, inp, traj):
            raise ruckig.RuckigError("\n[ruckig] error in step 1, dof: 0 input:\n...")

    monkeypatch.setattr(ruckig, "Ruckig", Broken)
    robot, motion = make_motion(tmp_path, "ruckig", [[0.0], [1.0]], velocity=1, acceleration=2,
                                jerk=10)
    with pytest.raises(PlanningError, match=r"waypoint\[0\] to waypoint\[1\]") as info:
        plan(robot, motion)
    assert "error in step 1, dof: 0 input:" in str(info.value)
    assert isinstance(info.value.__cause__, ruckig.RuckigError)


# --- samples ---------------------------------------------------------------------------------

def cubic(t):
    return (0.2 + 0.5 * t - 0.8 * t**2 + 0.3 * t**3,
            0.5 - 1.6 * t + 0.9 * t**2,
            -1.6 + 1.8 * t)


def write_log(tmp_path, t, *, dt, velocities=False):
    write_chain(tmp_path, [("turn", "revolute", -3, 3), ("slide", "prismatic", -1, 1)])
    q, qd, _ = cubic(t - t[0])
    header = "t,q_turn,q_slide" + (",qd_turn,qd_slide" if velocities else "")
    rows = np.c_[t, np.degrees(q), q, np.degrees(qd), qd] if velocities else \
        np.c_[t, np.degrees(q), q]
    (tmp_path / "log.csv").write_text(header + "\n" + "\n".join(
        ",".join(repr(float(x)) for x in row) for row in rows) + "\n")
    return load_case(write_motion(tmp_path, f"""\
        robot = "arm.urdf"
        planner = "samples"
        angle_unit = "deg"
        dt = {dt}
        [samples]
        file = "log.csv"
    """))


def test_samples_resampled_with_derived_velocities(tmp_path):
    rng = np.random.default_rng(1)
    t = 3.0 + np.r_[0.0, np.sort(rng.uniform(0.0, 2.0, 60)), 2.0]
    robot, motion = write_log(tmp_path, t, dt=0.01)
    trajectory = plan(robot, motion)
    check_grid(trajectory, motion)
    assert trajectory.duration == pytest.approx(2.0)
    inside = trajectory.t <= 2.0
    q, qd, qdd = cubic(trajectory.t[inside])  # the log's time starts at 3 s, shifted to 0
    for column in range(2):
        np.testing.assert_allclose(trajectory.q[inside, column], q, atol=1e-9)
        np.testing.assert_allclose(trajectory.qd[inside, column], qd, atol=1e-8)
        np.testing.assert_allclose(trajectory.qdd[inside, column], qdd, atol=1e-7)
    np.testing.assert_array_equal(trajectory.qd[~inside], 0.0)


def test_samples_uniform_log_used_as_is(tmp_path):
    t = np.arange(101) * 0.004
    robot, motion = write_log(tmp_path, t, dt=0.004, velocities=True)
    trajectory = plan(robot, motion)
    np.testing.assert_array_equal(trajectory.q, motion.samples.q)
    np.testing.assert_array_equal(trajectory.qd, motion.samples.qd)
    _, qd, qdd = cubic(t)
    np.testing.assert_allclose(trajectory.qd[:, 1], qd, atol=1e-12)
    np.testing.assert_allclose(trajectory.qdd[:, 1], qdd, atol=1e-8)


def test_a_long_log_is_resampled_in_chunks_equal_to_one_spline(tmp_path, monkeypatch):
    """The spline through a long log is evaluated chunk by chunk, each from the log samples
    it spans plus 64 on either side; the result is the spline through the whole log."""
    from scipy.interpolate import CubicSpline

    import hdselect.motion.logderivatives as derivatives

    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.008, 0.012, 1500))
    t -= t[0]
    write_chain(tmp_path, [("turn", "revolute", -3, 3), ("slide", "prismatic", -1, 1)])
    (tmp_path / "log.csv").write_text("t,q_turn,q_slide\n" + "".join(
        f"{x!r},{40 * math.sin(x) + 5 * math.sin(7.3 * x)!r},{0.5 * math.cos(2.1 * x)!r}\n"
        for x in t.tolist()))
    robot, motion = load_case(write_motion(tmp_path, """\
        robot = "arm.urdf"
        planner = "samples"
        angle_unit = "deg"
        dt = 0.001
        [samples]
        file = "log.csv"
    """))
    monkeypatch.setattr(derivatives, "CHUNK", 997)  # 15 chunks, boundaries anywhere
    trajectory = plan(robot, motion)
    log = motion.samples
    whole = CubicSpline(log.t, log.q, axis=0)
    inside = trajectory.t <= log.t[-1]  # a last sample past the log holds its end
    times = trajectory.t[inside]
    for order, array in enumerate((trajectory.q, trajectory.qd, trajectory.qdd)):
        expected = whole(times, order)
        np.testing.assert_allclose(array[inside], expected, rtol=0,
                                   atol=1e-12 * np.abs(expected).max())
    monkeypatch.setattr(derivatives, "MARGIN", 2)  # too short a margin shows
    short = plan(robot, motion).qdd[inside]
    assert np.abs(short - whole(times, 2)).max() > 1e-6 * np.abs(short).max()


def test_batched_torque_constraint_equals_toppras_own(tmp_path):
    # TOPPRA's JointTorqueConstraint calls pinocchio's rnea three times per gridpoint;
    # SecondOrderBounds gets the same a, b, c from three batched passes.
    import toppra.constraint as constraint

    from hdselect.motion.planning.constraints import SecondOrderBounds, path_torque_coefficients
    from hdselect.motion.planning.toppra import path_pieces
    from hdselect.robot.dynamics import rnea_function

    points = [[0.0, -1.2], [1.0, 0.4], [0.2, 1.1], [-0.6, 0.3]]
    robot, motion = make_motion(tmp_path, "toppra", points, velocity=3, acceleration=20)
    (piece,) = path_pieces(robot, motion, 40)
    limit = np.array([2.0, 1.5])
    theirs = constraint.JointTorqueConstraint(
        rnea_function(robot), np.column_stack([-limit, limit]), np.zeros(2),
        discretization_scheme=constraint.DiscretizationType.Interpolation)
    a, b, c = path_torque_coefficients(robot, piece.q, piece.dq, piece.ddq)
    mine = SecondOrderBounds.two_sided(piece.gridpoints, a, b, c, -limit, limit)
    expected = theirs.compute_constraint_params(piece.path, piece.gridpoints)
    got = mine.compute_constraint_params(piece.path, piece.gridpoints)
    for x, y in zip(got, expected, strict=True):
        if y is None:
            assert x is None
        else:
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-12)


def test_toppra_profile_samples_as_toppras_parametrizer(tmp_path):
    import toppra.algorithm as algorithm

    from hdselect.motion.planning.toppra import kinematic_constraints, path_pieces, solve_piece

    robot, motion = make_motion(tmp_path, "toppra", CASES[2], velocity=[1.0, 2.0],
                                acceleration=[3.0, 5.0])
    (piece,) = path_pieces(robot, motion, 30)
    constraints = kinematic_constraints(motion.velocity_limit, motion.acceleration_limit)
    profile = solve_piece(piece, constraints, where="test")
    reference = algorithm.TOPPRA(constraints, piece.path, parametrizer="ParametrizeConstAccel",
                                 gridpoints=piece.gridpoints).compute_trajectory()
    assert profile.duration == pytest.approx(reference.duration, rel=1e-12)
    times = np.linspace(0.0, profile.duration, 777)
    for order, mine in enumerate(profile.sample(times)):
        np.testing.assert_allclose(mine, reference(times, order), rtol=0, atol=1e-12)


def test_a_log_leaving_a_limit_names_the_joint_in_the_files_units(tmp_path):
    """A logged sample past a joint's limit is refused as the log is read: the first one,
    by column, data row and line, in the file's units (the planner's own check then only
    meets a spline that overshoots between samples)."""
    write_chain(tmp_path, [("turn", "revolute", -0.5, 0.5), ("slide", "prismatic", -1, 1)])
    t = np.arange(101) * 0.01
    turn = 40.0 * np.sin(np.pi * t)  # deg: peaks at 40 deg, 11.35 deg past the 0.5 rad stop
    (tmp_path / "log.csv").write_text("t,q_turn,q_slide\n" + "\n".join(
        f"{a:.6f},{b:.9f},0.0" for a, b in zip(t, turn, strict=True)) + "\n")
    first = int(np.argmax(turn > math.degrees(0.5)))  # the first sample past the stop
    with pytest.raises(InputError) as info:
        load_case(write_motion(tmp_path, """\
            robot = "arm.urdf"
            planner = "samples"
            angle_unit = "deg"
            dt = 0.01
            [samples]
            file = "log.csv"
        """))
    message = str(info.value)
    assert (f"log.csv: q_turn: data row {first + 1} (line {first + 2}): {turn[first]:g} deg is "
            "outside the limits of joint 'turn' [-28.6479, 28.6479] deg") in message


TOPPRA_MOTIONS = {
    "contour": ("benchtop6_contour.toml", None),
    "pan-tilt": ("pan_tilt_scan.toml", None),
    **{f"cases-{dof}": (None, CASES[dof]) for dof in CASES},
    "near-limit": (None, [[0.0, 0.0], [3.1, 0.0], [3.1, 3.0], [0.0, 3.0]]),
    "on-limit": (None, [[0.0, 0.0], [math.pi, 0.5], [2.0, 1.0], [math.pi, 2.0]]),
    "start-on": (None, [[-math.pi, 0.0], [-3.1, 2.0], [-2.0, 2.1]]),
    "bulge": (None, [[0.0, 0.0], [1.0, 0.5], [1.0, 1.0], [0.0, 1.5]]),
    "short": (None, [[0.0, 0.0], [0.01, 0.0]]),
    "torque-arm": (None, [[0.0, -math.pi / 2], [math.pi / 2, math.pi / 2]]),
    "codesign": (None, [[0.0, 0.5, -0.8], [1.2, -0.3, 0.2], [0.4, 0.9, 0.6],
                        [-0.5, 0.2, -0.4]]),
}


@pytest.mark.parametrize("name", list(TOPPRA_MOTIONS))
def test_toppra_on_its_refined_grid_keeps_the_dense_grids_cycle(tmp_path, name):
    """The planner solves 50 gridpoints per waypoint and refines where a limit is broken
    between them: its cycle is within 0.1 % of the dense grid's (200 per waypoint)."""
    from helpers import REPO

    shipped, made = TOPPRA_MOTIONS[name]
    if shipped is not None:
        robot, motion = load_case(REPO / "trajectories" / shipped)
    else:
        points, dof = made, len(made[0])
        robot, motion = make_motion(tmp_path, "toppra", points,
                                    velocity=np.linspace(1.0, 2.0, dof).tolist(),
                                    acceleration=np.linspace(3.0, 6.0, dof).tolist())
    trajectory = plan(robot, motion)
    assert trajectory.duration == pytest.approx(dense_toppra_cycle(robot, motion), rel=1e-3)
    assert np.all(np.abs(trajectory.qd) <= motion.velocity_limit * (1 + TOPPRA_TOLERANCE))
    assert np.all(np.abs(trajectory.qdd) <= motion.acceleration_limit * (1 + TOPPRA_TOLERANCE))
