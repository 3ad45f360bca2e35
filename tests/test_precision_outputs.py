"""The precision figures' outputs: the parts list's stiffness, the terminal, JSON and HTML."""

from __future__ import annotations

import csv
import io
import math
import tomllib
from pathlib import Path

import pytest

from hdselect import load_catalog, size
from hdselect.report.html_summary import parts_section
from hdselect.report.parts import PARTS_COLUMNS, STIFFNESS_NOT_RATED, parts_csv

ROOT = Path(__file__).resolve().parents[1]
BENCHTOP = ROOT / "trajectories" / "benchtop6_pick_place.toml"
DATA = ROOT / "src" / "hdselect" / "catalog" / "data"
ARCMIN = math.pi / (180.0 * 60.0)


def catalog_entries(name: str) -> dict[str, dict]:
    """A built-in catalog file's units by id, read straight from its TOML (the oracle)."""
    document = tomllib.loads((DATA / name).read_text(encoding="utf-8"))
    return {entry["id"]: entry for entry in document["unit"]}


@pytest.fixture(scope="module")
def shg_result():
    return size(None, BENCHTOP, catalog=load_catalog(["shg-2uh"], series=["shg-2uh"]))


def test_parts_list_gives_each_units_stiffness_as_its_catalog_file_writes_it(shg_result):
    """Every SHG-2UH row: `rated`, and K1, T1, T2, K2, K3, the hysteresis loss, the lost
    motion and the bearing's K_B equal to the numbers of shg_2uh.toml itself."""
    entries = catalog_entries("shg_2uh.toml")
    *rows, total = csv.DictReader(io.StringIO(parts_csv(shg_result)))
    assert list(rows[0]) == list(PARTS_COLUMNS)
    for row in rows:
        entry = entries[row["gearhead"]]
        stiffness, bearing = entry["stiffness"], entry["bearing"]
        assert row["stiffness"] == "rated"
        for column in ("k1_nm_per_rad", "t1_nm", "t2_nm", "k2_nm_per_rad", "k3_nm_per_rad",
                       "hysteresis_loss_arcmin", "lost_motion_arcmin"):
            assert float(row[column]) == pytest.approx(stiffness[column], rel=1e-5), column
        assert float(row["moment_stiffness_nm_per_rad"]) == pytest.approx(
            bearing["moment_stiffness_nm_per_rad"], rel=1e-5)
    assert total["stiffness"] == "" and total["k1_nm_per_rad"] == ""


def test_a_unit_whose_source_rates_no_stiffness_says_so_and_leaves_the_figures_empty():
    """PSA-G rates neither the twist nor the bearing: the words, and no number made up."""
    *rows, _ = csv.DictReader(io.StringIO(parts_csv(size(None, BENCHTOP))))
    for row in rows:
        assert row["stiffness"] == STIFFNESS_NOT_RATED == "not rated by the source"
        assert all(row[column] == "" for column in PARTS_COLUMNS[PARTS_COLUMNS.index(
            "stiffness") + 1:])


def test_the_reports_parts_list_tables_the_stiffness(shg_result):
    section = parts_section(shg_result)
    assert "K1 [N m/rad]" in section and "bearing K_B [N m/rad]" in section
    k1 = catalog_entries("shg_2uh.toml")[shg_result.joints[0].selected.unit.id]["stiffness"]
    assert f"{k1['k1_nm_per_rad']:,.0f}" in section
    assert STIFFNESS_NOT_RATED in parts_section(size(None, BENCHTOP))
