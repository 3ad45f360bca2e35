"""Read catalog files (TOML) into units: the built-in catalogs, and a user's own.

Every number is checked and converted to SI once, here; where the source's two
unit systems disagree the lower value is taken and flagged. What a file says of
itself and of its sources is read by `hdselect.catalog.sources`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError, deprecated
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.catalog.builtin import DATA, catalog_files, default_file, of_series
from hdselect.catalog.columns import QUANTITIES, RANGES, agree, imperial, unit_label
from hdselect.catalog.sources import (
    HEADER_KEYS,
    STIFFNESS_KEYS,
    catalog_info,
    optional_text,
    read_documents,
    read_sources,
    read_stiffness,
    rule_keys,
    sourced_keys,
    unit_notes,
)
from hdselect.catalog.units import (
    BEARING_RULE_KEYS,
    KG_M2_PER_KG_CM2,
    MISSING_LIMITS,
    NOT_RATED,
    RULE_KEYS,
    BearingRating,
    EfficiencyTable,
    Flag,
    MeanSpeed,
    SeriesRules,
    Unit,
    logger,
)

_REQUIRED = ("rated_torque", "repeated_torque", "mass")


_UNIT_KEYS = ["id", "size", "ratio", "max_input_speed_rpm", "max_average_input_speed_rpm",
              "efficiency", "bearing", "starting_torque_nm", "backdriving_torque_nm",
              "stiffness", "defects", "provenance"] + [
    key for pair in QUANTITIES.values() for key, _ in pair
]


_EFFICIENCY_KEYS = ["input_speed_rpm", "torque_percent", "value"]


# [unit.bearing] key -> (BearingRating field, range)
_BEARING_KEYS = {"pitch_diameter_m": ("pitch_diameter", bounds.PITCH_DIAMETER),
                 "dynamic_rating_n": ("dynamic_rating", bounds.BEARING_LOAD),
                 "static_rating_n": ("static_rating", bounds.BEARING_LOAD),
                 "max_moment_nm": ("max_moment", bounds.TORQUE),
                 "max_radial_n": ("max_radial", bounds.BEARING_LOAD),
                 "max_axial_n": ("max_axial", bounds.BEARING_LOAD),
                 "offset_m": ("offset", bounds.BEARING_OFFSET),
                 "moment_stiffness_nm_per_rad": ("moment_stiffness", bounds.TORSIONAL_STIFFNESS)}


# optional unit keys of a torque [N m] -> Unit field
_TORQUES = {"starting_torque_nm": "starting_torque", "backdriving_torque_nm": "backdriving_torque"}


# every key a [provenance] table may source
_SOURCEABLE = [*(key for key in _UNIT_KEYS if key not in ("id", "defects", "provenance",
                                                          "stiffness", "bearing")),
               *(f"stiffness.{key}" for key in STIFFNESS_KEYS),
               *(f"bearing.{key}" for key in _BEARING_KEYS),
               *(f"rules.{key}" for key in [*RULE_KEYS, *BEARING_RULE_KEYS, "missing_limits"])]


_EFFICIENCY_AXES = {"input_speed_rpm": bounds.Bound("a speed", "rpm", 0.0, 1e6),
                    "torque_percent": bounds.PERCENT}


BUILTIN = "psa_g.toml"
"""The default built-in catalog's file name in ``hdselect/catalog/data``."""


def load_catalog(catalog: Sequence[str | Path] = (), *,
                 extra: Sequence[str | Path] | None = None,
                 series: Sequence[str] = ()) -> tuple[Unit, ...]:
    """Load the built-in PSA-G catalog and any other catalogs: built-in ones by name, files.

    Args:
        catalog: Built-in catalog names (e.g. ``"csg-2uh"``, `hdselect.catalog.builtin`)
            and catalog files of the same schema as the built-in ones. A file without a
            ``[rules]`` table is judged by the PSA-G file's rules, and each of its units
            carries a flag that says so. Naming PSA-G adds nothing: it is always loaded.
        extra: Deprecated: the user catalog files, now given as `catalog`.
        series: Keep only the units of these series, each a series (``"CSG-2UH"``) or a
            catalog's name (``"csg-2uh"``); empty: every unit loaded.

    Returns:
        Every unit (of `series`), sorted by size, then ratio, then id.

    Raises:
        InputError: A file is missing or malformed, a value is missing, not a
            finite number in its range (`hdselect.base.bounds`) or inconsistent, two units
            share an id, `catalog` is not a list of names and files, a name is also a
            file in the current directory, a value is neither, or a series matches no
            unit loaded.
    """
    if extra is not None:
        old = bounds.files_argument(extra, "extra")
        if catalog:
            raise InputError("give either catalog or extra (its old spelling), not both",
                             field="extra")
        deprecated("load_catalog(extra=...)", "load_catalog(catalog=...)")
        catalog = old
    files = catalog_files(catalog)
    units = list(_read_file(default_file(), None))
    assumed = _assumed(units[0])
    seen = {unit.id: unit.source for unit in units}
    for file in files:
        for unit in _read_file(Path(file), assumed):
            if unit.id in seen:
                raise InputError(f"unit id '{unit.id}' is already defined in {seen[unit.id]}",
                                 path=file, field=f"unit[{unit.id}].id")
            seen[unit.id] = unit.source
            units.append(unit)
    return of_series(sorted(units, key=lambda u: (u.size, u.ratio, u.id)), series)


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
    check_keys(document, ["series", "source", "rules", "unit", *HEADER_KEYS], path, "")
    series = document.get("series", "")
    if not isinstance(series, str) or not series:
        raise InputError("required: the series name, a non-empty string", path=path,
                         field="series")
    optional_text(document, "source", path, "source")
    info = catalog_info(document, path)
    known = read_documents(document, path)
    claimed = read_sources(document.get("provenance", {}), known, _SOURCEABLE, path,
                           "provenance")
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
    builtin = path.parent.resolve() == DATA.resolve()
    for values, entry in zip(raw, entries, strict=True):
        values["catalog"] = info
        values["flags"] += unit_notes(entry, info, path, values["where"])
        own = read_sources(entry.get("provenance", {}), known, _SOURCEABLE, path,
                           f"{values['where']}.provenance")
        needed = sourced_keys(entry) + rule_keys(document.get("rules", {}))
        values["provenance"] = {key: source for key, source in {**claimed, **own}.items()
                                if key in needed}
        if builtin or claimed or own:
            _all_sourced(needed, values["provenance"], path, values["where"])
    ids = [values["id"] for values in raw]
    for unit_id in ids:
        if ids.count(unit_id) > 1:
            raise InputError(f"unit id '{unit_id}' appears more than once", path=path,
                             field=f"unit[{unit_id}].id")
    for values in raw:
        yield _complete(values, raw, path)


def _all_sourced(needed: list[str], found: dict[str, Any], path: Path, where: str) -> None:
    """Refuse a unit of a file that claims sources (or is built in) with an unsourced key."""
    for key in needed:
        if key not in found:
            raise InputError(f"no source for {where}'s {key}: give its document, page and "
                             "table in [provenance] or the unit's [unit.provenance]", path=path,
                             field=f'provenance."{key}"')


def _read_rules(table: dict[str, Any], path: Path) -> SeriesRules:
    check_keys(table, [*RULE_KEYS, *BEARING_RULE_KEYS, "missing_limits"], path, "rules")
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
    missing = table.get("missing_limits", MISSING_LIMITS[0])
    if not (isinstance(missing, str) and missing in MISSING_LIMITS):
        raise InputError(f"expected one of {', '.join(map(repr, MISSING_LIMITS))}, got "
                         f"{missing!r}", path=path, field="rules.missing_limits")
    return SeriesRules(
        rated_input_speed=values["rated_input_speed_rpm"],
        rated_life_hours=values["rated_life_hours"], life_basis=values["life_basis"],
        mean_torque_limit=values["mean_torque_limit"], mean_speed=MeanSpeed(values["mean_speed"]),
        max_momentary_events=values["max_momentary_events"], source=path,
        missing_limits=missing, **bearing)


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
    for quantity, ((si_key, si_factor), (imp_key, imp_factor)) in QUANTITIES.items():
        given = [(key, entry[key], factor) for key, factor in
                 ((si_key, si_factor), (imp_key, imp_factor)) if key in entry]
        for key, raw, factor in given:
            as_number(raw, path, f"{where}.{key}", bound=RANGES[quantity], scale=factor,
                      unit=unit_label(key))
        if not given:
            if quantity in _REQUIRED:
                raise InputError(f"required: {si_key} or {imp_key}", path=path,
                                 field=f"{where}.{si_key}")
            values[quantity] = None
            continue
        values[quantity] = agree(quantity, given, values["flags"])
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
    values["stiffness"] = (read_stiffness(table_of(entry["stiffness"], path,
                                                      f"{where}.stiffness"),
                                             path, f"{where}.stiffness")
                           if "stiffness" in entry else None)
    for key, name in _TORQUES.items():
        values[name] = (as_number(entry[key], path, f"{where}.{key}", bound=bounds.TORQUE)
                        if key in entry else None)
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
    figures = ("pitch_diameter", "offset", "moment_stiffness")
    if not set(values) - set(figures):
        raise InputError("gives no rating: give at least one of "
                         + ", ".join(key for key, (name, _) in _BEARING_KEYS.items()
                                     if name not in figures),
                         path=path, field=where)
    for rating in ("dynamic_rating", "static_rating"):
        if rating in values and "pitch_diameter" not in values:
            raise InputError(f"{rating}_n needs pitch_diameter_m (the equivalent load counts "
                             "the tilting moment as 2 M / d_p)", path=path,
                             field=f"{where}.pitch_diameter_m")
    return BearingRating(**values)


def _complete(values: dict[str, Any], file_units: list[dict[str, Any]], path: Path) -> Unit:
    """Fill the gaps a source leaves with flagged conservative stand-ins."""
    flags: list[Flag] = values["flags"]
    where = values["where"]
    for limit in ("momentary_torque", "static_torque"):
        name = limit.replace("_", " ").replace("torque", "limit")
        if values[limit] is None and values["rules"].missing_limits == "not-rated":
            rule = limit.replace("_torque", "")
            flags.append(Flag(limit, "not-rated",
                              f"{name} {NOT_RATED}: the {rule} rule is not checked"))
        elif values[limit] is None:
            values[limit] = values["repeated_torque"]
            text = f"{name} not rated by the source; the repeated-peak limit ({{}}) is used"
            flags.append(Flag(limit, "fallback",
                              text.format(f"{values['repeated_torque']:.3g} N m"),
                              text.format(imperial(limit, values["repeated_torque"]))))
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
                          text.format(imperial("input_inertia", inertia))))
    return Unit(
        id=values["id"], series=values["series"], size=values["size"], ratio=values["ratio"],
        rated_torque=values["rated_torque"], repeated_torque=values["repeated_torque"],
        momentary_torque=values["momentary_torque"], static_torque=values["static_torque"],
        max_input_speed=values["max_input_speed"], input_inertia=values["input_inertia"],
        mass=values["mass"], efficiency=values["efficiency"], rules=values["rules"],
        average_torque=values["average_torque"],
        max_average_input_speed=values["max_average_input_speed"], flags=tuple(flags),
        source=path, bearing=values["bearing"], starting_torque=values["starting_torque"],
        backdriving_torque=values["backdriving_torque"], stiffness=values["stiffness"],
        provenance=values["provenance"], catalog=values["catalog"],
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
