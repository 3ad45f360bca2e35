"""The assumptions of a sizing run: validated once, whichever front end built them."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.catalog.rules import DEFAULT_MARGIN
from hdselect.catalog.select import DEFAULT_INERTIA_TARGET, PREFERENCES
from hdselect.motion.motionfile import LIFE_BASES, Motion
from hdselect.sizing.reflect import DEFAULT_EFFICIENCY

DEFAULT_STOP_TIME = 0.1
"""Time in which an emergency stop or a crash brings the arm to rest [s]."""
MAX_THREADS = 256
"""Most threads the batched dynamics may be given (each holds a copy of the model)."""


@dataclass(frozen=True)
class Options:
    """Assumptions of a sizing run, stated in every report.

    Every value is checked when an Options is made: the command line, a motion
    file and a Python caller all go through the same checks.

    Attributes:
        stop_time: Emergency-stop and crash time [s], positive.
        efficiency: Gear efficiency where a unit has no table [-], in (0, 1].
        rotor_inertia: Motor rotor inertia J_m [kg m^2], zero or positive.
        motor_mass: Motor mass carried with each gearhead [kg], zero or positive.
        mass_coupling: Whether chosen units' masses load the joints nearer the base.
        prefer: Selection order, a key of `hdselect.catalog.select.PREFERENCES`, or None for the
            default: ``"mass"`` (the lightest pair) where motors are given, else ``"size"``.
            A sizing result holds the order it used.
        life_hours: Required life [h] on `life_basis`, positive, or None.
        life_basis: ``"L50"`` (average life) or ``"L10"`` (90 % survive it).
        threads: Threads for the batched dynamics, a positive whole number, or None to
            choose from the sample count (a study's workers use 1).
        max_samples: Most samples a trajectory may have
            (`hdselect.base.bounds.DEFAULT_MAX_SAMPLES`);
            a motion needing more is refused before anything is allocated.
        margin: Design margin [-], in [0, 0.9]: every rule must hold at (1 - margin) of
            its limit (`hdselect.catalog.rules.holds`); 0 by default. Utilization stays
            demand / limit.
        max_inertia_ratio: Largest load-to-rotor inertia ratio of a (gearhead, motor)
            pair [-], positive, or None: then each motor's own (its file's
            ``max_inertia_ratio``), else no limit.
        inertia_target: The load-to-rotor inertia ratio ``prefer = "inertia"`` aims at [-].
        bearing_offset: Where each named joint's output flange sits along its axis from
            the joint origin [m], signed along the robot file's axis (the motion file's
            ``[sizing] bearing_offset_m``): its output bearing's loads are taken about
            that point, or a unit's catalog offset from it. Joints not named: 0.
        bearing_loads: Compute the loads on every sized joint's output bearing (one more
            batched pass); False leaves them out, and is refused where a candidate unit's
            catalog rates its bearing (its checks need them).

    Raises:
        InputError: A value is out of range or of the wrong type; the field is its name.
    """

    stop_time: float = DEFAULT_STOP_TIME
    efficiency: float = DEFAULT_EFFICIENCY
    rotor_inertia: float = 0.0
    motor_mass: float = 0.0
    mass_coupling: bool = True
    prefer: str | None = None
    life_hours: float | None = None
    life_basis: str = "L50"
    threads: int | None = None
    max_samples: int = bounds.DEFAULT_MAX_SAMPLES
    margin: float = DEFAULT_MARGIN
    max_inertia_ratio: float | None = None
    inertia_target: float = DEFAULT_INERTIA_TARGET
    bearing_offset: Mapping[str, float] = field(default_factory=dict)
    bearing_loads: bool = True

    def __post_init__(self) -> None:
        for name, bound in (("stop_time", bounds.STOP_TIME), ("efficiency", bounds.EFFICIENCY),
                            ("rotor_inertia", bounds.ROTOR_INERTIA),
                            ("motor_mass", bounds.ADDED_MASS)):
            _set(self, name, bound.check(getattr(self, name), field=name))
        for name in ("mass_coupling", "bearing_loads"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"expected true or false, got {getattr(self, name)!r}",
                                 field=name)
        if self.prefer is not None and (not isinstance(self.prefer, str)
                                        or self.prefer not in PREFERENCES):
            raise InputError(f"unknown order {self.prefer!r}; choose one of: "
                             f"{', '.join(PREFERENCES)}", field="prefer")
        if self.life_hours is not None:
            _set(self, "life_hours", bounds.LIFE.check(self.life_hours, field="life_hours"))
        if not isinstance(self.life_basis, str) or self.life_basis not in LIFE_BASES:
            raise InputError(f"unknown basis {self.life_basis!r}; choose one of: "
                             f"{', '.join(LIFE_BASES)}", field="life_basis")
        if self.threads is not None and (isinstance(self.threads, bool)
                                         or not isinstance(self.threads, int)
                                         or not 1 <= self.threads <= MAX_THREADS):
            raise InputError(f"must be a whole number in [1, {MAX_THREADS}], got "
                             f"{self.threads!r}", field="threads")
        _set(self, "max_samples", bounds.check_max_samples(self.max_samples))
        _set(self, "margin", bounds.MARGIN.check(self.margin, field="margin"))
        if self.max_inertia_ratio is not None:
            _set(self, "max_inertia_ratio", bounds.INERTIA_RATIO.check(
                self.max_inertia_ratio, field="max_inertia_ratio"))
        _set(self, "inertia_target", bounds.INERTIA_RATIO.check(self.inertia_target,
                                                                 field="inertia_target"))
        if not isinstance(self.bearing_offset, Mapping) or not all(
                isinstance(name, str) for name in self.bearing_offset):
            raise InputError("expected a mapping of joint names to offsets [m], got "
                             f"{self.bearing_offset!r}", field="bearing_offset")
        _set(self, "bearing_offset", {
            name: bounds.AXIAL_OFFSET.check(value, field=f"bearing_offset.{name}")
            for name, value in self.bearing_offset.items()})


def options_for(motion: Motion | None, **given: Any) -> Options:
    """Options from keyword values, else the motion file's, else the defaults.

    Args:
        motion: The motion whose ``[safety]`` and ``[requirements]`` fill what is not given.
        **given: Fields of `Options`; a value of None means "not given".

    Returns:
        The validated options.

    Raises:
        InputError: An unknown name, or a value out of range.
    """
    if motion is not None and not isinstance(motion, Motion):
        raise InputError(f"expected a Motion or None, got {type(motion).__name__}",
                         field="motion")
    names = [f.name for f in fields(Options)]
    for name in given:
        if name not in names:
            raise InputError(f"unknown option {name!r}; options are: {', '.join(names)}",
                             field=name)
    values = {name: value for name, value in given.items() if value is not None}
    if motion is not None:
        for name in ("stop_time", "life_hours", "life_basis", "margin"):
            if name not in values and getattr(motion, name) is not None:
                values[name] = getattr(motion, name)
        if "bearing_offset" not in values and motion.bearing_offset:
            values["bearing_offset"] = dict(motion.bearing_offset)
    return Options(**values)


def _set(options: Options, name: str, value: object) -> None:
    object.__setattr__(options, name, value)
