"""Where a result came from: the command, the software, every input file and the case as run.

A report carries this so that a reader can check it and re-run it: the same
command, in the same directory, on files with the same hashes, gives the same
numbers. It names no absolute path of the machine it was made on: the input files
are named relative to the working directory (the built-in catalog relative to the
installed package), the working directory by its name alone.
"""

from __future__ import annotations

import datetime
import hashlib
import math
import os
import platform
from collections.abc import Sequence
from dataclasses import dataclass, fields
from importlib import metadata
from pathlib import Path

import numpy as np

from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_LOG_BYTES, read_input
from hdselect.robot.mounting import MOUNTINGS, shown_numbers
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task

DEG_PER_RAD = 180.0 / math.pi
_SOFTWARE = ("pin", "ruckig", "toppra", "numpy", "scipy", "matplotlib")
"""The distributions whose versions can change a result, by their PyPI names."""
_PACKAGE = Path(__file__).resolve().parents[1]
"""The installed ``hdselect`` package's folder."""


@dataclass(frozen=True)
class InputFile:
    """One file a result was computed from.

    Attributes:
        role: What it is: ``robot``, ``mix``, ``motion``, ``samples``, ``catalog``,
            ``catalog (built in)`` or ``motors``.
        path: The path relative to the working directory (the built-in catalog's:
            ``hdselect/...``, relative to the installed package's folder).
        sha256: Hex SHA-256 of its content, or an explanation if it cannot be read now.
        size: Its size [bytes], or None if it cannot be read.
    """

    role: str
    path: str
    sha256: str
    size: int | None


@dataclass(frozen=True)
class Provenance:
    """What a report needs to be checked and re-run.

    Attributes:
        version: The hdselect version.
        created: When it was made, ISO 8601 in UTC, to the second.
        command: The command line as given (program name first), or None when the
            result came from the Python API.
        cwd: The name of the working directory the command ran in (its last
            component: the files' paths are relative to it).
        software: Python and each library that can change a number, with its version.
        files: Every input file, hashed.
        settings: The case as resolved, as (what, value) text pairs.
        limits: Header and rows of the motion's kinematic limits per joint.
        waypoints: Header and rows of the waypoints (positions and dwell).
    """

    version: str
    created: str
    command: tuple[str, ...] | None
    cwd: str
    software: tuple[tuple[str, str], ...]
    files: tuple[InputFile, ...]
    settings: tuple[tuple[str, str], ...]
    limits: tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]
    waypoints: tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]


def provenance(result: SizingResult, command: Sequence[str] | None = None, *,
               cwd: str | Path | None = None,
               created: datetime.datetime | None = None) -> Provenance:
    """Collect the provenance of a sizing result.

    Args:
        result: The result.
        command: The command line that produced it, program name first; None for the
            Python API.
        cwd: The working directory the files' paths are made relative to (default: the
            current one).
        created: The time to record (default: now).

    Returns:
        The provenance; files that cannot be read are listed with the reason.
    """
    from hdselect import __version__

    when = created or datetime.datetime.now(datetime.UTC)
    robot, motion = result.robot, result.motion
    files = [("robot", robot.path)]
    if result.mix is not None:
        files.append(("mix", result.mix.path))
    motions = ([task.motion for task in result.tasks if task.motion is not None]
               if len(result.tasks) > 1 else [motion] if motion is not None else [])
    for each in dict.fromkeys(motions):
        files.append(("motion", each.path))
        if each.samples is not None:
            files.append(("samples", each.samples.path))
    here = Path(cwd if cwd is not None else os.getcwd())
    builtin = _PACKAGE / "catalog" / "data"
    files += [("catalog (built in)" if Path(source).resolve().parent == builtin else "catalog",
               source)
              for source in dict.fromkeys(u.source for u in result.units)]
    files += [("motors", source) for source in dict.fromkeys(
        m.source for ms in result.motors.values() for m in ms if m.source is not None)]
    software = [("Python", platform.python_version())]
    for name in _SOFTWARE:
        try:
            software.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            software.append((name, "not installed"))
    return Provenance(
        version=__version__,
        created=when.astimezone(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        command=None if command is None else tuple(command),
        cwd=here.absolute().name or str(here.absolute().anchor),
        software=tuple(software),
        files=tuple(_hashed(role, path, here) for role, path in files),
        settings=tuple(_settings(result)),
        limits=_limits(result),
        waypoints=_waypoints(result),
    )


def _hashed(role: str, path: Path, here: Path) -> InputFile:
    shown = _relative(Path(path), here)
    try:
        content = read_input(Path(path), MAX_LOG_BYTES)
    except InputError as err:
        return InputFile(role, shown, f"cannot be read now: {err.reason}", None)
    return InputFile(role, shown, hashlib.sha256(content).hexdigest(), len(content))


def _relative(path: Path, here: Path) -> str:
    """`path` as a report names it, never absolute.

    Relative to `here`; a file of hdselect's own relative to the installed package's
    folder (``hdselect/...``).
    """
    if not path.is_absolute():
        return str(path)
    if path.resolve().is_relative_to(_PACKAGE):
        return str(Path(_PACKAGE.name) / path.resolve().relative_to(_PACKAGE))
    try:
        return os.path.relpath(path, here.absolute())
    except ValueError:  # another drive (Windows): the name alone
        return path.name


def _settings(result: SizingResult) -> list[tuple[str, str]]:
    """The resolved case: robot, mounting, payload, planner, trajectory and options."""
    robot, motion, traj = result.robot, result.motion, result.trajectory
    kinds = ", ".join(f"{name} ({'revolute' if rev else 'prismatic'}"
                      f"{'' if name in robot.sized_joints else ', not sized'})"
                      for name, rev in zip(robot.joint_names, robot.revolute, strict=True))
    gravity = tuple(float(g) for g in robot.gravity)
    named = [name for name, vector in MOUNTINGS.items() if np.allclose(vector, gravity)]
    rows = [("joints", kinds),
            ("mounting", f"{named[0] + ': ' if named else ''}gravity "
                         f"[{shown_numbers(gravity)}] m/s^2 in the base frame")]
    payload = robot.payload
    if payload is None:
        rows.append(("payload", "none"))
    else:
        default = " (by default: the tip of the longest chain of joints not excluded)"
        frame = f"{robot.payload_frame}{'' if payload.frame else default}"
        inertia = "; ".join(", ".join(f"{v:g}" for v in row) for row in payload.inertia)
        rows.append(("payload", f"{payload.mass:g} kg on {frame}, centre of mass "
                                f"[{', '.join(f'{c:g}' for c in payload.com)}] m, inertia about "
                                f"it [{inertia}] kg m^2"))
    if motion is not None:
        rows.append(("planner", f"{motion.planner}, sampled every {motion.dt:g} s" + (
            f", refined to {traj.dt:.3g} s to resolve every move" if traj.dt < motion.dt
            * (1.0 - 1e-12) else "")))
        rows.append(("requirements in the motion file",
                     f"stop time {_opt(motion.stop_time, ' s')}, life "
                     f"{_opt(motion.life_hours, ' h')} {motion.life_basis or ''}".rstrip()))
    else:
        rows.append(("planner", "none: the trajectory was given directly"))
    rows.append(("trajectory", f"cycle {traj.duration:.6g} s, {len(traj.t):,} samples every "
                               f"{traj.dt:g} s"))
    if result.motors:
        lists = {name: ", ".join(m.id for m in ms) for name, ms in result.motors.items()}
        same = len(set(lists.values())) == 1 and len(lists) == len(robot.sized_joints)
        rows.append(("motors", f"every sized joint chooses from {next(iter(lists.values()))}"
                     if same else "; ".join(f"{name}: {ids}" for name, ids in lists.items())))
    else:
        rows.append(("motors", "none given"))
    if len(result.tasks) > 1:  # a duty: each task's own case
        rows = [row for row in rows if row[0] not in ("mounting", "payload", "planner",
                                                        "requirements in the motion file",
                                                        "trajectory")]
        rows += [(f"task {task.label}", _task_text(task)) for task in result.tasks]
        if result.idle > 0.0:
            rows.append(("idle", f"{result.idle:.6g} of the time"))
    options = result.options
    rows.append(("options", ", ".join(
        f"{f.name} = {_option_text(f.name, getattr(options, f.name))}" for f in fields(options))))
    return rows


def _task_text(task: Task) -> str:
    """One task of a duty: its motion, share, planner, cycle, payload and gravity."""
    traj, robot = task.trajectory, task.robot
    payload = robot.payload
    carried = ("no payload" if payload is None else
               f"payload {payload.mass:g} kg on {robot.payload_frame} at "
               f"[{', '.join(f'{c:g}' for c in payload.com)}] m")
    planner = "" if task.motion is None else f"{task.motion.path.name} ({task.motion.planner}), "
    return (f"{planner}share {task.share:.6g}, cycle {traj.duration:.6g} s, {len(traj.t):,} "
            f"samples every {traj.dt:g} s, {carried}, gravity "
            f"[{', '.join(f'{g:g}' for g in robot.gravity)}] m/s^2")


def _option_text(name: str, value: object) -> str:
    """An option as a reader wants it: what None stands for, not None."""
    if value is not None:
        return str(value)
    return {"threads": "automatic (up to the cores)", "life_hours": "none required",
            "prefer": "size (mass with motors)"}.get(name, "default")


def _opt(value: float | None, unit: str) -> str:
    return "not given" if value is None else f"{value:g}{unit}"


def _scales(result: SizingResult) -> list[tuple[float, str]]:
    """Per joint, the factor from SI to the unit shown and that unit's name."""
    return [(DEG_PER_RAD, "deg") if revolute else (1.0, "m") for revolute in result.robot.revolute]


def _limits(result: SizingResult) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    motion = result.motion
    if motion is None or len(result.tasks) > 1:  # a duty's motions: their files, hashed
        return (), ()
    given = [(name, values) for name, values in (
        ("velocity", motion.velocity_limit), ("acceleration", motion.acceleration_limit),
        ("jerk", motion.jerk_limit), ("torque", motion.torque_limit)) if values is not None]
    header = ("joint", *(name for name, _ in given))
    rows = []
    for j, (name, (scale, unit)) in enumerate(zip(motion.joint_names, _scales(result),
                                                  strict=True)):
        cells = [name]
        for quantity, values in given:
            factor = 1.0 if quantity == "torque" else scale
            cells.append(f"{values[j] * factor:.6g} {_unit(quantity, unit)}")
        rows.append(tuple(cells))
    return header, tuple(rows)


def _per(quantity: str) -> str:
    return {"velocity": "/s", "acceleration": "/s^2", "jerk": "/s^3",
            "torque": "N m or N"}[quantity]


def _unit(quantity: str, unit: str) -> str:
    if quantity == "torque":
        return "N m" if unit == "deg" else "N"
    return unit + _per(quantity)


def _waypoints(result: SizingResult) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    motion = result.motion
    if motion is None or not len(motion.waypoints) or len(result.tasks) > 1:
        return (), ()
    scales = _scales(result)
    header = ("#", *(f"{name} [{unit}]" for name, (_, unit) in zip(motion.joint_names, scales,
                                                                   strict=True)), "dwell [s]")
    rows = tuple((str(k), *(f"{q * scale:.6g}" for q, (scale, _) in zip(point, scales,
                                                                       strict=True)),
                  f"{dwell:g}")
                 for k, (point, dwell) in enumerate(zip(motion.waypoints, motion.dwells,
                                                        strict=True)))
    return header, rows
