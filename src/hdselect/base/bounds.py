"""What a valid input is: the physical range of every number, the type of every argument.

Every number that enters (a TOML or CSV file, a robot file, the command line, a
Python argument) is finite and inside the range of its kind, or it is refused
with one line naming the file, the field and the range. The ranges are wide (a
payload up to 100 t, a gear ratio up to 100,000) but finite, so no product of
two valid inputs overflows and every number written out is finite. A Python
argument of the wrong type is refused the same way, the field naming the
parameter. The limit on samples bounds the memory a run may take.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from hdselect.base.errors import InputError


@dataclass(frozen=True)
class Bound:
    """The closed range [low, high] of one kind of quantity, in SI.

    Attributes:
        what: The kind, for messages, e.g. ``"a mass"``.
        unit: Its SI unit, e.g. ``"kg"`` (empty when dimensionless).
        low: Smallest allowed value.
        high: Largest allowed value.
        low_open: True when `low` itself is not allowed (a mass must exceed 0).
        smallest: Smallest magnitude of a value that is not 0 (0: no such limit); a
            quantity that divides another (a rotor inertia) has one.
    """

    what: str
    unit: str
    low: float
    high: float
    low_open: bool = False
    smallest: float = 0.0

    def check(self, value: object, *, path: str | Path | None = None,
              field: str | None = None, scale: float = 1.0, unit: str | None = None) -> float:
        """`value` as a float, if it is a finite number in range.

        Args:
            value: The number as given.
            path: The file it came from, for the message.
            field: The key, column or option, for the message.
            scale: SI per unit of `value` (e.g. pi/180 for degrees); the range is
                checked in SI and the message states it in the given unit.
            unit: The given unit's label (default: the SI unit).

        Returns:
            The value in the unit it was given in.

        Raises:
            InputError: It is not a number, not finite, or out of range.
        """
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise InputError(f"expected a number, got {value!r}", path=path, field=field)
        try:
            number = float(value)
        except OverflowError as err:
            raise InputError("must be finite, got an integer too large for a float",
                             path=path, field=field) from err
        if not math.isfinite(number):
            raise InputError(f"must be finite, got {number}", path=path, field=field)
        si = number * scale
        if si > self.high or si < self.low or (self.low_open and si <= self.low):
            raise InputError(f"must be {self.describe(scale, unit)}, got {number:g}",
                             path=path, field=field)
        if number != 0.0 and abs(si) < self.smallest:  # si may underflow to 0
            label = self.unit if unit is None else unit
            raise InputError(f"must be 0 or at least {self.smallest / scale:g} {label}, got "
                             f"{number:g}", path=path, field=field)
        return number

    def describe(self, scale: float = 1.0, unit: str | None = None) -> str:
        """The range in words, e.g. ``a positive mass, at most 1e+05 kg``."""
        label = self.unit if unit is None else unit
        low, high = self.low / scale, self.high / scale
        suffix = f" {label}" if label else ""
        if self.low == 0.0 and self.low_open:
            return f"{_positive(self.what)}, at most {high:g}{suffix}"
        if self.low == 0.0:
            return f"{self.what} of at least 0, at most {high:g}{suffix}"
        return f"{self.what} between {low:g} and {high:g}{suffix}"


def _positive(what: str) -> str:
    """``a mass`` -> ``a positive mass``."""
    article, _, noun = what.partition(" ")
    return f"a positive {noun}" if article in ("a", "an") else f"positive {what}"


# --- bodies ------------------------------------------------------------------------------------
MASS = Bound("a mass", "kg", 0.0, 1e5, low_open=True)
"""A payload, a link, a gearhead [kg]: more than 0, at most 100 t."""
ADDED_MASS = Bound("a mass", "kg", 0.0, 1e5)
"""A motor mass carried with each gearhead [kg]: zero or more, at most 100 t."""
LENGTH = Bound("a coordinate", "m", -1e3, 1e3)
"""A coordinate of a centre of mass or a joint origin [m]: within 1 km."""
INERTIA = Bound("an inertia", "kg m^2", -1e6, 1e6)
"""An element of a rotational inertia [kg m^2]."""
ROTOR_INERTIA = Bound("an inertia", "kg m^2", 0.0, 1e3, smallest=1e-12)
"""A motor rotor inertia [kg m^2]: 0 (none given) or from 1e-12 (the load-to-rotor inertia
ratio divides by it)."""
GRAVITY = Bound("an acceleration", "m/s^2", -1e3, 1e3)
"""A component of the gravity vector [m/s^2]: within 100 g."""
MIMIC_MULTIPLIER = Bound("a multiplier", "", -1e3, 1e3)
"""A mimic follower's motion per unit of its leader's [-]: within a factor of 1000."""

# --- motion ------------------------------------------------------------------------------------
POSITION = Bound("a position", "rad", -1e6, 1e6)
"""A joint position [rad or m]."""
VELOCITY = Bound("a speed", "rad/s", -1e6, 1e6)
"""A logged joint velocity [rad/s or m/s]."""
ACCELERATION = Bound("an acceleration", "rad/s^2", -1e9, 1e9)
"""A logged joint acceleration [rad/s^2 or m/s^2]."""
MOTION_LIMITS = {
    "velocity": Bound("a speed limit", "rad/s", 1e-6, 1e6),
    "acceleration": Bound("an acceleration limit", "rad/s^2", 1e-6, 1e9),
    "jerk": Bound("a jerk limit", "rad/s^3", 1e-6, 1e12),
    "torque": Bound("a torque limit", "N m", 1e-6, 1e9),
}
"""The limits of a motion file's ``[limits]`` table, in SI per joint."""
ANGLE = Bound("an angle", "rad", -1e3, 1e3)
"""A roll, pitch or yaw angle of a tool pose or a base pose [rad]."""
POSE_POSITION_TOLERANCE = Bound("a position tolerance", "m", 1e-9, 1e-2)
"""How far a solved tool position may be from the one asked for [m]: 1 nm to 10 mm."""
POSE_ORIENTATION_TOLERANCE = Bound("an orientation tolerance", "rad", 1e-9, 0.1)
"""How far a solved tool orientation may be turned from the one asked for [rad]: up to
about 5.7 deg."""
TIME = Bound("a time", "s", 0.0, 1e12, low_open=True)
"""A sample period [s]; its samples are bounded by the sample limit, not here."""
PHASE_TIME = Bound("a time", "s", 1e-6, 1e9)
"""A phase or a momentary event of a duty profile [s]: 1 us to 30 years."""
DWELL = Bound("a time", "s", 0.0, 1e12)
"""A dwell [s]; its samples are bounded by the sample limit, not here."""
STOP_TIME = Bound("a time", "s", 1e-4, 1e3)
"""An emergency-stop and crash time [s]: 0.1 ms to about 17 minutes."""

# --- gearheads and requirements -----------------------------------------------------------------
TORQUE = Bound("a torque", "N m", 1e-4, 1e7)
"""A gearhead's rated or limit torque [N m]."""
LOAD_TORQUE = Bound("a torque", "N m", -1e7, 1e7)
"""A torque of a duty profile [N m]."""
INPUT_SPEED = Bound("a speed", "rpm", 1.0, 1e6)
"""A gearhead's rated or maximum input speed [rpm]."""
OUTPUT_SPEED = Bound("a speed", "rpm", -1e5, 1e5)
"""An output speed of a duty profile [rpm]."""
RATIO = Bound("a ratio", "", 1.0, 1e5)
"""A reduction ratio [-]."""
FRAME_SIZE = Bound("a size", "", 1.0, 1e4)
"""A gearhead frame size [-]."""
GEAR_INERTIA = Bound("an inertia", "kg m^2", 1e-12, 1e3)
"""A gearhead's input inertia [kg m^2]: from 1e-12 (1e-8 kg cm^2, far below the smallest
gearhead's, about 3e-8 kg m^2) to 1000."""
GEAR_MASS = Bound("a mass", "kg", 1e-3, 1e5)
"""A gearhead's mass [kg]: from 1 g (the smallest gearheads weigh tens of grams) to 100 t."""
EFFICIENCY = Bound("an efficiency", "", 0.01, 1.0)
"""A gear efficiency [-]: 1 % to 100 %."""
LIFE = Bound("a life", "h", 0.0, 1e12, low_open=True)
"""A required life [h]."""
RATED_LIFE = Bound("a life", "h", 1.0, 1e12)
"""A series' rated life [h]: from 1 h (catalogs rate thousands of hours); every life is
computed from it, so no life and no life utilization underflows or overflows."""
EVENTS = Bound("a count", "", 1.0, 1e12)
"""A cap on momentary events [-]."""
PERCENT = Bound("a percentage", "%", 0.0, 1e4)
"""A load in % of the rated torque."""
BEARING_LOAD = Bound("a load", "N", 1.0, 1e9)
"""An output bearing's load rating or allowable force [N]: from 1 N (the smallest
gearheads' bearings are rated for hundreds of newtons) to 1 GN. The ratings divide the
loads (the static safety C0 / P0, the life's (C / P)^(10/3)): with these bounds, and the
loads every valid robot and motion give, each stays a finite, non-zero number."""
PITCH_DIAMETER = Bound("a diameter", "m", 1e-3, 10.0)
"""An output bearing's pitch circle diameter d_p [m]: 1 mm to 10 m (gearhead bearings
span about 20 mm to 1 m). It divides the tilting moment in the equivalent loads."""
BEARING_OFFSET = Bound("a distance", "m", 0.0, 100.0)
"""A catalog's distance from the output flange to the bearing centre [m]."""
TORSIONAL_STIFFNESS = Bound("a stiffness", "N m/rad", 1.0, 1e12)
"""A gearhead's torsional stiffness K1..K3, or its output bearing's moment stiffness K_B
[N m/rad]: from 1 N m/rad (the smallest units are stiffer than 100 N m/rad) to 1e12."""
TWIST = Bound("an angle", "rad", 0.0, 0.1)
"""A gearhead's hysteresis loss or lost motion [rad]: 0 to 0.1 rad (about 344 arcmin;
catalogs give a few arcmin)."""
LOAD_FACTOR = Bound("a load factor", "", 1.0, 10.0)
"""Harmonic Drive's load factor f_w of a bearing life [-]."""
SAFETY_FACTOR = Bound("a safety factor", "", 0.1, 100.0)
"""A required static safety factor [-]."""
AXIAL_OFFSET = Bound("a position along the axis", "m", -100.0, 100.0)
"""Where a joint's output flange sits along its axis from the joint origin [m]."""
MARGIN = Bound("a margin", "", 0.0, 0.9)
"""A design margin [-]: the share of every limit kept in reserve, 0 to 90 %."""
INERTIA_RATIO = Bound("a ratio", "", 1e-3, 1e6)
"""A load-to-rotor inertia ratio [-], largest allowed or aimed at: 0.001 to 1e6 (designs
aim at 1 to 10); the ratio found is divided by it."""
TORSION_TARGET = Bound("an angle", "rad", 0.0, 0.1, low_open=True)
"""A joint's largest twist allowed [rad]: more than 0, at most 0.1 rad (about 344 arcmin;
catalogs' twists are a few arcmin)."""
FREQUENCY_TARGET = Bound("a frequency", "Hz", 0.0, 1e4, low_open=True)
"""A lowest natural frequency asked for [Hz]: more than 0, at most 10 kHz (Harmonic
Drive's application classes ask 4 to 30 Hz)."""
DEFLECTION_TARGET = Bound("a distance", "m", 0.0, 1.0, low_open=True)
"""A tool's largest deflection allowed [m]: more than 0, at most 1 m."""

# --- motors ------------------------------------------------------------------------------------
MOTOR_TORQUE = TORQUE
"""A motor's rated or peak torque [N m]."""
MOTOR_SPEED = INPUT_SPEED
"""A motor's maximum or rated speed [rpm]."""
CURVE_SPEED = Bound("a speed", "rpm", 0.0, 1e6)
"""A speed of a motor's torque-speed curve [rpm]: from standstill."""
CURVE_TORQUE = Bound("a torque", "N m", 0.0, 1e7)
"""A peak torque of a motor's torque-speed curve [N m]."""
TORQUE_CONSTANT = Bound("a torque constant", "N m/A", 1e-6, 1e4)
"""A motor's torque constant k_t [N m/A]: from 1e-6 (below any motor; the current T / k_t
and the copper loss R I^2 stay finite for every valid torque and resistance)."""
RESISTANCE = Bound("a resistance", "ohm", 1e-6, 1e6)
"""A motor's winding resistance [ohm]: 1 micro-ohm to 1 M ohm (windings span about
0.01 to 100 ohm)."""

# --- studies -----------------------------------------------------------------------------------
TIME_SCALE = Bound("a time scale", "", 1e-3, 1e3)
"""A study's time scale s: the motion run s times slower [-], as far as the exact slow-down
search goes (`hdselect.sizing.timescale`)."""

# --- resources ---------------------------------------------------------------------------------
MAX_STUDY_CASES = 1_000_000
"""Most cases one study file may make: they are all resolved and keyed before any runs."""
DEFAULT_MAX_SAMPLES = 30_000_000
"""Default limit on the samples of one trajectory: an 8-hour log at 1 kHz fits (28.8 million)."""


def check_max_samples(value: object, field: str = "max_samples") -> int:
    """A limit on samples: a whole number of at least 2.

    Raises:
        InputError: It is not.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or int(value) < 2:
        raise InputError(f"must be a whole number of samples, at least 2, got {value!r}",
                         field=field)
    return int(value)


def bytes_per_sample(dof: int) -> int:
    """Memory a sizing run holds per sample of a robot with `dof` joints [bytes], at most.

    The trajectory (t, q, qd, qdd: 8 + 24 dof), the torques along the motion and an
    emergency stop (16 dof), and the split torques and scaled copies of a joint no unit
    fits; everything else runs in chunks. An upper estimate: measured 125 B on a 2-axis
    log, 270 B on the 6-axis arm, 366 B when a joint of it has no unit.
    """
    return 128 + 48 * dof


# --- Python arguments ---------------------------------------------------------------------------
def expect_type(value: object, types: type | tuple[type, ...], field: str, expected: str) -> None:
    """Refuse a Python argument of the wrong type, naming the parameter.

    Args:
        value: The argument.
        types: The types it may have.
        field: The parameter's name.
        expected: What it should be, in words, e.g. ``"a Robot"``.

    Raises:
        InputError: `value` is not an instance of `types`.
    """
    if not isinstance(value, types):
        raise InputError(f"expected {expected}, got {type(value).__name__}", field=field)


def file_argument(value: object, field: str) -> Path:
    """A Python argument that names one file, as a path.

    Raises:
        InputError: It is not a string or a path.
    """
    if isinstance(value, Path):
        return value
    if not isinstance(value, str) or not value:
        raise InputError(f"expected a file name, got {value!r}", field=field)
    return Path(value)


def files_argument(value: object, field: str) -> list[Path]:
    """A Python argument that must be a list of files, as paths.

    Raises:
        InputError: It is a single string or path (not a list), or holds something else.
    """
    if isinstance(value, str | Path | bytes) or not isinstance(value, Iterable):
        raise InputError(f"expected a list of files, got {value!r}", field=field)
    return [file_argument(item, field) for item in value]


SHARE_TOLERANCE = 1e-9
"""How far the shares of a robot's tasks may sum from 1 [-]."""


def check_shares(shares: list[float] | tuple[float, ...], *, field: str = "share",
                 idle: float = 0.0) -> None:
    """Shares of operating time are non-negative, finite, not all zero, and sum to 1.

    Args:
        shares: Each task's fraction of the time [-].
        field: The field named in messages.
        idle: The fraction of the time no task runs [-], in [0, 1).

    Raises:
        InputError: They do not (the message gives the sum).
    """
    if not (isinstance(idle, float | int) and math.isfinite(idle) and 0.0 <= idle < 1.0):
        raise InputError(f"must be a fraction of time in [0, 1), got {idle!r}", field="idle")
    for i, share in enumerate(shares):
        if not (isinstance(share, float | int) and not isinstance(share, bool)
                and math.isfinite(share) and share >= 0.0):
            raise InputError(f"must be a fraction of time >= 0, got {share!r}",
                             field=f"{field}[{i}]")
    total = math.fsum([*shares, idle])
    if abs(total - 1.0) > SHARE_TOLERANCE:
        what = "the shares" if idle == 0.0 else f"the shares and the idle time {idle:.12g}"
        raise InputError(f"{what} sum to {total:.12g}; they must sum to 1 (within "
                         f"{SHARE_TOLERANCE:g})", field=field)
    if not any(share > 0.0 for share in shares):
        raise InputError("every share is 0: some task must run", field=field)
