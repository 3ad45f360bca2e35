"""The duty-wide values of a mix file, and how they compare with its motion files'.

A mix file's ``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]`` tables give
what belongs to the whole duty: the sized joints, the selection order and assumptions,
the stop time, the required life and design margin, the motors. Its motion files may
give the same values; `hdselect.motion.mixfile.Mix.duty_value` settles them.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hdselect.base.errors import InputError
from hdselect.base.tomlfile import check_keys, table_of
from hdselect.catalog.builtin import catalog_file
from hdselect.motion.motionfile import Motion
from hdselect.motion.motor_tables import motion_file_motors
from hdselect.motion.option_specs import EVERY_JOINT, OPTION, OPTIONS, file_keys, file_options
from hdselect.motion.sizing_table import bearing_offsets, chosen_joints
from hdselect.robot.model import Robot

SIZING_KEYS = ("joints", "exclude", "catalog", *file_keys("mix", "sizing"))
"""The keys of a mix file's ``[sizing]``."""
MOTION_FIELD = {**{option.name: str(option.key) for option in OPTIONS
                   if {"mix", "motion"} <= set(option.files)},
                "joints": "sizing.joints", "exclude": "sizing.exclude", "motors": "motor"}
"""Where a motion file gives each duty-wide value (the options both files give, the sized
joints and the motors): the mix file gives it in the same place."""
SECTION_OF = {name: field.split(".")[0] for name, field in MOTION_FIELD.items()}
"""Where each duty-wide value a motion file may also give lives in the mix file."""


def duty_tables(doc: dict[str, Any], path: Path,
                 robot: Robot) -> tuple[dict[str, Any], tuple[Path, ...]]:
    """The duty-wide values of ``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]``."""
    for table in ("safety", "requirements", "precision"):
        check_keys(table_of(doc.get(table, {}), path, table), file_keys("mix", table), path,
                   table)
    sizing = table_of(doc.get("sizing", {}), path, "sizing")
    check_keys(sizing, SIZING_KEYS, path, "sizing")
    given: dict[str, Any] = file_options(doc, path, "mix", robot.joint_names)
    given.update(chosen_joints(sizing, path, robot))
    offsets = bearing_offsets(doc, path, robot)
    if offsets:
        given["bearing_offset"] = offsets
    catalog: list[Path] = []
    if "catalog" in sizing:
        files = sizing["catalog"] if isinstance(sizing["catalog"], list) else [sizing["catalog"]]
        for i, file in enumerate(files):
            if not isinstance(file, str) or not file:
                raise InputError(f"catalog file not found: {file!r}", path=path,
                                 field=f"sizing.catalog[{i}]")
            catalog.append(catalog_file(file, base=path.parent, path=path,
                                        field=f"sizing.catalog[{i}]"))
    if "motor" in doc:
        given["motors"] = motion_file_motors(doc["motor"], path, robot)
        given["motor_joints"] = tuple(key for key, block in doc["motor"].items()
                                      if isinstance(block, dict) and key != "curve")
    return given, tuple(catalog)


def motion_value(motion: Motion, name: str) -> Any:
    """A motion file's duty-wide value, None where it gives none.

    None too for a name not in `MOTION_FIELD`: an option only a mix file gives.
    """
    if name not in MOTION_FIELD:
        return None
    if name == "joints":
        return motion.sized_joints
    if name == "exclude":
        return motion.excluded_joints or None
    value = getattr(motion, name)
    return None if isinstance(value, Mapping) and not value else value


def comparable(value: Any) -> Any:
    """A duty-wide value in a form two files' values compare in (motors by id and file)."""
    if isinstance(value, Mapping):  # motors by joint, or offsets by joint [m]
        return {joint: tuple((m.id, str(m.source)) for m in item) if isinstance(item, tuple)
                else item for joint, item in value.items()}
    if isinstance(value, list | tuple):
        return tuple(value)
    return value


def shown(value: Any, name: str | None = None) -> str:
    """A duty-wide value as a message shows it (option `name`'s in its files' unit)."""
    option = OPTION.get(name) if name is not None else None
    if option is not None and option.scale != 1.0:  # SI inside, arcmin or mm in the files
        value = ({k: v / option.scale for k, v in value.items()}
                 if isinstance(value, Mapping) else value / option.scale)
    if isinstance(value, Mapping) and set(value) == {EVERY_JOINT}:
        value = value[EVERY_JOINT]  # given as one value for every joint
    if isinstance(value, Mapping) and all(isinstance(item, float) for item in value.values()):
        return "{" + ", ".join(f"{joint} = {item:g}" for joint, item in value.items()) + "}"
    if isinstance(value, Mapping):
        return "motors " + "; ".join(f"{joint}: {', '.join(m.id for m in motors)}"
                                     for joint, motors in value.items())
    if isinstance(value, list | tuple):
        return "[" + ", ".join(map(str, value)) + "]"
    return f"{value:g}" if isinstance(value, float) else str(value)
