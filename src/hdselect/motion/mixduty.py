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

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, table_of
from hdselect.catalog.select import PREFERENCES
from hdselect.motion.motionfile import LIFE_BASES, Motion
from hdselect.motion.motor_tables import motion_file_motors
from hdselect.motion.sizing_table import chosen_joints
from hdselect.robot.model import Robot

SIZING_KEYS = ("joints", "exclude", "catalog", "prefer", "efficiency", "mass_coupling",
               "rotor_inertia", "motor_mass")
"""The keys of a mix file's ``[sizing]``."""
SECTION_OF = {"stop_time": "safety", "life_hours": "requirements",
              "life_basis": "requirements", "margin": "requirements", "joints": "sizing",
              "exclude": "sizing", "motors": "motor"}
"""Where each duty-wide value a motion file may also give lives in the mix file."""
MOTION_FIELD = {"stop_time": "safety.stop_time", "life_hours": "requirements.life_hours",
                "life_basis": "requirements.life_basis", "margin": "requirements.margin",
                "joints": "sizing.joints", "exclude": "sizing.exclude", "motors": "motor"}
"""Where a motion file gives each duty-wide value."""


def duty_tables(doc: dict[str, Any], path: Path,
                 robot: Robot) -> tuple[dict[str, Any], tuple[Path, ...]]:
    """The duty-wide values of ``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]``."""
    given: dict[str, Any] = {}
    safety = table_of(doc.get("safety", {}), path, "safety")
    check_keys(safety, ("stop_time",), path, "safety")
    if "stop_time" in safety:
        given["stop_time"] = as_number(safety["stop_time"], path, "safety.stop_time",
                                       bound=bounds.STOP_TIME)
    needs = table_of(doc.get("requirements", {}), path, "requirements")
    check_keys(needs, ("life_hours", "life_basis", "margin"), path, "requirements")
    for key, bound in (("life_hours", bounds.LIFE), ("margin", bounds.MARGIN)):
        if key in needs:
            given[key] = as_number(needs[key], path, f"requirements.{key}", bound=bound)
    if "life_basis" in needs:
        if needs["life_basis"] not in LIFE_BASES:
            raise InputError(f"unknown value {needs['life_basis']!r}; choose one of: "
                             f"{', '.join(LIFE_BASES)}", path=path,
                             field="requirements.life_basis")
        given["life_basis"] = needs["life_basis"]
    sizing = table_of(doc.get("sizing", {}), path, "sizing")
    check_keys(sizing, SIZING_KEYS, path, "sizing")
    given.update(chosen_joints(sizing, path, robot))
    if "prefer" in sizing:
        if sizing["prefer"] not in PREFERENCES:
            raise InputError(f"unknown order {sizing['prefer']!r}; choose one of: "
                             f"{', '.join(PREFERENCES)}", path=path, field="sizing.prefer")
        given["prefer"] = sizing["prefer"]
    if "mass_coupling" in sizing:
        if not isinstance(sizing["mass_coupling"], bool):
            raise InputError(f"expected true or false, got {sizing['mass_coupling']!r}",
                             path=path, field="sizing.mass_coupling")
        given["mass_coupling"] = sizing["mass_coupling"]
    for key, bound in (("efficiency", bounds.EFFICIENCY), ("rotor_inertia", bounds.ROTOR_INERTIA),
                       ("motor_mass", bounds.ADDED_MASS)):
        if key in sizing:
            given[key] = as_number(sizing[key], path, f"sizing.{key}", bound=bound)
    catalog: list[Path] = []
    if "catalog" in sizing:
        files = sizing["catalog"] if isinstance(sizing["catalog"], list) else [sizing["catalog"]]
        for i, file in enumerate(files):
            if not isinstance(file, str) or not (path.parent / file).is_file():
                raise InputError(f"catalog file not found: {file!r}", path=path,
                                 field=f"sizing.catalog[{i}]")
            catalog.append(path.parent / file)
    if "motor" in doc:
        given["motors"] = motion_file_motors(doc["motor"], path, robot)
        given["motor_joints"] = tuple(key for key, block in doc["motor"].items()
                                      if isinstance(block, dict) and key != "curve")
    return given, tuple(catalog)


def motion_value(motion: Motion, name: str) -> Any:
    """A motion file's duty-wide value (a `MOTION_FIELD` name), None where it gives none."""
    if name == "joints":
        return motion.sized_joints
    if name == "exclude":
        return motion.excluded_joints or None
    return getattr(motion, name)


def comparable(value: Any) -> Any:
    """A duty-wide value in a form two files' values compare in (motors by id and file)."""
    if isinstance(value, Mapping):
        return {joint: tuple((m.id, str(m.source)) for m in motors)
                for joint, motors in value.items()}
    if isinstance(value, list | tuple):
        return tuple(value)
    return value


def shown(value: Any) -> str:
    """A duty-wide value as a message shows it."""
    if isinstance(value, Mapping):
        return "motors " + "; ".join(f"{joint}: {', '.join(m.id for m in motors)}"
                                     for joint, motors in value.items())
    if isinstance(value, list | tuple):
        return "[" + ", ".join(map(str, value)) + "]"
    return f"{value:g}" if isinstance(value, float) else str(value)
