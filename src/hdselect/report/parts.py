"""The parts list of a sizing: per joint the gearhead and motor chosen, their masses, why.

One row per sized joint, then a total; the same rows feed the CSV (``--bom``) and the
report's section. Formatting only: every number is the result's.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass

from hdselect.catalog.checks import life_capped
from hdselect.catalog.rules import CHECK_NAMES
from hdselect.catalog.stiffness import rates_torsion
from hdselect.catalog.units import RAD_PER_ARCMIN, Unit
from hdselect.report.terminal import life_text
from hdselect.sizing.diagnosis import diagnosis_of, with_diagnoses
from hdselect.sizing.precision_records import STIFFNESS_NOT_RATED
from hdselect.sizing.result import JointSizing, SizingResult

STIFFNESS_COLUMNS = (("k1_nm_per_rad", "K1 [N m/rad]", "k1"), ("t1_nm", "T1 [N m]", "t1"),
                     ("t2_nm", "T2 [N m]", "t2"), ("k2_nm_per_rad", "K2 [N m/rad]", "k2"),
                     ("k3_nm_per_rad", "K3 [N m/rad]", "k3"),
                     ("hysteresis_loss_arcmin", "hysteresis loss [arcmin]", "hysteresis_loss"),
                     ("lost_motion_arcmin", "lost motion [arcmin]", "lost_motion"),
                     ("moment_stiffness_nm_per_rad", "bearing K_B [N m/rad]", "moment_stiffness"))
"""A unit's stiffness in the parts list: (CSV column, report header, the unit's field).

The catalog's figures, each named as the catalog file's key: the twist's three segments
(K1 up to T1, K2 up to T2, K3 above; `hdselect.catalog.units.Stiffness`), the hysteresis
loss and lost motion (in arcmin, as the catalog gives them), and the output bearing's
moment stiffness K_B (`hdselect.catalog.units.BearingRating`)."""

PARTS_COLUMNS = ("joint", "gearhead", "ratio", "gearhead_mass_kg", "motor", "motor_mass_kg",
                 "mass_kg", "binding", "binding_rule", "utilization", "margin_left",
                 "margin_required", "life_l50_h", "life_l10_h", "inertia_ratio", "status",
                 "stiffness", *(name for name, _, _ in STIFFNESS_COLUMNS))
"""The CSV's columns, in order (docs/review.md describes each):

joint: the sized joint; ``total`` on the last row. gearhead: the unit chosen (empty
where none fits). ratio: its ratio [-]. gearhead_mass_kg: its mass [kg]. motor: the
motor chosen with it (empty without motor data). motor_mass_kg: that motor's mass, or
the assumed motor mass (``--motor-mass``) [kg]. mass_kg: the two together [kg].
binding: the rule closest to its limit, by name (a key of the JSON's ``checks``);
binding_rule: the same in words. utilization: its demand / limit [-]. margin_left:
1 - utilization [-]. margin_required: the design margin every rule was held to [-].
life_l50_h, life_l10_h: the gearhead's life [h], as the terminal writes it: ``unlimited``
(no load while moving), ``> 1e6`` at the cap (`hdselect.catalog.checks.LIFE_CAP`) and
beyond, else the hours. inertia_ratio:
load-to-rotor inertia ratio of the pair [-], empty without a motor. status:
``selected``, or for a joint no unit fits ``no unit fits: `` and its headline shortfall
(e.g. ``peak 87.3 > 20.3 N m``: the demand against the strongest candidate's limit,
`hdselect.sizing.diagnosis`); that row names no unit and no mass, its binding,
binding_rule, utilization and margin_left are the shortfall's (against the strongest
candidate). On the ``total`` row the masses are sums over the joints with a unit.
stiffness: ``rated`` where the unit's source rates its torsional stiffness K1, else
`STIFFNESS_NOT_RATED`; then each figure of `STIFFNESS_COLUMNS`, empty where the source
gives none (and on a row without a unit)."""


@dataclass(frozen=True)
class Part:
    """One row of the parts list; numbers None where they do not apply (see `PARTS_COLUMNS`)."""

    joint: str
    gearhead: str | None
    ratio: float | None
    gearhead_mass_kg: float | None
    motor: str | None
    motor_mass_kg: float | None
    mass_kg: float | None
    binding: str | None
    binding_rule: str | None
    utilization: float | None
    margin_left: float | None
    margin_required: float | None
    life_l50_h: float | None
    life_l10_h: float | None
    inertia_ratio: float | None
    status: str
    stiffness: str | None = None
    k1_nm_per_rad: float | None = None
    t1_nm: float | None = None
    t2_nm: float | None = None
    k2_nm_per_rad: float | None = None
    k3_nm_per_rad: float | None = None
    hysteresis_loss_arcmin: float | None = None
    lost_motion_arcmin: float | None = None
    moment_stiffness_nm_per_rad: float | None = None


def parts(result: SizingResult) -> list[Part]:
    """The parts list: one row per sized joint, then the ``total`` row."""
    result = with_diagnoses(result)
    rows = [_part(result, joint) for joint in result.joints]
    chosen = [row for row in rows if row.gearhead is not None]
    gearheads = sum(row.gearhead_mass_kg or 0.0 for row in chosen)
    motors = sum(row.motor_mass_kg or 0.0 for row in chosen)
    missing = len(rows) - len(chosen)
    rows.append(Part("total", None, None, gearheads, None, motors, gearheads + motors, None,
                     None, None, None, result.options.margin, None, None, None,
                     f"{missing} joint{'s' if missing != 1 else ''} without a unit"
                     if missing else "every joint has a unit"))
    return rows


def _part(result: SizingResult, joint: JointSizing) -> Part:
    chosen = joint.selected
    if chosen is None:
        found = diagnosis_of(result, joint.name)
        if found is None:
            raise RuntimeError(f"joint {joint.name} has no diagnosis (with_diagnoses first)")
        short = found.headline
        return Part(joint.name, *(None,) * 6, short.rule, CHECK_NAMES.get(short.rule, short.rule),
                    short.utilization, 1.0 - short.utilization, result.options.margin, None,
                    None, None, f"no unit fits: {short.short()}")
    motor = chosen.motor_unit
    motor_mass = motor.mass if motor is not None else result.options.motor_mass
    check = chosen.checks[chosen.binding]
    return Part(joint.name, chosen.unit.id, float(chosen.unit.ratio), chosen.unit.mass,
                None if motor is None else motor.id, motor_mass, chosen.unit.mass + motor_mass,
                chosen.binding, CHECK_NAMES.get(chosen.binding, chosen.binding),
                check.utilization, 1.0 - check.utilization, chosen.required_margin,
                chosen.life_hours, chosen.l10_hours, joint.inertia_ratio(chosen), "selected",
                *unit_stiffness(chosen.unit))


def unit_stiffness(unit: Unit) -> tuple[str, *tuple[float | None, ...]]:
    """A unit's stiffness: ``rated`` or `STIFFNESS_NOT_RATED`, then its figures.

    The figures are `STIFFNESS_COLUMNS`' in order and units (None where the unit's source
    gives none).
    """
    figures = []
    for column, _, field in STIFFNESS_COLUMNS:
        rating = unit.bearing if field == "moment_stiffness" else unit.stiffness
        value = None if rating is None else getattr(rating, field)
        figures.append(value / RAD_PER_ARCMIN if value is not None
                       and column.endswith("_arcmin") else value)
    return ("rated" if rates_torsion(unit.stiffness) else STIFFNESS_NOT_RATED, *figures)


def parts_csv(result: SizingResult) -> str:
    """The parts list as CSV text (`PARTS_COLUMNS`; numbers to 6 significant digits, empty: n/a)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(PARTS_COLUMNS)
    for part in parts(result):
        writer.writerow([_life(part, value) if name in _LIVES else
                         "" if value is None else (f"{value:.6g}" if isinstance(value, float)
                                                   else value)
                         for name, value in ((name, getattr(part, name))
                                             for name in PARTS_COLUMNS)])
    return buffer.getvalue()


_LIVES = ("life_l50_h", "life_l10_h")


def _life(part: Part, hours: float | None) -> str:
    """A life cell as the terminal writes it; empty on a row without a unit."""
    if part.gearhead is None:
        return ""
    return life_text(hours, "") if hours is None or life_capped(hours) else f"{hours:.6g}"
