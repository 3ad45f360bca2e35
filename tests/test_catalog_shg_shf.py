"""The shipped SHG-2UH catalog against its sources, as printed, and the vendor's rules by hand.

Every number of ``shg_2uh.toml`` is checked against ``tests/data/transcriptions/shg_2uh.toml``
(the documents' numbers as printed, in their units) converted to SI; the public
transcription is compared with the vendor's document wherever both give a number; every
number carries its source. The torsional stiffness is Harmonic Drive AG's CHA table where it
has the size (checked against the transcription's SHG table, number by number, and against
the vendor's worked torsion-angle example); the output bearing rests on the transcription.
SHF-2UH is not shipped: no stored copy of an SHF table is
legible and no public transcription covers it (docs/catalogs.md).

No Harmonic Drive worked selection example for SHG is legible in any stored copy (the SHF/SHG
catalog's "Selection Example" page and the engineering data's example pages are not), so
the last tests apply the engineering data's own selection procedure (page 30, equations
30.2 to 30.11, and page 32, equation 32.2) by hand to a duty of this file's own and compare
it with ``hdselect duty``.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.duty import load_duty, size_duty
from helpers import REPO

SHIPPED = REPO / "src" / "hdselect" / "catalog" / "data" / "shg_2uh.toml"
PRINTED = REPO / "tests" / "data" / "transcriptions" / "shg_2uh.toml"
NM_PER_LB_IN = 0.1129848  # 1 lb-in = 0.1129848 N m
KG_M2_PER_E4 = 1e-4  # the table's "x10^-4 kg m^2"


def read(path: Path) -> dict[str, Any]:
    with path.open("rb") as file:
        return tomllib.load(file)


RAW = read(SHIPPED)
TABLE = read(PRINTED)
ROWS = {(row["size"], row["ratio"]): row for row in TABLE["row"]}
RAW_UNITS = {unit["id"]: unit for unit in RAW["unit"]}

# shipped key -> (Unit attribute, the as-printed column of each source, SI per printed unit)
KEYS = {
    "rated_torque_nm": ("rated_torque", "rated_torque_nm", 1.0),
    "repeated_torque_nm": ("repeated_torque", "repeated_torque_nm", 1.0),
    "average_torque_nm": ("average_torque", "average_torque_nm", 1.0),
    "momentary_torque_nm": ("momentary_torque", "momentary_torque_nm", 1.0),
    "max_input_speed_rpm": ("max_input_speed", "max_input_speed_rpm", 1.0),
    "input_inertia_kg_cm2": ("input_inertia", "inertia_1e_4_kg_m2", KG_M2_PER_E4),
    "mass_kg": ("mass", "weight_kg", 1.0),
}
# the provenance's document -> the table's part that prints its numbers
PART = {"shglw": "lw", "ahtranscription": "ah"}

# Every disagreement between the transcription and the vendor's document, with its
# resolution: none in the numbers both give (44 rated torques, 11 repeated peaks).
NUMBER_DISAGREEMENTS: dict[tuple[int, int, str], str] = {}

# The transcription's series labels that disagree with the flyer, and their resolution.
LABEL_DISAGREEMENTS = {
    (14, 50): "labelled HFUS; the flyer's SHG-14-50 rated torque 7.0 N m: read as SHG",
    (17, 50): "labelled HFUS; the flyer's SHG-17-50 rated torque 21 N m: read as SHG",
    (50, 80): "labelled HFUS; the flyer's SHG-50-80 rated torque 484 N m: read as SHG",
    (58, 80): "labelled HFUS; the flyer's SHG-58-80 rated torque 714 N m: read as SHG",
}


def source(unit_id: str, key: str) -> dict[str, str]:
    """The provenance entry of one unit's key: the unit's own, else the file's."""
    return RAW_UNITS[unit_id].get("provenance", {}).get(key) or RAW["provenance"][key]


def printed(unit_id: str, key: str) -> float:
    """The as-printed number of one unit's key, from the source its provenance names."""
    unit = RAW_UNITS[unit_id]
    part = PART[source(unit_id, key)["document"]]
    return float(ROWS[unit["size"], unit["ratio"]][part][KEYS[key][1]])


@pytest.fixture(scope="module")
def shg() -> dict[str, Any]:
    """The built-in catalog by its name, as ``--catalog shg-2uh`` loads it."""
    units = {unit.id: unit for unit in load_catalog(["shg-2uh"]) if unit.series == "SHG-2UH"}
    assert {Path(unit.source).resolve() for unit in units.values()} == {SHIPPED.resolve()}
    return units


def test_every_result_says_the_file_uses_a_transcription(shg: dict[str, Any]) -> None:
    for unit in shg.values():
        kinds = [flag.kind for flag in unit.flags]
        assert kinds.count("transcription") == 1, unit.id
        assert "defect" in kinds, unit.id


CASES = [(unit_id, key) for unit_id, unit in RAW_UNITS.items() for key in KEYS if key in unit]


@pytest.mark.parametrize(("unit_id", "key"), CASES, ids=[f"{u}:{k}" for u, k in CASES])
def test_shipped_number_is_the_printed_one_in_si(shg: dict[str, Any], unit_id: str,
                                                 key: str) -> None:
    attribute, _column, factor = KEYS[key]
    expected = printed(unit_id, key) * factor
    assert RAW_UNITS[unit_id][key] * factor == pytest.approx(expected, rel=1e-12)
    assert getattr(shg[unit_id], attribute) == pytest.approx(expected, rel=1e-12)


def test_every_unit_of_the_table_is_shipped_once() -> None:
    ids = [f"SHG-{size}-{ratio}-2UH" for size, ratio in ROWS]
    assert ids == list(RAW_UNITS)  # same units, same order (the flyer's)
    for unit in RAW["unit"]:
        assert unit["id"] == f"SHG-{unit['size']}-{unit['ratio']}-2UH"
    assert len(RAW_UNITS) == 44
    assert {size for size, _ in ROWS} == {14, 17, 20, 25, 32, 40, 45, 50, 58, 65}
    assert {ratio for _, ratio in ROWS} == {50, 80, 100, 120, 160}


def test_every_number_has_a_source() -> None:
    documents = RAW["documents"]
    for unit_id, unit in RAW_UNITS.items():
        numeric = [key for key, value in unit.items() if isinstance(value, int | float)
                   and key not in ("size", "ratio")]
        assert set(numeric) <= set(KEYS), unit_id
        for key in numeric:
            entry = source(unit_id, key)
            assert entry["document"] in documents, (unit_id, key)
            assert entry["page"].strip() and entry["table"].strip(), (unit_id, key)
    for key in RAW["rules"]:
        if key == "missing_limits":
            continue
        entry = RAW["provenance"][f"rules.{key}"]
        assert entry["document"] == "shgdata", key
        assert entry["page"] in ("30", "32"), key
    for name, document in documents.items():
        assert all(document[field].strip() for field in ("title", "publisher", "edition",
                                                         "copy")), name


def test_transcription_is_declared_for_what_it_gives() -> None:
    declared = RAW["transcription"]
    transcribed = {key for unit_id in RAW_UNITS for key in KEYS if key in RAW_UNITS[unit_id]
                   and source(unit_id, key)["document"] == "ahtranscription"}
    assert transcribed == {"repeated_torque_nm", "average_torque_nm", "momentary_torque_nm",
                           "max_input_speed_rpm", "input_inertia_kg_cm2", "mass_kg"}
    for words in ("repeated-peak", "average-torque", "momentary", "maximum input speeds",
                  "input inertias", "masses", "AimanHaidar/harmonic-drive-selector"):
        assert words in declared
    # the repeated peaks read from the vendor's flyer are exactly its legible ones
    from_flyer = [unit_id for unit_id in RAW_UNITS
                  if source(unit_id, "repeated_torque_nm")["document"] == "shglw"]
    assert from_flyer == [f"SHG-{s}-{r}-2UH" for (s, r), row in ROWS.items()
                          if "repeated_torque_nm" in row["lw"]]
    assert len(from_flyer) == 11


def test_flyer_columns_agree_with_each_other() -> None:
    """Legibility check: the flyer's N m and lb-in columns agree within their rounding."""
    for (size, ratio), row in ROWS.items():
        nm, lb_in = row["lw"]["rated_torque_nm"], row["lw"]["rated_torque_lb_in"]
        half_nm = 0.05 if isinstance(nm, float) else 0.5
        assert abs(lb_in * NM_PER_LB_IN - nm) <= half_nm + 0.5 * NM_PER_LB_IN, (size, ratio)


def test_second_transcription_agrees_with_the_document() -> None:
    found = {}
    compared = 0
    for (size, ratio), row in ROWS.items():
        for column, value in row["lw"].items():
            if column not in row["ah"]:
                continue  # the lb-in column: the transcription has N m only
            compared += 1
            if float(row["ah"][column]) != float(value):
                found[size, ratio, column] = f"{row['ah'][column]} against {value}"
    assert compared == 44 + 11
    assert found.keys() == NUMBER_DISAGREEMENTS.keys()


def test_second_transcription_labels_resolved_by_the_document() -> None:
    mislabelled = {key for key, row in ROWS.items() if row["ah"]["label"] != "SHG"}
    assert mislabelled == set(LABEL_DISAGREEMENTS)
    for size, ratio in mislabelled:
        unit = RAW_UNITS[f"SHG-{size}-{ratio}-2UH"]
        assert any("labels this row HFUS" in defect for defect in unit["defects"])
        assert f"{ROWS[size, ratio]['lw']['rated_torque_nm']} N m" in \
            LABEL_DISAGREEMENTS[size, ratio]
    # the rows not taken: no SHG unit of that size and ratio, a rated torque of none
    for row in TABLE["excluded"]:
        assert (row["size"], row["ratio"]) not in ROWS
        assert row["rated_torque_nm"] not in {r["lw"]["rated_torque_nm"] for r in ROWS.values()
                                             if r["size"] == row["size"]}


def test_average_input_speed_left_out_for_the_transcriptions_inconsistency() -> None:
    by_size: dict[int, set[int]] = {}
    for (size, _), row in ROWS.items():
        by_size.setdefault(size, set()).add(row["ah"]["average_input_speed_rpm"])
    assert by_size[14] == {3500, 1100}  # one size, two limits: no rating table prints that
    assert sum(len(values) > 1 for values in by_size.values()) == 8
    for unit_id, unit in RAW_UNITS.items():
        assert "max_average_input_speed_rpm" not in unit
        assert any(defect.startswith("limit for average input speed left out")
                   for defect in unit["defects"]), unit_id


def test_rules_as_the_engineering_data_states_them(shg: dict[str, Any]) -> None:
    assert RAW["rules"] == {"rated_input_speed_rpm": 2000, "rated_life_hours": 50000,
                            "life_basis": "L50", "mean_torque_limit": "tabulated",
                            "mean_speed": "whole-cycle", "max_momentary_events": 10000,
                            "missing_limits": "not-rated"}
    rules = shg["SHG-32-100-2UH"].rules
    assert rules.rated_input_speed == 2000.0
    assert rules.rated_l50_hours == 50000.0  # = 5 x L10 10000 h
    assert "misprint" in RAW["provenance"]["rules.rated_life_hours"]["table"]


# A duty of this file's own (no vendor example is legible): output torque [N m], time [s]
# and output speed [rpm] per phase, a pause, an emergency stop and a required life.
PHASES = [("accelerate", 300.0, 0.2, 10.0), ("run", 150.0, 1.5, 20.0),
          ("decelerate", 250.0, 0.2, 10.0), ("pause", 0.0, 1.1, 0.0)]
STOP = (700.0, 20.0, 0.1)  # T_k [N m], n_k [rpm], t_k [s]
LIFE = 20000.0  # required L50 [h]


def by_hand(row: dict[str, Any], ratio: int) -> dict[str, float]:
    """The engineering data's equations 30.2 to 30.11 and 32.2 for one unit, by hand."""
    moving = [(t, time, n) for _, t, time, n in PHASES if n > 0.0]
    travel = sum(n * time for _, time, n in moving)
    t_av = (sum(n * time * t**3 for t, time, n in moving) / travel) ** (1.0 / 3.0)  # 30.2
    n_out_av = travel / sum(time for _, _, time, _ in PHASES)  # 30.5: t_p counts
    n_in_av = ratio * n_out_av  # 30.6
    n_in_max = ratio * max(n for _, _, n in moving)  # 30.7
    life = 50000.0 * (2000.0 / n_in_av) * (row["rated_torque_nm"] / t_av) ** 3  # 32.2
    torque, n_k, t_k = STOP
    events = min(1e4 / (2.0 * n_k * ratio / 60.0 * t_k), 1e4)  # 30.11
    use = {"peak": max(t for t, _, _ in moving) / row["repeated_torque_nm"],  # 30.8
           "mean": t_av / row["average_torque_nm"],  # 30.4
           "speed": n_in_max / row["max_input_speed_rpm"],
           "momentary": torque / row["momentary_torque_nm"],  # 30.10
           "life": LIFE / life}
    return {"t_av": t_av, "n_out_av": n_out_av, "life": life, "events": events,
            "worst": max(use.values())}


def write_duty(tmp_path: Path) -> Path:
    text = "".join(f'[[phase]]\nname = "{name}"\ntorque = {t}\ntime = {time}\nspeed = {n}\n'
                   for name, t, time, n in PHASES)
    torque, n_k, t_k = STOP
    text += (f"[momentary]\ntorque = {torque}\nspeed = {n_k}\ntime = {t_k}\n"
             f'[requirements]\nlife_hours = {LIFE}\nlife_basis = "L50"\n')
    path = tmp_path / "shg_duty.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_duty_by_the_engineering_data_procedure(tmp_path: Path, shg: dict[str, Any]) -> None:
    result = size_duty(load_duty(write_duty(tmp_path)), list(shg.values()))
    # 30.2: sum n t T^3 = 2 x 300^3 + 30 x 150^3 + 2 x 250^3 = 186.5e6 over sum n t = 34
    hand = by_hand(ROWS[32, 120]["ah"], 120)
    assert hand["t_av"] == pytest.approx((186.5e6 / 34.0) ** (1.0 / 3.0), rel=1e-12)
    assert result.load.mean_torque == pytest.approx(hand["t_av"], rel=1e-9)
    assert result.load.mean_torque == pytest.approx(176.36, abs=0.005)
    rules = shg["SHG-32-120-2UH"].rules
    rpm = 2.0 * math.pi / 60.0
    assert result.load.mean_speed_under(rules) == pytest.approx(34.0 / 3.0 * rpm, rel=1e-12)
    for candidate in result.candidates:
        unit = candidate.unit
        row = ROWS[unit.size, unit.ratio]["ah"] | {"rated_torque_nm":
                                                   ROWS[unit.size, unit.ratio]["lw"][
                                                       "rated_torque_nm"]}
        expected = by_hand(row, unit.ratio)
        assert candidate.checks["mean"].limit == pytest.approx(row["average_torque_nm"])
        assert candidate.checks["life"].value == pytest.approx(expected["life"], rel=1e-9)
        assert candidate.checks["momentary"].detail["allowed_events"] == pytest.approx(
            expected["events"], rel=1e-12)
        assert candidate.feasible == (expected["worst"] <= 1.0), unit.id
        # not rated by the source, so not checked: no limit, no share of the verdict
        assert candidate.checks["static"].detail["not_rated"] == "not rated by the source"
        assert candidate.checks["average_speed"].detail["not_rated"] == "not rated by the source"
        assert candidate.checks["average_speed"].utilization == 0.0
    # smallest size that holds, then the largest margin: SHG-32-120 and -160 tie (the
    # momentary limit 892 N m binds both), the lower ratio wins
    assert result.selected is not None
    assert result.selected.unit.id == "SHG-32-120-2UH"
    fits = [c.unit.id for c in result.candidates if c.feasible and c.unit.size == 32]
    assert fits == ["SHG-32-80-2UH", "SHG-32-100-2UH", "SHG-32-120-2UH", "SHG-32-160-2UH"]
    assert by_hand(ROWS[32, 120]["ah"] | {"rated_torque_nm": 178}, 120)["events"] == \
        pytest.approx(1250.0)  # 1e4 / (2 x 2400 / 60 x 0.1)


def test_lower_csg_momentary_limits_are_flagged_not_used(shg: dict[str, Any]) -> None:
    """Where the same size and ratio's CSG rows print a lower momentary limit, say so."""
    noted = {f"SHG-{s}-{r}-2UH": row for (s, r), row in ROWS.items()
             if "csg_momentary_lowest_nm" in row}
    flagged = {unit_id for unit_id, unit in RAW_UNITS.items()
               if any(defect.startswith("momentary limit:") for defect in unit["defects"])}
    assert flagged == set(noted)
    assert len(noted) == 11
    for unit_id, row in noted.items():
        assert row["csg_momentary_lowest_nm"] < row["ah"]["momentary_torque_nm"], unit_id
        assert shg[unit_id].momentary_torque == row["ah"]["momentary_torque_nm"], unit_id


# Torsional stiffness and output bearing: shipped key -> (printed key of each source, SI
# per printed unit). CHA: Harmonic Drive AG's Tables 50.3/50.4 (x10^3 N m/rad); ahtables:
# the transcription's shg_torsional_data (x10^4 N m/rad) and shg_output_bearing_data.
RAD_PER_ARCMIN = math.pi / (180.0 * 60.0)
STIFFNESS = {"t1_nm": ("t1", "t1_nm", "t1_nm", 1.0, 1.0),
             "t2_nm": ("t2", "t2_nm", "t2_nm", 1.0, 1.0),
             "k1_nm_per_rad": ("k1", "k1_1e3_nm_per_rad", "k1_1e4_nm_per_rad", 1e3, 1e4),
             "k2_nm_per_rad": ("k2", "k2_1e3_nm_per_rad", "k2_1e4_nm_per_rad", 1e3, 1e4),
             "k3_nm_per_rad": ("k3", "k3_1e3_nm_per_rad", "k3_1e4_nm_per_rad", 1e3, 1e4)}
BEARING = {"pitch_diameter_m": ("pitch_diameter", "d_p_m", 1.0),
           "offset_m": ("offset", "r_m", 1.0),
           "dynamic_rating_n": ("dynamic_rating", "c_n", 1.0),
           "static_rating_n": ("static_rating", "c0_n", 1.0),
           "max_moment_nm": ("max_moment", "m_nm", 1.0),
           "moment_stiffness_nm_per_rad": ("moment_stiffness", "k_b_nm_per_arcmin",
                                           1.0 / RAD_PER_ARCMIN)}
CHA_SIZES = {14, 17, 20, 25, 32, 40, 50, 58}  # the CHA sizes of Tables 50.1 to 50.4
# Every disagreement between the CHA tables and the transcription's SHG table, with its
# resolution: none (8 sizes x 2 ratio columns x T1, T2, K1-K3 compared).
STIFFNESS_DISAGREEMENTS: dict[tuple[int, int, str], str] = {}
UNIT_IDS = list(RAW_UNITS)


def stiffness_printed(unit_id: str, key: str) -> float:
    """The as-printed stiffness number in SI, from the source the provenance names."""
    unit = RAW_UNITS[unit_id]
    row = ROWS[unit["size"], unit["ratio"]]
    _, cha_key, ah_key, cha_factor, ah_factor = STIFFNESS[key]
    document = source(unit_id, f"stiffness.{key}")["document"]
    if document == "cha":
        return float(row["cha"][cha_key]) * cha_factor
    assert document == "ahtables", (unit_id, key)
    return float(row["ah_torsion"][ah_key]) * ah_factor


@pytest.mark.parametrize("unit_id", UNIT_IDS)
def test_stiffness_is_the_printed_one_in_si(shg: dict[str, Any], unit_id: str) -> None:
    unit = RAW_UNITS[unit_id]
    assert set(unit["stiffness"]) >= set(STIFFNESS)
    for key, (attribute, *_rest) in STIFFNESS.items():
        expected = stiffness_printed(unit_id, key)
        assert unit["stiffness"][key] == pytest.approx(expected, rel=1e-12), key
        assert getattr(shg[unit_id].stiffness, attribute) == pytest.approx(expected, rel=1e-12)
    stiffness = shg[unit_id].stiffness
    assert stiffness.t1 < stiffness.t2
    assert stiffness.k1 < stiffness.k2 < stiffness.k3  # stiffer as the teeth load up


@pytest.mark.parametrize("unit_id", UNIT_IDS)
def test_stiffness_from_the_vendor_where_it_prints_it(unit_id: str) -> None:
    unit = RAW_UNITS[unit_id]
    row = ROWS[unit["size"], unit["ratio"]]
    documents = {source(unit_id, f"stiffness.{key}")["document"] for key in STIFFNESS}
    if unit["size"] in CHA_SIZES:
        assert documents == {"cha"}
        assert row["cha"]["column"] == ("50" if unit["ratio"] == 50 else "> 50")
    else:
        assert documents == {"ahtables"} and "cha" not in row
        assert "provenance" in unit  # the file-level source is overridden for this unit
    assert row["ah_torsion"]["column"] == ("i50" if unit["ratio"] == 50 else "i80")


def test_stiffness_sources_agree() -> None:
    """Harmonic Drive's CHA tables and the transcription's SHG table, number by number."""
    found = {}
    compared = 0
    for (size, ratio), row in ROWS.items():
        if "cha" not in row:
            continue
        for key, (_, cha_key, ah_key, cha_factor, ah_factor) in STIFFNESS.items():
            compared += 1
            cha = float(row["cha"][cha_key]) * cha_factor
            ah = float(row["ah_torsion"][ah_key]) * ah_factor
            if cha != pytest.approx(ah, rel=1e-12):
                found[size, ratio, key] = f"CHA {cha} against transcription {ah}"
    assert compared == 5 * sum(size in CHA_SIZES for size, _ in ROWS)
    assert found.keys() == STIFFNESS_DISAGREEMENTS.keys()


@pytest.mark.parametrize("unit_id", UNIT_IDS)
def test_hysteresis_and_lost_motion_as_bounded_by_the_vendor(shg: dict[str, Any],
                                                            unit_id: str) -> None:
    unit = RAW_UNITS[unit_id]
    row = ROWS[unit["size"], unit["ratio"]]
    stiffness = shg[unit_id].stiffness
    if "cha" not in row:
        assert "hysteresis_loss_arcmin" not in unit["stiffness"]
        assert (stiffness.hysteresis_loss, stiffness.lost_motion) == (None, None)
        return
    for key, attribute in (("hysteresis_loss_arcmin", "hysteresis_loss"),
                           ("lost_motion_arcmin", "lost_motion")):
        printed_text = row["cha"][key]
        assert printed_text.startswith("< ")  # a bound: the value used is the bound
        assert unit["stiffness"][key] == float(printed_text[2:])
        assert getattr(stiffness, attribute) == pytest.approx(
            float(printed_text[2:]) * RAD_PER_ARCMIN, rel=1e-12)
        assert source(unit_id, f"stiffness.{key}")["document"] == "cha"


def test_vendors_torsion_angle_example_from_the_shipped_stiffness(
        shg: dict[str, Any]) -> None:
    """Harmonic Drive's worked example (1018854 p. 68, Eq. 68.2) with SHG-32's numbers."""
    example = TABLE["torsion_example"]

    def german(text: str) -> float:  # "6,7 . 10^4" as printed -> 67000.0
        mantissa, _, power = text.replace(",", ".").partition(" . 10^")
        return float(mantissa) * 10.0 ** int(power or 0)

    torque = float(example["torque_nm"])
    for ratio in (80, 100, 120, 160):
        s = shg[f"SHG-32-{ratio}-2UH"].stiffness
        assert (s.t1, s.t2) == (example["t1_nm"], example["t2_nm"])
        assert (s.k1, s.k2, s.k3) == pytest.approx(
            [german(example[f"k{i}_nm_per_rad"]) for i in (1, 2, 3)], rel=1e-12)
        assert s.t1 < torque <= s.t2  # Equation 68.2's range
        angle = s.t1 / s.k1 + (torque - s.t1) / s.k2
        assert angle == pytest.approx(german(example["angle_rad"]), abs=0.005e-4)
        assert angle / RAD_PER_ARCMIN == pytest.approx(german(example["angle_arcmin"]),
                                                       abs=0.05)


@pytest.mark.parametrize("unit_id", UNIT_IDS)
def test_bearing_is_the_printed_one_in_si(shg: dict[str, Any], unit_id: str) -> None:
    unit = RAW_UNITS[unit_id]
    printed_row = ROWS[unit["size"], unit["ratio"]]["ah_bearing"]
    assert set(unit["bearing"]) == set(BEARING)  # F_a and F_r are left out
    bearing = shg[unit_id].bearing
    for key, (attribute, column, factor) in BEARING.items():
        expected = float(printed_row[column]) * factor
        assert unit["bearing"][key] == pytest.approx(expected, rel=1e-12), key
        assert getattr(bearing, attribute) == pytest.approx(expected, rel=1e-12), key
        assert source(unit_id, f"bearing.{key}")["document"] == "ahtables"
    assert (bearing.max_radial, bearing.max_axial) == (None, None)
    assert bearing.dynamic_rating < bearing.static_rating
    assert bearing.offset < bearing.pitch_diameter / 2.0


def test_one_bearing_per_size() -> None:
    """The bearing is the unit's, not the ratio's: every ratio of a size has the same one."""
    by_size: dict[int, set[tuple[float, ...]]] = {}
    for unit in RAW_UNITS.values():
        by_size.setdefault(unit["size"], set()).add(tuple(unit["bearing"].values()))
    assert all(len(bearings) == 1 for bearings in by_size.values())
    diameters = [next(iter(by_size[size]))[0] for size in sorted(by_size)]
    assert diameters == sorted(diameters)  # larger size, larger bearing


def test_transcription_declares_the_bearing_and_the_stiffness_it_gives() -> None:
    declared = RAW["transcription"]
    assert "every output-bearing number" in declared
    assert "torsional stiffness of SHG-45 and SHG-65" in declared
    assert "d0bd9b5" in declared and "d0bd9b5" in RAW["documents"]["ahtables"]["edition"]
    from_transcription = {RAW_UNITS[u]["size"] for u in UNIT_IDS
                          if source(u, "stiffness.k1_nm_per_rad")["document"] == "ahtables"}
    assert from_transcription == {45, 65}
    assert RAW["documents"]["cha"]["publisher"] == "Harmonic Drive AG"
