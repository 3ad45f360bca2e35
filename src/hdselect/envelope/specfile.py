"""Read an envelope file (TOML): a robot's spec before any motion exists.

The same keys as a motion file where they mean the same thing (``robot``,
``angle_unit``, ``mounting``, ``[payload]``, ``[limits]``, ``[safety]``,
``[requirements]``, ``[sizing]``), no waypoints, and a ``[duty]`` table: the motion
file whose cycle stands for the averaged rules (``motion``), or how the default duty
of random moves is drawn (``moves``, ``seed``). ``[limits]`` gives ``velocity``,
``acceleration`` and ``jerk`` (the default duty's, optional) as one number, a list in
the robot's joint order, or a table keyed by joint name; a table may name only some
joints, the others taking the command line's value or the robot file's velocity limit.
Everything is validated here, once, and converted to SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.motion.motionfile import mounting_of, payload_table
from hdselect.motion.option_specs import OPTION, file_keys, file_options
from hdselect.motion.sizing_table import bearing_offsets
from hdselect.robot.model import Robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.options import WHOLE_ARM_TARGETS

ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
"""Valid values of ``angle_unit`` and their size [rad]."""
LIMIT_KEYS = ("velocity", "acceleration", "jerk")
"""The keys of ``[limits]``."""
DUTY_MOVES = 20
"""Moves of the default duty, unless ``[duty] moves`` says otherwise."""
MAX_DUTY_MOVES = 10_000
"""Most moves a default duty may have."""

_TOP_KEYS = ("robot", "angle_unit", "mounting", "base", "payload", "limits", "safety",
             "requirements", "sizing", "precision", "duty")
_SECTIONS = {"safety": file_keys("envelope", "safety"),
             "requirements": file_keys("envelope", "requirements"),
             "sizing": ("joints", "exclude", *file_keys("envelope", "sizing")),
             "precision": file_keys("envelope", "precision"),
             "duty": ("motion", "moves", "seed")}


@dataclass(frozen=True, eq=False)
class EnvelopeFile:
    """A validated envelope file, in SI.

    Attributes:
        path: The file.
        robot_file: Its ``robot``, resolved against its folder, or None.
        angle_unit: ``"deg"`` or ``"rad"``: how its revolute limits were written.
        limits: Per ``[limits]`` key, the limit per joint in the robot's order [rad/s,
            rad/s^2, rad/s^3 or m/s, ...], NaN where the file gives none, each (dof,).
        mounting: Its ``mounting``, or None.
        payload: Its ``[payload]``, or None.
        stop_time: ``[safety] stop_time`` [s], or None.
        life_hours: ``[requirements] life_hours`` [h], or None.
        life_basis: ``[requirements] life_basis``, or None.
        margin: ``[requirements] margin``, the design margin [-], or None.
        joints: ``[sizing] joints``, or None.
        exclude: ``[sizing] exclude``.
        bearing_offset: ``[sizing] bearing_offset_m``: each named joint's output flange
            along its axis from the joint origin [m], as a motion file's.
        max_torsion: ``[precision] max_torsion_arcmin``: the largest twist of each
            sized joint's unit [rad], by joint name (``"*"``: every joint); empty
            where the file gives none.
        min_natural_frequency: ``[precision] min_natural_frequency_hz``: each sized
            joint's lowest single-axis natural frequency [Hz], the same way.
        max_tool_deflection: ``[precision] max_tool_deflection_mm`` [m], or None.
        min_arm_frequency: ``[precision] min_arm_frequency_hz`` [Hz], or None.
        duty: ``[duty] motion``, resolved against the file's folder, or None.
        moves: ``[duty] moves``, or None.
        seed: ``[duty] seed``, or None.
    """

    path: Path
    robot_file: Path | None
    angle_unit: str
    limits: dict[str, np.ndarray]
    mounting: Mounting | None = None
    payload: Payload | None = None
    stop_time: float | None = None
    life_hours: float | None = None
    life_basis: str | None = None
    margin: float | None = None
    joints: tuple[str, ...] | None = None
    exclude: tuple[str, ...] = ()
    bearing_offset: dict[str, float] = field(default_factory=dict)
    max_torsion: dict[str, float] = field(default_factory=dict)
    min_natural_frequency: dict[str, float] = field(default_factory=dict)
    max_tool_deflection: float | None = None
    min_arm_frequency: float | None = None
    duty: Path | None = None
    moves: int | None = None
    seed: int | None = None


def refuse_arm_targets(options: Any, given: Any, file: EnvelopeFile | None,
                       duty: Any) -> None:
    """Refuse a whole-arm precision target: the envelope does not raise units for one.

    A whole-arm target is met by raising units along a motion's figures (`hdselect
    size`); the envelope's figures are its duty's and its selection is for any motion
    within the spec, so it judges the per-joint targets only (``max_torsion``,
    ``min_natural_frequency``, in its selection, at the worst states too).

    Args:
        options: The envelope's options (`hdselect.sizing.options.Options`).
        given: The options given as arguments, by name (a flag's, from the command line).
        file: The envelope file, if any.
        duty: The duty's motion or mix file as read, if any.

    Raises:
        InputError: A whole-arm target is set, naming where: the argument (its name), the
            envelope file's key, else the duty's.
    """
    for name in WHOLE_ARM_TARGETS:
        if getattr(options, name) is None:
            continue
        key = str(OPTION[name].key)
        where: dict[str, Any] = {"field": name}
        if given.get(name) is None and file is not None and getattr(file, name) is not None:
            where = {"path": file.path, "field": key}
        elif given.get(name) is None and duty is not None:
            where = {"path": duty.path, "field": key}
        raise InputError("the envelope judges the per-joint precision targets only "
                         "(max_torsion, min_natural_frequency): a whole-arm target is met "
                         "by raising units along a motion; size its duty with `hdselect "
                         "size` for it", **where)


def envelope_robot_file(path: str | Path) -> Path:
    """The robot file an envelope file names (to load the robot before reading the limits).

    Raises:
        InputError: The file is unreadable or names no robot file that exists.
    """
    path = bounds.file_argument(path, "spec")
    doc = read_toml(path)
    found = _robot_file(doc, path)
    if found is None:
        raise InputError("no robot given: set the key or pass a robot file", path=path,
                         field="robot")
    return found


def load_envelope_file(path: str | Path, robot: Robot) -> EnvelopeFile:
    """Read and validate an envelope file for a robot's joints.

    Args:
        path: The envelope file (TOML).
        robot: The robot (its joints' order and types).

    Returns:
        The file's values, in SI.

    Raises:
        InputError: The file is missing, malformed, or names an unknown joint; the message
            names the file and the field.
    """
    path = bounds.file_argument(path, "spec")
    doc = read_toml(path)
    check_keys(doc, _TOP_KEYS, path, "")
    if "angle_unit" not in doc or doc["angle_unit"] not in ANGLE_UNITS:
        raise InputError(f"expected one of: {', '.join(ANGLE_UNITS)}, got "
                         f"{doc.get('angle_unit', 'nothing')!r}", path=path, field="angle_unit")
    scale = np.where(robot.revolute, ANGLE_UNITS[doc["angle_unit"]], 1.0)
    limits_table = table_of(doc.get("limits", {}), path, "limits")
    check_keys(limits_table, LIMIT_KEYS, path, "limits")
    limits = {key: frozen(_per_joint(value, robot, path, f"limits.{key}", scale,
                                     doc["angle_unit"]))
              for key, value in limits_table.items()}
    sections = {name: table_of(doc.get(name, {}), path, name) for name in _SECTIONS}
    for name, keys in _SECTIONS.items():
        check_keys(sections[name], keys, path, name)
    sizing, duty = sections["sizing"], sections["duty"]
    names = {key: _names(sizing[key], path, f"sizing.{key}") for key in ("joints", "exclude")
             if key in sizing}
    return EnvelopeFile(
        path=path, robot_file=_robot_file(doc, path), angle_unit=doc["angle_unit"],
        limits=limits,
        mounting=mounting_of(doc, path, ANGLE_UNITS[doc["angle_unit"]], doc["angle_unit"]),
        payload=payload_table(doc["payload"], path) if "payload" in doc else None,
        joints=names.get("joints"), exclude=names.get("exclude", ()),
        bearing_offset=bearing_offsets(doc, path, robot),
        **file_options(doc, path, "envelope", robot.joint_names),
        duty=_duty_file(duty, path), moves=_whole(duty, "moves", path, 1, MAX_DUTY_MOVES),
        seed=_whole(duty, "seed", path, 0, 2**63 - 1))


def _per_joint(value: Any, robot: Robot, path: Path, field: str, scale: np.ndarray,
               angle_unit: str) -> np.ndarray:
    """One limit per joint in SI, NaN where a table leaves a joint out."""
    kind = field.split(".")[-1]
    bound = bounds.MOTION_LIMITS[kind]
    power = {"velocity": "/s", "acceleration": "/s^2", "jerk": "/s^3"}[kind]
    units = [(angle_unit if r else "m") + power for r in robot.revolute]

    def read(raw: Any, j: int, where: str) -> float:
        return as_number(raw, path, where, bound=bound, scale=float(scale[j]),
                         unit=units[j]) * float(scale[j])

    out = np.full(robot.dof, np.nan)
    if isinstance(value, dict):
        for name, raw in value.items():
            if name in robot.mimic:
                raise InputError(f"joint '{name}' follows '{robot.mimic[name].leader}' (mimic);"
                                 " give its leader instead", path=path, field=f"{field}.{name}")
            j = robot.joint_index(name, source=path, field=f"{field}.{name}")
            out[j] = read(raw, j, f"{field}.{name}")
    elif isinstance(value, list):
        if len(value) != robot.dof:
            raise InputError(f"expected {robot.dof} values (list order: "
                             f"{', '.join(robot.joint_names)}), got {len(value)}", path=path,
                             field=field)
        out[:] = [read(raw, j, f"{field}[{j}]") for j, raw in enumerate(value)]
    else:
        out[:] = [read(value, j, field) for j in range(robot.dof)]
    return out


def _robot_file(doc: dict[str, Any], path: Path) -> Path | None:
    if "robot" not in doc:
        return None
    if not isinstance(doc["robot"], str):
        raise InputError("expected a file name", path=path, field="robot")
    found = path.parent / doc["robot"]
    if not found.is_file():
        raise InputError(f"robot file not found: {found}", path=path, field="robot")
    return found


def _duty_file(table: dict[str, Any], path: Path) -> Path | None:
    if "motion" not in table:
        return None
    if "moves" in table or "seed" in table:
        raise InputError("a duty is a motion file or the default random moves, not both; "
                         "remove moves and seed, or motion", path=path, field="duty.motion")
    if not isinstance(table["motion"], str):
        raise InputError("expected a file name", path=path, field="duty.motion")
    found = path.parent / table["motion"]
    if not found.is_file():
        raise InputError(f"duty file not found: {found}", path=path, field="duty.motion")
    return found


def _whole(table: dict[str, Any], key: str, path: Path, low: int, high: int) -> int | None:
    if key not in table:
        return None
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"expected a whole number in [{low}, {high}], got {value!r}",
                         path=path, field=f"duty.{key}")
    return value


def _names(value: Any, path: Path, field: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise InputError(f"expected a list of joint names, got {value!r}", path=path,
                         field=field)
    return tuple(value)
