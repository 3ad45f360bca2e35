"""The ``[motor]`` tables of a motion file: a joint's motor data inline, or a motor file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hdselect.base.errors import InputError
from hdselect.base.inputfiles import is_input_file
from hdselect.base.tomlfile import check_keys, table_of
from hdselect.catalog.motors import MOTOR_KEYS, Motor, load_motors, motor_from_table
from hdselect.robot.model import Robot


def motion_file_motors(value: Any, path: Path, robot: Robot) -> Mapping[str, tuple[Motor, ...]]:
    """``[motor]`` and ``[motor.JOINT]``: the candidate motors of every rotary joint given."""
    table = table_of(value, path, "motor")
    own = {}
    for key, block in table.items():
        if isinstance(block, dict) and key != "curve":
            j = robot.joint_index(key, source=path, field=f"motor.{key}")
            if not robot.revolute[j]:
                raise InputError(f"'{key}' is a prismatic joint; gearheads and motors are "
                                 "sized for rotary joints only", path=path, field=f"motor.{key}")
            own[key] = table_of(block, path, f"motor.{key}")
    shared = {key: block for key, block in table.items() if key not in own}
    check_keys(shared, ["catalog", *MOTOR_KEYS], path, "motor")
    files: dict[Path, tuple[Motor, ...]] = {}
    shared_catalog = _motor_catalog(shared, path, "motor", files)
    every = _motor_block(shared, path, "motor", files, None) if shared else None
    motors: dict[str, tuple[Motor, ...]] = {}
    for name, revolute in zip(robot.joint_names, robot.revolute, strict=True):
        if name in own:
            check_keys(own[name], ["catalog", *MOTOR_KEYS], path, f"motor.{name}")
            motors[name] = _motor_block(own[name], path, f"motor.{name}", files, shared_catalog)
        elif every is not None and revolute:
            motors[name] = every
    return motors


def _motor_catalog(block: dict[str, Any], path: Path, where: str,
                   files: dict[Path, tuple[Motor, ...]]) -> tuple[Path, tuple[Motor, ...]] | None:
    """The motor file a block's ``catalog`` names (read once per file), or None."""
    if "catalog" not in block:
        return None
    if not isinstance(block["catalog"], str):
        raise InputError("expected a motor file name, relative to this file", path=path,
                         field=f"{where}.catalog")
    file = path.parent / block["catalog"]
    if not is_input_file(file):
        raise InputError(f"motor file not found: {file}", path=path, field=f"{where}.catalog")
    key = file.resolve()
    if key not in files:
        files[key] = load_motors(file)
    return file, files[key]


def _motor_block(block: dict[str, Any], path: Path, where: str,
                 files: dict[Path, tuple[Motor, ...]],
                 shared: tuple[Path, tuple[Motor, ...]] | None) -> tuple[Motor, ...]:
    """One block's motors: its inline motor, the motor `id` of a catalog, or the whole catalog.

    A joint's block giving only ``id`` looks it up in the ``[motor]`` block's catalog.
    """
    data = [key for key in block if key not in ("catalog", "id")]
    if data:
        if "catalog" in block:
            raise InputError("give either a catalog (and an id from it) or the motor's data, "
                             "not both", path=path, field=f"{where}.catalog")
        return (motor_from_table(block, path, where, default_id=where),)
    catalog = _motor_catalog(block, path, where, files) or shared
    if catalog is None:
        what = ("an id needs a catalog: give catalog here or in [motor]" if "id" in block else
                "give catalog (choose from its motors), catalog and id (a fixed motor), or the "
                "motor's data")
        raise InputError(what, path=path, field=f"{where}.{'id' if 'id' in block else 'catalog'}")
    file, motors = catalog
    if "id" not in block:
        return motors
    motor_id = block["id"]
    found = [motor for motor in motors if motor.id == motor_id]
    if not found:
        raise InputError(f"unknown motor id {motor_id!r}; {file.name} has: "
                         f"{', '.join(motor.id for motor in motors)}", path=path,
                         field=f"{where}.id")
    return (found[0],)
