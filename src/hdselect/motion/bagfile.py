"""Read a ROS bag's joint states, or a planned joint trajectory, as a log; and ``[samples]``.

A bag is a rosbag2 folder (``metadata.yaml`` beside its SQLite3 ``.db3`` or MCAP
``.mcap`` files), one such ``.db3`` or ``.mcap`` file alone, or a ROS 1 ``.bag``, read
with the pure-Python ``rosbags`` package (no ROS installation). Its topic is a
``sensor_msgs/JointState`` (each message one sample: joints matched by name, positions
and, where every message gives them, velocities; the time is the header stamp, or the
time the bag recorded the message where every stamp is zero) or a
``trajectory_msgs/JointTrajectory`` (one planned motion: each point one sample at its
``time_from_start``, with its velocities and accelerations where every point gives
them). The samples are then the rows a CSV log gives (`hdselect.motion.logfile`), in
SI units, checked and resampled by the same code.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_LOG_BYTES, is_input_file, readable
from hdselect.base.tomlfile import check_keys, number, table_of
from hdselect.motion.logfile import TIMESTAMP, LogTable, SampleLog, Window, checked_log, read_log
from hdselect.robot.model import Robot

BAG_SUFFIXES = (".bag", ".db3", ".mcap")
"""The file names a bag has: ROS 1, and rosbag2's SQLite3 and MCAP storage."""
JOINT_STATE = "sensor_msgs/msg/JointState"
"""The message type of recorded joint states."""
TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
"""The message type of a planned joint trajectory."""
SAMPLES_KEYS = ("file", "topic", "start", "stop")
"""The keys of a motion file's ``[samples]`` table."""
LISTED = 12
"""Most topics a message lists (joint states and trajectories first) [-]."""
_WORDS = {JOINT_STATE: ("message", "position", "velocity", "acceleration"),
          TRAJECTORY: ("point", "positions", "velocities", "accelerations")}
"""How a sample and its fields are named in each message type."""


def read_samples(value: Any, path: Path, robot: Robot, scale: np.ndarray, units: Sequence[str],
                 angle: tuple[float, str]) -> SampleLog:
    """A motion file's ``[samples]`` table read: its log, a CSV file or a ROS bag.

    Args:
        value: The ``[samples]`` table as read.
        path: The motion file; ``file`` is relative to it.
        robot: The robot whose joints the log gives.
        scale: SI per file unit of each joint's position (a CSV log's; a bag is in SI).
        units: The file unit of each joint's position, for messages.
        angle: SI per unit of the file's angles and its label.

    Returns:
        The log in SI units, within the window ``start`` to ``stop``.

    Raises:
        InputError: A key is unknown or malformed, the log is missing, or reading it fails.
    """
    table = table_of(value, path, "samples")
    check_keys(table, SAMPLES_KEYS, path, "samples")
    if not isinstance(table.get("file"), str):
        raise InputError("required: the log (a CSV file or a ROS bag), relative to this file",
                         path=path, field="samples.file")
    start, stop = (number(table, key, path, "samples", bound=TIMESTAMP) if key in table else None
                   for key in ("start", "stop"))
    if start is not None and stop is not None and stop <= start:
        raise InputError(f"must be after start ({start:g} s), got {stop:g} s", path=path,
                         field="samples.stop")
    topic = table.get("topic")
    if topic is not None and not isinstance(topic, str):
        raise InputError(f"expected a topic name, got {topic!r}", path=path,
                         field="samples.topic")
    log, window = path.parent / table["file"], Window(path, start, stop)
    if is_bag(log):
        return read_bag(log, path, robot, units, topic, window)
    if topic is not None:
        raise InputError(f"only for a ROS bag ({', '.join(BAG_SUFFIXES)} or a rosbag2 folder); "
                         f"{log.name} is read as a CSV log", path=path, field="samples.topic")
    if not is_input_file(log):
        raise InputError(f"log file not found: {log}", path=path, field="samples.file")
    return read_log(log, robot, scale, units, angle, window)


def log_files(log: Path) -> list[Path]:
    """The files a log is read from: itself, or every file of a rosbag2 folder.

    What a study digests (a case re-runs when a recording changes) and ships to workers.
    """
    try:
        return sorted(p for p in log.iterdir() if p.is_file()) if log.is_dir() else [log]
    except OSError:
        return [log]


def is_bag(path: Path) -> bool:
    """`path` names a ROS bag: a ``.bag``, ``.db3`` or ``.mcap`` file, or a folder."""
    try:
        return path.suffix.lower() in BAG_SUFFIXES or path.is_dir()
    except (OSError, ValueError):
        return False


def read_bag(bag: Path, motion: Path, robot: Robot, units: Sequence[str], topic: str | None,
             window: Window) -> SampleLog:
    """Read and check a bag's joint states or planned trajectory for a robot's joints.

    Args:
        bag: The bag (a file, or a rosbag2 folder).
        motion: The motion file that names it, for messages about its keys.
        robot: The robot: its joints by name (others are ignored, said in a note), and
            its mimic followers, checked against their leaders where every sample has them.
        units: The motion file's unit of each joint's position: ``m`` for a prismatic one.
        topic: The topic, or None for the bag's one topic of either message type.
        window: The part of the log to read, in its time [s]: from the topic's first
            message, or a trajectory's ``time_from_start``.

    Returns:
        The log in SI units; its path is the bag's, or a rosbag2 folder's one storage file
        (which a report's provenance hashes and an output may not overwrite).

    Raises:
        InputError: The bag cannot be read, the topic is not in it or not of either type,
            a robot joint is missing from a sample, or `checked_log` refuses the numbers.
    """
    source = _source(bag, motion)
    msgtype, name, rows = _read(source, bag, motion, topic)
    table = _table(bag, robot, name, msgtype, rows)
    si_units = ["m" if unit == "m" else "rad" for unit in units]
    log = checked_log(table, robot, np.ones(robot.dof), si_units, (1.0, "rad"), window)
    stored = sorted(p for p in bag.iterdir() if p.suffix in (".db3", ".mcap")) \
        if bag.is_dir() else []
    return replace(log, path=stored[0]) if len(stored) == 1 else log  # a file to hash, to keep


def _source(bag: Path, motion: Path) -> Path:
    """The bag checked as an input (its size bounded, a stream copied), for the reader."""
    try:
        found, folder = bag.exists(), bag.is_dir()
        described = not folder or (bag / "metadata.yaml").is_file()
    except OSError as err:
        raise InputError(f"cannot read {bag} ({err.strerror})", path=motion,
                         field="samples.file") from err
    if not found:
        raise InputError(f"bag not found: {bag}", path=motion, field="samples.file")
    if not described:
        raise InputError(f"{bag} is a folder without metadata.yaml: not a rosbag2 bag (give "
                         "its folder, or its .db3 or .mcap file)", path=motion,
                         field="samples.file")
    return bag if folder else readable(bag, MAX_LOG_BYTES)


Row = tuple[int, int, tuple[str, ...], tuple[Any, Any, Any]]
"""One sample as read: its time [ns] (a header stamp, a ``time_from_start``), the time the
bag recorded its message [ns], the joint names, and its positions, velocities and
accelerations (each empty where not given)."""


def _read(source: Path, bag: Path, motion: Path,
          topic: str | None) -> tuple[str, str, list[Row]]:
    """The topic's message type, its name and its samples (`Row`), read by ``rosbags``.

    Whatever the library raises on a file it cannot read is one `InputError`.
    """
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    store = Stores.ROS1_NOETIC if source.suffix.lower() == ".bag" else Stores.ROS2_HUMBLE
    try:
        with AnyReader([source], default_typestore=get_typestore(store)) as reader:
            topics = {name: (info.msgtype, info.msgcount) for name, info in
                      reader.topics.items()}
            name = _topic(topics, bag, motion, topic)
            msgtype, count = str(topics[name][0]), topics[name][1]
            if msgtype == TRAJECTORY and count > 1:
                raise InputError(f"holds {count} trajectories: a log replays one planned "
                                 "motion (give a bag of one JointTrajectory, or the joint "
                                 "states the robot recorded)", path=bag, field=name)
            connections = [c for c in reader.connections if c.topic == name]
            rows: list[Row] = []
            for connection, logged, raw in reader.messages(connections):
                message: Any = reader.deserialize(raw, connection.msgtype)
                if msgtype == TRAJECTORY:
                    if rows:  # more messages than its summary counted
                        raise InputError("holds more than one trajectory: a log replays one "
                                         "planned motion", path=bag, field=name)
                    rows += [(_ns(point.time_from_start), logged, tuple(message.joint_names),
                              (point.positions, point.velocities, point.accelerations))
                             for point in message.points]
                else:
                    rows.append((_ns(message.header.stamp), logged, tuple(message.name),
                                 (message.position, message.velocity, ())))
    except InputError:
        raise
    except MemoryError as err:  # a corrupt record's length asks the reader for petabytes
        raise InputError("cannot read it as a ROS bag (out of memory: a corrupt record's size, "
                         "or a bag too large to hold)", path=bag) from err
    except Exception as err:  # noqa: BLE001 - whatever a hostile file makes the reader raise
        text = str(err).strip()
        reason = text.splitlines()[0] if text else type(err).__name__
        raise InputError(f"cannot read it as a ROS bag ({reason})", path=bag) from err
    return msgtype, name, rows


def _ns(time: Any) -> int:
    """A ROS time or duration (``sec``, ``nanosec``) in ns."""
    return int(time.sec) * 1_000_000_000 + int(time.nanosec)


def _topic(topics: Mapping[str, tuple[str | None, int]], bag: Path, motion: Path,
           topic: str | None) -> str:
    """The topic to read: the one given, or the bag's one of either message type."""
    fits = [name for name, (kind, _) in topics.items() if kind in _WORDS]
    shown = sorted(topics, key=lambda name: (name not in fits, name))[:LISTED]
    listed = "; ".join(f"{name} ({topics[name][0] or 'several types'}, {topics[name][1]} "
                       "messages)" for name in shown) or "none"
    if len(topics) > len(shown):
        listed += f"; and {len(topics) - len(shown)} more"
    if topic is None:
        if len(fits) != 1:
            raise InputError(f"{bag.name} has {len(fits) or 'no'} topics of joint states or "
                             f"trajectories; name one with topic = \"...\"; its topics are: "
                             f"{listed}", path=motion, field="samples.topic")
        topic = fits[0]
    if topic not in topics:
        raise InputError(f"topic {topic!r} is not in {bag.name}; its topics are: {listed}",
                         path=motion, field="samples.topic")
    kind, count = topics[topic]
    if kind not in _WORDS:
        raise InputError(f"{topic} is {kind or 'of several types'}; a log needs "
                         f"{JOINT_STATE} or {TRAJECTORY}", path=motion, field="samples.topic")
    if not count:
        raise InputError(f"{topic} has no messages in {bag.name}", path=motion,
                         field="samples.topic")
    return topic


def _table(bag: Path, robot: Robot, topic: str, msgtype: str, rows: list[Row]) -> LogTable:
    """A topic's samples as the rows of a log (`LogTable`), joints matched by name, SI units.

    A sample that names none of the robot's joints (another publisher's, a gripper's) is
    skipped; one that names some of them must name them all. Followers are checked where
    every sample names them.
    """
    sample, *fields = _WORDS[msgtype]
    joints, mimic = list(robot.joint_names), list(robot.mimic)
    groups: dict[tuple[str, ...], list[int]] = {}
    for k, row in enumerate(rows):
        groups.setdefault(row[2], []).append(k)
    maps: dict[tuple[str, ...], list[int]] = {}
    for names, members in groups.items():
        index = _names(bag, topic, names, f"{sample} {members[0] + 1}")
        if any(name in index for name in joints + mimic):
            missing = [name for name in joints if name not in index]
            if missing:
                raise InputError(f"joint '{missing[0]}' is missing from {sample} "
                                 f"{members[0] + 1} (it names: {', '.join(names)})", path=bag,
                                 field=topic)
            maps[names] = [index[name] for name in joints]
    if not maps:
        named = sorted({name for names in groups for name in names})
        raise InputError(f"joint '{joints[0]}' is in no {sample} of {topic}; its joints are: "
                         f"{', '.join(named) or 'none'}", path=bag, field=topic)
    used = np.array(sorted(k for names in maps for k in groups[names]))
    kinds = _kinds(bag, topic, rows, used, sample, fields)
    both = [name for name in mimic if all(name in names for names in maps)]
    columns = [f"{kind}_{name}" for kind in kinds for name in joints] + \
              [f"{kind}_{name}" for kind in kinds for name in both]
    data = np.empty((len(used), 1 + len(columns)))
    place = {k: i for i, k in enumerate(used.tolist())}
    size, extra = len(joints), 1 + len(kinds) * len(joints)
    for names, picked in maps.items():
        picked = picked + [names.index(name) for name in both]
        at = [place[k] for k in groups[names]]
        for i in range(len(kinds)):
            block = np.array([rows[k][3][i] for k in groups[names]], dtype=float)
            data[at, 1 + i * size:1 + (i + 1) * size] = block[:, picked[:size]]
            data[at, extra + i * len(both):extra + (i + 1) * len(both)] = block[:, picked[size:]]
    times, clock = _times(bag, topic, rows, used, msgtype, sample)
    data[:, 0] = times
    names_of = {f"{kind}_{name}": f"{topic} {fields[i]} of '{name}'"
                for i, kind in enumerate(("q", "qd", "qdd")) for name in joints + mimic}
    names_of["t"] = f"{topic} {clock}"
    ignored = sorted({name for names in maps for name in names} - set(joints + mimic))
    skipped = len(rows) - len(used)
    notes = ([f"joints the robot does not have are ignored: {', '.join(ignored)}"]
             if ignored else []) + \
        ([f"{skipped} {sample}s that name none of its joints are skipped"] if skipped else [])
    numbers = used + 1

    def where(row: int) -> str:
        return f"{sample} {numbers[row - 1]} (t = {data[row - 1, 0]:.6g} s)"

    return LogTable(bag, kinds, ("t", *columns), data, where,
                    lambda column: names_of.get(column, f"{topic} {column}"),
                    f"at least two {sample}s that name the robot's joints",
                    tuple(f"{bag.name}: {topic}: {note}" for note in notes))


def _names(bag: Path, topic: str, names: tuple[str, ...], first: str) -> dict[str, int]:
    """Each joint name of a sample -> its index in the sample's arrays; a name twice refused."""
    index: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in index:
            raise InputError(f"{first} names joint {name!r} twice", path=bag, field=topic)
        index[name] = i
    return index


def _kinds(bag: Path, topic: str, rows: list[Row], used: np.ndarray, sample: str,
           fields: list[str]) -> tuple[str, ...]:
    """``q``, and ``qd`` (``qdd``) where every used sample gives velocities (accelerations).

    Accelerations count only beside velocities, as a CSV log's ``qdd_`` columns.

    Raises:
        InputError: A sample gives a number of positions (or velocities, accelerations)
            other than its joints' (or none).
    """
    kinds = ["q"]
    for i, kind in enumerate(("q", "qd", "qdd")):
        sizes = np.array([len(rows[k][3][i]) for k in used])
        joints = np.array([len(rows[k][2]) for k in used])
        wrong = np.flatnonzero((sizes != joints) & ((sizes != 0) | (i == 0)))
        if wrong.size:
            k = int(used[wrong[0]])
            raise InputError(f"{sample} {k + 1} gives {sizes[wrong[0]]} {fields[i]} values "
                             f"for {joints[wrong[0]]} joints", path=bag, field=topic)
        if i and kinds[-1] == ("q", "qd")[i - 1] and np.all(sizes == joints):
            kinds.append(kind)
    return tuple(kinds)


def _times(bag: Path, topic: str, rows: list[Row], used: np.ndarray, msgtype: str,
           sample: str) -> tuple[np.ndarray, str]:
    """The used samples' times [s] and the field they come from.

    A trajectory's points are at their ``time_from_start``. Joint states are at their
    header stamps from the first one's; where every stamp is zero (a publisher that does
    not stamp), at the times the bag recorded them.

    Raises:
        InputError: Some stamps are zero and others are not.
    """
    stamps = np.array([rows[k][0] for k in used], dtype=np.int64)
    if msgtype == TRAJECTORY:
        return stamps / 1e9, "time_from_start"
    clock = "header.stamp"
    if not stamps.any():
        stamps, clock = np.array([rows[k][1] for k in used], dtype=np.int64), "log time"
    elif not stamps.all():
        k = int(used[np.flatnonzero(stamps == 0)[0]])
        raise InputError(f"{sample} {k + 1} has a zero header stamp and others do not: the "
                         "times of one log come from one clock", path=bag,
                         field=f"{topic} header.stamp")
    return (stamps - stamps[0]) / 1e9, clock
