"""Payload events in a sizing: a part carried between its attach and its release only.

Oracles: the index table by hand (tau = J qdd with J = J_table + m r^2 + I_zz of the part
where it is carried, the catalog's cubic mean and L50 formulas written out again), a
two-task mix built by hand from the loaded and the unloaded samples, and per-sample
`pinocchio.rnea` of the arm with and without the part written into the model by hand.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from hdselect import load_case, load_catalog, size
from hdselect.motion.planning.trajectory import trajectory
from hdselect.sizing.core import size_tasks
from hdselect.sizing.problem import resolve
from hdselect.sizing.tasks import Task, by_state, pooled
from hdselect.sizing.torques import DirectTorques
from helpers import REPO, run
from helpers.dynamics import J_TABLE, pin_config

RPM = 60 / (2 * np.pi)  # rpm per rad/s
PART_MASS, PART_R, PART_IZZ = 1.2, 0.11, 3e-4  # kg, m, kg m^2 (about its own centre)

INDEX_PICK = f"""
robot = "{(REPO / 'robots' / 'index_table.urdf').as_posix()}"
planner = "ruckig"
angle_unit = "deg"
dt = 0.001

[payloads.part]
mass = {PART_MASS}
com = [{PART_R}, 0.0, 0.04]
inertia = [[2e-4, 0.0, 0.0], [0.0, 2e-4, 0.0], [0.0, 0.0, {PART_IZZ}]]
frame = "disk"

[limits]
velocity = 270
acceleration = 2000
jerk = 30000

[safety]
stop_time = 0.1

[requirements]
life_hours = 20000

[[waypoint]]
q = [0]
dwell = 0.6

[[waypoint]]
q = [90]
dwell = 0.5
attach = "part"

[[waypoint]]
q = [180]
dwell = 0.3

[[waypoint]]
q = [270]
dwell = 0.4
release = "part"

[[waypoint]]
q = [360]
"""


def index_pick(folder: Path, text: str = INDEX_PICK) -> Path:
    path = folder / "index_pick.toml"
    path.write_text(text)
    return path


def test_index_table_part_carried_between_the_events_by_hand(tmp_path):
    """The pooled cubic-mean torque and L50 of every unit, by hand, to 1e-9."""
    result = size(None, index_pick(tmp_path))
    motion, traj = result.motion, result.trajectory
    qd, qdd, dt = traj.qd[:, 0], traj.qdd[:, 0], traj.dt
    # the part rides from the arrival at waypoint[1] to the end of waypoint[3]'s dwell
    t = np.minimum(traj.t, traj.duration)
    start = traj.waypoint_times[1]
    end = traj.waypoint_times[3] + motion.dwells[3]
    loaded = (t >= start - 1e-9) & (t <= end + 1e-9)
    assert 0 < loaded.sum() < len(t) - 100
    inertia = J_TABLE + loaded * (PART_MASS * PART_R**2 + PART_IZZ)
    tau = inertia * qdd
    moving = (np.abs(qd) > 1e-9) | (np.abs(qdd) > 1e-9)
    (joint,) = result.joints
    for candidate in joint.candidates:
        unit, rules = candidate.unit, candidate.unit.rules
        n = unit.ratio * np.abs(qd) * RPM
        t_av = np.cbrt(np.sum(n[moving] * np.abs(tau[moving]) ** 3 * dt)
                       / np.sum(n[moving] * dt))
        n_av = np.sum(n[moving] * dt) / (moving.sum() * dt)
        life = (rules.rated_l50_hours * (rules.rated_input_speed / n_av)
                * (unit.rated_torque / t_av) ** 3)
        assert candidate.checks["mean"].value == pytest.approx(t_av, rel=1e-9)
        assert candidate.life_hours == pytest.approx(life, rel=1e-9)
        assert candidate.checks["peak"].value == pytest.approx(np.abs(tau[moving]).max(),
                                                               rel=1e-9)
    # carrying the part all cycle gives more: the events are what lowers the mean
    always = size(None, index_pick(tmp_path, INDEX_PICK.replace('attach = "part"', "")
                                   .replace('release = "part"', "")))
    for a, b in zip(joint.candidates, always.joints[0].candidates, strict=True):
        assert a.checks["mean"].value < b.checks["mean"].value
        assert a.life_hours > b.life_hours


def test_index_table_events_equal_a_two_task_mix_of_the_halves(tmp_path):
    """The loaded and unloaded samples as two tasks, shares by their sample counts."""
    problem = resolve(None, index_pick(tmp_path))
    (task,) = problem.tasks
    traj, units = task.trajectory, load_catalog()
    events = size_tasks(problem.tasks, units, problem.options)
    loaded = task.carried.mask[:, 0]
    part = task.carried.parts[0]
    halves = []
    for rows, robot in ((loaded, task.robot.with_parts([part])), (~loaded, task.robot)):
        half = trajectory(task.motion, len(traj.t[rows]) * traj.dt, traj.t[rows].copy(),
                          traj.q[rows].copy(), traj.qd[rows].copy(), traj.qdd[rows].copy(),
                          dt=traj.dt)
        halves.append(Task(robot, half, float(rows.sum()) / len(rows), task.motion))
    mix = size_tasks(halves, units, problem.options)
    for a, b in zip(events.joints[0].candidates, mix.joints[0].candidates, strict=True):
        assert a.unit.id == b.unit.id
        for name in ("mean", "peak", "momentary", "speed", "life"):
            assert a.checks[name].value == pytest.approx(b.checks[name].value, rel=1e-9)
        assert a.life_hours == pytest.approx(b.life_hours, rel=1e-9)
    assert events.joints[0].selected.unit.id == mix.joints[0].selected.unit.id


SIX_AXIS_EVENTS = [("q = [-45, -35, 105, -160, 90, 0]      # pick: close the gripper\ndwell = 1.5",
                    "q = [-45, -35, 105, -160, 90, 0]\ndwell = 1.5\nattach = \"part\""),
                   ("q = [45, -35, 105, -160, 90, 90]      # place: open the gripper\ndwell = 1.5",
                    "q = [45, -35, 105, -160, 90, 90]\ndwell = 1.5\nrelease = \"part\"")]


def six_axis(folder: Path) -> Path:
    """benchtop6's pick-and-place with a 0.4 kg part between its pick and its place."""
    text = (REPO / "trajectories" / "benchtop6_pick_place.toml").read_text()
    text = text.replace('robot = "../robots/', f'robot = "{(REPO / "robots").as_posix()}/')
    for old, new in SIX_AXIS_EVENTS:
        if old in text:
            text = text.replace(old, new)
    if "[payloads.part]" not in text:
        text = text.replace("[limits]", "[payloads.part]\nmass = 0.4\ncom = [0.0, 0.0, 0.06]\n"
                            'frame = "tool0"\n\n[limits]')
    path = folder / "six.toml"
    path.write_text(text)
    return path


def test_six_axis_torques_equal_rnea_with_the_part_where_carried(tmp_path):
    problem = resolve(None, six_axis(tmp_path))
    (task,) = problem.tasks
    assert task.carried is not None and [p.name for p in task.carried.parts] == ["part"]
    samples = pooled(problem.tasks)
    model = DirectTorques(problem.tasks, samples, problem.options.stop_time)
    traj = task.trajectory
    # the models by hand: the file's robot, the payload (and the part) appended at tool0
    bare = load_case(six_axis(tmp_path))[0].with_payload(None).model
    models = []
    for bodies in ((task.robot.payload,), (task.robot.payload, task.carried.parts[0])):
        built = pin.Model(bare)
        frame = built.frames[built.getFrameId("tool0")]
        for body in bodies:
            built.appendBodyToJoint(frame.parentJoint, pin.Inertia(
                body.mass, np.array(body.com), np.array(body.inertia)), frame.placement)
        models.append(built)
    loaded = task.carried.mask[:, 0]
    rows = np.unique(np.r_[np.flatnonzero(loaded)[::97], np.flatnonzero(~loaded)[::97],
                           np.flatnonzero(np.diff(loaded)), np.flatnonzero(np.diff(loaded)) + 1])
    for joint in problem.robot.sized_joints:
        tau, _ = model.torques(joint, {})
        j = problem.robot.joint_index(joint)
        for k in rows:
            built = models[int(loaded[k])]
            want = pin.rnea(built, built.createData(), pin_config(built, traj.q[k]),
                            traj.qd[k], traj.qdd[k])[j]
            assert tau[k] == pytest.approx(want, rel=1e-9, abs=1e-9), (joint, k, loaded[k])
    # the states in the order of their first sample: unloaded from the start, then loaded
    assert [len(robot.parts) for robot, _ in by_state(task, task.robot)] == [0, 1]


def test_a_motion_without_events_sizes_as_before(tmp_path):
    """No events: the task carries nothing by events and sizes bit for bit as with None."""
    path = REPO / "trajectories" / "index_table_indexing.toml"
    problem = resolve(None, path)
    assert problem.tasks[0].carried is None
    plain = size_tasks(problem.tasks, load_catalog(), problem.options)
    again = size_tasks([replace(problem.tasks[0], carried=None)], load_catalog(),
                       problem.options)
    for a, b in zip(plain.joints[0].candidates, again.joints[0].candidates, strict=True):
        assert a.checks["mean"].value == b.checks["mean"].value
        assert a.life_hours == b.life_hours


def test_events_carrying_a_part_all_cycle_equal_the_part_on_the_robot(tmp_path):
    """Attached on arrival at the first waypoint, released after the last one's dwell."""
    text = (INDEX_PICK.replace('attach = "part"', "").replace('release = "part"', "")
            .replace("[[waypoint]]\nq = [0]\ndwell = 0.6", "[[waypoint]]\nq = [0]\ndwell = 0.6"
                     '\nattach = "part"')
            .replace("[[waypoint]]\nq = [360]", '[[waypoint]]\nq = [360]\nrelease = "part"'))
    events = resolve(None, index_pick(tmp_path, text))
    assert events.tasks[0].carried.mask.all()
    whole = resolve(None, index_pick(tmp_path, INDEX_PICK.replace('attach = "part"', "")
                                     .replace('release = "part"', "")))
    assert whole.tasks[0].carried is None and whole.tasks[0].robot.parts
    a = size_tasks(events.tasks, load_catalog(), events.options)
    b = size_tasks(whole.tasks, load_catalog(), whole.options)
    for x, y in zip(a.joints[0].candidates, b.joints[0].candidates, strict=True):
        assert x.checks["mean"].value == y.checks["mean"].value  # bit for bit
        assert x.life_hours == y.life_hours


# --- bad input, through the command line ---------------------------------------------------

LOG_MOTION = """robot = "{robot}"
planner = "samples"
angle_unit = "deg"
dt = 0.002

[payloads.part]
mass = 0.5
frame = "{frame}"

[samples]
file = "{log}"
{extra}
"""


def _refused(capsys, path: Path, field: str, words: str) -> None:
    status, out, err = run(capsys, "size", path)
    lines = err.strip().splitlines()
    assert status == 2 and out == "" and len(lines) == 1, err
    assert lines[0].startswith("hdselect: error: ") and field in lines[0] and words in lines[0]


@pytest.mark.parametrize(("old", "new", "field", "words"), [
    ('attach = "part"', 'attach = "bolt"', "waypoint[1].attach", "unknown part 'bolt'"),
    ('release = "part"', 'attach = "part"', "waypoint[1].attach", "never released"),
    ("dwell = 0.3", 'dwell = 0.3\nattach = "part"', "waypoint[2].attach", "attached again"),
    ('attach = "part"', "attach = 3", "waypoint[1].attach", "a part's name"),
    ("[payloads.part]", "[payloads.part]\nspin = 1", "payloads.part.spin", "unknown key"),
    (f"mass = {PART_MASS}", "mass = -1", "payloads.part.mass", ""),
    ('frame = "disk"', 'frame = "nowhere"', "payloads.part.frame", "unknown frame"),
    ("[limits]", "[[event]]\nt = 1.0\nattach = \"part\"\n\n[limits]", "event", "log"),
])
def test_bad_events_of_a_waypoint_motion_are_one_line(tmp_path, capsys, old, new, field, words):
    assert old in INDEX_PICK
    _refused(capsys, index_pick(tmp_path, INDEX_PICK.replace(old, new, 1)), field, words)


@pytest.mark.parametrize(("extra", "field", "words"), [
    ("[[event]]\nt = 99.0\nattach = \"part\"\n[[event]]\nt = 1.0\nrelease = \"part\"",
     "event[0].t", "outside the log"),
    ("[[event]]\nt = nan\nattach = \"part\"\n[[event]]\nt = 1.0\nrelease = \"part\"",
     "event[0].t", "finite"),
    ("[[event]]\nt = 0.5\nattach = \"part\"\n[[event]]\nt = 1.0\nattach = \"part\"",
     "event[0].t", "never released"),
    ("[[event]]\nt = 0.5\nattach = \"part\"\n[[event]]\nt = 1.0\nattach = \"part\"\n"
     "[[event]]\nt = 1.5\nrelease = \"part\"", "event[1].t", "attached again"),
    ("[[event]]\nt = 0.5\nattach = \"part\"\n[[event]]\nt = 0.5\nrelease = \"part\"",
     "event[1].t", "same time"),
    ("[[event]]\nt = 0.5\nattach = \"bolt\"", "event[0].attach", "unknown part"),
    ("[[event]]\nt = 0.5", "event[0].attach", "one of attach or release"),
    ("[[event]]\nt = 0.5\nattach = \"part\"\nrelease = \"part\"", "event[0].attach",
     "one of attach or release"),
    ("[[waypoint]]\nq = [0, 0]\nattach = \"part\"", "waypoint", "samples"),
])
def test_bad_events_of_a_log_are_one_line(tmp_path, capsys, extra, field, words):
    text = LOG_MOTION.format(robot=(REPO / "robots" / "pan_tilt.urdf").as_posix(),
                             log=(REPO / "trajectories" / "logs" / "pan_tilt_log.csv").as_posix(),
                             frame="laser", extra=extra)
    path = tmp_path / "logged.toml"
    path.write_text(text)
    _refused(capsys, path, field, words)


def test_a_log_event_maps_to_the_samples_at_its_time(tmp_path):
    """Events by time: the samples from the attach time to the release time carry it."""
    log = REPO / "trajectories" / "logs" / "pan_tilt_log.csv"
    text = LOG_MOTION.format(robot=(REPO / "robots" / "pan_tilt.urdf").as_posix(),
                             log=log.as_posix(), frame="laser",
                             extra="[[event]]\nt = 1.5\nrelease = \"part\"\n"
                                   "[[event]]\nt = 0.5\nattach = \"part\"")
    path = tmp_path / "logged.toml"
    path.write_text(text)
    problem = resolve(None, path)
    (task,) = problem.tasks
    first = float(np.loadtxt(log, delimiter=",", skiprows=1, max_rows=1)[0])
    t = task.trajectory.t
    want = (t >= 0.5 - first - 1e-9) & (t <= 1.5 - first + 1e-9)
    np.testing.assert_array_equal(task.carried.mask[:, 0], want)
    assert task.carried.events == ((pytest.approx(0.5 - first), "part", True),
                                   (pytest.approx(1.5 - first), "part", False))
