"""The catalog file's schema: every key read and checked, the built-in catalogs by name,
and the provenance of every number of every shipped file.

The fixture tests/data/invented_catalog.toml is invented (no vendor's data): it uses
every key of a catalog file once.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.catalog import catalogfile
from hdselect.catalog.builtin import DATA, builtin_catalogs
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import check_unit, cycle_load, rule
from hdselect.catalog.rules.load import Momentary
from hdselect.catalog.rules.masses import EVERY_MASS
from hdselect.catalog.units import NOT_RATED, WHOLE_UNIT
from hdselect.cli.main import main
from hdselect.sizing.records import candidate_json
from helpers import REPO

FIXTURE = Path(__file__).parent / "data" / "invented_catalog.toml"
CONVEYOR = REPO / "trajectories" / "duty" / "conveyor_index.toml"
ARCMIN = math.pi / (180.0 * 60.0)  # rad


def fixture_units() -> dict[str, object]:
    return {u.id: u for u in load_catalog([FIXTURE]) if u.series == "ZX"}


def altered(tmp_path: Path, old: str, new: str) -> Path:
    """A copy of the fixture with one line changed."""
    text = FIXTURE.read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / "altered.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


# ----------------------------------------------------------------------------- every key


def test_every_key_of_the_fixture_is_read_in_si() -> None:
    units = fixture_units()
    full = units["ZX-20-100-T"]
    assert full.starting_torque == 0.047 and full.backdriving_torque == 5.2
    s = full.stiffness
    assert (s.t1, s.t2, s.k1, s.k2, s.k3) == (7.0, 25.0, 13000.0, 18000.0, 23000.0)
    assert s.hysteresis_loss == pytest.approx(1.0 * math.pi / 10800.0, rel=1e-15)
    assert s.lost_motion == pytest.approx(1.5 * math.pi / 10800.0, rel=1e-15)
    assert full.bearing.moment_stiffness == 2.5e5 and full.bearing.max_moment == 187.0
    assert full.rules.missing_limits == "not-rated"
    assert full.rules.bearing_load_factor == 1.5
    assert full.catalog.name == "zx-test"
    assert full.catalog.check == "Invented for the tests; never use these numbers."
    assert full.catalog.title == "Invented ZX units (test fixture)"
    assert full.momentary_torque == 80.0 and full.static_torque == 60.0
    bare = units["ZX-25-100-T"]
    assert bare.stiffness is None and bare.bearing is None and bare.starting_torque is None


def test_provenance_per_key_with_the_units_own_override() -> None:
    units = fixture_units()
    full, bare = units["ZX-20-100-T"], units["ZX-25-100-T"]
    k1 = full.provenance["stiffness.k1_nm_per_rad"]
    assert (k1.title, k1.publisher, k1.edition, k1.page, k1.table) == (
        "ZX Invented Engineering Data", "Nobody Inc.", "not stated", "30", "Table 30-1")
    assert k1.copy == "https://example.invalid/zx-data"
    assert full.provenance["mass_kg"].page == "50"  # the unit's own entry wins
    assert bare.provenance["mass_kg"].page == "11"
    # a unit claims only the keys it uses (and the rules' numbers)
    assert "stiffness.k1_nm_per_rad" not in bare.provenance
    assert "rules.rated_life_hours" in bare.provenance
    lines = full.provenance_lines()
    assert len(lines) == len(full.provenance) == 31
    assert ("stiffness.k1_nm_per_rad: ZX Invented Engineering Data (Nobody Inc., not stated), "
            "page 30, Table 30-1; copy: https://example.invalid/zx-data") in lines


def test_transcription_and_defects_are_notes_on_every_result() -> None:
    units = fixture_units()
    full = units["ZX-20-100-T"]
    kinds = [(f.field, f.kind) for f in full.flags]
    assert kinds == [(WHOLE_UNIT, "transcription"), (WHOLE_UNIT, "defect")]
    load = cycle_load(np.array([5.0, 1.0]), np.array([2.0, 0.0]), np.array([0.5, 0.5]),
                      np.array([False, True]))
    document = candidate_json(check_unit(load, full))
    assert document["notes"] == [
        "The ZX-25 input inertia is taken from an invented public transcription.",
        "The invented page 10 and page 11 disagree on the mass; the higher, 1.0 kg, is used."]
    assert document["flags"] == ["unit:defect", "unit:transcription"]


# ----------------------------------------------------------------------------- not rated


def test_a_limit_not_rated_is_left_out_and_not_checked() -> None:
    bare = fixture_units()["ZX-25-100-T"]
    assert bare.momentary_torque is None and bare.static_torque is None
    # far above any rating: a stand-in (the repeated peak, 60 N m) would fail it
    load = cycle_load(np.array([5.0, 500.0]), np.array([2.0, 0.0]), np.array([0.5, 0.5]),
                      np.array([False, True]))
    candidate = check_unit(load, bare, momentary=Momentary(900.0, "given"))
    for name in ("momentary", "static"):
        check = candidate.checks[name]
        assert check.ok and check.utilization == 0.0 and check.limit == math.inf
        assert check.detail["not_rated"] == NOT_RATED
    document = candidate_json(candidate)
    assert document["checks"]["static"]["limit"] is None
    assert document["checks"]["static"]["not_rated"] == "not rated by the source"
    assert document["checks"]["static"]["value"] == 500.0
    assert "static limit not rated by the source: the static rule is not checked" in \
        document["notes"]
    assert candidate.feasible


def test_an_average_speed_limit_not_rated_says_so_where_the_series_says_not_rated() -> None:
    """SHG-2UH gives no limit for average input speed: not rated, never a silent 0 %."""
    shg = next(u for u in load_catalog(["shg-2uh"]) if u.id == "SHG-14-50-2UH")
    assert shg.max_average_input_speed is None and shg.rules.missing_limits == "not-rated"
    load = cycle_load(np.array([5.0, 5.0]), np.array([2.0, 2.0]), np.array([0.5, 0.5]),
                      np.array([False, False]))
    check = check_unit(load, shg).checks["average_speed"]
    assert check.ok and check.limit == math.inf and check.detail["not_rated"] == NOT_RATED
    assert check.value == pytest.approx(2.0 * 50 * 60 / (2 * math.pi))  # N_av [rpm]
    # a series that keeps PSA-G's stand-ins: no limit, no words (PSA-G rates none)
    psa = load_catalog()[0]
    assert "not_rated" not in check_unit(load, psa).checks["average_speed"].detail


def test_a_limit_not_rated_bounds_no_solver_form() -> None:
    bare = fixture_units()["ZX-25-100-T"]
    for name in ("momentary", "static"):
        found = rule(name)
        assert found.scale_rows(None, bare, 0.0) == []  # type: ignore[arg-type]

        class Case:
            unit = bare
            margin = 0.0
        assert found.payload_masses(Case()) is EVERY_MASS  # type: ignore[arg-type]
        assert found.path_rows(Case()) == []  # type: ignore[arg-type]
    rated = fixture_units()["ZX-20-100-T"]
    assert list(rule("static").utilizations(30.0, [bare, rated])) == [0.0, 0.5]


def test_stand_in_stays_the_default(tmp_path: Path) -> None:
    path = altered(tmp_path, 'missing_limits = "not-rated"\n', "")
    bare = {u.id: u for u in load_catalog([path])}["ZX-25-100-T"]
    assert bare.momentary_torque == bare.static_torque == 60.0
    assert [f.kind for f in bare.flags_for("momentary_torque", "static_torque")] == [
        "fallback", "fallback"]


def test_duty_shows_not_rated_in_its_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["duty", str(CONVEYOR), "--catalog", str(FIXTURE)]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines()
               if "ZX-25-100-T" in line)
    assert row.count("not rated") == 3  # momentary, static, average input speed


# ----------------------------------------------------------------------------- hostile values

HOSTILE = [
    ("k1_nm_per_rad = 13000.0", "k1_nm_per_rad = nan", "unit[ZX-20-100-T].stiffness.k1"),
    ("k1_nm_per_rad = 13000.0", "k1_nm_per_rad = inf", "stiffness.k1_nm_per_rad"),
    ("k2_nm_per_rad = 18000.0", "k2_nm_per_rad = 1e308", "stiffness.k2_nm_per_rad"),
    ("k3_nm_per_rad = 23000.0", "k3_nm_per_rad = -1.0", "stiffness.k3_nm_per_rad"),
    ("t1_nm = 7.0", 't1_nm = "7"', "stiffness.t1_nm"),
    ("t2_nm = 25.0", "t2_nm = 5.0", "stiffness.t2_nm"),
    ("hysteresis_loss_arcmin = 1.0", "hysteresis_loss_arcmin = 1e6", "hysteresis_loss_arcmin"),
    ("lost_motion_arcmin = 1.5", "lost_motion_arcmin = -0.5", "lost_motion_arcmin"),
    ("lost_motion_arcmin = 1.5", "lost_motion_arcmin = 1.5\nk4 = 1.0", "stiffness.k4"),
    ("starting_torque_nm = 0.047", "starting_torque_nm = nan", "starting_torque_nm"),
    ("backdriving_torque_nm = 5.2", "backdriving_torque_nm = -5.2", "backdriving_torque_nm"),
    ("moment_stiffness_nm_per_rad = 2.5e5", "moment_stiffness_nm_per_rad = 1e308",
     "bearing.moment_stiffness_nm_per_rad"),
    ("defects = [", "defects = [3, ", "defects[0]"),
    ('missing_limits = "not-rated"', 'missing_limits = "guess"', "rules.missing_limits"),
    ('name = "zx-test"', 'name = "ZX Test"', "name"),
    ('check = "Invented for the tests; never use these numbers."', "check = 1", "check"),
    ('transcription = "The ZX-25 input inertia is taken from an invented public transcription."',
     'transcription = "  "', "transcription"),
    ('edition = "Rev 0"\n', "", "documents.zxcat.edition"),
    ('edition = "Rev 0"', 'edition = "Rev 0"\nisbn = "0"', "documents.zxcat.isbn"),
    ('"mass_kg" = { document = "zxdata"', '"mass_kg" = { document = "zzz"', "document"),
    ('page = "50"', "page = 50", 'provenance."mass_kg".page'),
    ('"rated_torque_nm" = { document = "zxcat", page = "10", table = "Table 10-1" }\n', "",
     'provenance."rated_torque_nm"'),
    ('"rated_torque_nm" = {', '"rated_torque_knm" = {', 'provenance.rated_torque_knm'),
]


@pytest.mark.parametrize(("old", "new", "field"), HOSTILE, ids=[h[1][:30] for h in HOSTILE])
def test_a_bad_value_is_one_line_naming_file_and_field(tmp_path: Path, old: str, new: str,
                                                       field: str) -> None:
    path = altered(tmp_path, old, new)
    with pytest.raises(InputError) as err:
        load_catalog([path])
    assert err.value.path == path
    assert field in (err.value.field or ""), str(err.value)
    assert "\n" not in str(err.value)


def test_a_user_file_may_claim_no_source(tmp_path: Path) -> None:
    text = FIXTURE.read_text(encoding="utf-8")
    kept = "\n".join(line for line in text.splitlines() if "document =" not in line)
    kept = re.sub(r"\[provenance\]\n|\[unit\.provenance\]\n", "", kept)
    path = tmp_path / "unsourced.toml"
    path.write_text(kept, encoding="utf-8")
    units = [u for u in load_catalog([path]) if u.series == "ZX"]
    assert [u.provenance for u in units] == [{}, {}]


def test_a_shipped_file_must_source_every_number(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    text = (DATA / "psa_g.toml").read_text(encoding="utf-8")
    lines = [line for line in text.splitlines() if not line.startswith('"mass_lb"')]
    shipped = tmp_path / "psa_g.toml"
    shipped.write_text("\n".join(lines), encoding="utf-8")
    monkeypatch.setattr(catalogfile, "DATA", tmp_path)
    with pytest.raises(InputError, match=r"provenance\.\"mass_lb\": no source for "
                                         r"unit\[PSA-08-80\]'s mass_lb"):
        list(catalogfile._read_file(shipped, None))


# ----------------------------------------------------------------------------- by name


def test_naming_psa_g_loads_it_once() -> None:
    assert load_catalog(["psa-g"]) == load_catalog() == load_catalog(["psa-g", "psa-g"])


def test_builtin_catalogs_are_found_in_the_data_directory() -> None:
    found = builtin_catalogs()
    assert found[0].name == "psa-g" and found[0].series == "PSA"
    assert sorted(c.file.name for c in found) == sorted(p.name for p in DATA.glob("*.toml"))


def test_a_name_that_is_also_a_file_is_refused(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "psa-g").write_text(FIXTURE.read_text(encoding="utf-8"), encoding="utf-8")
    with pytest.raises(InputError, match=r"both a built-in catalog and the file psa-g; "
                                         r"write the file as a path, \./psa-g"):
        load_catalog(["psa-g"])
    assert main(["catalog", "--catalog", "psa-g"]) == 2
    assert "--catalog: 'psa-g' is both" in capsys.readouterr().err
    assert any(u.series == "ZX" for u in load_catalog(["./psa-g"]))
    assert any(u.series == "ZX" for u in load_catalog([Path("psa-g")]))  # a Path is a file


def test_an_unknown_name_lists_the_builtin_catalogs(tmp_path: Path,
                                                    monkeypatch: pytest.MonkeyPatch,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    names = ", ".join(c.name for c in builtin_catalogs())
    with pytest.raises(InputError, match=f"file not found; built-in catalogs: {names}$"):
        load_catalog(["csg-2uhh"])
    assert main(["catalog", "--catalog", "csg-2uhh"]) == 2
    assert capsys.readouterr().err.strip().endswith(
        f"csg-2uhh: file not found; built-in catalogs: {names}")


def test_a_mix_file_names_a_builtin_catalog(tmp_path: Path) -> None:
    from hdselect import load_robot
    from hdselect.motion.mixduty import duty_tables

    robot = load_robot(REPO / "robots" / "planar2.urdf")
    document = {"sizing": {"catalog": ["psa-g"]}}
    _, files = duty_tables(document, tmp_path / "mix.toml", robot)
    assert files == (DATA / "psa_g.toml",)
    document = {"sizing": {"catalog": ["nothing-here"]}}
    with pytest.raises(InputError, match=r"sizing\.catalog\[0\]: catalog file not found: "
                                         r"'nothing-here'; built-in catalogs: psa-g"):
        duty_tables(document, tmp_path / "mix.toml", robot)


# ----------------------------------------------------------------------------- every shipped file


def _numeric_keys(unit: dict[str, object], rules: dict[str, object]) -> set[str]:
    """Every numeric key a unit uses, dotted for its sub-tables, and the rules' numbers."""
    keys = {f"rules.{k}" for k, v in rules.items() if isinstance(v, int | float)}
    for key, value in unit.items():
        if key in ("size", "ratio", "id", "defects", "provenance"):
            continue
        if key in ("stiffness", "bearing"):
            assert isinstance(value, dict)
            keys |= {f"{key}.{k}" for k, v in value.items() if isinstance(v, int | float)}
        else:
            keys.add(key)  # a number, or the efficiency table
    return keys


SHIPPED = sorted(DATA.glob("*.toml"))


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_every_shipped_file_loads_and_sources_every_number(path: Path) -> None:
    document = tomllib.loads(path.read_text(encoding="utf-8"))
    assert document["name"] == path.stem.replace("_", "-")
    if path.stem != "psa_g":
        assert "vendor" in str(document.get("check", "")).lower()  # check the vendor data
    documents = document["documents"]
    for key, entry in documents.items():
        for field in ("title", "publisher", "edition", "copy"):
            assert isinstance(entry.get(field), str) and entry[field].strip(), (key, field)
    units = [u for u in load_catalog([path.stem.replace("_", "-")]) if u.source == path]
    assert len(units) == len(document["unit"])
    by_id = {u.id: u for u in units}
    for raw in document["unit"]:
        own = raw.get("provenance", {})
        for key in _numeric_keys(raw, document.get("rules", {})):
            entry = own.get(key, document["provenance"].get(key))
            assert entry is not None, (raw.get("id"), key)
            assert entry["document"] in documents, (raw.get("id"), key)
            assert str(entry["page"]).strip() and str(entry["table"]).strip(), (raw["id"], key)
        unit = by_id[raw.get("id", f"{document['series']}-{raw['size']:02d}-{raw['ratio']}")]
        assert set(unit.provenance) == _numeric_keys(raw, document.get("rules", {}))


def test_unit_ids_are_unique_across_the_builtin_catalogs() -> None:
    ids: list[str] = []
    for path in SHIPPED:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
        ids += [u.get("id", f"{document['series']}-{u['size']:02d}-{u['ratio']}")
                for u in document["unit"]]
    assert len(ids) == len(set(ids))
    units = load_catalog([c.name for c in builtin_catalogs()])
    assert len(units) == len(ids)


def test_catalog_json_says_which_limit_is_not_rated(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "--catalog", str(FIXTURE), "--json"]) == 0
    units = {u["unit"]: u for u in json.loads(capsys.readouterr().out)["units"]}
    assert units["ZX-25-100-T"]["momentary_torque_nm"] is None
    assert units["ZX-25-100-T"]["not_rated"] == {"momentary_torque_nm": NOT_RATED,
                                                 "static_torque_nm": NOT_RATED}
    assert units["PSA-14-100"]["not_rated"] == {}


# ----------------------------------------------------------------------------- --series


def test_series_keeps_the_units_of_a_series_or_a_catalog_name() -> None:
    zx = load_catalog([FIXTURE], series=["ZX"])
    assert [u.id for u in zx] == ["ZX-20-100-T", "ZX-25-100-T"]
    assert load_catalog([FIXTURE], series=["zx-test"]) == zx
    assert {u.series for u in load_catalog([FIXTURE], series=["psa-g"])} == {"PSA"}
    assert len(load_catalog([FIXTURE], series=["PSA", "ZX"])) == 9
    with pytest.raises(InputError, match=r"^series: no unit loaded is of series 'XY-9'; "
                                         r"loaded: PSA \(psa-g\), ZX \(zx-test\)"):
        load_catalog([FIXTURE], series=["XY-9"])
    # a built-in series named is loaded as if given as a catalog
    assert {u.series for u in load_catalog(series=["CSG-2UH"])} == {"CSG-2UH"}
    assert load_catalog(series=["csg-2uh"]) == load_catalog(["csg-2uh"], series=["csg-2uh"])
    with pytest.raises(InputError, match="expected a list of series names"):
        load_catalog(series="ZX")  # type: ignore[arg-type]


def test_series_on_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "--catalog", str(FIXTURE), "--series", "ZX", "--json"]) == 0
    units = json.loads(capsys.readouterr().out)["units"]
    assert [u["unit"] for u in units] == ["ZX-20-100-T", "ZX-25-100-T"]
    assert main(["catalog", "--series", "CSG-9"]) == 2
    err = capsys.readouterr().err
    assert "--series: no unit loaded is of series 'CSG-9'; loaded: PSA (psa-g)" in err
    assert main(["duty", str(CONVEYOR), "--catalog", str(FIXTURE), "--series", "zx-test",
                 "--json", "-"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert [c["unit"] for c in result["candidates"]] == ["ZX-20-100-T", "ZX-25-100-T"]
    # a built-in series named alone is loaded: no --catalog needed beside it
    assert main(["catalog", "--series", "SHG-2UH", "--json"]) == 0
    shg = json.loads(capsys.readouterr().out)["units"]
    assert len(shg) == 44 and all(u["unit"].startswith("SHG-") for u in shg)


def test_series_restricts_size(capsys: pytest.CaptureFixture[str]) -> None:
    motion = REPO / "trajectories" / "benchtop6_pick_place.toml"
    assert main(["size", str(motion), "--catalog", str(FIXTURE), "--series", "ZX",
                 "--json", "-"]) == 0
    result = json.loads(capsys.readouterr().out)
    chosen = [joint["selected"] for joint in result["joints"]]
    assert chosen and all(unit.startswith("ZX-") for unit in chosen)
    assert main(["size", str(motion), "--series", "ZX"]) == 2
    assert "--series: no unit loaded is of series 'ZX'" in capsys.readouterr().err


# ----------------------------------------------------------------------------- catalog --list


def test_list_gives_every_builtin_catalog(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "--list", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)["catalogs"]
    assert [c["name"] for c in listed] == [c.name for c in builtin_catalogs()]
    psa = listed[0]
    assert (psa["name"], psa["series"], psa["units"], psa["sizes"], psa["ratios"]) == (
        "psa-g", "PSA", 7, [8, 10, 14], [50, 80, 100])
    assert psa["repeated_torque_nm"] == [2.6, 20.3] and psa["bearing_rated"] == "none"
    assert psa["documents"][0]["edition"] == "not stated" and psa["transcription"] is None
    assert main(["catalog", "--list"]) == 0
    table = capsys.readouterr().out
    assert max(len(line) for line in table.splitlines()) <= 80
    for c in listed:
        row = next(line for line in table.splitlines() if line.startswith(c["name"] + " "))
        assert c["series"] in row and str(c["units"]) in row
    for series in ("PSA", "csg-2uh"):  # a built-in series named is loaded, but --series said
        assert main(["catalog", "--list", "--series", series]) == 2
        assert "--series: --list lists the built-in catalogs" in capsys.readouterr().err


def test_catalog_table_ends_with_the_check_and_transcription_notes(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "--catalog", str(FIXTURE), "--series", "ZX"]) == 0
    lines = capsys.readouterr().out.splitlines()
    text = "\n".join(lines)
    assert text.count("invented public") == 1  # once per catalog, not per unit
    assert lines[-3:] == [
        "zx-test: Invented for the tests; never use these numbers.",
        "zx-test: transcription: The ZX-25 input inertia is taken from an invented public",
        "  transcription."]


def test_catalog_json_has_stiffness_bearing_torques_and_provenance(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["catalog", "--catalog", str(FIXTURE), "--series", "ZX", "--json"]) == 0
    unit = json.loads(capsys.readouterr().out)["units"][0]
    assert unit["stiffness"]["k1_nm_per_rad"] == 13000.0
    assert unit["stiffness"]["lost_motion_rad"] == pytest.approx(1.5 * ARCMIN, rel=1e-15)
    assert unit["bearing"]["moment_stiffness_nm_per_rad"] == 2.5e5
    assert (unit["starting_torque_nm"], unit["backdriving_torque_nm"]) == (0.047, 5.2)
    assert unit["provenance"]["mass_kg"] == {
        "title": "ZX Invented Engineering Data", "publisher": "Nobody Inc.",
        "edition": "not stated", "copy": "https://example.invalid/zx-data", "page": "50",
        "table": "Table 50-1, the higher mass"}
    assert unit["catalog"] == "zx-test"


def test_a_study_names_a_builtin_catalog(tmp_path: Path) -> None:
    from hdselect.study import load_study
    from helpers.studies import workspace

    root = workspace(tmp_path)
    shutil.copy(FIXTURE, root / "zx.toml")
    path = root / "named.toml"
    path.write_text('[base]\nmotion = "trajectories/planar2_pick_place.toml"\n'
                    '[grid]\ncatalog = [["psa-g"], ["zx.toml"]]\n', encoding="utf-8")
    first, second = load_study(path).cases
    assert first.catalog == (DATA / "psa_g.toml",) and second.catalog == (root / "zx.toml",)
    (root / "psa-g").write_text("", encoding="utf-8")
    with pytest.raises(InputError, match=r"'psa-g' is both a built-in catalog and the file"):
        load_study(path)


def test_a_note_on_every_unit_of_a_catalog_is_said_once(tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    path = altered(tmp_path, "static_torque_nm = 60.0\n", "")
    text = path.read_text(encoding="utf-8").replace("repeated_torque_nm = 60.0",
                                                    "repeated_torque_nm = 1260.0")
    path.write_text(text, encoding="utf-8")
    assert main(["catalog", "--catalog", str(path), "--series", "ZX"]) == 0
    out = capsys.readouterr().out
    assert " ".join(out.split()).count("static limit not rated by the source") == 1
    assert "zx-test (every unit): static limit not rated by the source" in out
    assert "ZX-25-100-T: momentary limit not rated by the source" in out  # one unit's own
    row = next(line for line in out.splitlines() if line.startswith("ZX-25-100-T"))
    assert row.split()[2] == "1260"  # whole, never 1.26e+03
