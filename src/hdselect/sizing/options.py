"""The assumptions of a sizing run: validated once, whichever front end built them.

Each field, its default and its check are declared in `hdselect.motion.option_specs`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS
from hdselect.catalog.units import Unit
from hdselect.motion.motionfile import Motion
from hdselect.motion.option_specs import (
    OPTION,
    OPTIONS,
    given_by,
)


def _default(name: str) -> Any:
    return OPTION[name].default


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
        max_torsion: The largest twist of each sized joint's unit over the cycle [rad]:
            joint name -> target, the key ``"*"`` (`EVERY_JOINT`) for every joint not
            named; a bare number is read as every joint's. Empty: no target.
        min_natural_frequency: The lowest single-axis natural frequency sqrt(K1 / J) / 2 pi
            of each sized joint [Hz], the same way; a value may name one of Harmonic
            Drive's application classes (`hdselect.catalog.stiffness.APPLICATION_CLASSES`).
        max_tool_deflection: The largest deflection of the tool holding the payload still
            at any pose of the cycle [m], or None.
        min_arm_frequency: The lowest natural frequency of the whole arm [Hz] (or a
            class's name), or None.
        precision: Compute the precision figures (twists, resonances, tool deflection,
            the arm's modes) after the selection.

    Raises:
        InputError: A value is out of range or of the wrong type; the field is its name.
    """

    stop_time: float = _default("stop_time")
    efficiency: float = _default("efficiency")
    rotor_inertia: float = _default("rotor_inertia")
    motor_mass: float = _default("motor_mass")
    mass_coupling: bool = _default("mass_coupling")
    prefer: str | None = _default("prefer")
    life_hours: float | None = _default("life_hours")
    life_basis: str = _default("life_basis")
    threads: int | None = _default("threads")
    max_samples: int = _default("max_samples")
    margin: float = _default("margin")
    max_inertia_ratio: float | None = _default("max_inertia_ratio")
    inertia_target: float = _default("inertia_target")
    bearing_offset: Mapping[str, float] = field(default_factory=dict)
    bearing_loads: bool = _default("bearing_loads")
    max_torsion: Mapping[str, float] = field(default_factory=dict)
    min_natural_frequency: Mapping[str, float] = field(default_factory=dict)
    max_tool_deflection: float | None = _default("max_tool_deflection")
    min_arm_frequency: float | None = _default("min_arm_frequency")
    precision: bool = _default("precision")

    def __post_init__(self) -> None:
        for option in OPTIONS:
            _set(self, option.name, option.check(getattr(self, option.name)))
        if not self.precision:
            for name in WHOLE_ARM_TARGETS:
                if getattr(self, name) is not None:
                    raise InputError("a whole-arm target is judged on the precision figures, "
                                     f"which {OPTION['precision'].flag} leaves out: give the "
                                     "target or that flag, not both", field=OPTION[name].flag)

    def joint_value(self, name: str, joint: str) -> float | None:
        """A per-joint option's value for one joint [SI]: its own, else every joint's.

        Args:
            name: The option (``"max_torsion"`` or ``"min_natural_frequency"``).
            joint: The joint.

        Returns:
            The value, or None where the option sets none for this joint.
        """
        return OPTION[name].joint_value(getattr(self, name), joint)


WHOLE_ARM_TARGETS = ("max_tool_deflection", "min_arm_frequency")
"""The options judged on the whole arm's precision figures (`hdselect.sizing.stiffening`)."""


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
    return Options(**{**(given_by(motion, "motion") if motion is not None else {}), **values})


def fixed_choice(options: Options, units: Mapping[str, Unit],
                 motors: Mapping[str, Sequence[Motor]], joints: Sequence[str]
                 ) -> tuple[Options, dict[str, float]]:
    """The options and carried masses for checking given units (and motors), no choice.

    Args:
        options: The assumptions.
        units: The unit of every joint in `joints`.
        motors: The motor behind the unit of some joints (the first of each is used).
        joints: The sized joints.

    Returns:
        The options with `prefer` defaulted (by mass with motors, else by size), and with
        mass coupling each joint's unit mass plus its motor's (else the options' motor
        mass) [kg]; empty without mass coupling.
    """
    resolved = options if options.prefer is not None else replace(
        options, prefer=DEFAULT_PREFER_WITH_MOTORS if motors else DEFAULT_PREFER)
    masses = ({name: units[name].mass + (motors[name][0].mass if name in motors
                                         else options.motor_mass)
               for name in joints} if options.mass_coupling else {})
    return resolved, masses


def _set(options: Options, name: str, value: object) -> None:
    object.__setattr__(options, name, value)
