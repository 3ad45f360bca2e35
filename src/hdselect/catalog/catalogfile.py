"""Read catalog files (TOML) into units: the built-in PSA-G page, and a user's own.

Every number is checked and converted to SI once, here; where the source's two
unit systems disagree the lower value is taken and flagged.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError, deprecated
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.catalog.units import (
    BEARING_RULE_KEYS,
    KG_M2_PER_KG_CM2,
    KG_M2_PER_LB_IN2,
    KG_PER_LB,
    NM_PER_LB_IN,
    RULE_KEYS,
    BearingRating,
    EfficiencyTable,
    Flag,
    MeanSpeed,
    SeriesRules,
    Unit,
    logger,
)

# quantity -> ((SI key, factor to SI), (imperial key, factor to SI))
_QUANTITIES = {
    "rated_torque": (("rated_torque_nm", 1.0), ("rated_torque_lb_in", NM_PER_LB_IN)),
    "repeated_torque": (("repeated_torque_nm", 1.0), ("repeated_torque_lb_in", NM_PER_LB_IN)),
    "momentary_torque": (("momentary_torque_nm", 1.0),
                         ("momentary_torque_lb_in", NM_PER_LB_IN)),
    "static_torque": (("static_torque_nm", 1.0), ("static_torque_lb_in", NM_PER_LB_IN)),
    "average_torque": (("average_torque_nm", 1.0), ("average_torque_lb_in", NM_PER_LB_IN)),
    "input_inertia": (("input_inertia_kg_cm2", KG_M2_PER_KG_CM2),
                      ("input_inertia_lb_in2", KG_M2_PER_LB_IN2)),
    "mass": (("mass_kg", 1.0), ("mass_lb", KG_PER_LB)),
}


_REQUIRED = ("rated_torque", "repeated_torque", "mass")


_UNIT_KEYS = ["id", "size", "ratio", "max_input_speed_rpm", "max_average_input_speed_rpm",
              "efficiency", "bearing"] + [
    key for pair in _QUANTITIES.values() for key, _ in pair
]


_EFFICIENCY_KEYS = ["input_speed_rpm", "torque_percent", "value"]


# [unit.bearing] key -> (BearingRating field, range)
_BEARING_KEYS = {"pitch_diameter_m": ("pitch_diameter", bounds.PITCH_DIAMETER),
                 "dynamic_rating_n": ("dynamic_rating", bounds.BEARING_LOAD),
                 "static_rating_n": ("static_rating", bounds.BEARING_LOAD),
                 "max_moment_nm": ("max_moment", bounds.TORQUE),
                 "max_radial_n": ("max_radial", bounds.BEARING_LOAD),
                 "max_axial_n": ("max_axial", bounds.BEARING_LOAD),
                 "offset_m": ("offset", bounds.BEARING_OFFSET)}


# quantity -> its physical range in SI
_RANGES = {"rated_torque": bounds.TORQUE, "repeated_torque": bounds.TORQUE,
           "momentary_torque": bounds.TORQUE, "static_torque": bounds.TORQUE,
           "average_torque": bounds.TORQUE, "input_inertia": bounds.GEAR_INERTIA,
           "mass": bounds.GEAR_MASS}


_EFFICIENCY_AXES = {"input_speed_rpm": bounds.Bound("a speed", "rpm", 0.0, 1e6),
                    "torque_percent": bounds.PERCENT}


BUILTIN = "psa_g.toml"


def load_catalog(catalog: Sequence[str | Path] = (), *,
                 extra: Sequence[str | Path] | None = None) -> tuple[Unit, ...]:
    """Load the built-in PSA-G catalog and any user catalog files.

    Args:
        catalog: User catalog files of the same schema as the built-in one. A file
            without a ``[rules]`` table is judged by the built-in file's rules, and
            each of its units carries a flag that says so.
        extra: Deprecated: the user catalog files, now given as `catalog`.

    Returns:
        Every unit, sorted by size, then ratio, then id.

    Raises:
        InputError: A file is missing or malformed, a value is missing, not a
            finite number in its range (`hdselect.base.bounds`) or inconsistent, two units
            share an id, or `catalog` is not a list of files.
    """
    if extra is not None:
        old = bounds.files_argument(extra, "extra")
        if catalog:
            raise InputError("give either catalog or extra (its old spelling), not both",
                             field="extra")
        deprecated("load_catalog(extra=...)", "load_catalog(catalog=...)")
        catalog = old
    files = bounds.files_argument(catalog, "catalog")
    builtin = resources.files("hdselect.catalog") / "data" / BUILTIN
    with resources.as_file(builtin) as path:
        units = list(_read_file(Path(path), None))
    assumed = _assumed(units[0])
    seen = {unit.id: unit.source for unit in units}
    for file in files:
        for unit in _read_file(Path(file), assumed):
            if unit.id in seen:
                raise InputError(f"unit id '{unit.id}' is already defined in {seen[unit.id]}",
                                 path=file, field=f"unit[{unit.id}].id")
            seen[unit.id] = unit.source
            units.append(unit)
    return tuple(sorted(units, key=lambda u: (u.size, u.ratio, u.id)))


def _assumed(builtin: Unit) -> SeriesRules:
    """The built-in file's rules, flagged for the units of a file that states none."""
    rules = builtin.rules
    note = (f"the catalog file states no [rules]; the built-in {builtin.series} catalog's are "
            f"assumed: rated torque at {rules.rated_input_speed:g} rpm input, rated life "
            f"{rules.rated_life_hours:g} h {rules.life_basis}, {rules.mean_torque_limit} "
            "mean-torque limit, mean speed over "
            f"{rules.mean_speed.over}")
    return replace(rules, flag=Flag("rules", "assumed", note))


def _read_file(path: Path, assumed: SeriesRules | None) -> Iterable[Unit]:
    document = read_toml(path)
    check_keys(document, ["series", "source", "rules", "unit"], path, "")
    series = document.get("series", "")
    if not isinstance(series, str) or not series:
        raise InputError("required: the series name, a non-empty string", path=path,
                         field="series")
    if "rules" in document:
        rules = _read_rules(table_of(document["rules"], path, "rules"), path)
    elif assumed is None:
        raise InputError("required: a [rules] table", path=path, field="rules")
    else:
        rules = assumed
    entries = document.get("unit")
    if not isinstance(entries, list) or not entries:
        raise InputError("no [[unit]] entries", path=path, field="unit")
    raw = [_read_unit(table_of(entry, path, f"unit[{i}]"), series, rules, path, i)
           for i, entry in enumerate(entries)]
    ids = [values["id"] for values in raw]
    for unit_id in ids:
        if ids.count(unit_id) > 1:
            raise InputError(f"unit id '{unit_id}' appears more than once", path=path,
                             field=f"unit[{unit_id}].id")
    for values in raw:
        yield _complete(values, raw, path)


def _read_rules(table: dict[str, Any], path: Path) -> SeriesRules:
    check_keys(table, [*RULE_KEYS, *BEARING_RULE_KEYS], path, "rules")
    values: dict[str, Any] = {}
    for key, choices in RULE_KEYS.items():
        field = f"rules.{key}"
        if key not in table:
            raise InputError("required key is missing", path=path, field=field)
        if isinstance(choices, bounds.Bound):
            values[key] = as_number(table[key], path, field, bound=choices)
        elif isinstance(table[key], str) and table[key] in choices:
            values[key] = table[key]
        else:
            raise InputError(f"expected one of {', '.join(map(repr, choices))}, got "
                             f"{table[key]!r}", path=path, field=field)
    bearing: dict[str, Any] = {key: as_number(table[key], path, f"rules.{key}", bound=bound)
                               for key, bound in BEARING_RULE_KEYS.items() if key in table}
    return SeriesRules(
        rated_input_speed=values["rated_input_speed_rpm"],
        rated_life_hours=values["rated_life_hours"], life_basis=values["life_basis"],
        mean_torque_limit=values["mean_torque_limit"], mean_speed=MeanSpeed(values["mean_speed"]),
        max_momentary_events=values["max_momentary_events"], source=path, **bearing)


def _read_unit(entry: dict[str, Any], series: str, rules: SeriesRules, path: Path,
               index: int) -> dict[str, Any]:
    where = f"unit[{index}]"
    check_keys(entry, _UNIT_KEYS, path, where)
    values: dict[str, Any] = {"series": series, "rules": rules, "flags": []}
    for key, bound in (("size", bounds.FRAME_SIZE), ("ratio", bounds.RATIO)):
        if key not in entry:
            raise InputError("required key is missing", path=path, field=f"{where}.{key}")
        number = as_number(entry[key], path, f"{where}.{key}", bound=bound)
        if number != int(number):
            raise InputError(f"must be a whole number, got {number:g}", path=path,
                             field=f"{where}.{key}")
        values[key] = int(number)
    default_id = f"{series}-{values['size']:02d}-{values['ratio']}"
    if "id" in entry and (not isinstance(entry["id"], str) or not entry["id"].strip()):
        raise InputError(f"expected a non-empty unit id, got {entry['id']!r}", path=path,
                         field=f"{where}.id")
    values["id"] = str(entry.get("id", default_id))
    where = f"unit[{values['id']}]"
    values["where"] = where
    if "max_input_speed_rpm" not in entry:
        raise InputError("required key is missing", path=path,
                         field=f"{where}.max_input_speed_rpm")
    values["max_input_speed"] = as_number(entry["max_input_speed_rpm"], path,
                                          f"{where}.max_input_speed_rpm",
                                          bound=bounds.INPUT_SPEED)
    values["max_average_input_speed"] = (
        as_number(entry["max_average_input_speed_rpm"], path,
                  f"{where}.max_average_input_speed_rpm", bound=bounds.INPUT_SPEED)
        if "max_average_input_speed_rpm" in entry else None)
    for quantity, ((si_key, si_factor), (imp_key, imp_factor)) in _QUANTITIES.items():
        given = [(key, entry[key], factor) for key, factor in
                 ((si_key, si_factor), (imp_key, imp_factor)) if key in entry]
        for key, raw, factor in given:
            as_number(raw, path, f"{where}.{key}", bound=_RANGES[quantity], scale=factor,
                      unit=_unit_label(key))
        if not given:
            if quantity in _REQUIRED:
                raise InputError(f"required: {si_key} or {imp_key}", path=path,
                                 field=f"{where}.{si_key}")
            values[quantity] = None
            continue
        values[quantity] = _agree(quantity, given, values["flags"])
    if rules.mean_torque_limit == "tabulated" and values["average_torque"] is None:
        raise InputError("required: average_torque_nm or average_torque_lb_in, since the "
                         "[rules] mean_torque_limit is 'tabulated'", path=path,
                         field=f"{where}.average_torque_nm")
    if values["repeated_torque"] < values["rated_torque"]:
        raise InputError(f"the repeated-peak limit {values['repeated_torque']:.3g} N m is below "
                         f"the rated torque {values['rated_torque']:.3g} N m", path=path,
                         field=f"{where}.repeated_torque_nm")
    values["efficiency"] = (_efficiency(table_of(entry["efficiency"], path, f"{where}.efficiency"),
                                        path, f"{where}.efficiency")
                            if "efficiency" in entry else None)
    values["bearing"] = (_bearing(table_of(entry["bearing"], path, f"{where}.bearing"), path,
                                  f"{where}.bearing") if "bearing" in entry else None)
    return values


def _bearing(table: dict[str, Any], path: Path, where: str) -> BearingRating:
    """A unit's ``[unit.bearing]``: its output bearing's ratings, each optional.

    Raises:
        InputError: An unknown key, a number out of range, no rating at all, or a load
            rating without the pitch diameter its equivalent load needs.
    """
    check_keys(table, list(_BEARING_KEYS), path, where)
    values = {name: as_number(table[key], path, f"{where}.{key}", bound=bound)
              for key, (name, bound) in _BEARING_KEYS.items() if key in table}
    if not set(values) - {"pitch_diameter", "offset"}:
        raise InputError("gives no rating: give at least one of "
                         + ", ".join(key for key in _BEARING_KEYS
                                     if key not in ("pitch_diameter_m", "offset_m")),
                         path=path, field=where)
    for rating in ("dynamic_rating", "static_rating"):
        if rating in values and "pitch_diameter" not in values:
            raise InputError(f"{rating}_n needs pitch_diameter_m (the equivalent load counts "
                             "the tilting moment as 2 M / d_p)", path=path,
                             field=f"{where}.pitch_diameter_m")
    return BearingRating(**values)


def _agree(quantity: str, given: list[tuple[str, Any, float]], flags: list[Flag]) -> float:
    """One SI value from one or two published columns; the lower where they disagree.

    Two columns agree when their rounding intervals (half a unit of the last
    printed digit of each) overlap after conversion.
    """
    si = [(key, raw, float(raw) * factor, _half_digit(raw) * factor) for key, raw, factor in given]
    if len(si) == 1:
        return si[0][2]
    (key_a, raw_a, a, tol_a), (key_b, raw_b, b, tol_b) = si
    if abs(a - b) <= tol_a + tol_b:
        return a
    low = min(a, b)
    si_label = {"input_inertia": "kg m^2", "mass": "kg"}.get(quantity, "N m")
    label = (quantity.replace("_", " ").replace("torque", "limit")
             .replace("rated limit", "rated torque").replace("average limit",
                                                             "average-torque limit"))
    disagree = (f"{label}: the source's {raw_a:g} {_unit_label(key_a)} and {raw_b:g} "
                f"{_unit_label(key_b)} disagree; the lower, ")
    flags.append(Flag(quantity, "corrected", f"{disagree}{low:.3g} {si_label}, is used",
                      f"{disagree}{_imperial(quantity, low)}, is used"))
    return low


def _imperial(quantity: str, value: float) -> str:
    """An SI value of a catalog quantity in the page's imperial units, e.g. ``70 lb-in``."""
    if quantity == "input_inertia":
        return f"{value / KG_M2_PER_LB_IN2:.3g} lb-in^2"
    if quantity == "mass":
        return f"{value / KG_PER_LB:.3g} lb"
    return f"{value / NM_PER_LB_IN:.3g} lb-in"


def _unit_label(key: str) -> str:
    """The unit a catalog key is written in, e.g. ``lb-in`` for ``static_torque_lb_in``."""
    for suffix, label in (("_lb_in2", "lb-in^2"), ("_lb_in", "lb-in"), ("_nm", "N m"),
                          ("_kg_cm2", "kg cm^2"), ("_kg", "kg"), ("_lb", "lb")):
        if key.endswith(suffix):
            return label
    return ""


def _half_digit(raw: int | float) -> float:
    """Half a unit of the last digit of a TOML number as written (0.5 for an integer)."""
    text = repr(raw)
    if isinstance(raw, int) or "e" in text or "." not in text:
        return 0.5
    return 0.5 * 10.0 ** -len(text.split(".")[1])


def _complete(values: dict[str, Any], file_units: list[dict[str, Any]], path: Path) -> Unit:
    """Fill the gaps a source leaves with flagged conservative stand-ins."""
    flags: list[Flag] = values["flags"]
    where = values["where"]
    for limit in ("momentary_torque", "static_torque"):
        name = limit.replace("_", " ").replace("torque", "limit")
        if values[limit] is None:
            values[limit] = values["repeated_torque"]
            text = f"{name} not rated by the source; the repeated-peak limit ({{}}) is used"
            flags.append(Flag(limit, "fallback",
                              text.format(f"{values['repeated_torque']:.3g} N m"),
                              text.format(_imperial(limit, values["repeated_torque"]))))
        elif values[limit] < values["repeated_torque"]:
            logger.warning("%s: %s: %s %.3g N m is below the repeated-peak limit %.3g N m",
                           path, where, name, values[limit], values["repeated_torque"])
    if values["input_inertia"] is None:
        larger = sorted((other["size"], other["input_inertia"]) for other in file_units
                        if other["size"] > values["size"] and other["input_inertia"] is not None)
        if not larger:
            raise InputError("input inertia missing and no larger unit in the file bounds it",
                             path=path, field=f"{where}.input_inertia_kg_cm2")
        size, inertia = larger[0]
        values["input_inertia"] = inertia
        text = f"input inertia not given by the source; the size {size:02d} value ({{}}) bounds it"
        flags.append(Flag("input_inertia", "fallback",
                          text.format(f"{inertia / KG_M2_PER_KG_CM2:.4g} kg cm^2"),
                          text.format(_imperial("input_inertia", inertia))))
    return Unit(
        id=values["id"], series=values["series"], size=values["size"], ratio=values["ratio"],
        rated_torque=values["rated_torque"], repeated_torque=values["repeated_torque"],
        momentary_torque=values["momentary_torque"], static_torque=values["static_torque"],
        max_input_speed=values["max_input_speed"], input_inertia=values["input_inertia"],
        mass=values["mass"], efficiency=values["efficiency"], rules=values["rules"],
        average_torque=values["average_torque"],
        max_average_input_speed=values["max_average_input_speed"], flags=tuple(flags),
        source=path, bearing=values["bearing"],
    )


def _efficiency(table: dict[str, Any], path: Path, where: str) -> EfficiencyTable:
    check_keys(table, _EFFICIENCY_KEYS, path, where)
    axes = {}
    for axis, bound in _EFFICIENCY_AXES.items():
        raw = table.get(axis, [0.0])
        if not isinstance(raw, list) or not raw:
            raise InputError("expected a non-empty list of numbers", path=path,
                             field=f"{where}.{axis}")
        values = [as_number(v, path, f"{where}.{axis}", bound=bound) for v in raw]
        if any(b <= a for a, b in zip(values, values[1:], strict=False)):
            raise InputError("must be strictly increasing", path=path, field=f"{where}.{axis}")
        axes[axis] = tuple(values)
    raw_value = table.get("value")
    rows = raw_value if isinstance(raw_value, list) else None
    if rows and not isinstance(rows[0], list):
        rows = [[v] for v in rows] if len(axes["torque_percent"]) == 1 else [rows]
    shape = (len(axes["input_speed_rpm"]), len(axes["torque_percent"]))
    if rows is None or len(rows) != shape[0] or any(
            not isinstance(r, list) or len(r) != shape[1] for r in rows):
        raise InputError(f"expected {shape[0]} x {shape[1]} efficiencies (input speeds x torque "
                         "percentages)", path=path, field=f"{where}.value")
    value = tuple(tuple(as_number(v, path, f"{where}.value", bound=bounds.EFFICIENCY)
                        for v in row) for row in rows)
    return EfficiencyTable(axes["input_speed_rpm"], axes["torque_percent"], value)
