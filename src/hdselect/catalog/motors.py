"""Motors: TOML files of servo or frameless motors, loaded into immutable SI records.

A motor is checked against what it must deliver behind a gearhead (`hdselect.catalog.motor_rules`):
every sample's (input speed, motor torque) under its peak torque-speed limit, the
cycle's RMS torque against its rated (continuous) torque, and the largest input speed
against its maximum. Speeds are in rpm, as datasheets give them; everything else SI.

A motor file holds ``[[motor]]`` entries; a motion file may give one motor's data inline
(`motor_from_table`). Every value is validated by `Motor` itself, so a Python caller and
a file go through the same checks.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.catalog.units import KG_M2_PER_KG_CM2

# Motor field -> its key in a file, and the factor from the file's unit to SI
_KEYS = {
    "rated_torque": ("rated_torque_nm", 1.0),
    "peak_torque": ("peak_torque_nm", 1.0),
    "max_speed": ("max_speed_rpm", 1.0),
    "rated_speed": ("rated_speed_rpm", 1.0),
    "mass": ("mass_kg", 1.0),
    "torque_constant": ("torque_constant_nm_per_a", 1.0),
    "resistance": ("resistance_ohm", 1.0),
}
_INERTIA_KEYS = (("rotor_inertia_kg_cm2", KG_M2_PER_KG_CM2), ("rotor_inertia_kg_m2", 1.0))
_OPTIONAL = ("torque_constant", "resistance")
_BOUNDS = {"rated_torque": bounds.MOTOR_TORQUE, "peak_torque": bounds.MOTOR_TORQUE,
           "max_speed": bounds.MOTOR_SPEED, "rated_speed": bounds.MOTOR_SPEED,
           "rotor_inertia": bounds.ROTOR_INERTIA, "mass": bounds.ADDED_MASS,
           "torque_constant": bounds.TORQUE_CONSTANT, "resistance": bounds.RESISTANCE}
"""The physical range of each number of a motor (`hdselect.base.bounds`)."""
MOTOR_KEYS = ("id", *(key for key, _ in _KEYS.values()), *(key for key, _ in _INERTIA_KEYS),
              "curve", "max_inertia_ratio")
"""Keys of one motor's table, in a motor file or inline in a motion file."""
_CURVE_KEYS = ("speed_rpm", "peak_torque_nm")
_CURVE_TOLERANCE = 1e-9
"""Relative slack when comparing the curve with the motor's own peak and rated torque."""


@dataclass(frozen=True)
class Motor:
    """One motor, in SI (speeds in rpm).

    Attributes:
        id: Motor id, unique within its file.
        rated_torque: Rated (continuous) torque [N m]: the limit for the cycle's RMS torque.
        peak_torque: Peak torque [N m]: the limit for any sample without a curve, and the
            largest value a curve may reach.
        max_speed: Maximum speed [rpm].
        rated_speed: Speed at which the rated torque is given [rpm], at most `max_speed`.
        rotor_inertia: Rotor inertia J_m [kg m^2], zero or positive.
        mass: Mass carried with the gearhead [kg], zero or positive.
        torque_constant: Torque constant k_t [N m/A], or None; gives the current figures.
        resistance: Winding (terminal) resistance [ohm], or None; with k_t, the copper loss.
        curve: Peak torque over speed, points (speed [rpm], peak torque [N m]) with the
            speeds strictly increasing from 0 to at least `max_speed`, interpolated
            linearly; None for a flat `peak_torque` up to `max_speed`.
        source: The file it came from, or None.
        max_inertia_ratio: Largest load-to-rotor inertia ratio a pair with this motor may
            have [-] (the file's ``max_inertia_ratio``, for every motor of it, or the
            motor's own), or None for no such limit; ``--max-inertia-ratio`` overrides it.

    Raises:
        InputError: A value is missing, not a finite number, out of its range in
            `hdselect.base.bounds`, or the curve is not a function of speed; the field is the
            attribute's name.
    """

    id: str
    rated_torque: float
    peak_torque: float
    max_speed: float
    rated_speed: float
    rotor_inertia: float
    mass: float
    torque_constant: float | None = None
    resistance: float | None = None
    curve: tuple[tuple[float, float], ...] | None = None
    source: Path | None = None
    max_inertia_ratio: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.id, str) or not self.id.strip():
            raise InputError(f"expected a non-empty name, got {self.id!r}", field="id")
        if self.max_inertia_ratio is not None:
            _set(self, "max_inertia_ratio", bounds.INERTIA_RATIO.check(
                self.max_inertia_ratio, field="max_inertia_ratio"))
        for name, bound in _BOUNDS.items():
            if name not in _OPTIONAL or getattr(self, name) is not None:
                _set(self, name, bound.check(getattr(self, name), field=name))
        if self.peak_torque < self.rated_torque:
            raise InputError(f"the peak torque {self.peak_torque:.4g} N m is below the rated "
                             f"torque {self.rated_torque:.4g} N m", field="peak_torque")
        if self.rated_speed > self.max_speed:
            raise InputError(f"the rated speed {self.rated_speed:g} rpm is above the maximum "
                             f"speed {self.max_speed:g} rpm", field="rated_speed")
        if self.curve is not None:
            _set(self, "curve", self._checked_curve(self.curve))

    def peak_torque_at(self, speed_rpm: np.ndarray) -> np.ndarray:
        """The peak torque the motor can give at each speed [N m] (sign of speed ignored).

        Args:
            speed_rpm: Speeds [rpm], any shape.

        Returns:
            The curve interpolated linearly (held at its last value beyond its last
            point), or the flat peak torque without a curve; the shape of `speed_rpm`.
        """
        speed = np.abs(np.asarray(speed_rpm, dtype=float))
        if self.curve is None:
            return np.full(speed.shape, self.peak_torque)
        speeds, torques = zip(*self.curve, strict=True)
        return np.interp(speed, speeds, torques)

    def _checked_curve(self, curve: Any) -> tuple[tuple[float, float], ...]:
        if not isinstance(curve, Sequence) or isinstance(curve, str) or len(curve) < 2:
            raise InputError("expected at least two points (speed [rpm], peak torque [N m])",
                             field="curve")
        points = []
        for i, point in enumerate(curve):
            if not isinstance(point, Sequence) or isinstance(point, str) or len(point) != 2:
                raise InputError(f"point {i}: expected (speed [rpm], peak torque [N m]), got "
                                 f"{point!r}", field="curve")
            speed = bounds.CURVE_SPEED.check(point[0], field=f"curve[{i}].speed")
            torque = bounds.CURVE_TORQUE.check(point[1], field=f"curve[{i}].peak_torque")
            points.append((float(speed), float(torque)))
        for i, ((a, _), (b, _)) in enumerate(zip(points, points[1:], strict=False)):
            if b <= a:
                raise InputError(f"not a function of speed: point {i + 1} has speed {b:g} rpm "
                                 f"after {a:g} rpm; speeds must strictly increase",
                                 field="curve")
        if points[0][0] != 0.0:
            raise InputError(f"must start at 0 rpm (it starts at {points[0][0]:g} rpm); give "
                             "the peak torque at standstill first", field="curve")
        if points[-1][0] < self.max_speed:
            raise InputError(f"ends at {points[-1][0]:g} rpm, below the maximum speed "
                             f"{self.max_speed:g} rpm; extend it to the maximum speed",
                             field="curve")
        top = max(torque for _, torque in points)
        if top > self.peak_torque * (1.0 + _CURVE_TOLERANCE):
            raise InputError(f"reaches {top:.4g} N m, above the peak torque "
                             f"{self.peak_torque:.4g} N m", field="curve")
        speeds, torques = zip(*points, strict=True)
        at_rated = float(np.interp(self.rated_speed, speeds, torques))
        if at_rated < self.rated_torque * (1.0 - _CURVE_TOLERANCE):
            raise InputError(f"gives {at_rated:.4g} N m at the rated speed "
                             f"{self.rated_speed:g} rpm, below the rated torque "
                             f"{self.rated_torque:.4g} N m", field="curve")
        return tuple(points)


def load_motors(path: str | Path) -> tuple[Motor, ...]:
    """Read a motor file: ``[[motor]]`` entries, each a motor's table (see `MOTOR_KEYS`).

    A top-level ``max_inertia_ratio`` is the largest load-to-rotor inertia ratio of every
    motor of the file that gives none of its own (`Motor.max_inertia_ratio`).

    Args:
        path: The motor file (TOML).

    Returns:
        Its motors, in the file's order.

    Raises:
        InputError: The file is missing or malformed, a value is missing or not physical,
            a curve is not a function of speed, or two motors share an id; the message
            names the file and the field.
    """
    path = bounds.file_argument(path, "path")
    document = read_toml(path)
    check_keys(document, ["source", "motor", "max_inertia_ratio"], path, "")
    if "source" in document and not isinstance(document["source"], str):
        raise InputError("expected a text describing where the values come from", path=path,
                         field="source")
    largest = (as_number(document["max_inertia_ratio"], path, "max_inertia_ratio",
                         bound=bounds.INERTIA_RATIO)
               if "max_inertia_ratio" in document else None)
    entries = document.get("motor")
    if not isinstance(entries, list) or not entries:
        raise InputError("no [[motor]] entries", path=path, field="motor")
    motors: list[Motor] = []
    for i, entry in enumerate(entries):
        table = table_of(entry, path, f"motor[{i}]")
        if "id" not in table:
            raise InputError("required key is missing", path=path, field=f"motor[{i}].id")
        motor = motor_from_table(table, path, f"motor[{table['id']}]")
        if largest is not None and motor.max_inertia_ratio is None:
            motor = replace(motor, max_inertia_ratio=largest)
        if any(other.id == motor.id for other in motors):
            raise InputError(f"motor id '{motor.id}' appears more than once", path=path,
                             field=f"motor[{motor.id}].id")
        motors.append(motor)
    return tuple(motors)


def motor_from_table(table: Mapping[str, Any], path: Path, where: str, *,
                     default_id: str | None = None) -> Motor:
    """One motor from its TOML table (a motor file's entry, or inline in a motion file).

    Args:
        table: The motor's keys (`MOTOR_KEYS`).
        path: The file, for messages.
        where: The table's dotted location in the file, for messages.
        default_id: The id when the table gives none; None makes ``id`` required.

    Returns:
        The motor, its `Motor.source` the file.

    Raises:
        InputError: A key is unknown or missing, or a value is not physical.
    """
    check_keys(table, MOTOR_KEYS, path, where)
    motor_id = table.get("id", default_id)
    if motor_id is None:
        raise InputError("required key is missing", path=path, field=f"{where}.id")
    if not isinstance(motor_id, str) or not motor_id.strip():
        raise InputError(f"expected a non-empty name, got {motor_id!r}", path=path,
                         field=f"{where}.id")
    values: dict[str, Any] = {}
    for name, (key, factor) in _KEYS.items():
        if key in table:
            values[name] = as_number(table[key], path, f"{where}.{key}") * factor
        elif name not in _OPTIONAL:
            raise InputError("required key is missing", path=path, field=f"{where}.{key}")
    given = [(key, factor) for key, factor in _INERTIA_KEYS if key in table]
    if len(given) != 1:
        keys = " or ".join(key for key, _ in _INERTIA_KEYS)
        raise InputError(f"give exactly one of {keys}", path=path,
                         field=f"{where}.{given[-1][0] if given else _INERTIA_KEYS[0][0]}")
    key, factor = given[0]
    values["rotor_inertia"] = as_number(  # checked as given: kg cm^2 may underflow to 0
        table[key], path, f"{where}.{key}", bound=bounds.ROTOR_INERTIA, scale=factor,
        unit="kg cm^2" if factor != 1.0 else None) * factor
    if "max_inertia_ratio" in table:
        values["max_inertia_ratio"] = as_number(table["max_inertia_ratio"], path,
                                                f"{where}.max_inertia_ratio",
                                                bound=bounds.INERTIA_RATIO)
    if "curve" in table:
        values["curve"] = _curve(table_of(table["curve"], path, f"{where}.curve"), path,
                                 f"{where}.curve")
    try:
        return Motor(id=motor_id, source=path, **values)
    except InputError as err:
        raise InputError(err.reason, path=path,
                         field=f"{where}.{_file_key(str(err.field), key)}") from err


def _curve(table: Mapping[str, Any], path: Path, where: str) -> list[tuple[float, float]]:
    """The curve's two lists as points; their values are checked by `Motor`."""
    check_keys(table, _CURVE_KEYS, path, where)
    columns = []
    for key in _CURVE_KEYS:
        raw = table.get(key)
        if not isinstance(raw, list) or not raw:
            raise InputError("expected a non-empty list of numbers", path=path,
                             field=f"{where}.{key}")
        columns.append([as_number(v, path, f"{where}.{key}[{i}]") for i, v in enumerate(raw)])
    speeds, torques = columns
    if len(speeds) != len(torques):
        raise InputError(f"{len(speeds)} speeds but {len(torques)} torques; give one peak "
                         "torque per speed", path=path, field=f"{where}.peak_torque_nm")
    return list(zip(speeds, torques, strict=True))


def _file_key(field: str, inertia_key: str) -> str:
    """The file's key for a `Motor` field named in an error (``curve[2].speed`` too)."""
    if field == "rotor_inertia":
        return inertia_key
    if field.startswith("curve["):
        index, part = field[len("curve["):].split("].")
        return f"curve.{'speed_rpm' if part == 'speed' else 'peak_torque_nm'}[{index}]"
    return _KEYS[field][0] if field in _KEYS else field


def _set(motor: Motor, name: str, value: object) -> None:
    object.__setattr__(motor, name, value)
