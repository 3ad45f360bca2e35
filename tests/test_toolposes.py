"""Tool-pose motions end to end: read, solved for a mounting, planned, sized, written.

Oracles that do not come from the code under test: forward kinematics on a Pinocchio
model built here (`test_ik.fk`), the mountings' base poses written here from their
definition in words, MuJoCo's own model of the robot file with the base turned onto the
wall in its world and ordinary gravity (inverse dynamics and forward kinematics), and a
brute-force search for the nearest point of a line.
"""

from __future__ import annotations

import math
import re
import shlex

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

import hdselect
from docs_examples import examples, matches, run, scratch
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.ik.poses import pose_error
from hdselect.motion.motionfile import load_motion
from hdselect.motion.planning import plan_motion
from hdselect.motion.planning.solve import solve_motion
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import load_robot
from hdselect.robot.mounting import STANDARD_GRAVITY, BasePose, shown_numbers
from hdselect.sizing.records import base_text
from helpers import REPO
from helpers.poses import SHORT, TOLERANCE, fk, written_pose
from helpers.robots import ARMS as EXAMPLE_ARMS
from helpers.robots import example_robots, robot_path

EXAMPLE = REPO / "trajectories" / "benchtop6_pick_place_poses.toml"

WALL = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])
"""The wall mounting written from its definition: columns are the base's x (world +z, up),
y (z cross x = world -y) and z (world +x) axes in the world."""
BASES = {"floor": pin.SE3.Identity(), "wall": pin.SE3(WALL, np.zeros(3)),
         "ceiling": pin.SE3(np.diag([1.0, -1.0, -1.0]), np.zeros(3))}


@pytest.mark.parametrize("name", ["floor", "wall", "ceiling"])
def test_a_named_mounting_is_one_placement_for_gravity_and_poses(name):
    g = STANDARD_GRAVITY
    by_hand = {"floor": (0, 0, -g), "wall": (-g, 0, 0), "ceiling": (0, 0, g)}[name]
    robot = load_robot(robot_path("planar2"), mounting=name)
    np.testing.assert_array_equal(robot.base_pose.matrix, BASES[name].rotation)
    np.testing.assert_allclose(robot.gravity, by_hand, atol=1e-15)
    np.testing.assert_allclose(robot.model.gravity.linear, by_hand, atol=1e-15)


def test_a_base_hung_upside_down_reads_as_written():
    """A rotation's rounding (cos 180 deg = -1, sin 180 deg = 1.2e-16) is not shown as
    gravity of -1.2e-15 m/s^2 or a pitch of -0 deg."""
    hung = BasePose.from_xyz_rpy([0.0, 0.0, 0.44], [math.pi, 0.0, 0.0])
    robot = load_robot(robot_path("benchtop6")).with_mounting(hung)
    assert abs(robot.gravity[1]) > 0.0  # the rounding is there
    line = base_text(robot)
    assert "rpy (180, 0, 0) deg" in line and "gravity (0, 0, 9.807) m/s^2" in line, line
    assert shown_numbers([-0.0, 1e-300, -2.5]) == "0, 0, -2.5"
    assert shown_numbers([1e-13, 1.0]) == "0, 1" and shown_numbers([1e-3, 1.0]) == "0.001, 1"


def test_a_base_pose_sets_gravity_and_a_gravity_vector_no_pose():
    tilted = BasePose.from_xyz_rpy([0.1, 0.2, 0.3], [0.0, math.radians(30), 0.0])
    robot = load_robot(robot_path("planar2")).with_mounting(tilted)
    # pitched 30 deg about y, the base x axis points 30 deg below the horizon, (cos 30, 0,
    # -sin 30) in the world, and base z is (sin 30, 0, cos 30): g_base = R^T (0, 0, -g)
    # = (g sin 30, 0, -g cos 30)
    np.testing.assert_allclose(robot.gravity, [STANDARD_GRAVITY * math.sin(math.radians(30)),
                                               0.0,
                                               -STANDARD_GRAVITY * math.cos(math.radians(30))],
                               atol=1e-12)
    assert robot.with_mounting([0.0, 0.0, -9.81]).base_pose is None
    with pytest.raises(InputError, match="rotation matrix"):
        BasePose(rotation=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)))


def write(tmp_path, text: str, name: str = "motion.toml"):
    path = tmp_path / name
    path.write_text(text.format(robot=robot_path("benchtop6")))
    return path


@pytest.mark.slow
@pytest.mark.parametrize("mounting", ["floor", "wall", "base pose"])
def test_every_solved_waypoint_lands_on_its_pose_in_the_world(mounting, tmp_path):
    if mounting == "base pose":  # on a plinth 5 cm high, turned 30 deg, tilted 10 deg
        path = tmp_path / "plinth.toml"
        path.write_text(EXAMPLE.read_text().replace(
            'mounting = "floor"', "base = {xyz = [0.02, -0.03, 0.05], rpy = [10, 0, 30]}").replace(
            '"../robots/benchtop6.urdf"', f'"{robot_path("benchtop6")}"'))
        base = pin.SE3(Rotation.from_euler("xyz", [10, 0, 30], degrees=True).as_matrix(),
                       np.array([0.02, -0.03, 0.05]))
        robot, motion = hdselect.load_case(path)
    else:
        base = BASES[mounting]
        robot, motion = hdselect.load_case(EXAMPLE, mounting=mounting)
    assert np.all(np.isfinite(motion.waypoints))
    kin = FrameKinematics(robot, "tool0")
    for i in range(len(motion.waypoints)):
        reached = base * fk(kin, motion.waypoints[i])
        assert TOLERANCE.holds(*pose_error(reached, written_pose(motion, i))), i
    for line in motion.lines:  # every joint sample on its line, as the file writes it
        start, end = written_pose(motion, line.last - 1), written_pose(motion, line.last)
        for fraction, q in zip(line.fractions, line.q, strict=True):
            turn = pin.log3(start.rotation.T @ end.rotation)
            on_line = pin.SE3(start.rotation @ pin.exp3(fraction * turn),
                              (1 - fraction) * start.translation + fraction * end.translation)
            assert TOLERANCE.holds(*pose_error(base * fk(kin, q), on_line))


def mujoco_benchtop6(base: np.ndarray, payload: hdselect.Payload) -> mujoco.MjModel:
    """MuJoCo's own model of benchtop6.urdf, its base turned by `base` in a z-up world."""
    spec = mujoco.MjSpec.from_file(str(robot_path("benchtop6")))
    spec.compiler.fusestatic = False  # keep tool0 as a body
    spec.option.gravity = [0.0, 0.0, -STANDARD_GRAVITY]
    quaternion = np.zeros(4)
    mujoco.mju_mat2Quat(quaternion, base.flatten())
    spec.worldbody.bodies[0].quat = quaternion
    load = spec.body("tool0").add_body(name="payload")
    load.mass, load.ipos, load.explicitinertial = payload.mass, list(payload.com), True
    load.inertia = [payload.inertia[0][0], payload.inertia[1][1], payload.inertia[2][2]]
    return spec.compile()


@pytest.mark.slow
def test_floor_and_wall_size_the_same_physical_task():
    """The wall's poses are the floor's poses, and its torques MuJoCo's with the robot on a wall.

    hdselect keeps the robot's model in its base frame and turns gravity into it:
    g_base = R^T g_world, R the base's rotation in the world (on the wall, base x up and
    base z along world +x, so g_base = (-g, 0, 0)). The other way round, MuJoCo places the
    robot's base turned by R in its world and keeps gravity g_world = (0, 0, -g). A joint
    torque tau_i = s_i . f_i (the joint axis against the force its body transmits) is a
    scalar, the same in any frame the Newton-Euler recursion is written in; the recursion
    enters gravity as the base's acceleration -g, which in base coordinates is -R^T g_world.
    So along the same joint trajectory both give the same torques, for the same payload.
    And the wall's joint waypoints, placed on the wall by MuJoCo, put the tool on the
    poses the file writes, as the floor's do on the floor: the same task.
    """
    wall_robot, wall = hdselect.load_case(EXAMPLE, mounting="wall")
    floor_robot, floor = hdselect.load_case(EXAMPLE)
    payload = wall_robot.payload
    assert payload is not None and payload.frame == "tool0"
    np.testing.assert_allclose(wall_robot.gravity, WALL.T @ [0, 0, -STANDARD_GRAVITY])
    assert np.abs(wall.waypoints - floor.waypoints).max() > 0.5  # other joints, same task
    for motion, base in ((floor, np.eye(3)), (wall, WALL)):
        model = mujoco_benchtop6(base, payload)
        data = mujoco.MjData(model)
        for i, q in enumerate(motion.waypoints):
            data.qpos[:] = q
            mujoco.mj_kinematics(model, data)
            tool = model.body("tool0").id
            reached = pin.SE3(data.xmat[tool].reshape(3, 3), data.xpos[tool].copy())
            assert TOLERANCE.holds(*pose_error(reached, written_pose(motion, i))), i
    trajectory = hdselect.plan(wall_robot, wall)
    tau = inverse_dynamics(wall_robot, trajectory.q, trajectory.qd, trajectory.qdd)
    model = mujoco_benchtop6(WALL, payload)
    data = mujoco.MjData(model)
    for k in range(0, len(trajectory.t), 23):
        data.qpos[:], data.qvel[:], data.qacc[:] = (trajectory.q[k], trajectory.qd[k],
                                                    trajectory.qdd[k])
        mujoco.mj_inverse(model, data)
        np.testing.assert_allclose(data.qfrc_inverse, tau[k], rtol=1e-9, atol=1e-9)
    on_the_floor = inverse_dynamics(floor_robot, trajectory.q, trajectory.qd, trajectory.qdd)
    assert np.abs(on_the_floor - tau).max() > 1.0  # the mounting matters to these torques


def deviation_here(start: pin.SE3, end: pin.SE3, poses: list[pin.SE3]):
    """Each pose's distance from the segment (its projection) and angle from the nearest of
    1,001 orientations of the line."""
    step = end.translation - start.translation
    along = [np.clip((p.translation - start.translation) @ step / (step @ step), 0, 1)
             for p in poses]
    distance = [np.linalg.norm(p.translation - start.translation - f * step)
                for p, f in zip(poses, along, strict=True)]
    turn = Rotation.from_matrix(start.rotation.T @ end.rotation).as_rotvec()
    arc = Rotation.from_matrix(start.rotation) * Rotation.from_rotvec(
        np.linspace(0.0, 1.0, 1001)[:, None] * turn)
    angle = [(arc.inv() * Rotation.from_matrix(p.rotation)).magnitude().min() for p in poses]
    return np.array(distance), np.array(angle)


@pytest.mark.slow
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_lines_hold_at_every_planned_sample(mounting):
    robot, motion = hdselect.load_case(EXAMPLE, mounting=mounting)
    planned = plan_motion(robot, motion)
    trajectory, solved = planned.trajectory, planned.motion
    kin = FrameKinematics(robot, "tool0")
    rest = [i for i in range(len(solved.waypoints)) if solved.dwells[i] > 0]
    for i in rest:  # the planner's waypoint times: the arm rests there on its waypoint
        k = int(math.ceil(trajectory.waypoint_times[i] / trajectory.dt))
        np.testing.assert_allclose(trajectory.q[k], solved.waypoints[i], atol=1e-9)
    base = BASES[mounting]
    assert [d.last for d in planned.lines] == [2, 3, 5, 6]
    for found in planned.lines:
        leave = trajectory.waypoint_times[found.last - 1] + solved.dwells[found.last - 1]
        inside = (trajectory.t >= leave) & (trajectory.t <= trajectory.waypoint_times[found.last])
        assert np.array_equal(np.flatnonzero(inside), found.index) and inside.sum() > 100
        poses = [base * fk(kin, q) for q in trajectory.q[inside]]
        distance, angle = deviation_here(written_pose(solved, found.last - 1),
                                                written_pose(solved, found.last), poses)
        assert distance.max() <= TOLERANCE.position and angle.max() <= TOLERANCE.orientation
        np.testing.assert_allclose(found.position, distance, atol=1e-12)
        np.testing.assert_allclose(found.orientation, angle, atol=1e-6)


HUNG = BasePose.from_xyz_rpy([0.0, 0.0, 0.44], [math.pi, 0.0, 0.0])
"""Hung from a ceiling 0.44 m above the floor the poses are written on (issue 27)."""
PLINTH = BasePose.from_xyz_rpy([0.02, -0.03, 0.05], [math.radians(10), 0.0, math.radians(30)])


@pytest.mark.slow
@pytest.mark.parametrize("mounting", ["floor", "wall", HUNG, PLINTH],
                         ids=["floor", "wall", "ceiling", "base pose"])
def test_lines_keep_the_dense_grids_cycle_on_every_mounting(mounting):
    """Where a free move meets a line the spline turns within the line's close samples:
    the planner's cycle stays within 0.1 % of TOPPRA's on the dense grid (every knot a
    gridpoint), with no uniform slow-down to report. Before the fix, the ceiling's pieces
    were slowed 1.2 to 1.5 % each, silently (4.796 s for 4.761 s)."""
    from helpers.motions import dense_toppra_cycle

    robot, motion = hdselect.load_case(EXAMPLE, mounting=mounting)
    planned = plan_motion(robot, motion)
    trajectory, solved = planned.trajectory, planned.motion
    assert trajectory.notes == ()
    assert trajectory.duration == pytest.approx(dense_toppra_cycle(robot, solved), rel=1e-3)
    assert np.all(np.abs(trajectory.qd) <= solved.velocity_limit * (1 + 1e-6))
    assert np.all(np.abs(trajectory.qdd) <= solved.acceleration_limit * (1 + 1e-6))


@pytest.mark.slow
def test_a_slow_down_beyond_the_tolerance_is_reported(monkeypatch, tmp_path, capsys):
    """Forced: a planner that solves a coarse grid without its knots once, never refining,
    must slow the pieces down; each such piece is named with its joint and factor in the
    trajectory's notes, the sizing's warnings, the JSON and on the terminal, once."""
    import json

    import hdselect.motion.planning.toppra as toppra

    def coarse(dense, *, full=False):
        return toppra.with_gridpoints(dense, np.linspace(0.0, 1.0, 41))

    monkeypatch.setattr(toppra, "first_grid", coarse)
    monkeypatch.setattr(toppra, "REFINE_ROUNDS", 1)
    robot, motion = hdselect.load_case(EXAMPLE, mounting=HUNG)
    trajectory = plan_motion(robot, motion).trajectory
    assert trajectory.notes, "nothing reported"
    pieces = {(0, 2), (2, 5), (5, 7)}
    for note in trajectory.notes:
        found = re.fullmatch(r"toppra slowed the path from waypoint\[(\d)\] to waypoint\[(\d)\] "
                             r"down ([\d.]+) times: joint '(\w+)' broke its (velocity|acceleration)"
                             r" limit between gridpoints after refining the grid; the cycle is "
                             r"longer than the time-optimal one", note)
        assert found, note
        assert (int(found[1]), int(found[2])) in pieces and found[4] in robot.joint_names
        assert float(found[3]) > 1.001
    result = hdselect.size(robot, motion)
    assert result.trajectory.notes
    assert [w for w in result.warnings if w.startswith("cycle: toppra")] == [
        f"cycle: {note}" for note in result.trajectory.notes]
    path = tmp_path / "hung.toml"
    path.write_text(EXAMPLE.read_text().replace(
        'mounting = "floor"', "base = {xyz = [0, 0, 0.44], rpy = [180, 0, 0]}").replace(
        '"../robots/benchtop6.urdf"', f'"{robot_path("benchtop6")}"'))
    assert main(["size", str(path), "--json", str(tmp_path / "hung.json")]) == 0
    capsys.readouterr()
    document = json.loads((tmp_path / "hung.json").read_text())
    noted = [w for w in document["warnings"] if w.startswith("cycle: toppra")]
    assert noted and all(" waypoint[" in w and " times: joint '" in w for w in noted)
    assert main(["size", str(path)]) == 0
    out, err = capsys.readouterr()
    shown = " ".join((out + err).split())
    for note in noted:
        assert shown.count(note.removeprefix("cycle: ")) == 1, note


@pytest.mark.slow
def test_a_solved_motion_is_an_ordinary_motion(tmp_path):
    path = write(tmp_path, SHORT)
    robot = load_robot(robot_path("benchtop6"))
    read = load_motion(path, robot)
    assert np.isnan(read.waypoints).all() and read.solution is None and read.tool is not None
    solved = solve_motion(robot, read)
    assert np.isfinite(solved.waypoints).all() and solved.solution is not None
    assert solve_motion(robot, solved) is solved  # solved once per robot and mounting
    np.testing.assert_array_equal(hdselect.plan(robot, read).q, hdselect.plan(robot, solved).q)
    wall = robot.with_mounting("wall")
    assert solve_motion(wall, solved).solution.base == BasePose(
        rotation=tuple(map(tuple, WALL)))  # another mounting: solved again
    result = hdselect.size(robot, read)
    assert np.isfinite(result.motion.waypoints).all()


def test_joint_and_pose_waypoints_mix(tmp_path):
    text = SHORT.replace("[[waypoint]]\npose = {{xyz = [0.26, 0.0, 0.30], rpy = [180, 0, -90]}}",
                         "[[waypoint]]\nq = [0, -90, 90, -90, 90, 0]", 1)
    robot, motion = hdselect.load_case(write(tmp_path, text))
    np.testing.assert_allclose(motion.waypoints[0], np.radians([0, -90, 90, -90, 90, 0]))
    assert motion.warnings == ()  # on the floor, joint waypoints stay where they were
    robot, motion = hdselect.load_case(write(tmp_path, text), mounting="wall")
    assert motion.warnings == (
        "waypoint 0 (joint positions) keeps its joint angles on the wall mounting: the task "
        "moved with the robot; write them as tool poses (pose = {xyz, rpy}) to keep the task "
        "where it is in the world",)
    on_the_floor = solve_motion(robot.with_mounting("floor"), motion)
    assert on_the_floor.warnings == ()  # the wall's note went with the wall


@pytest.mark.slow
def test_joint_waypoints_on_the_wall_print_a_note(capsys):
    joint_motion = REPO / "trajectories" / "benchtop6_pick_place.toml"
    assert main(["plan", str(joint_motion), "--mounting", "wall", "--out", "-"]) == 0
    err = capsys.readouterr().err
    assert "the joint waypoints keep their joint angles on the wall mounting: the task moved " \
        "with the robot" in " ".join(err.split())
    assert main(["plan", str(joint_motion), "--out", "-"]) == 0
    assert "moved with the robot" not in capsys.readouterr().err


@pytest.mark.slow
def test_plan_writes_the_solved_waypoints_and_the_line_errors(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    out, solved, errors = (tmp_path / name for name in ("out.csv", "solved.csv", "lines.csv"))
    assert main(["plan", str(EXAMPLE), "--mounting", "wall", "--out", str(out), "--waypoints",
                 str(solved), "--line-errors", str(errors)]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "tool poses: 8 waypoints solved for 'tool0' on the wall mounting" in text
    assert "straight lines: 4, through" in text
    robot, motion = hdselect.load_case(EXAMPLE, mounting="wall")
    rows = np.genfromtxt(solved, delimiter=",", names=True)
    assert rows.dtype.names == ("waypoint", "fraction", *(f"q_{n}" for n in robot.joint_names),
                                "position_error", "orientation_error")
    assert np.all(np.isfinite(rows.view((float, len(rows.dtype.names)))))
    at_waypoints = rows[rows["fraction"] == 1.0]
    np.testing.assert_array_equal(at_waypoints["waypoint"], np.arange(8))
    kin = FrameKinematics(robot, "tool0")
    for row in at_waypoints:  # the errors written are those of the joints written
        q = np.array([row[f"q_{n}"] for n in robot.joint_names])
        error = pose_error(BASES["wall"] * fk(kin, q), written_pose(motion, int(row["waypoint"])))
        assert error[0] == pytest.approx(row["position_error"], abs=1e-9)
        assert error[1] == pytest.approx(row["orientation_error"], abs=1e-9)
    samples = rows[rows["fraction"] < 1.0]
    assert set(samples["waypoint"]) == {2, 3, 5, 6} and len(samples) > 20
    assert samples["position_error"].max() <= TOLERANCE.position
    trajectory = np.genfromtxt(out, delimiter=",", names=True)
    assert len(trajectory.dtype.names) == 1 + 4 * 6  # as for any motion
    lines = np.loadtxt(errors, delimiter=",", skiprows=1)
    assert errors.read_text().split("\n", 1)[0] == "t,line,distance,angle,fraction"
    assert set(lines[:, 1]) == {2, 3, 5, 6} and len(lines) > 400
    assert lines[:, 2].max() <= TOLERANCE.position and lines[:, 3].max() <= TOLERANCE.orientation
    np.testing.assert_allclose(lines[:, 0], trajectory["t"][np.isin(trajectory["t"], lines[:, 0])])


@pytest.mark.slow
def test_init_writes_a_tool_pose_starter_that_solves_back_and_sizes(tmp_path, capsys):
    for name in ("benchtop6", "planar2", "scara", "pan_tilt", "index_table"):
        out = tmp_path / f"{name}.toml"
        assert main(["init", str(robot_path(name)), "--tool-poses", "--out", str(out)]) == 0
        robot, motion = hdselect.load_case(out)
        near = motion.tool.poses[0].near
        np.testing.assert_allclose(motion.waypoints[0], [near[n] for n in robot.joint_names],
                                   atol=1e-3)  # the poses solve back to the configuration
        np.testing.assert_allclose(motion.waypoints[2], motion.waypoints[0], atol=1e-3)
        assert main(["size", str(out)]) in (0, 1)
    capsys.readouterr()


@pytest.mark.slow
@pytest.mark.parametrize("arm", ["UR5", "Panda", "Kinova", "SO-101", "TIAGo arm"])
def test_init_tool_poses_for_real_arms_plan_and_size(arm, tmp_path, capsys):
    """6 joints, 7 joints and a finger, continuous joints, a 5-joint arm, 12 joints."""
    out = tmp_path / "starter.toml"
    assert main(["init", str(example_robots() / EXAMPLE_ARMS[arm]), "--tool-poses", "--out",
                 str(out)]) == 0
    robot, motion = hdselect.load_case(out)
    near = motion.tool.poses[0].near
    np.testing.assert_allclose(motion.waypoints[0], [near[n] for n in robot.joint_names],
                               atol=1e-3)
    assert main(["size", str(out)]) in (0, 1)  # a big arm's shoulder may fit no unit
    capsys.readouterr()


BAD = [
    ("xyz = [0.28, -0.20, 0.16]", "xyz = [0.9, -0.20, 0.16]",
     "waypoint[1].pose: the tool frame 'tool0' cannot reach this pose on the floor mounting: the "
     "closest it comes is"),
    ("dwell = 0.2\n\n[[waypoint]]\npose = {{xyz = [0.28",
     "dwell = 0.2\n\n[[waypoint]]\nq = [0, 0, 0, 0, 0, 0]\npose = {{xyz = [0.28",
     "waypoint[1].q: give either q (joint positions) or pose"),
    ("rpy = [180, 0, -90]}}", "rpy = [180, 0]}}", "waypoint[0].pose.rpy: expected a list of 3"),
    ("pose = {{xyz = [0.26, 0.0, 0.30], rpy = [180, 0, -90]}}",
     "pose = {{xyz = [0.26, 0.0, 0.30], rpy = [180, 0, -90], axis = [0, 0, -1]}}",
     "waypoint[0].pose.axis: give one of rpy (a full pose), axis (the approach axis, roll "
     "free) or yaw (tilt free), not both rpy and axis"),
    ('"toppra"\nangle_unit = "deg"\n\n[limits]', '"ruckig"\nangle_unit = "deg"\n\n[limits]\n'
     "jerk = 4000", "waypoint[2].line: a straight line needs planner \"toppra\" (\"ruckig\" moves"),
    ("line = true", "line = true\nnear = {{elbow = 90}}", "waypoint[2].near: a line decides"),
    ('angle_unit = "deg"', 'angle_unit = "deg"\n[tool]\nframe = "tool9"',
     "tool.frame: unknown frame 'tool9'; the robot's links are: base_link, shoulder_link"),
    ('angle_unit = "deg"', 'angle_unit = "deg"\n[tool]\nposition_tolerance = 0.5',
     "tool.position_tolerance: must be a position tolerance between 1e-09 and 0.01 m"),
    ('angle_unit = "deg"', 'angle_unit = "deg"\nmounting = [0, 0, -9.81]',
     "mounting: the tool poses are in the world, and the mounting given as a gravity vector"),
    ('angle_unit = "deg"', 'angle_unit = "deg"\nmounting = "wall"\nbase = {{xyz = [0, 0, 0]}}',
     "base: give either mounting or base"),
    ("dwell = 0.2\n\n[[waypoint]]\npose = {{xyz = [0.28",
     "dwell = 0.2\nline = true\n\n[[waypoint]]\npose = {{xyz = [0.28",
     "waypoint[0].line: the first waypoint has no waypoint before it"),
    ("line = true", "line = true\nreconfigure = 1", "waypoint[2].reconfigure: expected true or "
     "false"),
    ("dwell = 0.2\n", "near = {{elbow = 9000}}\ndwell = 0.2\n",  # clipped unseen, before
     "waypoint[0].near.elbow: 9000 deg is outside the limits of joint 'elbow' [-160, 160] deg"),
]


@pytest.mark.slow
@pytest.mark.parametrize(("old", "new", "message"), BAD, ids=[m[:30] for _, _, m in BAD])
def test_bad_tool_pose_input_is_one_line_naming_the_field(old, new, message, tmp_path, capsys):
    text = SHORT.replace(old, new, 1)
    assert text != SHORT
    path = write(tmp_path, text)
    assert main(["plan", str(path), "--out", str(tmp_path / "out.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: {message}" in err
    assert not (tmp_path / "out.csv").exists()


def test_unreachable_pose_names_the_limit_in_the_way(tmp_path):
    # shoulder_pan within +-10 deg: home, 6 cm beside the pan axis's plane, needs -13 deg
    urdf = robot_path("benchtop6").read_text().replace(
        'lower="-2.9670597" upper="2.9670597" effort="25.0"',
        'lower="-0.17453293" upper="0.17453293" effort="25.0"')
    (tmp_path / "narrow.urdf").write_text(urdf)
    path = tmp_path / "motion.toml"
    path.write_text(SHORT.format(robot=tmp_path / "narrow.urdf"))
    with pytest.raises(InputError) as caught:
        hdselect.load_case(path)
    assert caught.value.field == "waypoint[0].pose"
    message = str(caught.value)
    assert "cannot reach this pose on the floor mounting: the closest it comes is" in message
    assert message.endswith("in the way: the lower limit of shoulder_pan (-10 deg)")


@pytest.mark.slow
def test_line_through_a_singularity_names_where(tmp_path):
    # straight down from above the pick to below the base: the arm folds onto itself
    text = SHORT.replace("xyz = [0.28, -0.20, 0.08]", "xyz = [0.28, -0.20, -0.6]")
    with pytest.raises(InputError) as caught:
        hdselect.load_case(write(tmp_path, text))
    assert caught.value.field == "waypoint[2].line"
    message = str(caught.value)
    assert "the straight line from waypoint[1] stops" in message and "% of the way" in message
    assert "in the world" in message
    assert any(word in message for word in ("singularity", "in the way", "reach"))


ELBOW_UP = SHORT.replace("dwell = 0.2\n", "near = {{elbow = 80}}\ndwell = 0.2\n", 1)
"""`SHORT` with its first pose's branch chosen: elbow bent up."""


def test_a_change_of_branch_is_refused_unless_allowed(tmp_path):
    """The same pose twice, the second with a hint that bends the elbow the other way."""
    flip = ELBOW_UP.replace(
        "[[waypoint]]\npose = {{xyz = [0.28, -0.20, 0.08], rpy = [180, 0, -135]}}\nline = true",
        "[[waypoint]]\npose = {{xyz = [0.28, -0.20, 0.16], rpy = [180, 0, -135]}}\n"
        "near = {{shoulder_lift = -10, elbow = -97, wrist_1 = 110}}")
    with pytest.raises(InputError) as caught:
        hdselect.load_case(write(tmp_path, flip))
    assert caught.value.field == "waypoint[2]"
    message = str(caught.value)
    assert "the arm changes branch between waypoint[1] and waypoint[2]" in message
    assert "elbow indicator changes sign" in message
    assert message.endswith("waypoint[2]'s near chose the other branch: change it, or allow the "
                            "change with reconfigure = true")
    allowed = flip.replace("wrist_1 = 110}}", "wrist_1 = 110}}\nreconfigure = true")
    robot, motion = hdselect.load_case(write(tmp_path, allowed))
    assert motion.waypoints[2][2] < 0 < motion.waypoints[1][2]  # the elbow bent the other way
    assert any("allowed by waypoint[2].reconfigure" in w for w in motion.warnings)


def test_a_joint_waypoint_on_another_branch_than_the_pose_before_is_named(tmp_path):
    text = ELBOW_UP.replace(
        "[[waypoint]]\npose = {{xyz = [0.28, -0.20, 0.16], rpy = [180, 0, -135]}}",
        "[[waypoint]]\nq = [-13, -20, -80, 120, -90, -13]", 1).replace(
        "line = true\n", "")
    with pytest.raises(InputError) as caught:
        hdselect.load_case(write(tmp_path, text))
    assert caught.value.field == "waypoint[1]"
    assert "waypoint[0]'s pose was solved on another branch than waypoint[1]'s joints: give " \
        "waypoint[0] a hint such as near = {" in str(caught.value)


def test_the_first_pose_takes_the_branch_that_carries_the_motion_through(tmp_path):
    """Without a hint, a first pose whose first solution leads into a change of branch is
    solved on another of its branches: here the second pose forces the elbow down."""
    text = SHORT.replace(
        "[[waypoint]]\npose = {{xyz = [0.28, -0.20, 0.08], rpy = [180, 0, -135]}}\nline = true",
        "[[waypoint]]\npose = {{xyz = [0.28, -0.20, 0.16], rpy = [180, 0, -135]}}\n"
        "near = {{shoulder_lift = -10, elbow = -97, wrist_1 = 110}}")
    robot, motion = hdselect.load_case(write(tmp_path, text))
    assert np.all(motion.waypoints[:, 2] < 0)  # every waypoint with the elbow down
    kin = FrameKinematics(robot, "tool0")
    assert TOLERANCE.holds(*pose_error(fk(kin, motion.waypoints[0]), written_pose(motion, 0)))


@pytest.mark.slow
@pytest.mark.parametrize("command", [
    f"size {EXAMPLE}", f"size {EXAMPLE} --mounting wall", f"plan {EXAMPLE} --out -",
    f"fastest {EXAMPLE} --mounting wall"])
def test_the_example_runs_on_the_floor_and_on_the_wall(command, capsys):
    assert main(shlex.split(command)) in (0, 1)
    assert capsys.readouterr().err == ""


DOC = REPO / "docs" / "tool-poses.md"


@pytest.mark.slow
@pytest.mark.parametrize("example", [e for e in examples(DOC) if e.shown is not None],
                         ids=lambda e: e.source.splitlines()[0][:50])
def test_the_docs_examples_print_what_tool_poses_md_shows(example, tmp_path):
    """docs/tool-poses.md, run as tests/docs_examples.py runs every page (outputs in out/)."""
    printed = run(example, scratch(tmp_path))
    assert printed is not None and matches(printed, example.shown), printed
    for word in example.source.split():
        if word.startswith("out/"):
            assert (tmp_path / word).stat().st_size > 0
