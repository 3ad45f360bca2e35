"""A motion file's ``[sizing]`` table: which joints get a gearhead, where their flanges sit."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hdselect.base.errors import InputError
from hdselect.base.tomlfile import check_keys, table_of
from hdselect.motion.option_specs import OPTION, file_keys
from hdselect.robot.model import Robot

SIZING_KEYS = ("joints", "exclude", *file_keys("motion", "sizing"))
"""The keys of a motion file's ``[sizing]``."""


def sizing_joints(doc: dict[str, Any], path: Path, robot: Robot) -> dict[str, tuple[str, ...]]:
    """The ``[sizing]`` table: joints to size and to leave out, checked against the robot.

    Raises:
        InputError: An unknown key, a list that is not of joint names, or a choice the
            robot refuses (`Robot.with_sized_joints`).
    """
    table = table_of(doc.get("sizing", {}), path, "sizing")
    check_keys(table, SIZING_KEYS, path, "sizing")
    return chosen_joints(table, path, robot)


def chosen_joints(table: dict[str, Any], path: Path, robot: Robot) -> dict[str, tuple[str, ...]]:
    """``joints`` and ``exclude`` of a checked ``[sizing]`` table, checked against the robot.

    The table is a motion file's or a mix file's, its keys already checked.

    Raises:
        InputError: A list that is not of joint names, or a choice the robot refuses
            (`Robot.with_sized_joints`).
    """
    names: dict[str, tuple[str, ...]] = {}
    for key in ("joints", "exclude"):
        if key in table:
            value = table[key]
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise InputError(f"expected a list of joint names, got {value!r}", path=path,
                                 field=f"sizing.{key}")
            names[key] = tuple(value)
    if names:
        try:
            robot.with_sized_joints(names.get("joints"), names.get("exclude", ()))
        except InputError as err:
            raise InputError(err.reason, path=path, field=f"sizing.{err.field}") from err
    return names


def bearing_offsets(doc: dict[str, Any], path: Path, robot: Robot) -> dict[str, float]:
    """``[sizing] bearing_offset_m``: each named rotary joint's flange along its axis [m].

    Raises:
        InputError: A name is not a joint, or a prismatic one, or an offset is out of range.
    """
    option = OPTION["bearing_offset"]
    where = str(option.key)
    section, key = where.split(".")
    table = table_of(table_of(doc.get(section, {}), path, section).get(key, {}), path, where)
    for name in table:
        j = robot.joint_index(name, source=path, field=f"{where}.{name}")
        if not robot.revolute[j]:
            raise InputError(f"joint '{name}' is prismatic; only rotary joints take a gearhead "
                             "and its bearing", path=path, field=f"{where}.{name}")
    return option.check(table, path=path, field=where)
