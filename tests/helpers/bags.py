"""ROS bags written with the rosbags package's own writers, for the tests of bag logs."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

JOINT_STATE = "sensor_msgs/msg/JointState"
TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
KINDS = ("sqlite", "mcap", "ros1")
"""rosbag2 in SQLite3, rosbag2 in MCAP, ROS 1."""
EPOCH_NS = 1_700_000_000_000_000_000
"""Where the stamps of a written bag start [ns]: a real clock's epoch time."""


def typestore(kind: str):
    """The rosbags type store of a bag kind (ROS 2 Humble, or ROS 1 Noetic)."""
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS1_NOETIC if kind == "ros1" else Stores.ROS2_HUMBLE)


def write_bag(path: Path, kind: str, topics: dict[str, tuple[str, Sequence[tuple[int, object]]]]):
    """Write a bag of `kind`: each topic -> (its message type, its (log time [ns], message)).

    Returns:
        The bag: the ``.bag`` file, or the rosbag2 folder.
    """
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    store = typestore(kind)
    if kind == "ros1":
        writer = Writer1(path)
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(path, version=9, storage_plugin=plugin)
    with writer:
        for topic, (msgtype, messages) in topics.items():
            connection = writer.add_connection(topic, msgtype, typestore=store)
            for logged, message in messages:
                data = (store.serialize_ros1(message, msgtype) if kind == "ros1"
                        else store.serialize_cdr(message, msgtype))
                writer.write(connection, logged, data)
    return path


def _header(store, stamp_ns: int, seq: int):
    header, time = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    extra = {"seq": seq} if "seq" in header.__dataclass_fields__ else {}
    return header(stamp=time(sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9), frame_id="",
                  **extra)


def joint_states(kind: str, t: np.ndarray, names: Sequence[Sequence[str]] | Sequence[str],
                 positions: np.ndarray, velocities: np.ndarray | None = None, *,
                 stamped: bool = True) -> list[tuple[int, object]]:
    """JointState messages, one per sample, at EPOCH_NS + t (stamps zero unless `stamped`).

    Args:
        kind: The bag kind (its type store).
        t: Sample times [s], shape (n,).
        names: The joint names of every message, or one sequence of names per message.
        positions: Each message's positions in the order of its names, shape (n, k)
            or a list of n arrays.
        velocities: Likewise, or None for messages without velocities.
        stamped: Header stamps are the sample times; else zero (the log time is).
    """
    store = typestore(kind)
    message = store.types[JOINT_STATE]
    per = names if names and not isinstance(names[0], str) else [names] * len(t)
    ns = EPOCH_NS + np.round(np.asarray(t) * 1e9).astype(np.int64)
    out = []
    for k, stamp in enumerate(ns.tolist()):
        out.append((stamp, message(header=_header(store, stamp if stamped else 0, k),
                                   name=list(per[k]), position=_array(positions, k),
                                   velocity=_array(velocities, k), effort=np.empty(0))))
    return out


def _array(values, k: int) -> np.ndarray:
    """Row k of `values` as the contiguous float array a message holds; empty for None."""
    return np.empty(0) if values is None else np.ascontiguousarray(values[k], dtype=float)


def trajectory(kind: str, t: np.ndarray, names: Sequence[str], positions: np.ndarray,
               velocities: np.ndarray | None = None,
               accelerations: np.ndarray | None = None) -> tuple[int, object]:
    """One JointTrajectory message: a point at each time_from_start `t` [s]."""
    store = typestore(kind)
    message = store.types[TRAJECTORY]
    point, duration = (store.types["trajectory_msgs/msg/JointTrajectoryPoint"],
                       store.types["builtin_interfaces/msg/Duration"])
    points = []
    for k, since in enumerate(np.round(np.asarray(t) * 1e9).astype(np.int64).tolist()):
        points.append(point(
            positions=_array(positions, k), velocities=_array(velocities, k),
            accelerations=_array(accelerations, k), effort=np.empty(0),
            time_from_start=duration(sec=since // 10**9, nanosec=since % 10**9)))
    return EPOCH_NS, message(header=_header(store, EPOCH_NS, 0), joint_names=list(names),
                             points=points)
