"""Studies: the precision targets as parameters, and the precision figures as CSV columns.

The oracle is `hdselect.size` (and `size_trajectory` of the case's own trajectory) run
the ordinary way: a grouped case's figures, computed from its basis, must equal them.
"""

from __future__ import annotations

import csv
import math

import pytest

import hdselect
from hdselect import Options, load_case, load_catalog
from hdselect.base.errors import InputError
from hdselect.catalog.units import RAD_PER_ARCMIN as ARCMIN
from hdselect.study import load_study, run_study
from hdselect.study.casetasks import Inputs
from hdselect.study.group import build_basis
from hdselect.study.pooled import size_case
from hdselect.study.precise import NOT_RATED_CELL, precision_fields
from helpers import REPO
from helpers.studies import differences, separate, workspace

PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
SHG = ("SHG-2UH",)


@pytest.fixture(scope="module")
def benchtop():
    robot, motion = load_case(PICK)
    bare = robot.with_payload(None)
    return bare, motion, build_basis(bare, motion, motion.payload, inertias=True)


def _relative(a: float, b: float) -> float:
    return 0.0 if a == b else abs(a - b) / max(abs(a), abs(b))


@pytest.mark.parametrize(("mass", "time_scale"), [(1.3, 1.2), (0.4, 0.8)])
def test_a_grouped_case_has_the_precision_figures_of_its_own_sizing(benchtop, mass, time_scale):
    robot, motion, basis = benchtop
    units = load_catalog(["shg-2uh"], series=SHG)
    options = Options(stop_time=0.15, threads=1)
    grouped = size_case(basis, mass, time_scale, units, options)
    reference = separate(robot, motion, mass, time_scale, units, options)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    figures = grouped.precision
    assert figures is not None and not figures["not_rated"]
    assert figures["tool_holding"] > 0.0 and figures["arm_frequency"] > 0.0
    assert all(joint["rated"] and joint["max_torsion"] > 0.0 for joint in figures["joints"])


def test_a_grouped_case_without_the_figures_has_none(benchtop):
    _, _, basis = benchtop
    summary = size_case(basis, 1.0, 1.0, load_catalog(["shg-2uh"], series=SHG),
                        Options(threads=1, precision=False))
    assert summary.precision is None


def _study(root, grid: str, base: str = "") -> hdselect.study.Study:
    path = root / "study.toml"
    path.write_text(f"""title = "precision"
[base]
motion = "trajectories/benchtop6_pick_place.toml"
series = "SHG-2UH"
{base}
[grid]
{grid}
""")
    return load_study(path)


def _rows(csv_path):
    with open(csv_path, newline="") as handle:
        return list(csv.DictReader(handle))


@pytest.mark.slow
def test_a_study_cases_figures_equal_hdselect_size(tmp_path):
    root = workspace(tmp_path)
    study = _study(root, "time_scale = [1.0, 1.1, 1.2, 1.3]",
                   "max_torsion = 30.0\nmin_natural_frequency = \"slow-turntables\"")
    out = tmp_path / "out.csv"
    done = run_study(study, out, workers=0)
    assert [record["method"] for record in list(done.records.values())] == ["grouped"] * 4
    sized = hdselect.size(None, root / "trajectories" / "benchtop6_pick_place.toml",
                          catalog=load_catalog(["shg-2uh"], series=SHG), max_torsion=30 * ARCMIN,
                          min_natural_frequency=4.0)
    figures = sized.precision
    assert figures is not None and figures.tool is not None and figures.modes is not None
    record = next(r for r in list(done.records.values()) if r["case"] == 0)["result"]["precision"]
    rows = [row for row in _rows(out) if row["case"] == "0"]
    assert [row["joint"] for row in rows] == [joint.name for joint in figures.joints]
    for row, joint, kept in zip(rows, figures.joints, record["joints"], strict=True):
        assert _relative(kept["max_torsion"], joint.max_torsion) < 1e-9
        assert _relative(kept["lowest_frequency"], joint.lowest_frequency) < 1e-9
        assert _relative(float(row["torsion_arcmin"]), joint.max_torsion / ARCMIN) < 1e-9
        assert _relative(float(row["holding_torsion_arcmin"]),
                         joint.holding_torsion / ARCMIN) < 1e-9
        assert _relative(float(row["natural_frequency_hz"]), joint.lowest_frequency) < 1e-9
        assert _relative(float(row["tool_holding_mm"]), figures.tool.max_holding * 1e3) < 1e-9
        assert _relative(float(row["tool_cycle_mm"]),
                         figures.tool.max_translation * 1e3) < 1e-9
        assert _relative(float(row["arm_frequency_hz"]), figures.modes.lowest_frequency) < 1e-9
        assert row["tool_deflection_target"] == row["arm_frequency_target"] == ""
    assert study.cases[0].values["max_torsion"] == 30.0  # the parameter as written


@pytest.mark.slow
def test_not_rated_cells_where_the_catalog_rates_no_stiffness(tmp_path):
    root = workspace(tmp_path)
    path = root / "study.toml"
    path.write_text("""[base]
motion = "trajectories/planar2_pick_place.toml"
[grid]
precision = [true, false]
""")
    done = run_study(load_study(path), tmp_path / "out.csv", workers=0)
    assert all(record["ok"] for record in list(done.records.values()))
    rows = _rows(tmp_path / "out.csv")
    on = [row for row in rows if row["precision"] == "true"]
    off = [row for row in rows if row["precision"] == "false"]
    assert on and off  # the built-in PSA-G page rates no stiffness
    for row in on:
        assert row["torsion_arcmin"] == row["natural_frequency_hz"] == NOT_RATED_CELL
        assert row["tool_holding_mm"] == row["arm_frequency_hz"] == NOT_RATED_CELL
    for row in off:
        assert row["torsion_arcmin"] == row["tool_holding_mm"] == ""


def test_the_targets_are_parameters_in_the_files_units(tmp_path):
    root = workspace(tmp_path)
    study = _study(root, "max_torsion = [1.5, 3.0]\nmax_tool_deflection = [0.2]\n"
                         "min_arm_frequency = [\"hand-axes\", 12.0]")
    assert len(study.cases) == 4
    assert study.varied == ("max_torsion", "min_arm_frequency")
    options = Inputs().duty(study.cases[0]).options
    assert math.isclose(options.joint_value("max_torsion", "elbow"), 1.5 * ARCMIN)
    assert math.isclose(options.max_tool_deflection, 0.2e-3)
    assert options.min_arm_frequency == 15.0
    assert Inputs().duty(study.cases[1]).options.min_arm_frequency == 12.0
    assert len({case.key for case in study.cases}) == 4


@pytest.mark.parametrize(("grid", "field", "words"), [
    ("max_torsion = [{elbow = 2.0}]", "grid.max_torsion[0]", "one value"),
    ("min_natural_frequency = [\"hand\"]", "grid.min_natural_frequency[0]",
     "unknown application class"),
    ("max_tool_deflection = [-1.0]", "grid.max_tool_deflection[0]", ""),
    ("series = [3]", "grid.series[0]", "series name"),
    ("precision = [\"yes\"]", "grid.precision[0]", "true or false"),
])
def test_bad_precision_parameters_are_refused_naming_the_field(tmp_path, grid, field, words):
    root = workspace(tmp_path)
    with pytest.raises(InputError) as caught:
        _study(root, grid)
    assert caught.value.field == field and words in caught.value.reason


@pytest.mark.slow
def test_a_series_no_unit_is_of_fails_its_case_alone(tmp_path):
    root = workspace(tmp_path)
    study = _study(root, "series = [\"SHG-2UH\", \"XYZ-9\"]")
    done = run_study(study, tmp_path / "out.csv", workers=0)
    ok, failed = (record for record in sorted(list(done.records.values()), key=lambda r: r["case"]))
    assert ok["ok"] and not failed["ok"] and "XYZ-9" in failed["error"]


@pytest.mark.slow
def test_a_max_payload_case_stops_at_its_torsion_target_and_shows_it(tmp_path):
    root = workspace(tmp_path)
    path = root / "study.toml"
    path.write_text("""compute = "max-payload"
[base]
motion = "trajectories/index_table_indexing.toml"
series = "SHG-2UH"
payload = {mass = 1.0, com = [0.2, 0.0, 0.0], frame = "disk"}
[grid]
max_torsion = [0.5, 2.0]
""")
    study = load_study(path)
    done = run_study(study, tmp_path / "out.csv", workers=0)
    assert all(record["ok"] for record in done.records.values())
    rows = _rows(tmp_path / "out.csv")
    assert [float(row["max_torsion"]) for row in rows] == [0.5, 2.0]
    for row in rows:  # the target binds: the unit twists by it at the largest payload
        assert row["payload_limit"].endswith(" torsion")
        assert _relative(float(row["torsion_arcmin"]), float(row["max_torsion"])) < 1e-6


@pytest.mark.slow
def test_a_grouped_case_raises_units_for_a_whole_arm_target_as_size_does(benchtop):
    robot, motion, basis = benchtop
    units = load_catalog(["shg-2uh"], series=SHG)
    free = size_case(basis, 1.0, 1.0, units, Options(threads=1))
    target = 0.8 * free.precision["tool_holding"]  # [m]: the per-joint choice misses it
    options = Options(threads=1, max_tool_deflection=target)
    grouped = size_case(basis, 1.0, 1.0, units, options)
    reference = separate(robot, motion, 1.0, 1.0, units, options)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    figures = grouped.precision
    assert figures["raised"] and figures["tool_holding"] <= target
    (check,) = figures["targets"]
    assert check["name"] == "tool_deflection" and check["ok"]
    cells = {joint["name"]: precision_fields(joint["name"], figures)
             for joint in figures["joints"]}
    assert all(cells[item["joint"]]["raised_from"] == item["chosen"]
               for item in figures["raised"])
    assert {cell["tool_deflection_target"] for cell in cells.values()} == {"met"}
