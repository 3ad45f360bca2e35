"""The gearhead catalog: TOML files of units, loaded into immutable SI records.

The built-in file is the PSA-G page's specification table, transcribed as
published, with the page's rules in its ``[rules]`` table. Gaps and
contradictions of a source are never papered over in silence: each value that
is a stand-in or a correction carries a `Flag`, and every result that uses the
value repeats it. A file without a ``[rules]`` table is judged by the built-in
file's rules, and says so on every result.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path

import numpy as np

from hdselect.base import bounds

logger = logging.getLogger(__name__)


NM_PER_LB_IN = 0.1129848
"""Newton metres in one pound-force inch."""


KG_M2_PER_LB_IN2 = 2.9264e-4
"""Kilogram square metres in one pound square inch."""


KG_M2_PER_KG_CM2 = 1e-4
"""Kilogram square metres in one kilogram square centimetre."""


KG_PER_LB = 0.45359237
"""Kilograms in one pound."""


L50_PER_L10 = 5.0
"""Harmonic Drive's ratio of average (L50) to 90 %-survival (L10) wave generator life."""


LIFE_BASES = ("L10", "L50")


MEAN_TORQUE_LIMITS = ("tabulated", "speed-adjusted")


class MeanSpeed(StrEnum):
    """How a series averages the output speed N_av of its mean-torque and life rules.

    Its value is the catalog's ``mean_speed`` spelling: ``"whole-cycle"`` (pauses count)
    or ``"moving"`` (the moving part only).
    """

    WHOLE_CYCLE = "whole-cycle"
    MOVING = "moving"

    @property
    def over(self) -> str:
        """What it averages over, in words: ``"the whole cycle"`` or ``"the moving part"``."""
        return "the moving part" if self is MeanSpeed.MOVING else "the whole cycle"

    def of(self, moving: float, whole_cycle: float) -> float:
        """N_av by this definition, of the mean over the moving part and over the whole cycle."""
        return moving if self is MeanSpeed.MOVING else whole_cycle


MEAN_SPEED_RULES = tuple(rule.value for rule in MeanSpeed)
"""The catalog's spellings of `MeanSpeed`."""


MISSING_LIMITS = ("stand-in", "not-rated")
"""What a series' ``[rules]`` ``missing_limits`` does with a momentary or static limit its
source does not give: ``"stand-in"`` (the repeated-peak limit, flagged) or ``"not-rated"``
(left out: the rule reports "not rated by the source" and is not checked)."""


NOT_RATED = "not rated by the source"
"""What a table or JSON says of a rule whose limit the unit's source does not give."""


WHOLE_UNIT = "unit"
"""The `Flag.field` of a note on the whole unit (a transcription, a defect of the source):
every result that uses the unit repeats it."""


# [rules] key -> the choices it takes, or the range of the number it is
RULE_KEYS: dict[str, tuple[str, ...] | bounds.Bound] = {
    "rated_input_speed_rpm": bounds.INPUT_SPEED, "rated_life_hours": bounds.RATED_LIFE,
    "life_basis": LIFE_BASES, "mean_torque_limit": MEAN_TORQUE_LIMITS,
    "mean_speed": MEAN_SPEED_RULES, "max_momentary_events": bounds.EVENTS,
}


DEFAULT_BEARING_LOAD_FACTOR = 1.2
"""Harmonic Drive's load factor f_w for smooth operation without shock (1 to 1.2) [-]."""


DEFAULT_BEARING_STATIC_SAFETY = 1.5
"""Static safety C0 / P0 the output bearing must reach by default [-]."""


# optional [rules] keys of the output bearing -> the range of the number
BEARING_RULE_KEYS: dict[str, bounds.Bound] = {
    "bearing_load_factor": bounds.LOAD_FACTOR,
    "bearing_static_safety": bounds.SAFETY_FACTOR,
}


@dataclass(frozen=True)
class Flag:
    """A catalog value that is a stand-in or a correction, with the reason.

    Attributes:
        field: The quantity it concerns, e.g. ``"static_torque"``, or `WHOLE_UNIT`.
        kind: ``"fallback"`` (the source gives no value), ``"not-rated"`` (the source
            gives no value and the rule is not checked), ``"corrected"`` (the source's
            columns disagree), ``"assumed"`` (the source states no rules),
            ``"transcription"`` (numbers taken from a public transcription of the source)
            or ``"defect"`` (a disagreement in the source and what was used).
        note: One sentence for the reader, its figures in SI units.
        imperial: The same sentence with its figures in the catalog's imperial units
            (lb-in, lb-in^2, lb); empty when the note has no figure to convert.
    """

    field: str
    kind: str
    note: str
    imperial: str = ""

    def text(self, imperial: bool = False) -> str:
        """The note for a reader of SI (default) or imperial units."""
        return self.imperial if imperial and self.imperial else self.note

    @property
    def code(self) -> str:
        """Short id for reports, e.g. ``static_torque:corrected``."""
        return f"{self.field}:{self.kind}"


@dataclass(frozen=True)
class SeriesRules:
    """How a series' catalog rates its units: the rules every check reads.

    Attributes:
        rated_input_speed: Input speed at which the rated torque is given [rpm].
        rated_life_hours: Life at rated torque and rated input speed [h], on `life_basis`.
        life_basis: ``"L10"`` or ``"L50"``: which life `rated_life_hours` is.
        mean_torque_limit: ``"tabulated"`` (each unit's limit for average torque) or
            ``"speed-adjusted"`` ((rated speed / N_av)^0.33 x rated torque, capped at
            the repeated-peak limit).
        mean_speed: How N_av is averaged (`MeanSpeed`; its spelling is taken too).
        max_momentary_events: Cap on the allowed count of momentary events [-].
        source: The file whose ``[rules]`` table states them.
        flag: Set when the unit's own file states no rules and these are assumed.
        bearing_load_factor: Load factor f_w of the output bearing's life [-].
        bearing_static_safety: Least static safety C0 / P0 of the output bearing [-].
        missing_limits: ``"stand-in"`` or ``"not-rated"`` (`MISSING_LIMITS`).
    """

    rated_input_speed: float
    rated_life_hours: float
    life_basis: str
    mean_torque_limit: str
    mean_speed: MeanSpeed
    max_momentary_events: float
    source: Path
    flag: Flag | None = None
    bearing_load_factor: float = DEFAULT_BEARING_LOAD_FACTOR
    bearing_static_safety: float = DEFAULT_BEARING_STATIC_SAFETY
    missing_limits: str = "stand-in"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mean_speed", MeanSpeed(self.mean_speed))

    @property
    def rated_l50_hours(self) -> float:
        """The rated life on the L50 basis, L50 = 5 x L10 [h]."""
        factor = L50_PER_L10 if self.life_basis == "L10" else 1.0
        return self.rated_life_hours * factor


@dataclass(frozen=True)
class BearingRating:
    """What a catalog rates a unit's output bearing (a cross-roller bearing) for.

    Each figure is None where the catalog does not give it; the checks that need it
    are then not made.

    Attributes:
        pitch_diameter: Pitch circle diameter of the rollers d_p [m].
        dynamic_rating: Basic dynamic load rating C [N].
        static_rating: Basic static load rating C0 [N].
        max_moment: Allowable tilting moment [N m].
        max_radial: Allowable radial load [N].
        max_axial: Allowable axial load [N].
        offset: Distance from the output flange to the bearing centre along the axis,
            the catalog's R [m].
        moment_stiffness: Tilting (moment) stiffness K_B [N m/rad].
    """

    pitch_diameter: float | None = None
    dynamic_rating: float | None = None
    static_rating: float | None = None
    max_moment: float | None = None
    max_radial: float | None = None
    max_axial: float | None = None
    offset: float = 0.0
    moment_stiffness: float | None = None


RAD_PER_ARCMIN = math.pi / (180.0 * 60.0)
"""Radians in one minute of arc."""


@dataclass(frozen=True)
class Stiffness:
    """A unit's torsional stiffness with the input locked, as the catalog's three segments.

    The twist under an output torque T rises at K1 up to T1, at K2 from T1 to T2 and at
    K3 above T2. Each figure is None where the catalog does not give it.

    Attributes:
        t1: Torque T1 at the end of the first segment [N m].
        t2: Torque T2 at the end of the second segment [N m].
        k1: Stiffness K1 below T1 [N m/rad].
        k2: Stiffness K2 from T1 to T2 [N m/rad].
        k3: Stiffness K3 above T2 [N m/rad].
        hysteresis_loss: Hysteresis loss [rad].
        lost_motion: Lost motion [rad].
    """

    t1: float | None = None
    t2: float | None = None
    k1: float | None = None
    k2: float | None = None
    k3: float | None = None
    hysteresis_loss: float | None = None
    lost_motion: float | None = None


@dataclass(frozen=True)
class Source:
    """Where one number of a catalog file was read: a document, its page and table.

    Attributes:
        title: The document's title.
        publisher: Who published it.
        edition: Its edition or revision as printed (``"not stated"`` if none).
        copy: Where the copy that was read is (a URL).
        page: The page number as printed, e.g. ``"10"`` or ``"10-11"``.
        table: The table or figure as the document names it.
    """

    title: str
    publisher: str
    edition: str
    copy: str
    page: str
    table: str

    def line(self, key: str) -> str:
        """One readable line for the catalog key it sources, e.g. ``rated_torque_nm: ...``."""
        return (f"{key}: {self.title} ({self.publisher}, {self.edition}), page {self.page}, "
                f"{self.table}; copy: {self.copy}")


@dataclass(frozen=True)
class CatalogInfo:
    """What a catalog file says of itself.

    Attributes:
        name: Its built-in name, e.g. ``"csg-2uh"``; empty where the file gives none.
        title: Its title; empty where the file gives none.
        check: Its note on checking the numbers before use (e.g. against the current
            vendor data); empty where the file gives none.
        transcription: Which numbers were taken from a public transcription rather
            than from the vendor's document; empty where none were.
    """

    name: str = ""
    title: str = ""
    check: str = ""
    transcription: str = ""


@dataclass(frozen=True)
class EfficiencyTable:
    """Gear efficiency over input speed and load, interpolated linearly and clamped.

    Attributes:
        input_speed_rpm: Input speeds of the rows [rpm], increasing; one row if empty axis.
        torque_percent: Output torque of the columns in % of the rated torque, increasing.
        value: Efficiency [-], shape (len(input_speed_rpm), len(torque_percent)).
    """

    input_speed_rpm: tuple[float, ...]
    torque_percent: tuple[float, ...]
    value: tuple[tuple[float, ...], ...]

    def __call__(self, input_speed_rpm: np.ndarray, torque_percent: np.ndarray) -> np.ndarray:
        """Efficiency [-] at each (input speed [rpm], torque [% of rated]) pair."""
        input_speed_rpm = np.atleast_1d(np.asarray(input_speed_rpm, dtype=float))
        torque_percent = np.atleast_1d(np.asarray(torque_percent, dtype=float))
        table = np.asarray(self.value)
        by_speed = np.array([np.interp(torque_percent, self.torque_percent, row)
                             for row in table])  # (rows, n)
        if len(self.input_speed_rpm) == 1:
            return by_speed[0]
        speeds = np.asarray(self.input_speed_rpm)
        x = np.clip(input_speed_rpm, speeds[0], speeds[-1])
        upper = np.clip(np.searchsorted(speeds, x, side="right"), 1, len(speeds) - 1)
        lower = upper - 1
        frac = (x - speeds[lower]) / (speeds[upper] - speeds[lower])
        cols = np.arange(by_speed.shape[1])
        return by_speed[lower, cols] * (1.0 - frac) + by_speed[upper, cols] * frac


@dataclass(frozen=True)
class Unit:
    """One gearhead, all values in SI (speeds in rpm, as the catalog rates them).

    Attributes:
        id: Unit id, ``<series>-<size:02d>-<ratio>``, e.g. ``PSA-14-100``.
        series: Series name, e.g. ``PSA``.
        size: Frame size.
        ratio: Reduction ratio N (input turns per output turn).
        rated_torque: T_N, rated output torque at the rules' rated input speed [N m].
        repeated_torque: Limit for repeated output torque [N m].
        momentary_torque: Limit for momentary overload torque [N m]; None where the
            source does not rate it and its rules' ``missing_limits`` is ``"not-rated"``.
        static_torque: Static torque limit, input locked [N m]; None as `momentary_torque`.
        max_input_speed: Maximum input speed [rpm].
        input_inertia: Inertia at the input shaft [kg m^2].
        mass: Mass [kg].
        efficiency: Efficiency table, or None to use the report's default efficiency.
        rules: The rules its series' catalog rates it by.
        average_torque: Limit for average output torque [N m], if the catalog tabulates one.
        max_average_input_speed: Limit for the mean input speed [rpm], if any.
        flags: Stand-ins and corrections among the values above.
        source: The catalog file it came from.
        bearing: What the catalog rates its output bearing for; None when it rates it
            for nothing (the bearing's loads are then reported, not checked).
        starting_torque: No-load starting torque at the input [N m], if given.
        backdriving_torque: No-load backdriving torque at the output [N m] (the lower end
            of a range), if given.
        stiffness: Its torsional stiffness, if given.
        provenance: Catalog key (dotted for a sub-table, e.g. ``"stiffness.k1_nm_per_rad"``)
            -> where the number was read; empty where the file claims no source.
        catalog: What its catalog file says of itself.
    """

    id: str
    series: str
    size: int
    ratio: int
    rated_torque: float
    repeated_torque: float
    momentary_torque: float | None
    static_torque: float | None
    max_input_speed: float
    input_inertia: float
    mass: float
    efficiency: EfficiencyTable | None
    rules: SeriesRules
    average_torque: float | None
    max_average_input_speed: float | None
    flags: tuple[Flag, ...]
    source: Path
    bearing: BearingRating | None = None
    starting_torque: float | None = None
    backdriving_torque: float | None = None
    stiffness: Stiffness | None = None
    provenance: Mapping[str, Source] = field(default_factory=dict, compare=False)
    catalog: CatalogInfo = CatalogInfo()

    def flags_for(self, *fields: str) -> tuple[Flag, ...]:
        """The flags on the given quantities (`WHOLE_UNIT`: those on the whole unit)."""
        return tuple(flag for flag in self.flags if flag.field in fields)

    def provenance_lines(self) -> list[str]:
        """One readable line per sourced catalog key, in key order (`Source.line`)."""
        return [self.provenance[key].line(key) for key in sorted(self.provenance)]
