"""The sizing core's arguments checked once: units, motors per joint, a trajectory's arrays."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TypedDict

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError, deprecated
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.motion.option_specs import EVERY_JOINT
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.sizing.options import Options
from hdselect.sizing.result import Motors


class OptionValues(TypedDict, total=False):
    """The fields of `Options` as keyword arguments (``hdselect.size(..., stop_time=0.15)``).

    Each is the `Options` field of its name, in its units; None means not given (the
    files' value, else the default).
    """

    stop_time: float | None
    efficiency: float | None
    rotor_inertia: float | None
    motor_mass: float | None
    mass_coupling: bool | None
    prefer: str | None
    life_hours: float | None
    life_basis: str | None
    threads: int | None
    max_samples: int | None
    margin: float | None
    max_inertia_ratio: float | None
    inertia_target: float | None
    bearing_offset: Mapping[str, float] | None
    bearing_loads: bool | None
    max_torsion: float | Mapping[str, float] | None
    min_natural_frequency: float | str | Mapping[str, float | str] | None
    max_tool_deflection: float | None
    min_arm_frequency: float | str | None
    precision: bool | None


def not_sized(robot: Robot, name: str, field: str) -> InputError:
    """The refusal of a joint named where a sized joint is wanted: unknown, or not sized."""
    what = (f"'{name}' is not a sized joint" if name in robot.joint_names
            else f"unknown joint '{name}'")
    return InputError(f"{what}; sized joints are: {', '.join(robot.sized_joints)}", field=field)


def checked_motors(robot: Robot, motors: Motors | Mapping[str, Motor] | None,
                   options: Options) -> dict[str, tuple[Motor, ...]]:
    """The candidate motors per sized joint, checked; empty when none are given.

    Args:
        robot: The robot as sized.
        motors: Candidate motors per joint name (a single `Motor` is one candidate).
        options: The assumptions: with motors, their rotor inertia and motor mass must
            not be given too.

    Returns:
        Joint name -> its candidate motors, in the order given.

    Raises:
        InputError: A joint is not sized, has no motor or a motor id twice, or the
            options give a rotor inertia or motor mass beside the motors.
    """
    if not motors:
        return {}
    if isinstance(motors, str | Path) or not isinstance(motors, Mapping):
        raise InputError("expected a mapping of joint name to candidate motors",
                         field="motors")
    checked: dict[str, tuple[Motor, ...]] = {}
    for name, given in motors.items():
        if name not in robot.sized_joints:
            raise InputError(f"'{name}' is not a sized joint; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field=f"motors.{name}")
        candidates = (given,) if isinstance(given, Motor) else tuple(given)
        if not candidates or not all(isinstance(m, Motor) for m in candidates):
            raise InputError("expected one or more hdselect.catalog.motors.Motor",
                             field=f"motors.{name}")
        ids = [m.id for m in candidates]
        for motor_id in ids:
            if ids.count(motor_id) > 1:
                raise InputError(f"motor id '{motor_id}' is given twice",
                                 field=f"motors.{name}")
        checked[name] = candidates
    if options.rotor_inertia > 0.0 or options.motor_mass > 0.0:
        raise InputError("motor data is given, so the rotor inertia and motor mass come from "
                         "the motors; drop rotor_inertia and motor_mass (--motor-inertia, "
                         "--motor-mass)", field="motors")
    return checked


def units_argument(units: object, field: str = "units") -> tuple[Unit, ...]:
    """Loaded catalog units given as the argument `field`, as a tuple.

    Raises:
        InputError: It is not a sequence of `hdselect.catalog.units.Unit`.
    """
    if isinstance(units, str | bytes | Path) or not isinstance(units, Sequence):
        raise InputError(f"expected a sequence of catalog units, got {type(units).__name__}",
                         field=field)
    for unit in units:
        expect_type(unit, (Unit,), field, "catalog units (hdselect.load_catalog)")
    return tuple(units)


def loaded_units(catalog: object) -> tuple[Unit, ...]:
    """The units of a loaded `catalog` argument; None is the built-in catalog.

    Raises:
        InputError: It is not a sequence of `hdselect.catalog.units.Unit`, or it is empty.
    """
    units = load_catalog() if catalog is None else units_argument(catalog, "catalog")
    if not units:
        raise InputError("no gearhead to choose from", field="catalog")
    return units


def check_trajectory(trajectory: Trajectory) -> None:
    """A trajectory's arrays agree in shape and hold finite numbers.

    Raises:
        InputError: They do not (the field names the array).
    """
    n, dof = len(trajectory.t), len(trajectory.joint_names)
    if not (isinstance(trajectory.dt, float | int) and math.isfinite(trajectory.dt)
            and trajectory.dt > 0.0):
        raise InputError(f"must be a positive time [s], got {trajectory.dt!r}",
                         field="trajectory.dt")
    for name, shape in (("t", (n,)), ("q", (n, dof)), ("qd", (n, dof)), ("qdd", (n, dof))):
        array = np.asarray(getattr(trajectory, name))
        if array.shape != shape or n == 0:
            raise InputError(f"expected shape {shape} with n >= 1, got {array.shape}",
                             field=f"trajectory.{name}")
        if not np.all(np.isfinite(array)):
            raise InputError("holds a number that is not finite", field=f"trajectory.{name}")


def check_joint_options(robot: Robot, options: Options) -> None:
    """The joints the options name (bearing offsets, per-joint targets) are sized joints.

    Raises:
        InputError: One is not; the field is the option and the joint.
    """
    for option in ("bearing_offset", "max_torsion", "min_natural_frequency"):
        for name in getattr(options, option):
            if name not in robot.sized_joints and name != EVERY_JOINT:
                raise InputError(f"'{name}' is not a sized joint; sized joints are: "
                                 f"{', '.join(robot.sized_joints)}", field=f"{option}.{name}")


def check_bearing_options(robot: Robot, units: Iterable[Unit], options: Options) -> None:
    """The options' joints are sized joints, and the bearing loads are on where needed.

    Raises:
        InputError: A joint an option names is not sized (`check_joint_options`), or
            ``bearing_loads`` is off while a candidate unit's catalog rates its bearing.
    """
    check_joint_options(robot, options)
    if not options.bearing_loads:
        rated = sorted({unit.id for unit in units if unit.bearing is not None})
        if rated:
            raise InputError(f"the bearing loads are off, but {', '.join(rated)} rate their "
                             "output bearing: its checks need the loads", field="bearing_loads")


def fixed_units(given: Mapping[str, Unit | str] | None, catalog: Sequence[Unit],
                robot: Robot) -> dict[str, Unit]:
    """The units given per joint (ids resolved in the catalog).

    Raises:
        InputError: Not a mapping, a name is not a sized joint, or an id is unknown.
    """
    if given is None:
        return {}
    if isinstance(given, str) or not isinstance(given, Mapping):
        raise InputError(f"expected a mapping of joint names to units or unit ids, got "
                         f"{type(given).__name__}", field="units")
    by_id = {unit.id: unit for unit in catalog}
    out: dict[str, Unit] = {}
    for name, unit in given.items():
        if name not in robot.sized_joints:
            raise not_sized(robot, name, "units")
        if isinstance(unit, str):
            if unit not in by_id:
                raise InputError(f"unknown unit '{unit}' for joint '{name}'; units are: "
                                 f"{', '.join(by_id)}", field="units")
            unit = by_id[unit]
        if not isinstance(unit, Unit):
            raise InputError(f"expected a catalog unit or unit id for joint '{name}', got "
                             f"{type(unit).__name__}", field="units")
        out[name] = unit
    return out


def units_as_catalog(units: object, catalog: object, call: str) -> tuple[Unit, ...]:
    """The deprecated ``units=`` of `call` (a loaded catalog), checked, as its ``catalog``.

    Raises:
        InputError: It is not units, it is empty, or `catalog` is given too.
    """
    checked = units_argument(units)
    if not checked:
        raise InputError("no gearhead to choose from", field="units")
    if catalog:
        raise InputError("give either catalog or units (its old spelling), not both",
                         field="units")
    deprecated(f"{call}(units=...)", f"{call}(catalog=...) with the loaded units", depth=2)
    return checked


def options_argument(options: object, values: Mapping[str, object]) -> None:
    """The assumptions come either whole (`options`) or as keywords, not both.

    Raises:
        InputError: `options` is not an `Options` or None, or keywords are given beside it.
    """
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    given = [name for name, value in values.items() if value is not None]
    if options is not None and given:
        raise InputError("give either options (an Options) or option keywords, not both",
                         field=given[0])
