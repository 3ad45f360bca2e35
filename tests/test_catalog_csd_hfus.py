"""The shipped HFUS-2UH catalog against its numbers as printed, with their sources.

No CSD-2UH/2UF catalog is shipped: no stored copy of its tables is legible and no public
transcription of them exists. The HFUS-2UH numbers are read from
tests/data/transcriptions/hfus_2uh.toml, written by hand from the printed rows, not from
the shipped file.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.duty import load_duty, size_duty
from hdselect.catalog.units import MeanSpeed, Unit

PRINTED = tomllib.loads(
    (Path(__file__).parent / "data" / "transcriptions" / "hfus_2uh.toml").read_text())
ROWS = {entry["id"]: entry for entry in PRINTED["unit"]}
KG_M2_PER_X1E4 = 1e-4  # the printed "x10^-4 kg m^2"
RAD_PER_ARCMIN = math.pi / (180.0 * 60.0)

# (printed list, index) -> (what it is on a Unit, SI per printed unit)
PRINTED_NUMBERS = {
    ("row", 3): ("repeated_torque", 1.0), ("row", 4): ("average_torque", 1.0),
    ("row", 5): ("rated_torque", 1.0), ("row", 6): ("momentary_torque", 1.0),
    ("row", 7): ("max_input_speed", 1.0), ("row", 9): ("input_inertia", KG_M2_PER_X1E4),
    ("row", 10): ("mass", 1.0),
    ("torsion", 0): ("stiffness.t1", 1.0), ("torsion", 1): ("stiffness.t2", 1.0),
    ("torsion", 2): ("stiffness.k3", 1e4), ("torsion", 3): ("stiffness.k2", 1e4),
    ("torsion", 4): ("stiffness.k1", 1e4),
    ("bearing", 0): ("bearing.pitch_diameter", 1.0), ("bearing", 1): ("bearing.offset", 1.0),
    ("bearing", 2): ("bearing.dynamic_rating", 1.0),
    ("bearing", 3): ("bearing.static_rating", 1.0),
    ("bearing", 4): ("bearing.max_moment", 1.0),
    ("bearing", 5): ("bearing.moment_stiffness", 1.0 / RAD_PER_ARCMIN),
}


def value_of(unit: Unit, name: str) -> float | None:
    """A unit's field by dotted name, e.g. ``"stiffness.k1"``."""
    value: object = unit
    for part in name.split("."):
        value = getattr(value, part)
    return value  # type: ignore[return-value]


@pytest.fixture(scope="module")
def units() -> dict[str, Unit]:
    """The shipped HFUS-2UH units by id."""
    return {u.id: u for u in load_catalog(["hfus-2uh"]) if u.series == "HFUS-2UH"}


def test_ships_exactly_the_printed_units(units):
    assert sorted(units) == sorted(ROWS)
    for unit_id, entry in ROWS.items():
        assert (units[unit_id].size, units[unit_id].ratio) == tuple(entry["row"][1:3])


@pytest.mark.parametrize("unit_id", sorted(ROWS))
@pytest.mark.parametrize("where", sorted(PRINTED_NUMBERS))
def test_shipped_number_is_the_printed_one(units, unit_id, where):
    name, si_per_printed = PRINTED_NUMBERS[where]
    printed = ROWS[unit_id][where[0]][where[1]]
    assert value_of(units[unit_id], name) == pytest.approx(printed * si_per_printed,
                                                           rel=1e-9)


@pytest.mark.parametrize("unit_id", sorted(ROWS))
def test_what_no_source_rates_is_left_out(units, unit_id):
    unit = units[unit_id]
    assert unit.max_average_input_speed is None  # the column is not read as a rating
    assert unit.static_torque is None
    assert unit.stiffness is not None and unit.bearing is not None
    assert (unit.stiffness.hysteresis_loss, unit.stiffness.lost_motion) == (None, None)
    assert (unit.bearing.max_radial, unit.bearing.max_axial) == (None, None)
    assert (unit.starting_torque, unit.backdriving_torque) == (None, None)


@pytest.mark.parametrize("unit_id", sorted(ROWS))
def test_same_gear_in_the_transcriptions_csg_table_agrees(unit_id):
    """Its HFUC row (same size, ratio and teeth) prints the same torques and speeds."""
    row, hfuc = ROWS[unit_id]["row"], ROWS[unit_id]["hfuc"]
    assert hfuc[1:3] == row[1:3]
    assert [float(x) for x in hfuc[3:9]] == [float(x) for x in row[3:9]]


@pytest.mark.parametrize("unit_id", sorted(ROWS))
def test_stiffness_agrees_with_harmonic_drives_cha_tables(unit_id):
    """CHA Tables 50.3/50.4 print T1, T2 [N m] and K3, K2, K1 [x10^3 N m/rad]."""
    torsion, cha = ROWS[unit_id]["torsion"], ROWS[unit_id]["cha"]
    assert torsion[:2] == pytest.approx(cha[:2])
    assert [k * 1e4 for k in torsion[2:]] == pytest.approx([k * 1e3 for k in cha[2:]])


@pytest.mark.parametrize("unit_id", sorted(ROWS))
def test_limits_are_ordered_as_a_rating_table_orders_them(units, unit_id):
    """Rated < average limit < repeated peak < momentary; K1 < K2 < K3; T1 < T2."""
    u = units[unit_id]
    assert u.rated_torque < u.average_torque < u.repeated_torque < u.momentary_torque
    assert u.stiffness.k1 < u.stiffness.k2 < u.stiffness.k3
    assert u.stiffness.t1 < u.stiffness.t2
    assert u.bearing.dynamic_rating < u.bearing.static_rating


def test_rows_labelled_hfus_that_are_shg_or_unknown_are_not_shipped(units):
    shipped = {(u.size, u.ratio) for u in units.values()}
    for entry in PRINTED["excluded"]:
        row = entry["row"]
        assert row[0] == "HFUS"
        assert (row[1], row[2]) not in shipped, entry["reason"]
        if "shg_rated_nm" in entry:  # its rated torque is the SHG unit's
            assert row[5] == entry["shg_rated_nm"]


def test_rules_are_the_printed_ones(units):
    printed = PRINTED["rules"]
    for unit in units.values():
        rules = unit.rules
        assert rules.rated_input_speed == printed["rated_input_speed_rpm"]["value"]
        assert (rules.rated_life_hours, rules.life_basis) == (
            printed["rated_life_hours"]["value"], "L50")
        assert rules.max_momentary_events == printed["max_momentary_events"]["value"]
        assert rules.mean_speed is MeanSpeed(printed["mean_speed"]["value"])
        assert rules.mean_torque_limit == "tabulated"
        assert rules.missing_limits == "not-rated"
        assert rules.flag is None


@pytest.mark.parametrize("unit_id", sorted(ROWS))
def test_every_number_has_its_source(units, unit_id):
    unit = units[unit_id]
    keys = {"rated_torque_nm", "repeated_torque_nm", "average_torque_nm",
            "momentary_torque_nm", "max_input_speed_rpm", "input_inertia_kg_cm2", "mass_kg",
            "stiffness.t1_nm", "stiffness.t2_nm", "stiffness.k1_nm_per_rad",
            "stiffness.k2_nm_per_rad", "stiffness.k3_nm_per_rad",
            "bearing.pitch_diameter_m", "bearing.offset_m", "bearing.dynamic_rating_n",
            "bearing.static_rating_n", "bearing.max_moment_nm",
            "bearing.moment_stiffness_nm_per_rad", "rules.rated_input_speed_rpm",
            "rules.rated_life_hours", "rules.max_momentary_events"}
    assert keys <= set(unit.provenance)
    for key in keys:
        source = unit.provenance[key]
        assert source.copy.startswith("https://"), key
        assert source.edition and source.page and source.table, key
    assert "d0bd9b5" in unit.provenance["rated_torque_nm"].edition  # the commit read
    assert unit.provenance["rules.rated_life_hours"].edition == "1019658 11/2014"


def test_file_says_it_is_a_transcription_to_check(units):
    info = next(iter(units.values())).catalog
    assert info.name == "hfus-2uh"
    assert "AimanHaidar/harmonic-drive-selector" in info.transcription
    assert "check the current vendor data" in info.check


def test_life_by_hand_counts_the_pause_in_the_mean_speed(units, tmp_path):
    """The duty method on HFUS-25-30 at its rated torque, half the cycle at rated speed.

    By hand (Equation 18.5 of the CSD-2A page, 21.2 of the HFUS-2A page): n_in av = 30 x
    (66.7 rpm x 1 s) / (1 s + 1 s) = 1000 rpm, so L50 = 35000 h x 2000 / 1000 x
    (27 / 27)^3 = 70000 h; a mean over the moving part only would give 35000 h.
    """
    unit = units["HFUS-25-30-2UH"]
    out_rpm = 2000.0 / unit.ratio
    profile = tmp_path / "half.toml"
    profile.write_text(
        f'[[phase]]\nname = "run"\ntorque = 27.0\ntime = 1.0\nspeed = {out_rpm!r}\n'
        '[[phase]]\nname = "dwell"\ntorque = 1.0\ntime = 1.0\nspeed = 0.0\n',
        encoding="utf-8")
    result = size_duty(load_duty(profile), [unit])
    n_in_av = unit.ratio * out_rpm * 1.0 / 2.0
    assert n_in_av == pytest.approx(1000.0)
    assert result.candidates[0].life_hours == pytest.approx(
        35000.0 * 2000.0 / n_in_av * (27.0 / 27.0) ** 3)
