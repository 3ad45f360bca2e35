"""Logs from ROS bags: a bag of the samples a CSV log holds sizes exactly as that log.

The bags are written here with the rosbags package's own writers (rosbag2 in SQLite3
and MCAP, ROS 1) from the shipped log and from a planned motion's samples.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.motion.motionfile import load_motion
from helpers import run
from helpers.bags import EPOCH_NS, JOINT_STATE, KINDS, TRAJECTORY, joint_states, trajectory
from helpers.bags import write_bag as write
from helpers.options import one_line_error
from helpers.robots import finger_arm

LOGGED = "pan_tilt_logged.toml"
"""The shipped log's motion: pan and tilt at 500 Hz, positions only, in degrees."""


def motion(name: str, log: str, *keys: str, base: str = LOGGED, **changes: str) -> Path:
    """A copy of a shipped log's motion (in tr/) reading `log`, with `keys` in [samples]."""
    text = Path("tr", base).read_text()
    text = text.replace('file = "logs/pan_tilt_log.csv"', "\n".join([f'file = "{log}"', *keys]))
    for old, new in changes.items():
        assert old in text
        text = text.replace(old, new)
    path = Path("tr", name)
    path.write_text(text)
    return path


def shipped():
    """The shipped CSV log as read (SI units)."""
    return load_motion(Path("tr", LOGGED)).samples


def bag_of(name: str, kind: str, topics) -> str:
    """A bag written in tr/ (a rosbag2 folder, or a ROS 1 file); its path from tr/."""
    path = Path("tr", name + (".bag" if kind == "ros1" else ""))
    write(path, kind, topics)
    return path.name


def same_sizing(a, b) -> None:
    """Every joint's chosen unit, peak and mean torque (and torques) exactly equal."""
    assert [j.name for j in a.joints] == [j.name for j in b.joints]
    for x, y in zip(a.joints, b.joints, strict=True):
        assert x.selected is not None and y.selected is not None
        assert x.selected.unit.id == y.selected.unit.id
        assert x.load.peak_torque == y.load.peak_torque
        assert x.load.mean_torque == y.load.mean_torque
        assert np.array_equal(x.torque, y.torque)


@pytest.mark.parametrize(("kind", "storage"), [("sqlite", ""), ("mcap", ""), ("ros1", ""),
                                               ("sqlite", "db3"), ("mcap", "mcap")])
def test_a_bag_of_the_logged_samples_sizes_exactly_as_the_csv_log(work, kind, storage, caplog):
    """Names in any order, an extra joint, another publisher's messages between: the same."""
    log = shipped()
    n = len(log.t)
    orders = [["tilt", "finger", "pan"], ["pan", "tilt"], ["finger", "pan", "tilt"]]
    names = [orders[k % 3] for k in range(n)]
    values = {"finger": np.zeros(n), "pan": log.q[:, 0], "tilt": log.q[:, 1]}
    positions = [[values[name][k] for name in names[k]] for k in range(n)]
    states = joint_states(kind, log.t, names, positions)
    gripper = joint_states(kind, log.t[::100] + 1e-4, ["gripper"], np.zeros((18, 1)))
    messages = sorted(states + gripper, key=lambda item: item[0])
    name = bag_of(f"run_{kind}", kind, {"/joint_states": (JOINT_STATE, messages)})
    if storage:
        name = f"{name}/{name}.{storage}"
    with caplog.at_level(logging.WARNING):
        from_bag = hdselect.size(None, motion("bag.toml", name))
    notes = [f"{Path(name).name}: /joint_states: {note}" for note in (
        "joints the robot does not have are ignored: finger",
        "18 messages that name none of its joints are skipped")]
    assert [f"motion file: {note}" for note in notes] == list(from_bag.warnings)
    assert all(f"tr/bag.toml: {note}" in caplog.text for note in notes)
    assert from_bag.motion.samples.path.is_file()  # a folder's storage file: provenance hashes it
    same_sizing(from_bag, hdselect.size(None, Path("tr", LOGGED)))


def planned_log(tmp: Path, kinds: str):
    """pan_tilt_scan planned (TOPPRA), its samples as a CSV log in rad of `kinds` columns.

    Returns:
        The trajectory, its times as a bag stores them [s], the CSV's name in tr/logs.
    """
    scan = load_motion(Path("tr", "pan_tilt_scan.toml"))
    robot = hdselect.load_robot(Path("robots", "pan_tilt.urdf"))
    traj = hdselect.plan(robot, scan)
    t = np.round(traj.t * 1e9).astype(np.int64) / 1e9  # what a bag's nanoseconds give
    header = ["t"] + [f"{kind}_{joint}" for kind in kinds.split(",") for joint in ("pan", "tilt")]
    columns = [t] + [getattr(traj, kind)[:, j] for kind in kinds.split(",") for j in (0, 1)]
    lines = [",".join(header)] + [",".join(repr(float(c[k])) for c in columns)
                                  for k in range(len(t))]
    Path("tr/logs/scan.csv").write_text("\n".join(lines) + "\n")
    return traj, t, "logs/scan.csv"


def scan_motion(name: str, log: str, *keys: str) -> Path:
    return motion(name, log, *keys, **{'angle_unit = "deg"': 'angle_unit = "rad"',
                                       "dt = 0.002": "dt = 0.001"})


@pytest.mark.parametrize("kind", KINDS)
def test_joint_states_with_velocities_size_as_the_csv_log_with_qd_columns(work, kind):
    traj, t, csv = planned_log(work, "q,qd")
    name = bag_of(f"scan_{kind}", kind, {"/joint_states": (JOINT_STATE, joint_states(
        kind, t, ["pan", "tilt"], traj.q, traj.qd))})
    from_bag = hdselect.size(None, scan_motion("bag.toml", name))
    assert from_bag.trajectory.qd is not None
    same_sizing(from_bag, hdselect.size(None, scan_motion("csv.toml", csv)))


@pytest.mark.parametrize("kind", KINDS)
def test_a_dense_joint_trajectory_sizes_as_the_csv_log_and_the_planned_motion(work, kind):
    """Its points with positions, velocities, accelerations: the samples as they are."""
    traj, t, csv = planned_log(work, "q,qd,qdd")
    name = bag_of(f"plan_{kind}", kind, {"/arm/joint_trajectory": (TRAJECTORY, [trajectory(
        kind, t, ["tilt", "pan"], traj.q[:, ::-1], traj.qd[:, ::-1], traj.qdd[:, ::-1])])})
    from_bag = hdselect.size(None, scan_motion("bag.toml", name))
    same_sizing(from_bag, hdselect.size(None, scan_motion("csv.toml", csv)))
    planned = hdselect.size(None, Path("tr", "pan_tilt_scan.toml"))
    for x, y in zip(from_bag.joints, planned.joints, strict=True):
        assert x.selected.unit.id == y.selected.unit.id
        assert x.load.peak_torque == pytest.approx(y.load.peak_torque, rel=1e-9)
        assert x.load.mean_torque == pytest.approx(y.load.mean_torque, rel=1e-9)


def test_a_sparse_joint_trajectory_is_splined_through_its_points(work):
    """A cubic in time, given at 6 points with its velocities: the grid holds the cubic.

    The samples planner's not-a-knot spline reproduces a cubic (and the velocities'
    spline a quadratic) exactly: q, qd and qdd on the 2 ms grid are the polynomial's.
    """
    c = np.array([[0.1, 0.3, -0.1], [0.05, 0.2, -0.07]])  # pan, tilt: c0 t + c1 t^2 + c2 t^3

    def cubic(t, order):
        powers = [(t, t**2, t**3), (1 + 0 * t, 2 * t, 3 * t**2), (0 * t, 2 + 0 * t, 6 * t)][order]
        return np.stack([sum(ci * p for ci, p in zip(row, powers, strict=True)) for row in c], 1)

    points = np.linspace(0.0, 2.0, 6)
    name = bag_of("sparse", "mcap", {"/plan": (TRAJECTORY, [trajectory(
        "mcap", points, ["pan", "tilt"], cubic(points, 0), cubic(points, 1))])})
    path = motion("sparse.toml", name)
    robot = hdselect.load_robot(Path("robots", "pan_tilt.urdf"))
    traj = hdselect.plan(robot, load_motion(path))
    assert traj.t[-1] == pytest.approx(2.0) and len(traj.t) == 1001
    for order, values in enumerate((traj.q, traj.qd, traj.qdd)):
        np.testing.assert_allclose(values, cubic(traj.t, order), rtol=0, atol=1e-12)


def test_a_window_keeps_the_samples_a_cut_csv_log_holds(work):
    log = shipped()
    name = bag_of("window", "sqlite", {"/joint_states": (JOINT_STATE, joint_states(
        "sqlite", log.t, ["pan", "tilt"], log.q))})
    keep = (log.t >= 0.5) & (log.t <= 3.0)
    rows = Path("tr/logs/pan_tilt_log.csv").read_text().splitlines()
    Path("tr/logs/cut.csv").write_text("\n".join([rows[0]] + [r for r, k in zip(
        rows[1:], keep, strict=True) if k]) + "\n")
    robot = hdselect.load_robot(Path("robots", "pan_tilt.urdf"))
    window = ("start = 0.5", "stop = 3.0")
    cut = hdselect.plan(robot, load_motion(motion("cut.toml", "logs/cut.csv")))
    for path in (motion("bag.toml", name, *window),
                 motion("csv.toml", "logs/pan_tilt_log.csv", *window)):
        traj = hdselect.plan(robot, load_motion(path))
        assert np.array_equal(traj.q, cut.q) and np.array_equal(traj.qdd, cut.qdd)
    assert load_motion(Path("tr/bag.toml")).samples.t[0] == 0.5  # the log's own time


def test_unstamped_joint_states_are_at_the_times_the_bag_recorded_them(work):
    log = shipped()
    robot = hdselect.load_robot(Path("robots", "pan_tilt.urdf"))
    trajs = []
    for stamped in (True, False):
        name = bag_of(f"stamped_{stamped}", "ros1", {"/joint_states": (JOINT_STATE, joint_states(
            "ros1", log.t, ["pan", "tilt"], log.q, stamped=stamped))})
        trajs.append(hdselect.plan(robot, load_motion(motion(f"{stamped}.toml", name))))
    assert np.array_equal(trajs[0].q, trajs[1].q) and np.array_equal(trajs[0].t, trajs[1].t)


def test_a_robot_joint_missing_from_the_bag_is_named_with_the_topic(work, capsys):
    log = shipped()
    name = bag_of("missing", "mcap", {"/joint_states": (JOINT_STATE, joint_states(
        "mcap", log.t, ["pan", "finger"], log.q))})
    status, out, err = run(capsys, "size", motion("missing.toml", name))
    assert status == 2 and out == ""
    one_line_error(err, "tr/missing", "/joint_states", "joint 'tilt' is missing from message 1",
                   "it names: pan, finger")


# --- hostile bags ----------------------------------------------------------------------------

def _states(kind: str = "mcap", **change):
    """The shipped log's joint states, first 50 samples, with `change` applied to them."""
    log = shipped()
    t, q = log.t[:50].copy(), log.q[:50].copy()
    if "nan" in change:
        q[7, 1] = math.nan
    if "duplicate" in change:
        t[12] = t[11]
    return joint_states(kind, t, ["pan", "tilt"], q)


def _hostile(case: str) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
    """Write a hostile bag; (its name from tr/, keys of [samples], what the error says)."""
    if case.startswith("not a bag"):
        suffix = case.split()[-1]
        Path("tr", f"junk{suffix}").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 4)
        return f"junk{suffix}", (), (f"junk{suffix}", "cannot read it as a ROS bag")
    if case == "truncated":
        bag_of("whole", "mcap", {"/joint_states": (JOINT_STATE, _states())})
        data = Path("tr/whole/whole.mcap").read_bytes()
        Path("tr/cut.mcap").write_bytes(data[:len(data) // 2])
        return "cut.mcap", (), ("cut.mcap", "cannot read it as a ROS bag")
    if case == "huge record":  # its header record claims 1 TB: the reader asks for it
        bag_of("whole", "mcap", {"/joint_states": (JOINT_STATE, _states())})
        data = Path("tr/whole/whole.mcap").read_bytes()
        Path("tr/huge.mcap").write_bytes(data[:9] + (1 << 40).to_bytes(8, "little") + data[17:])
        return "huge.mcap", (), ("huge.mcap", "out of memory: a corrupt record's size")
    if case == "no metadata":
        Path("tr/folder").mkdir()
        Path("tr/folder/folder.db3").write_bytes(b"")
        return "folder", (), ("samples.file", "tr/folder is a folder without metadata.yaml")
    if case == "no file":  # file = "": the motion file's own folder
        return "", (), ("samples.file", "is a folder without metadata.yaml")
    if case == "missing":
        return "nowhere.mcap", (), ("samples.file", "bag not found")
    topics = {"/joint_states": (JOINT_STATE, _states(nan=True) if case == "nan" else
                                _states(duplicate=True) if case == "duplicate" else _states())}
    keys: tuple[str, ...] = ()
    says: tuple[str, ...]
    if case == "empty topic":
        topics = {"/joint_states": (JOINT_STATE, [])}
        says = ("samples.topic", "/joint_states has no messages")
    elif case == "unknown topic":
        keys, says = ('topic = "/joint_state"',), ("samples.topic", "'/joint_state' is not in",
                                                    "/joint_states (sensor_msgs/msg/JointState")
    elif case == "two topics":
        topics["/other/joint_states"] = topics["/joint_states"]
        says = ("samples.topic", "has 2 topics", "name one with topic")
    elif case == "wrong type":
        topics["/chatter"] = ("std_msgs/msg/String", [(EPOCH_NS, _string())])
        keys, says = ('topic = "/chatter"',), ("samples.topic", "/chatter is std_msgs/msg/String")
    elif case == "nan":
        says = ("/joint_states position of 'tilt'", "message 8", "not a finite number: nan")
    elif case == "duplicate":
        says = ("/joint_states header.stamp", "time must increase; message 13")
    elif case == "empty window":
        keys, says = ("start = 5.0",), ("samples.start", "keeps 0 of the log's samples")
    elif case == "stop before start":
        keys, says = ("start = 0.05", "stop = 0.01"), ("samples.stop", "must be after start")
    elif case == "many topics":
        topics = {f"/chatter{k:02d}": ("std_msgs/msg/String", [(EPOCH_NS, _string())])
                  for k in range(15)}
        says = ("samples.topic", "has no topics of joint states", "/chatter11 (std_msgs/msg/"
                "String, 1 messages); and 3 more")
    elif case == "mixed stamps":
        states = _states()
        unstamped = joint_states("mcap", shipped().t[:50], ["pan", "tilt"],
                                 shipped().q[:50], stamped=False)
        topics = {"/joint_states": (JOINT_STATE, states[:20] + unstamped[20:])}
        says = ("/joint_states header.stamp", "message 21 has a zero header stamp")
    elif case == "named twice":
        log = shipped()
        topics = {"/joint_states": (JOINT_STATE, joint_states(
            "mcap", log.t[:5], ["pan", "tilt", "pan"], np.c_[log.q[:5], log.q[:5, 0]]))}
        says = ("/joint_states", "message 1 names joint 'pan' twice")
    elif case == "short positions":
        log = shipped()
        topics = {"/joint_states": (JOINT_STATE, joint_states(
            "mcap", log.t[:5], ["pan", "tilt"], [log.q[k, :1 + (k != 3)] for k in range(5)]))}
        says = ("/joint_states", "message 4 gives 1 position values for 2 joints")
    elif case == "two trajectories":
        one = trajectory("mcap", [0.0, 1.0], ["pan", "tilt"], np.zeros((2, 2)))
        topics = {"/plan": (TRAJECTORY, [one, (one[0] + 1, one[1])])}
        says = ("/plan", "holds 2 trajectories")
    else:
        raise AssertionError(case)
    return bag_of("hostile", "mcap", topics), keys, says


def _string():
    from helpers.bags import typestore

    return typestore("mcap").types["std_msgs/msg/String"](data="hello")


HOSTILE = ["not a bag .mcap", "not a bag .db3", "not a bag .bag", "truncated", "huge record",
           "no metadata", "no file",
           "missing", "empty topic", "unknown topic", "two topics", "wrong type", "nan",
           "duplicate", "empty window", "stop before start", "two trajectories",
           "mixed stamps", "named twice", "short positions", "many topics"]


@pytest.mark.parametrize("case", HOSTILE)
def test_a_hostile_bag_is_one_line_naming_the_file_and_field(work, capsys, case):
    name, keys, says = _hostile(case)
    path = motion("hostile.toml", name, *keys)
    before = set(Path(".").rglob("*"))
    status, out, err = run(capsys, "size", path, "--json", "out.json")
    assert status == 2 and out == "" and "Traceback" not in err, err
    one_line_error(err, *says)
    assert set(Path(".").rglob("*")) == before


def test_topic_is_for_a_bag_only(work):
    with pytest.raises(InputError, match="only for a ROS bag") as info:
        load_motion(motion("csv.toml", "logs/pan_tilt_log.csv", 'topic = "/joint_states"'))
    assert info.value.field == "samples.topic"



@pytest.mark.parametrize("kind", KINDS)
def test_a_bag_with_bytes_changed_reads_or_is_refused_in_one_error(work, kind):
    """Seeded corruptions of a valid bag: each one reads, or is one InputError naming it."""
    log = shipped()
    name = bag_of(f"whole_{kind}", kind, {"/joint_states": (JOINT_STATE, joint_states(
        kind, log.t[:40], ["pan", "tilt"], log.q[:40], log.q[:40]))})
    path = Path("tr", name)
    if path.is_dir():
        path = next(p for p in path.iterdir() if p.suffix in (".db3", ".mcap"))
    good, rng = path.read_bytes(), np.random.default_rng(31)
    refused = 0
    for _ in range(40):
        data = bytearray(good)
        for i in rng.integers(0, len(data), int(rng.choice([1, 3, 12]))):
            data[i] = int(rng.integers(0, 256))
        bad = Path("tr", f"bad{path.suffix}")
        bad.write_bytes(bytes(data))
        try:
            load_motion(motion("bad.toml", bad.name))
        except InputError as err:
            assert err.path is not None and err.path.name in ("bad" + path.suffix, "bad.toml")
            refused += 1
    assert refused >= 5  # the test reaches the reader's errors, not only harmless bytes


@pytest.mark.parametrize(("shift", "refused"), [(0.0, False), (0.01, True)])
def test_a_mimic_follower_the_messages_give_is_checked_against_its_leader(tmp_path, shift,
                                                                         refused):
    """As a CSV log's q_<follower> column: read as without it when it agrees, else refused."""
    finger_arm(tmp_path, multiplier=0.1)
    t = np.arange(60) * 0.01
    shoulder, elbow = 0.1 * np.sin(np.arange(60) / 5), -0.5 * np.sin(np.arange(60) / 7)
    write(tmp_path / "plain", "mcap", {"/joint_states": (JOINT_STATE, joint_states(
        "mcap", t, ["shoulder", "elbow"], np.stack([shoulder, elbow], 1)))})
    write(tmp_path / "listed", "mcap", {"/joint_states": (JOINT_STATE, joint_states(
        "mcap", t, ["finger", "elbow", "shoulder"],
        np.stack([0.1 * elbow + shift, elbow, shoulder], 1)))})
    sized = []
    for name in ("plain", "listed"):
        path = tmp_path / f"{name}.toml"
        path.write_text('robot = "finger.urdf"\nplanner = "samples"\nangle_unit = "rad"\n'
                        f'dt = 0.01\n[samples]\nfile = "{name}"\n')
        if refused and name == "listed":
            with pytest.raises(InputError, match="message 1 .* disagrees with its leader") as info:
                load_motion(path)
            assert info.value.field == "/joint_states position of 'finger'"
            return
        sized.append(hdselect.size(None, path))
    same_sizing(*sized)


def test_a_study_of_a_bag_folder_digests_and_ships_its_files(work):
    """A re-recorded bag is a new case (the resumable store does not reuse the old one)."""
    from hdselect.study.spec import load_study

    log = shipped()
    name = bag_of("study_bag", "sqlite", {"/joint_states": (JOINT_STATE, joint_states(
        "sqlite", log.t, ["pan", "tilt"], log.q))})
    motion("bag.toml", name)
    study = Path("tr/study.toml")
    study.write_text('compute = "size"\n[base]\nmotion = "bag.toml"\n[grid]\n'
                     'payload = [0.1]\n')
    (case,) = load_study(study).cases
    assert {p.name for p in case.files} >= {"metadata.yaml", "study_bag.db3"}
    Path("tr", name, "study_bag.db3").write_bytes(b"re-recorded")
    (again,) = load_study(study).cases
    assert again.key != case.key
