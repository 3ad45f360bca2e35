"""Every sizing option declared once: its type, default, range, unit, help, flag and file keys.

`hdselect.sizing.options.Options` takes its fields' defaults and checks from `OPTIONS`,
the command line its flags (`hdselect.cli.arguments.option_argument`), motion, mix and
envelope files the keys they read (`file_options`), a study file its parameters. A new
option is one `Option` here, a field of `Options`, and its effect.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any, cast

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import table_of
from hdselect.catalog.rules import DEFAULT_MARGIN
from hdselect.catalog.select import (
    DEFAULT_INERTIA_TARGET,
    DEFAULT_PREFER,
    DEFAULT_PREFER_WITH_MOTORS,
    PREFERENCES,
)
from hdselect.catalog.stiffness import APPLICATION_CLASSES, ClassFrequency
from hdselect.catalog.units import RAD_PER_ARCMIN

DEFAULT_STOP_TIME = 0.1
"""Time in which an emergency stop or a crash brings the arm to rest [s]."""
DEFAULT_EFFICIENCY = 0.70
"""Gear efficiency used where a catalog gives no table [-]. The PSA-G page shows
efficiency curves but no numbers; 70 % is a mid-range reading for small
Harmonic Drive units near rated torque, and lower at light load."""
MAX_THREADS = 256
"""Most threads the batched dynamics may be given (each holds a copy of the model)."""
LIFE_BASES = ("L50", "L10")
"""Valid values of ``[requirements] life_basis``: L50 (average) or L10 (90 % survival) life."""

KINDS = ("number", "count", "samples", "switch", "choice", "offsets", "joints")
"""What an option's value is: a float in `Option.bound`; a whole number from 1 to
`Option.most`; a limit on samples (`hdselect.base.bounds.check_max_samples`); true or
false; one of `Option.choices`; joint name -> a float in `Option.bound`; a value per
joint: joint name (or `EVERY_JOINT`) -> a float in `Option.bound`."""
EVERY_JOINT = "*"
"""The key of a "joints" option's value that applies to every sized joint not named."""
CLASS_FREQUENCIES = MappingProxyType({name: found.frequency
                                      for name, found in APPLICATION_CLASSES.items()})
"""Harmonic Drive's application classes by name: the frequency each asks for [Hz]."""
FILE_KINDS = ("motion", "mix", "envelope")
"""The files that give options under `Option.key`."""


@dataclass(frozen=True)
class Option:
    """One sizing option, as every front end reads it.

    Attributes:
        name: Its field of `hdselect.sizing.options.Options`, its keyword in Python and
            its key in a study file.
        kind: One of `KINDS`.
        default: Its value where nothing gives one (None: not given, or chosen later).
        help: What it is, in the flag's words, with its unit.
        label: Its short name and unit, for a figure's axis (a study's varied parameter).
        bound: The range of a number, or of each value of "offsets" (SI).
        most: The largest value of a "count".
        choices: The values of a "choice".
        noun: What a choice is called in messages ("unknown order ...").
        optional: None is a value (not given).
        flag: Its command-line flag, or None; a "switch" flag sets the value opposite
            its default.
        metavar: The flag's value in ``--help`` (None: argparse's own).
        default_help: The flag's default in words, where `flag_help`'s would not say it.
        group: The flags it is declared with: ``"sizing"`` (`sizing_arguments`),
            ``"motors"`` (`motor_arguments`, also on ``plan``) or ``"case"``
            (`robot_motion_arguments`), as `hdselect.cli.arguments` names them.
        key: Its key in files, ``"table.key"`` (``[safety] stop_time``), or None.
        files: The kinds of file (`FILE_KINDS`) that give `key`. One a mix file and its
            motion files both give is settled duty-wide (the mix file's, else the value
            its motions agree on).
        study: A study file may set or vary it.
        pairs: It acts on gearhead and motor pairs only (True), or these of its values do:
            refused where no motor is given.
        requires: (option, value): it acts only where that option has that value.
        scale: SI per unit of its value in flags and files (`RAD_PER_ARCMIN`: in arcmin).
        edge_unit: Its unit in flags and files, for messages (default: the bound's SI one).
        classes: Names a value may be given by, each standing for its SI value
            (`CLASS_FREQUENCIES`).
    """

    name: str
    kind: str
    default: Any
    help: str
    label: str = ""
    bound: bounds.Bound | None = None
    most: int = 0
    choices: tuple[str, ...] = ()
    noun: str = "value"
    optional: bool = False
    flag: str | None = None
    metavar: str | None = None
    default_help: str | None = None
    group: str | None = None
    key: str | None = None
    files: tuple[str, ...] = ()
    study: bool = True
    pairs: bool | tuple[str, ...] = False
    requires: tuple[str, str] | None = None
    scale: float = 1.0
    edge_unit: str | None = None
    classes: Mapping[str, float] | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS or not set(self.files) <= set(FILE_KINDS):
            raise ValueError(f"option {self.name}: kind {self.kind!r}, files {self.files}")
        if (self.key is None) != (not self.files):
            raise ValueError(f"option {self.name}: a key needs the files that give it")
        if not self.label:
            raise ValueError(f"option {self.name}: no label")
        if self.kind in ("number", "offsets", "joints") and self.bound is None:
            raise ValueError(f"option {self.name}: a {self.kind} needs its bound")

    @property
    def dest(self) -> str | None:
        """The attribute argparse stores the flag in, or None without a flag."""
        return None if self.flag is None else self.flag[2:].replace("-", "_")

    def check(self, value: Any, *, path: Path | None = None, field: str | None = None,
              edge: bool = False) -> Any:
        """`value` checked: a float, an int, a bool, a choice or a dict of floats by joint.

        Args:
            value: The value as given.
            path: The file it came from, for messages.
            field: Where it was given, for messages (default: the option's name).
            edge: The value is in the unit of flags and files (`scale`), not SI; the
                value returned is SI either way.

        Raises:
            InputError: It is of the wrong type or out of range.
        """
        field = self.name if field is None else field
        if value is None and self.optional:
            return None
        if self.kind in ("number", "joints"):
            return self._numbers(value, path, field, edge)
        if self.kind == "count":
            if isinstance(value, bool) or not isinstance(value, int) \
                    or not 1 <= value <= self.most:
                raise InputError(f"must be a whole number in [1, {self.most}], got {value!r}",
                                 path=path, field=field)
            return value
        if self.kind == "samples":
            try:
                return bounds.check_max_samples(value, field=field)
            except InputError as err:
                raise InputError(err.reason, path=path, field=field) from err
        if self.kind == "switch":
            if not isinstance(value, bool):
                raise InputError(f"expected true or false, got {value!r}", path=path,
                                 field=field)
            return value
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise InputError(f"unknown {self.noun} {value!r}; choose one of: "
                                 f"{', '.join(self.choices)}", path=path, field=field)
            return value
        bound = cast(bounds.Bound, self.bound)  # set for offsets
        if not isinstance(value, Mapping) or not all(isinstance(name, str) for name in value):
            raise InputError("expected a mapping of joint names to offsets [m], got "
                             f"{value!r}", path=path, field=field)
        return {name: bound.check(offset, path=path, field=f"{field}.{name}")
                for name, offset in value.items()}

    def _numbers(self, value: Any, path: Path | None, field: str, edge: bool) -> Any:
        """A "number" [SI], or a "joints" value as joint name -> number [SI]."""
        if self.kind == "number":
            return self._number(value, path, field, edge)
        if not isinstance(value, Mapping):  # one value for every joint
            return {EVERY_JOINT: self._number(value, path, field, edge)}
        if not all(isinstance(name, str) and name for name in value):
            raise InputError(f"expected joint names, got {list(value)!r}", path=path,
                             field=field)
        return {name: self._number(item, path, field if name == EVERY_JOINT
                                   else f"{field}.{name}", edge)
                for name, item in value.items()}

    def _number(self, value: Any, path: Path | None, field: str, edge: bool) -> float:
        """One number [SI]: given in SI, or with `edge` in `scale`s; or a class's name."""
        bound = cast(bounds.Bound, self.bound)  # set for a number and joints
        if self.classes and isinstance(value, ClassFrequency):
            return value  # a class's number, checked when its name was read
        if self.classes and isinstance(value, str):
            if value not in self.classes:
                raise InputError(f"unknown application class {value!r}; give a number "
                                 f"[{bound.unit}] or one of: {', '.join(self.classes)}",
                                 path=path, field=field)
            return ClassFrequency(value)
        scale = self.scale if edge else 1.0
        return bound.check(value, path=path, field=field, scale=scale,
                           unit=self.edge_unit if edge else None) * scale

    def from_flag(self, given: Any) -> Any:
        """The flag's value [SI]: a "joints" flag's ``VALUE`` and ``JOINT=VALUE`` strings.

        A number is read in the flag's unit (`scale`); a name of `classes` stands for its
        value. None where the flag is not given.

        Raises:
            InputError: A value that is not a number (or a class), or out of range,
                naming the flag.
        """
        if given is None or self.kind not in ("number", "joints") or not (
                self.classes or self.kind == "joints" or self.scale != 1.0):
            return given
        field = str(self.flag)
        if self.kind == "number":
            return self.check(_flag_number(given), field=field, edge=True)
        values: dict[str, Any] = {}
        for text in cast(Sequence[str], given):
            joint, equals, item = text.rpartition("=")
            if equals and not joint.strip():
                raise InputError(f"expected VALUE or JOINT=VALUE, got {text!r}", field=field)
            key = joint.strip() if equals else EVERY_JOINT
            if key in values:
                raise InputError(f"given twice for {'every joint' if key == EVERY_JOINT else key}"
                                 f": {text!r}", field=field)
            values[key] = _flag_number(item.strip())
        try:
            return self.check(values, field=field, edge=True)
        except InputError as err:  # the flag named, and the joint in the words
            joint = str(err.field).removeprefix(field).removeprefix(".")
            raise InputError(f"{joint}={values[joint]}: {err.reason}" if joint else err.reason,
                             field=field) from err

    def flag_help(self, kind: str | None = "motion", then: tuple[str, ...] = ()) -> str:
        """The flag's help: `help` and where its default comes from.

        Args:
            kind: The kind of file (`FILE_KINDS`) whose `key` gives the default, where the
                command reads one (None: a command that reads no such file).
            then: What gives the default next, where that file does not (``"the duty"``).
        """
        if self.kind == "switch":
            return f"do not {self.help}" if self.default else self.help
        if self.default_help is not None:
            return f"{self.help} ({self.default_help})"
        shown = (f"{self.default:g}" if isinstance(self.default, float)
                 else None if isinstance(self.default, Mapping) else self.default)
        if kind is not None and kind in self.files and self.key is not None:
            table, key = self.key.split(".")
            return (f"{self.help} (default: the {kind} file's [{table}] {key}, "
                    + "".join(f"else {source}'s, " for source in then)
                    + f"else {'none' if shown is None else shown})")
        return f"{self.help} (default: {shown})"

    def joint_value(self, value: Mapping[str, float], joint: str) -> float | None:
        """A "joints" value's for one joint: its own, else every joint's, else None."""
        return value.get(joint, value.get(EVERY_JOINT))

    def needs_motors(self, value: Any) -> bool:
        """The value, given, acts on gearhead and motor pairs only (`pairs`)."""
        return value is not None and (self.pairs is True or (
            isinstance(self.pairs, tuple) and value in self.pairs))


OPTIONS: tuple[Option, ...] = (
    Option("stop_time", "number", DEFAULT_STOP_TIME, "emergency-stop and crash time [s]",
           bound=bounds.STOP_TIME, flag="--stop-time", metavar="S", group="sizing",
           key="safety.stop_time", files=("motion", "mix", "envelope"),
           label="stop time [s]"),
    Option("efficiency", "number", DEFAULT_EFFICIENCY,
           "gear efficiency where a unit has no table", bound=bounds.EFFICIENCY,
           flag="--efficiency", group="sizing", key="sizing.efficiency", files=("mix",),
           label="gear efficiency [-]"),
    Option("rotor_inertia", "number", 0.0,
           "motor rotor inertia [kg m^2] where no motor data is given",
           bound=bounds.ROTOR_INERTIA, flag="--motor-inertia", metavar="KG_M2", group="sizing",
           key="sizing.rotor_inertia", files=("mix",),
           label="rotor inertia [kg m^2]"),
    Option("motor_mass", "number", 0.0,
           "motor mass carried with each gearhead [kg] where no motor data is given",
           bound=bounds.ADDED_MASS, flag="--motor-mass", metavar="KG", group="motors",
           key="sizing.motor_mass", files=("mix",),
           label="motor mass [kg]"),
    Option("mass_coupling", "switch", True,
           "carry chosen units' masses on the joints nearer the base",
           flag="--no-mass-coupling", group="motors",
           key="sizing.mass_coupling", files=("mix",),
           label="mass coupling"),
    Option("prefer", "choice", None,
           "; ".join(f"{order}: {words}" for order, (words, _) in PREFERENCES.items()),
           choices=tuple(PREFERENCES), noun="order", optional=True, flag="--prefer",
           default_help=f"default: {DEFAULT_PREFER_WITH_MOTORS} where motors are given, "
                        f"else {DEFAULT_PREFER}", group="sizing", key="sizing.prefer",
           files=("mix",), pairs=("motor-rms", "motor-peak", "inertia"),
           label="selection order"),
    Option("life_hours", "number", None, "required life [h]", bound=bounds.LIFE,
           optional=True, flag="--life-hours", metavar="H", group="sizing",
           key="requirements.life_hours", files=("motion", "mix", "envelope"),
           label="required life [h]"),
    Option("life_basis", "choice", "L50",
           "basis of the required life: L50, average life, or L10, 90 % survive it",
           choices=LIFE_BASES, noun="basis", flag="--life-basis", group="sizing",
           key="requirements.life_basis", files=("motion", "mix", "envelope"),
           label="life basis"),
    Option("threads", "count", None, "threads for the batched dynamics (None: chosen from "
           "the sample count; a study's workers use 1)", most=MAX_THREADS, optional=True,
           study=False,
           label="threads"),
    Option("max_samples", "samples", bounds.DEFAULT_MAX_SAMPLES,
           "refuse a trajectory of more samples than this, before allocating it",
           flag="--max-samples", metavar="N", group="case",
           default_help=f"default {bounds.DEFAULT_MAX_SAMPLES:,}: an 8-hour log at 1 kHz",
           label="sample limit"),
    Option("margin", "number", DEFAULT_MARGIN,
           "design margin: every rule must hold at (1 - M) of its limit, e.g. 0.2 for 80 %",
           bound=bounds.MARGIN, flag="--margin", metavar="M", group="sizing",
           key="requirements.margin", files=("motion", "mix", "envelope"),
           label="design margin [-]"),
    Option("max_inertia_ratio", "number", None,
           "a gearhead and motor pair whose load-to-rotor inertia ratio is above R is not "
           "feasible", bound=bounds.INERTIA_RATIO, optional=True, flag="--max-inertia-ratio",
           metavar="R", default_help="default: the motor file's max_inertia_ratio, else none",
           group="sizing", pairs=True,
           label="largest inertia ratio [-]"),
    Option("inertia_target", "number", DEFAULT_INERTIA_TARGET,
           "the load-to-rotor inertia ratio --prefer inertia aims at",
           bound=bounds.INERTIA_RATIO, flag="--inertia-target", metavar="R", group="sizing",
           pairs=True, requires=("prefer", "inertia"),
           label="inertia ratio aimed at [-]"),
    Option("bearing_offset", "offsets", MappingProxyType({}),
           "where each named joint's output flange sits along its axis from the joint "
           "origin [m]", bound=bounds.AXIAL_OFFSET, key="sizing.bearing_offset_m",
           files=("motion", "mix", "envelope"), study=False,
           label="flange offset [m]"),
    Option("bearing_loads", "switch", True,
           "compute the loads on every sized joint's output bearing",
           label="bearing loads"),
    Option("max_torsion", "joints", MappingProxyType({}),
           "largest twist of each sized joint's unit over the cycle [arcmin]: a value for "
           "every joint, or JOINT=ARCMIN (repeatable)", bound=bounds.TORSION_TARGET,
           flag="--max-torsion", metavar="[JOINT=]ARCMIN", group="sizing",
           key="precision.max_torsion_arcmin", files=("motion", "mix", "envelope"),
           scale=RAD_PER_ARCMIN, edge_unit="arcmin", label="largest torsion [arcmin]"),
    Option("min_natural_frequency", "joints", MappingProxyType({}),
           "lowest single-axis natural frequency of each sized joint [Hz], or an "
           "application class (e.g. hand-axes): a value for every joint, or JOINT=VALUE "
           "(repeatable)", bound=bounds.FREQUENCY_TARGET, flag="--min-natural-frequency",
           metavar="[JOINT=]HZ|CLASS", group="sizing",
           key="precision.min_natural_frequency_hz", files=("motion", "mix", "envelope"),
           classes=CLASS_FREQUENCIES, label="lowest joint frequency [Hz]"),
    Option("max_tool_deflection", "number", None,
           "largest deflection of the tool holding the payload still at any pose of the "
           "cycle [mm]", bound=bounds.DEFLECTION_TARGET, optional=True,
           flag="--max-tool-deflection", metavar="MM", group="sizing",
           key="precision.max_tool_deflection_mm", files=("motion", "mix", "envelope"),
           scale=1e-3, edge_unit="mm", label="largest tool deflection [mm]"),
    Option("min_arm_frequency", "number", None,
           "lowest natural frequency of the whole arm [Hz], or an application class",
           bound=bounds.FREQUENCY_TARGET, optional=True, flag="--min-arm-frequency",
           metavar="HZ|CLASS", group="sizing", key="precision.min_arm_frequency_hz",
           files=("motion", "mix", "envelope"), classes=CLASS_FREQUENCIES,
           label="lowest arm frequency [Hz]"),
    Option("precision", "switch", True,
           "compute the precision figures: each joint's twist and resonance, the tool's "
           "deflection, the arm's lowest modes", flag="--no-precision", group="sizing",
           label="precision figures"),
)
"""Every sizing option, in the order of `Options`' fields and of the flags in ``--help``."""

OPTION = MappingProxyType({option.name: option for option in OPTIONS})
"""Each option by name."""


def _flag_number(text: str) -> float | str:
    """A flag's value as a number, else as given (a class's name, or refused as no number)."""
    try:
        return float(text)
    except ValueError:
        return text


def from_edge(values: Mapping[str, Any]) -> dict[str, Any]:
    """Options by name given in the units of flags and files (arcmin, mm), in SI.

    Raises:
        InputError: A value out of range or of the wrong type, naming its option.
    """
    return {name: OPTION[name].check(value, edge=True) for name, value in values.items()}


def file_keys(kind: str, table: str) -> tuple[str, ...]:
    """The option keys a file of `kind` takes in `table` (``"safety"``, ``"sizing"``, ...)."""
    return tuple(option.key.split(".")[1] for option in OPTIONS
                 if kind in option.files and option.key is not None
                 and option.key.split(".")[0] == table)


def file_options(doc: Mapping[str, Any], path: Path, kind: str,
                 joints: Sequence[str] = ()) -> dict[str, Any]:
    """The options a file of `kind` gives under their keys, checked; "offsets" left out.

    The file's tables are read as given; their keys are the caller's to check first
    (`file_keys`), beside its own. Offsets need the robot: `bearing_offsets` reads them.

    Args:
        doc: The file as read.
        path: The file, for messages.
        kind: The kind of file (`FILE_KINDS`).
        joints: The robot's joints: the joints a "joints" option's table may name.

    Raises:
        InputError: A value out of range or of the wrong type, or an unknown joint,
            naming the file and key.
    """
    values: dict[str, Any] = {}
    for option in OPTIONS:
        if kind not in option.files or option.key is None or option.kind == "offsets":
            continue
        table, key = option.key.split(".")
        found = table_of(doc.get(table, {}), path, table)
        if key in found:
            values[option.name] = option.check(found[key], path=path, field=option.key,
                                               edge=True)
            for name in values[option.name] if option.kind == "joints" else ():
                if name != EVERY_JOINT and name not in joints:
                    raise InputError(f"unknown joint '{name}'; joints are: "
                                     f"{', '.join(joints)}", path=path,
                                     field=f"{option.key}.{name}")
    return values


def given_by(source: object, kind: str) -> dict[str, Any]:
    """The options a read file (a Motion, an envelope file) gives: its attributes by name.

    Args:
        source: The file as read, holding each option of `kind` under its name (None or
            empty where the file gives none).
        kind: The kind of file (`FILE_KINDS`).
    """
    return {option.name: value for option in OPTIONS if kind in option.files
            if (value := getattr(source, option.name)) is not None
            and not (isinstance(value, Mapping) and not value)}
