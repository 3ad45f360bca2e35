"""The catalog against the seed's specification table, and user catalog files."""

from __future__ import annotations

import dataclasses
import logging
import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog

NM_PER_LB_IN = 0.1129848  # N m per lbf in: 4.4482216 N x 0.0254 m
KG_M2_PER_LB_IN2 = 2.9264e-4
KG_M2_PER_KG_CM2 = 1e-4
KG_PER_LB = 0.45359237

# The PSA-G catalog page's specification table, both columns, transcribed by hand again
# (not read from catalog/data/psa_g.toml): (lb-in, N m) for torques; None where the page
# is blank or says NA.
SEED = {
    "PSA-08-80": dict(rated=(14, 1.6), repeated=(23, 2.6), momentary=None, static=None,
                      speed=7000, inertia=None, mass=(0.66, 0.3)),
    "PSA-08-100": dict(rated=(18, 2.0), repeated=(31, 3.5), momentary=None, static=None,
                       speed=7000, inertia=None, mass=(0.66, 0.3)),
    "PSA-10-50": dict(rated=(30, 3.4), repeated=(30, 3.4), momentary=(50, 5.7),
                      static=(50, 5.7), speed=7000, inertia=(0.0021, 0.0062), mass=(0.88, 0.4)),
    "PSA-10-80": dict(rated=(40, 4.5), repeated=(40, 4.5), momentary=(80, 9.0),
                      static=(70, 9.0), speed=7000, inertia=(0.0021, 0.0062), mass=(0.88, 0.4)),
    "PSA-14-50": dict(rated=(102, 11.5), repeated=(119, 13.4), momentary=(140, 15.8),
                      static=(202, 22.8), speed=6000, inertia=(0.0114, 0.033), mass=(1.1, 0.5)),
    "PSA-14-80": dict(rated=(102, 11.5), repeated=(140, 15.8), momentary=(200, 22.6),
                      static=(238, 26.9), speed=6000, inertia=(0.0114, 0.033), mass=(1.1, 0.5)),
    "PSA-14-100": dict(rated=(102, 11.5), repeated=(180, 20.3), momentary=(200, 22.6),
                       static=(300, 34.6), speed=6000, inertia=(0.0114, 0.033), mass=(1.1, 0.5)),
}
# The two contradictions of the source (docs/rules.md, "The catalog and its defects"):
# the lower column is used.
CORRECTED_STATIC = {
    "PSA-10-80": 70 * NM_PER_LB_IN,  # 70 x 0.1129848 = 7.908936 N m < 9.0 N m
    "PSA-14-100": 300 * NM_PER_LB_IN,  # 300 x 0.1129848 = 33.89544 N m < 34.6 N m
}
PSA10_INERTIA = 0.0062 * KG_M2_PER_KG_CM2  # 6.2e-7 kg m^2, the PSA-08 stand-in
TORQUES = ("rated", "repeated", "momentary", "static")


def builtin() -> dict[str, object]:
    return {unit.id: unit for unit in load_catalog()}


def test_builtin_has_the_seven_units_in_order() -> None:
    units = load_catalog()
    assert [u.id for u in units] == list(SEED)
    assert [(u.series, u.size, u.ratio) for u in units] == [
        ("PSA", 8, 80), ("PSA", 8, 100), ("PSA", 10, 50), ("PSA", 10, 80),
        ("PSA", 14, 50), ("PSA", 14, 80), ("PSA", 14, 100)]


@pytest.mark.parametrize("unit_id", list(SEED))
def test_si_values_match_the_seed_table(unit_id: str) -> None:
    unit = builtin()[unit_id]
    row = SEED[unit_id]
    repeated_nm = row["repeated"][1]
    expected = {
        "rated": row["rated"][1],
        "repeated": repeated_nm,
        # a blank momentary/static limit falls back to the repeated-peak limit
        "momentary": row["momentary"][1] if row["momentary"] else repeated_nm,
        "static": CORRECTED_STATIC.get(unit_id, row["static"][1] if row["static"] else
                                       repeated_nm),
    }
    for name in TORQUES:
        assert getattr(unit, f"{name}_torque") == pytest.approx(expected[name], abs=1e-12), name
    assert unit.max_input_speed == row["speed"]
    inertia_kg_cm2 = row["inertia"][1] if row["inertia"] else 0.0062  # blank: PSA-10 value
    assert unit.input_inertia == pytest.approx(inertia_kg_cm2 * 1e-4, rel=1e-12)
    assert unit.mass == pytest.approx(row["mass"][1], abs=1e-12)
    assert unit.efficiency is None


@pytest.mark.parametrize("unit_id", list(SEED))
def test_imperial_column_agrees_within_rounding(unit_id: str) -> None:
    # A printed integer lb-in is +-0.5 lb-in = +-0.0565 N m; a printed N m figure with one
    # decimal is +-0.05 N m. So the two columns agree when they differ by <= 0.1065 N m.
    unit = builtin()[unit_id]
    row = SEED[unit_id]
    for name in TORQUES:
        if row[name] is None:
            continue
        lb_in, _ = row[name]
        assert abs(getattr(unit, f"{name}_torque") - lb_in * NM_PER_LB_IN) <= (
            0.5 * NM_PER_LB_IN + 0.05), name
    if row["inertia"] is not None:
        # 0.0021 lb-in^2 = 6.145e-7 kg m^2 vs 6.2e-7; 0.0114 lb-in^2 = 3.336e-6 vs 3.3e-6
        lb_in2, _ = row["inertia"]
        half_digits = 0.00005 * KG_M2_PER_LB_IN2 + 0.0005 * KG_M2_PER_KG_CM2
        assert abs(unit.input_inertia - lb_in2 * KG_M2_PER_LB_IN2) <= half_digits
    # 0.66 lb = 0.2994 kg, 0.88 lb = 0.3992 kg, 1.1 lb = 0.4990 kg
    assert abs(unit.mass - row["mass"][0] * KG_PER_LB) <= 0.005 * KG_PER_LB + 0.05


def test_contradictory_static_limits_use_the_lower_and_are_flagged() -> None:
    units = builtin()
    # 70 lb-in = 70 x 0.1129848 = 7.908936 N m
    assert units["PSA-10-80"].static_torque == pytest.approx(7.908936, abs=1e-9)
    # 300 lb-in = 300 x 0.1129848 = 33.89544 N m
    assert units["PSA-14-100"].static_torque == pytest.approx(33.89544, abs=1e-9)
    for unit_id in CORRECTED_STATIC:
        flags = units[unit_id].flags
        assert [(f.field, f.kind) for f in flags] == [("static_torque", "corrected")]
        assert flags[0].code == "static_torque:corrected"
        assert "disagree" in flags[0].note


@pytest.mark.parametrize("unit_id", ["PSA-08-80", "PSA-08-100"])
def test_psa08_blanks_fall_back_and_are_flagged(unit_id: str) -> None:
    unit = builtin()[unit_id]
    repeated = SEED[unit_id]["repeated"][1]
    assert unit.momentary_torque == repeated
    assert unit.static_torque == repeated
    assert unit.input_inertia == pytest.approx(6.2e-7, rel=1e-12)  # 0.0062 kg cm^2
    assert sorted(f.code for f in unit.flags) == [
        "input_inertia:fallback", "momentary_torque:fallback", "static_torque:fallback"]
    assert all(f.note for f in unit.flags)


@pytest.mark.parametrize("unit_id", ["PSA-10-50", "PSA-14-50", "PSA-14-80"])
def test_other_units_have_no_flags(unit_id: str) -> None:
    assert builtin()[unit_id].flags == ()


def test_units_are_immutable() -> None:
    unit = load_catalog()[0]
    with pytest.raises(AttributeError):
        unit.rated_torque = 99.0  # type: ignore[misc]


# ----------------------------------------------------------------------------- user files

VALID_UNIT = {
    "size": 20,
    "ratio": 50,
    "rated_torque_nm": 30.0,
    "repeated_torque_nm": 40.0,
    "momentary_torque_nm": 60.0,
    "static_torque_nm": 70.0,
    "max_input_speed_rpm": 5000,
    "input_inertia_kg_cm2": 0.1,
    "mass_kg": 1.2,
}


def toml_value(value: object) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    return repr(value)  # ints, floats, inf and nan are all TOML as Python writes them


def unit_toml(extra_lines: str = "", **overrides: object) -> str:
    """One [[unit]] table: VALID_UNIT with overrides; an override of None drops the key."""
    values = {**VALID_UNIT, **overrides}
    lines = ["[[unit]]"] + [f"{key} = {toml_value(v)}" for key, v in values.items()
                            if v is not None]
    return "\n".join(lines) + "\n" + extra_lines + "\n"


def write_catalog(tmp_path: Path, *units: str, series: str = "XYZ",
                  name: str = "extra.toml", rules: str = "") -> Path:
    path = tmp_path / name
    path.write_text(f'series = "{series}"\n{rules}\n' + "\n".join(units), encoding="utf-8")
    return path


def test_valid_user_unit_is_added(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml())
    units = load_catalog([path])
    assert len(units) == 8
    extra = units[-1]  # sorted by size: 20 comes last
    assert extra.id == "XYZ-20-50"
    assert extra.series == "XYZ"
    assert extra.source == path
    assert (extra.rated_torque, extra.repeated_torque) == (30.0, 40.0)
    assert (extra.momentary_torque, extra.static_torque) == (60.0, 70.0)
    assert extra.input_inertia == pytest.approx(1e-5)  # 0.1 kg cm^2 x 1e-4
    assert extra.flags == ()


def test_user_unit_in_imperial_units(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(
        rated_torque_nm=None, rated_torque_lb_in=200, mass_kg=None, mass_lb=2.0,
        input_inertia_kg_cm2=None, input_inertia_lb_in2=0.05, id="custom"))
    extra = {u.id: u for u in load_catalog([path])}["custom"]
    assert extra.rated_torque == pytest.approx(22.59696)  # 200 x 0.1129848
    assert extra.mass == pytest.approx(0.90718474)  # 2 x 0.45359237
    assert extra.input_inertia == pytest.approx(1.4632e-5)  # 0.05 x 2.9264e-4


@pytest.mark.parametrize(("overrides", "field", "reason"), [
    ({"rated_torque_nm": None}, "unit[XYZ-20-50].rated_torque_nm", "required"),
    ({"repeated_torque_nm": None}, "unit[XYZ-20-50].repeated_torque_nm", "required"),
    ({"mass_kg": None}, "unit[XYZ-20-50].mass_kg", "required"),
    ({"max_input_speed_rpm": None}, "unit[XYZ-20-50].max_input_speed_rpm", "required"),
    ({"ratio": None}, "unit[0].ratio", "required"),
    ({"rated_torque_nm": 0.0}, "unit[XYZ-20-50].rated_torque_nm",
     "must be a torque between 0.0001 and 1e+07 N m"),
    ({"static_torque_nm": -5.0}, "unit[XYZ-20-50].static_torque_nm", "between 0.0001"),
    ({"rated_torque_nm": 1e308}, "unit[XYZ-20-50].rated_torque_nm", "between 0.0001"),
    ({"rated_torque_nm": 1e-300}, "unit[XYZ-20-50].rated_torque_nm", "between 0.0001"),
    ({"ratio": 1e300}, "unit[0].ratio", "a ratio between 1 and 100000"),
    ({"input_inertia_kg_cm2": 1e300}, "unit[XYZ-20-50].input_inertia_kg_cm2",
     "and 1e+07 kg cm^2"),
    ({"mass_kg": 1e6}, "unit[XYZ-20-50].mass_kg", "and 100000 kg"),
    ({"max_input_speed_rpm": 1e308}, "unit[XYZ-20-50].max_input_speed_rpm",
     "between 1 and 1e+06 rpm"),
    ({"mass_kg": math.inf}, "unit[XYZ-20-50].mass_kg", "finite"),
    ({"repeated_torque_nm": math.nan}, "unit[XYZ-20-50].repeated_torque_nm", "finite"),
    ({"max_input_speed_rpm": "fast"}, "unit[XYZ-20-50].max_input_speed_rpm", "number"),
    ({"size": 12.5}, "unit[0].size", "whole number"),
    ({"repeated_torque_nm": 25.0}, "unit[XYZ-20-50].repeated_torque_nm",
     "below the rated torque"),
    ({"rated_torqe_nm": 1.0}, "unit[0].rated_torqe_nm", "did you mean 'rated_torque_nm'"),
])
def test_bad_user_unit_names_file_unit_and_field(
        tmp_path: Path, overrides: dict[str, object], field: str, reason: str) -> None:
    path = write_catalog(tmp_path, unit_toml(**overrides))
    with pytest.raises(InputError) as info:
        load_catalog([path])
    err = info.value
    assert err.path == path
    assert err.field == field
    assert reason in err.reason
    assert str(path) in str(err) and field in str(err)


def test_duplicate_id_within_a_file(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(), unit_toml(mass_kg=2.0))
    with pytest.raises(InputError, match="more than once") as info:
        load_catalog([path])
    assert info.value.path == path
    assert info.value.field == "unit[XYZ-20-50].id"


def test_duplicate_id_against_the_builtin(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(size=14, ratio=80), series="PSA")
    with pytest.raises(InputError, match="already defined in .*psa_g.toml") as info:
        load_catalog([path])
    assert info.value.path == path
    assert info.value.field == "unit[PSA-14-80].id"


def test_duplicate_id_across_user_files(tmp_path: Path) -> None:
    first = write_catalog(tmp_path, unit_toml(), name="a.toml")
    second = write_catalog(tmp_path, unit_toml(), name="b.toml")
    with pytest.raises(InputError, match="already defined in .*a.toml") as info:
        load_catalog([first, second])
    assert info.value.path == second


def test_malformed_toml(tmp_path: Path) -> None:
    path = tmp_path / "broken.toml"
    path.write_text('series = "XYZ"\n[[unit]\nsize = 20\n', encoding="utf-8")
    with pytest.raises(InputError, match="not valid TOML") as info:
        load_catalog([path])
    assert info.value.path == path
    assert str(path) in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "absent.toml"
    with pytest.raises(InputError, match="file not found") as info:
        load_catalog([path])
    assert info.value.path == path


def test_file_without_units(tmp_path: Path) -> None:
    path = write_catalog(tmp_path)
    with pytest.raises(InputError, match=r"no \[\[unit\]\]") as info:
        load_catalog([path])
    assert info.value.field == "unit"


@pytest.mark.parametrize(("key", "name"), [("momentary_torque_nm", "momentary limit"),
                                           ("static_torque_nm", "static limit")])
def test_limit_below_repeated_is_accepted_with_a_warning(
        tmp_path: Path, caplog: pytest.LogCaptureFixture, key: str, name: str) -> None:
    path = write_catalog(tmp_path, unit_toml(**{key: 35.0}))  # repeated is 40 N m
    with caplog.at_level(logging.WARNING, logger="hdselect.catalog.units"):
        units = {u.id: u for u in load_catalog([path])}
    assert getattr(units["XYZ-20-50"], key.removesuffix("_nm")) == 35.0  # kept as given
    warnings = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 1
    message = warnings[0].getMessage()
    assert str(path) in message and "XYZ-20-50" in message and name in message


def test_builtin_loads_without_warnings(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.DEBUG, logger="hdselect"):
        load_catalog()
    assert caplog.records == []


EFFICIENCY_2D = """
[unit.efficiency]
input_speed_rpm = [1000, 3000]
torque_percent = [20, 100]
value = [[0.5, 0.7], [0.4, 0.6]]
"""


def test_efficiency_table_interpolates_and_clamps(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(extra_lines=EFFICIENCY_2D))
    table = {u.id: u for u in load_catalog([path])}["XYZ-20-50"].efficiency
    assert table is not None
    speed = np.array([2000.0, 1500.0, 1000.0, 500.0, 9000.0, 9000.0, 500.0])
    load = np.array([60.0, 40.0, 100.0, 10.0, 150.0, 10.0, 150.0])
    expected = [
        # 2000 rpm is half-way between the rows; 60 % is half-way between the columns:
        # row 1000: 0.5 + 0.5 (0.7 - 0.5) = 0.6; row 3000: 0.4 + 0.5 (0.6 - 0.4) = 0.5
        # -> 0.6 + 0.5 (0.5 - 0.6) = 0.55
        0.55,
        # 1500 rpm is 1/4 of the way; 40 % is 1/4 of the way (20 -> 100):
        # row 1000: 0.5 + 0.25 x 0.2 = 0.55; row 3000: 0.4 + 0.25 x 0.2 = 0.45
        # -> 0.55 + 0.25 (0.45 - 0.55) = 0.525
        0.525,
        0.7,  # a grid point: (1000 rpm, 100 %)
        0.5,  # below both axes: clamped to the corner (1000 rpm, 20 %)
        0.6,  # above both axes: clamped to (3000 rpm, 100 %)
        0.4,  # fast and light: (3000 rpm, 20 %)
        0.7,  # slow and overloaded: (1000 rpm, 100 %)
    ]
    np.testing.assert_allclose(table(speed, load), expected, rtol=1e-12)


def test_efficiency_over_load_only(tmp_path: Path) -> None:
    lines = "[unit.efficiency]\ntorque_percent = [0, 100]\nvalue = [0.6, 0.9]\n"
    path = write_catalog(tmp_path, unit_toml(extra_lines=lines))
    table = {u.id: u for u in load_catalog([path])}["XYZ-20-50"].efficiency
    assert table is not None
    # 50 %: 0.6 + 0.5 x 0.3 = 0.75; 200 % clamps to 0.9; speed plays no part
    np.testing.assert_allclose(table(np.array([100.0, 6000.0]), np.array([50.0, 200.0])),
                               [0.75, 0.9], rtol=1e-12)


@pytest.mark.parametrize(("lines", "field", "reason"), [
    ("[unit.efficiency]\ntorque_percent = [0, 100]\nvalue = [0.6, 1.2]\n",
     "unit[XYZ-20-50].efficiency.value", "between 0.01 and 1"),
    ("[unit.efficiency]\ntorque_percent = [100, 0]\nvalue = [0.6, 0.9]\n",
     "unit[XYZ-20-50].efficiency.torque_percent", "increasing"),
    ("[unit.efficiency]\ntorque_percent = [0, 100]\nvalue = [0.6]\n",
     "unit[XYZ-20-50].efficiency.value", "expected 1 x 2"),
    ("[unit.efficiency]\ntorque_percent = [0, 100]\nvalu = [0.6, 0.9]\n",
     "unit[XYZ-20-50].efficiency.valu", "did you mean 'value'"),
])
def test_bad_efficiency_table(tmp_path: Path, lines: str, field: str, reason: str) -> None:
    path = write_catalog(tmp_path, unit_toml(extra_lines=lines))
    with pytest.raises(InputError) as info:
        load_catalog([path])
    assert info.value.path == path
    assert info.value.field == field
    assert reason in info.value.reason


# ----------------------------------------------------------------------------- [rules]

# Harmonic Drive's CSF rules, as its selection procedure states them (Harmonic Drive AG,
# HFUS-2A/CSD-2A engineering data, "Torque based dimensioning" and "Life of the wave
# generator bearing"; Harmonic Drive LLC, CSF & CSG catalog, "Rated lifetime L10 CSF 7,000").
CSF_RULES = {
    "rated_input_speed_rpm": 2000,
    "rated_life_hours": 7000,
    "life_basis": "L10",
    "mean_torque_limit": "tabulated",
    "mean_speed": "whole-cycle",
    "max_momentary_events": 10000,
}


def rules_toml(**overrides: object) -> str:
    """A [rules] table: CSF_RULES with overrides; an override of None drops the key."""
    values = {**CSF_RULES, **overrides}
    return "[rules]\n" + "".join(f"{key} = {toml_value(v)}\n" for key, v in values.items()
                                  if v is not None)


def test_builtin_states_the_psa_g_rules() -> None:
    # The PSA-G page: T_N at 1750 rpm input for L50 = 35,000 h; (1750 / N)^0.33 x T_N;
    # mean speed over t1..t3. The 10^4 cap on momentary events is Harmonic Drive's.
    for unit in load_catalog():
        rules = unit.rules
        assert (rules.rated_input_speed, rules.rated_life_hours, rules.life_basis) == (
            1750.0, 35000.0, "L50")
        assert (rules.mean_torque_limit, rules.mean_speed) == ("speed-adjusted", "moving")
        assert rules.max_momentary_events == 10000.0
        assert rules.rated_l50_hours == 35000.0
        assert rules.flag is None and rules.source.name == "psa_g.toml"
        assert unit.average_torque is None and unit.max_average_input_speed is None


def test_user_rules_and_series_limits(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(average_torque_nm=35.0,
                                             max_average_input_speed_rpm=3000),
                         rules=rules_toml())
    unit = {u.id: u for u in load_catalog([path])}["XYZ-20-50"]
    rules = unit.rules
    assert (rules.rated_input_speed, rules.rated_life_hours, rules.life_basis) == (
        2000.0, 7000.0, "L10")
    assert (rules.mean_torque_limit, rules.mean_speed) == ("tabulated", "whole-cycle")
    assert rules.rated_l50_hours == 35000.0  # L50 = 5 x L10 = 5 x 7000 h
    assert rules.source == path and rules.flag is None
    assert unit.average_torque == 35.0
    assert unit.max_average_input_speed == 3000.0
    assert unit.flags == ()


def test_user_file_without_rules_is_judged_by_the_builtin_and_flagged(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(), unit_toml(ratio=100))
    builtin = load_catalog()[0].rules
    extra = [u for u in load_catalog([path]) if u.series == "XYZ"]
    assert len(extra) == 2
    for unit in extra:
        flag = unit.rules.flag
        assert flag is not None and flag.code == "rules:assumed"
        assert "states no [rules]" in flag.note and "1750 rpm" in flag.note
        assert "35000 h L50" in flag.note
        # the same numbers as the built-in file's rules, only flagged
        assert dataclasses.replace(unit.rules, flag=None) == builtin
        assert unit.flags == ()  # the catalog values themselves are as given


def test_average_torque_columns_are_reconciled(tmp_path: Path) -> None:
    # 300 lb-in = 33.89544 N m against 35 N m: more than the rounding of either column
    # (0.0565 + 0.5 N m), so the lower is used and flagged.
    path = write_catalog(tmp_path, unit_toml(average_torque_nm=35.0, average_torque_lb_in=300),
                         rules=rules_toml())
    unit = {u.id: u for u in load_catalog([path])}["XYZ-20-50"]
    assert unit.average_torque == pytest.approx(33.89544, abs=1e-9)
    assert [f.code for f in unit.flags] == ["average_torque:corrected"]
    assert "average-torque limit" in unit.flags[0].note


def test_tabulated_rule_needs_the_average_torque(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(), rules=rules_toml())
    with pytest.raises(InputError) as info:
        load_catalog([path])
    assert info.value.path == path
    assert info.value.field == "unit[XYZ-20-50].average_torque_nm"
    assert "tabulated" in info.value.reason
    # the speed-adjusted rule does not need it
    path = write_catalog(tmp_path, unit_toml(), rules=rules_toml(
        mean_torque_limit="speed-adjusted"))
    assert {u.id for u in load_catalog([path])} >= {"XYZ-20-50"}


@pytest.mark.parametrize(("overrides", "field", "reason"), [
    ({"life_basis": "L90"}, "rules.life_basis", "'L10', 'L50'"),
    ({"mean_torque_limit": "rated"}, "rules.mean_torque_limit", "'tabulated', 'speed-adjusted'"),
    ({"mean_speed": "average"}, "rules.mean_speed", "'whole-cycle', 'moving'"),
    ({"rated_input_speed_rpm": 0}, "rules.rated_input_speed_rpm", "between 1 and 1e+06 rpm"),
    ({"rated_life_hours": -7000}, "rules.rated_life_hours", "between 1 and 1e+12 h"),
    ({"rated_life_hours": math.inf}, "rules.rated_life_hours", "finite"),
    ({"max_momentary_events": math.nan}, "rules.max_momentary_events", "finite"),
    ({"rated_input_speed_rpm": "2000"}, "rules.rated_input_speed_rpm", "expected a number"),
    ({"mean_speed": None}, "rules.mean_speed", "required"),
    ({"rated_life_hour": 7000}, "rules.rated_life_hour", "did you mean 'rated_life_hours'"),
])
def test_bad_rules_name_file_and_field(tmp_path: Path, overrides: dict[str, object], field: str,
                                       reason: str) -> None:
    path = write_catalog(tmp_path, unit_toml(average_torque_nm=35.0),
                         rules=rules_toml(**overrides))
    with pytest.raises(InputError) as info:
        load_catalog([path])
    assert info.value.path == path
    assert info.value.field == field
    assert reason in info.value.reason
    assert str(path) in str(info.value) and field in str(info.value)


def test_rules_must_be_a_table(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(), rules="rules = 5\n")
    with pytest.raises(InputError, match="expected a table") as info:
        load_catalog([path])
    assert info.value.field == "rules"


def test_bad_average_input_speed_limit(tmp_path: Path) -> None:
    path = write_catalog(tmp_path, unit_toml(max_average_input_speed_rpm=-1))
    with pytest.raises(InputError, match=r"between 1 and 1e\+06 rpm") as info:
        load_catalog([path])
    assert info.value.field == "unit[XYZ-20-50].max_average_input_speed_rpm"
