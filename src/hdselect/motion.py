"""Read a motion file (TOML): the waypoints, limits and planner a robot's cycle is made of.

Everything is validated here, once, and converted to SI: revolute positions
[rad], prismatic positions [m], times [s]. The file's ``angle_unit`` applies to
revolute positions and every revolute limit (and to a ``samples`` log);
prismatic joints are always in m, m/s, m/s^2 and m/s^3.

A ``samples`` log is a CSV file with a header row: ``t`` [s], ``q_<joint>`` for
every joint, and optionally ``qd_<joint>`` and ``qdd_<joint>`` for every joint;
other columns are ignored.
"""

from __future__ import annotations

import csv
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.arrays import frozen
from hdselect.errors import InputError
from hdselect.robot import MOUNTINGS, Payload, Robot, load_robot
from hdselect.tomlfile import as_number, check_keys, number, read_toml, table_of

logger = logging.getLogger(__name__)

PLANNERS = ("ruckig", "toppra", "samples")
"""Valid values of the ``planner`` key."""

ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
"""Valid values of ``angle_unit`` and their size [rad]."""

_TOP_KEYS = ("robot", "planner", "angle_unit", "dt", "mounting", "payload", "limits", "safety",
             "requirements", "waypoint", "samples")
_LIMIT_KEYS = ("velocity", "acceleration", "jerk", "torque")
_NEEDED = {"ruckig": ("velocity", "acceleration", "jerk"), "toppra": ("velocity", "acceleration"),
           "samples": ()}
_ALLOWED = {"ruckig": _NEEDED["ruckig"], "toppra": ("velocity", "acceleration", "torque"),
            "samples": ()}


@dataclass(frozen=True)
class SampleLog:
    """A logged joint trajectory, in SI units, with time as logged.

    Attributes:
        path: The CSV file it came from.
        t: Sample times [s], strictly increasing, shape (n,).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof), or None if not logged.
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof), or None if not logged.
    """

    path: Path
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray | None
    qdd: np.ndarray | None


@dataclass(frozen=True, eq=False)
class Motion:
    """A validated motion file, all in SI units, joints in the robot's order.

    Attributes:
        path: The motion file.
        robot: The robot that makes the motion.
        planner: ``"ruckig"``, ``"toppra"`` or ``"samples"``.
        dt: Sample period of the planned trajectory [s].
        waypoints: Joint positions to pass through [rad or m], shape (k, dof); (0, dof)
            for the samples planner.
        dwells: Time held at rest after reaching each waypoint [s], shape (k,).
        velocity_limit: Joint speed limit [rad/s or m/s], shape (dof,), or None.
        acceleration_limit: Joint acceleration limit [rad/s^2 or m/s^2], (dof,), or None.
        jerk_limit: Joint jerk limit [rad/s^3 or m/s^3], shape (dof,), or None.
        torque_limit: Joint torque limit for TOPPRA [N m or N], shape (dof,), or None.
        stop_time: Time to stop every joint in an emergency stop [s], or None.
        life_hours: Required gearhead life L50 [h], or None.
        samples: The logged trajectory for the samples planner, else None.
    """

    path: Path
    robot: Robot
    planner: str
    dt: float
    waypoints: np.ndarray
    dwells: np.ndarray
    velocity_limit: np.ndarray | None = None
    acceleration_limit: np.ndarray | None = None
    jerk_limit: np.ndarray | None = None
    torque_limit: np.ndarray | None = None
    stop_time: float | None = None
    life_hours: float | None = None
    samples: SampleLog | None = None


def load_motion(
    path: str | Path,
    robot: Robot | str | Path | None = None,
    *,
    payload: Payload | None = None,
    mounting: str | Sequence[float] | None = None,
    joints: Sequence[str] | None = None,
) -> Motion:
    """Read and validate a motion file.

    Args:
        path: The motion file (TOML).
        robot: The robot, a robot file, or None to load the file named by the motion
            file's ``robot`` key (relative to the motion file).
        payload: Payload to attach instead of the motion file's ``[payload]``; used
            only when the robot is loaded here.
        mounting: Mounting instead of the motion file's ``mounting``: ``"floor"``,
            ``"wall"``, ``"ceiling"`` or gravity in the base frame [m/s^2]; used only
            when the robot is loaded here.
        joints: Joints to size (see `load_robot`); used only when the robot is loaded here.

    Returns:
        The motion, in SI units.

    Raises:
        InputError: The motion file, the robot file or the log is missing, malformed
            or inconsistent; the message names the file and the field.
    """
    path = Path(path)
    doc = read_toml(path)
    check_keys(doc, _TOP_KEYS, path, "")
    planner = _choice(doc, "planner", PLANNERS, path)
    unit = ANGLE_UNITS[_choice(doc, "angle_unit", tuple(ANGLE_UNITS), path)]
    dt = number(doc, "dt", path, "", default=0.001, positive=True)
    file_payload = _payload(doc["payload"], path) if "payload" in doc else None
    file_mounting = _mounting(doc["mounting"], path) if "mounting" in doc else "floor"
    if not isinstance(robot, Robot):
        if robot is None:
            if "robot" not in doc:
                raise InputError("no robot given: set the key or pass a robot file",
                                 path=path, field="robot")
            if not isinstance(doc["robot"], str):
                raise InputError("expected a file name", path=path, field="robot")
            robot = path.parent / doc["robot"]
            if not robot.is_file():
                raise InputError(f"robot file not found: {robot}", path=path, field="robot")
        try:
            robot = load_robot(robot, payload=payload or file_payload, joints=joints,
                               mounting=file_mounting if mounting is None else mounting)
        except InputError as err:
            if payload is None and file_payload is not None and err.field == "payload.frame":
                raise InputError(err.reason, path=path, field=err.field) from err
            raise
    elif "payload" in doc or "mounting" in doc:
        logger.warning("%s: the robot was given already loaded; this file's payload and "
                       "mounting are not applied", path)
    scale = np.where(robot.revolute, unit, 1.0)
    units = [("deg" if unit != 1.0 else "rad") if r else "m" for r in robot.revolute]
    limits = table_of(doc.get("limits", {}), path, "limits")
    check_keys(limits, _LIMIT_KEYS, path, "limits")
    for key in _NEEDED[planner]:
        if key not in limits:
            raise InputError(f"required by planner '{planner}'", path=path, field=f"limits.{key}")
    for key in limits:
        if key not in _ALLOWED[planner]:
            raise InputError(f"not used by planner '{planner}'; remove it (planner "
                             f"'{planner}' takes: {', '.join(_ALLOWED[planner]) or 'no limits'})",
                             path=path, field=f"limits.{key}")
    lim = {k: frozen(_per_joint(v, robot, path, f"limits.{k}", positive=True)
                      * (1.0 if k == "torque" else scale)) for k, v in limits.items()}
    stop_time = _section_number(doc, "safety", "stop_time", path)
    life_hours = _section_number(doc, "requirements", "life_hours", path)
    samples = None
    if planner == "samples":
        if "waypoint" in doc:
            raise InputError("planner 'samples' takes its motion from [samples] file; remove "
                             "the waypoints", path=path, field="waypoint")
        waypoints, dwells = np.empty((0, robot.dof)), np.empty(0)
        samples = _samples(doc, path, robot, scale)
    else:
        if "samples" in doc:
            raise InputError(f"only for planner 'samples', not '{planner}'", path=path,
                             field="samples")
        waypoints, dwells = _waypoints(doc.get("waypoint"), path, robot, scale, units)
    return Motion(
        path=path, robot=robot, planner=planner, dt=dt,
        waypoints=frozen(waypoints), dwells=frozen(dwells),
        velocity_limit=lim.get("velocity"), acceleration_limit=lim.get("acceleration"),
        jerk_limit=lim.get("jerk"), torque_limit=lim.get("torque"),
        stop_time=stop_time, life_hours=life_hours, samples=samples,
    )


def _choice(doc: dict[str, Any], key: str, choices: tuple[str, ...], path: Path) -> str:
    if key not in doc:
        raise InputError(f"required key is missing; choose one of: {', '.join(choices)}",
                         path=path, field=key)
    if doc[key] not in choices:
        raise InputError(f"unknown value {doc[key]!r}; choose one of: {', '.join(choices)}",
                         path=path, field=key)
    return doc[key]


def _section_number(doc: dict[str, Any], section: str, key: str, path: Path) -> float | None:
    table = table_of(doc.get(section, {}), path, section)
    check_keys(table, (key,), path, section)
    return number(table, key, path, section, positive=True) if key in table else None


def _vector(value: Any, size: int, path: Path, field: str) -> list[float]:
    if not isinstance(value, list) or len(value) != size:
        raise InputError(f"expected a list of {size} numbers, got {value!r}", path=path,
                         field=field)
    return [as_number(v, path, f"{field}[{i}]") for i, v in enumerate(value)]


def _payload(value: Any, path: Path) -> Payload:
    table = table_of(value, path, "payload")
    check_keys(table, ("mass", "com", "inertia", "frame"), path, "payload")
    mass = number(table, "mass", path, "payload", positive=True)
    com = _vector(table.get("com", [0.0] * 3), 3, path, "payload.com")
    rows = table.get("inertia", [[0.0] * 3] * 3)
    if not isinstance(rows, list) or len(rows) != 3:
        raise InputError("expected a 3x3 matrix [kg m^2]", path=path, field="payload.inertia")
    inertia = np.array([_vector(r, 3, path, f"payload.inertia[{i}]") for i, r in enumerate(rows)])
    if not np.allclose(inertia, inertia.T) or np.linalg.eigvalsh(inertia)[0] < -1e-12:
        raise InputError("must be symmetric positive semi-definite [kg m^2]", path=path,
                         field="payload.inertia")
    frame = table.get("frame")
    if frame is not None and not isinstance(frame, str):
        raise InputError(f"expected a frame name, got {frame!r}", path=path, field="payload.frame")
    return Payload(mass, (com[0], com[1], com[2]), tuple(tuple(r) for r in inertia.tolist()),
                   frame)


def _mounting(value: Any, path: Path) -> str | list[float]:
    if isinstance(value, str):
        if value not in MOUNTINGS:
            raise InputError(f"unknown mounting {value!r}; choose one of: {', '.join(MOUNTINGS)}"
                             " or a gravity vector [gx, gy, gz] in m/s^2", path=path,
                             field="mounting")
        return value
    return _vector(value, 3, path, "mounting")


def _per_joint(value: Any, robot: Robot, path: Path, field: str, *,
               positive: bool = False) -> np.ndarray:
    """One number per joint: from a number (all joints), a list or a table keyed by joint."""
    if isinstance(value, dict):
        for name in value:
            robot.joint_index(name, source=path, field=f"{field}.{name}")
        missing = [n for n in robot.joint_names if n not in value]
        if missing:
            raise InputError(f"missing joint(s) {', '.join(missing)}; give every joint: "
                             f"{', '.join(robot.joint_names)}", path=path, field=field)
        return np.array([as_number(value[n], path, f"{field}.{n}", positive=positive)
                         for n in robot.joint_names])
    if isinstance(value, list):
        if len(value) != robot.dof:
            raise InputError(f"expected {robot.dof} values (joints {', '.join(robot.joint_names)})"
                             f", got {len(value)}", path=path, field=field)
        return np.array([as_number(v, path, f"{field}[{i}]", positive=positive)
                         for i, v in enumerate(value)])
    return np.full(robot.dof, as_number(value, path, field, positive=positive))


def _waypoints(value: Any, path: Path, robot: Robot, scale: np.ndarray, units: list[str]):
    if not isinstance(value, list) or len(value) < 2:
        raise InputError("give at least two [[waypoint]] tables", path=path, field="waypoint")
    points, dwells = [], []
    for i, item in enumerate(value):
        where = f"waypoint[{i}]"
        table = table_of(item, path, where)
        check_keys(table, ("q", "dwell"), path, where)
        if "q" not in table:
            raise InputError("required key is missing", path=path, field=f"{where}.q")
        if not isinstance(table["q"], list | dict):
            raise InputError("expected a list or a table keyed by joint name", path=path,
                             field=f"{where}.q")
        given = _per_joint(table["q"], robot, path, f"{where}.q")
        q = given * scale
        for j in np.flatnonzero((q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)):
            name = robot.joint_names[j]
            key = f"[{j}]" if isinstance(table["q"], list) else f".{name}"
            raise InputError(
                f"{given[j]:g} {units[j]} is outside the limits of joint '{name}' "
                f"[{robot.lower[j] / scale[j]:g}, {robot.upper[j] / scale[j]:g}] {units[j]}",
                path=path, field=f"{where}.q{key}")
        points.append(q)
        dwells.append(number(table, "dwell", path, where, default=0.0, minimum=0.0))
    return np.array(points), np.array(dwells)


def _samples(doc: dict[str, Any], path: Path, robot: Robot, scale: np.ndarray) -> SampleLog:
    table = table_of(doc.get("samples", {}), path, "samples")
    check_keys(table, ("file",), path, "samples")
    if not isinstance(table.get("file"), str):
        raise InputError("required: the CSV log, relative to this file", path=path,
                         field="samples.file")
    log = path.parent / table["file"]
    if not log.is_file():
        raise InputError(f"log file not found: {log}", path=path, field="samples.file")
    try:
        with log.open(newline="", encoding="utf-8-sig") as stream:
            rows = [[c.strip() for c in r] for r in csv.reader(stream) if any(c.strip() for c in r)]
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise InputError(f"cannot read CSV ({err})", path=log) from err
    if len(rows) < 3:
        raise InputError("need a header row and at least two samples", path=log)
    header, body = rows[0], rows[1:]
    for r, row in enumerate(body, start=1):
        if len(row) != len(header):
            raise InputError(f"data row {r} (line {r + 1}) has {len(row)} cells, the header "
                             f"{len(header)}", path=log)
    columns = {name: i for i, name in enumerate(header)}
    for name in header:
        for prefix in ("qdd_", "qd_", "q_"):
            if name.startswith(prefix):
                robot.joint_index(name[len(prefix):], source=log, field=name)
                break
    cells = np.array(body, dtype=object)

    def column(name: str) -> np.ndarray:
        if name not in columns:
            raise InputError(f"column '{name}' is missing; columns are: {', '.join(header)}",
                             path=log, field=name)
        text = cells[:, columns[name]]
        try:
            values = text.astype(float)
        except ValueError:
            values = np.array([_float(v) for v in text])
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            r = int(bad[0]) + 1
            raise InputError(f"data row {r} (line {r + 1}): not a finite number: {text[r - 1]!r}",
                             path=log, field=name)
        return values

    def joints(prefix: str) -> np.ndarray:
        names = [f"{prefix}_{n}" for n in robot.joint_names]
        return frozen(np.column_stack([column(n) for n in names]) * scale)

    def logged(prefix: str) -> bool:
        return any(f"{prefix}_{n}" in columns for n in robot.joint_names)

    t = column("t")
    back = np.flatnonzero(np.diff(t) <= 0.0)
    if back.size:
        r = int(back[0]) + 2
        raise InputError(f"time must increase; data row {r} (line {r + 1}) has t = {t[r - 1]:g}"
                         f" after {t[r - 2]:g}", path=log, field="t")
    return SampleLog(path=log, t=frozen(t), q=joints("q"),
                     qd=joints("qd") if logged("qd") else None,
                     qdd=joints("qdd") if logged("qdd") else None)


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan
