"""The precision figures' outputs: the parts list's stiffness, the terminal, JSON and HTML."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from hdselect import load_catalog, size
from hdselect.cli.main import main
from hdselect.report.figures import png_bytes
from hdselect.report.html_summary import parts_section
from hdselect.report.parts import PARTS_COLUMNS, parts_csv
from hdselect.report.precision_figures import precision_figures
from hdselect.report.precision_html import precision_section
from hdselect.report.precision_tables import precision_tables, precision_warnings
from hdselect.report.tables import console_for
from hdselect.sizing.precision import Raise, TargetCheck
from hdselect.sizing.precision_records import STIFFNESS_NOT_RATED
from hdselect.sizing.records import size_json
from helpers.motions import gravity_overload_motion

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


# ------------------------------------------------------------------ JSON, terminal, HTML
def test_the_json_gives_the_figures_in_the_designers_units_at_the_samples_they_name(shg_result):
    """Twists in arcmin, the tool in mm, each named sample's task, time and pose read back
    from the trajectory itself; no NaN or Infinity."""
    document = json.loads(json.dumps(size_json(shg_result), allow_nan=False))["precision"]
    found = shg_result.precision
    traj = shg_result.trajectory
    for entry, joint in zip(document["joints"], found.joints, strict=True):
        assert entry["name"] == joint.name and entry["rated"] is True
        assert entry["max_torsion_arcmin"] == pytest.approx(
            joint.max_torsion * 60 * 180 / math.pi)
        assert entry["max_torsion_time_s"] == pytest.approx(traj.t[joint.max_torsion_sample])
        assert entry["hysteresis_loss_arcmin"] == pytest.approx(1.0)  # SHG-14: 1 arcmin
        assert entry["resonance_speed_rpm"] == pytest.approx(entry["lowest_frequency_hz"] * 30)
    tool = found.tool
    worst = document["tool"]["holding"]["worst"]
    assert document["tool"]["holding"]["max_translation_mm"] == pytest.approx(
        1000 * float(np.linalg.norm(tool.holding_translation[tool.worst_holding])))
    sample = int(tool.samples[tool.worst_holding])
    assert worst["time_s"] == pytest.approx(traj.t[sample])
    assert worst["pose"] == pytest.approx(dict(zip(traj.joint_names, traj.q[sample].tolist(),
                                                   strict=True)))
    assert math.hypot(*worst["translation_mm"]) == pytest.approx(
        document["tool"]["holding"]["max_translation_mm"])
    modes = document["modes"]
    assert modes["lowest_hz"] == pytest.approx(found.modes.lowest_frequency)
    assert modes["lowest_hz"] == min(modes["frequencies_hz"])
    assert max(abs(v) for v in modes["shape"].values()) == pytest.approx(1.0)
    assert document["not_rated"] == [] and document["note"] is None


def test_without_a_rated_stiffness_the_json_says_not_rated_and_computes_nothing():
    document = size_json(size(None, BENCHTOP))["precision"]
    assert document["tool"] is None and document["modes"] is None
    assert document["not_rated"] == [j["name"] for j in document["joints"]]
    assert all(j["max_torsion_arcmin"] is None and STIFFNESS_NOT_RATED in j["note"]
               for j in document["joints"])
    assert size_json(size(None, BENCHTOP, precision=False))["precision"] is None


def test_every_precision_key_is_documented_in_docs_precision():
    """The keys of docs/precision.md's JSON list are the document's, one for one."""
    page = (ROOT / "docs" / "precision.md").read_text(encoding="utf-8")
    document = json.loads(json.dumps(size_json(size(
        None, BENCHTOP, catalog=load_catalog(["shg-2uh"], series=["shg-2uh"]))),
        allow_nan=False))["precision"]
    keys = set(keys_of(document))
    missing = sorted(key for key in keys if f"`{key}`" not in page)
    assert missing == []


def keys_of(value):
    """Every key of a JSON value, nested; not the joint names keying a pose or a shape."""
    if isinstance(value, dict):
        for key, inner in value.items():
            yield key
            if key not in ("pose", "shape"):
                yield from keys_of(inner)
    elif isinstance(value, list):
        for inner in value:
            yield from keys_of(inner)


def printed(result) -> str:
    buffer = io.StringIO()
    console = console_for(buffer)
    for renderable in precision_tables(result):
        console.print(renderable)
    return buffer.getvalue()


def test_the_terminal_section_fits_80_columns_piped(shg_result, monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    text = printed(shg_result)
    assert "Precision" in text and "tool 'tool0': sags" in text and "arm: lowest mode" in text
    assert max(len(line) for line in text.splitlines()) <= 80
    for joint in shg_result.precision.joints:
        assert f"{joint.max_torsion * 60 * 180 / math.pi:.3g}" in text
    monkeypatch.setenv("COLUMNS", "40")
    narrow = printed(shg_result)
    assert max(len(line) for line in narrow.splitlines()) <= 40
    assert "  twist arcmin max /held: " in narrow  # one block per row


def test_the_terminal_says_not_rated_in_one_paragraph_and_nothing_without_figures(monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    text = printed(size(None, BENCHTOP))
    assert text.strip().startswith(f"Precision: {STIFFNESS_NOT_RATED} (PSA-")
    assert "--series shg-2uh" in text.replace("\n", " ")
    assert printed(size(None, BENCHTOP, precision=False)) == ""


def test_the_html_section_tables_the_worst_poses_and_embeds_both_figures(shg_result):
    pngs = {name: png_bytes(fig) for name, fig in precision_figures(shg_result).items()}
    assert sorted(pngs) == ["modes", "tool"]
    assert all(png.startswith(b"\x89PNG") for png in pngs.values())
    section = precision_section(shg_result, pngs)
    assert section.count("<img src='data:image/png;base64,") == 2
    assert "The worst poses" in section
    for name in shg_result.trajectory.joint_names:
        assert f">{name}</span>" in section
    tool = shg_result.precision.tool
    sample = int(tool.samples[tool.worst_holding])
    degrees = shg_result.trajectory.q[sample, 1] * 180 / math.pi
    assert f"{degrees:.1f}&deg;" in section
    assert precision_section(size(None, BENCHTOP, precision=False), {}) == ""


def test_a_twist_target_on_units_that_rate_no_stiffness_reads_not_rated(monkeypatch, capsys):
    """Regression: every PSA-G check of a --max-torsion target has no value (no K1): the
    column was left out, as if no target had been set; now its cells say so."""
    monkeypatch.setenv("COLUMNS", "120")
    assert main(["compare", str(BENCHTOP), "--max-torsion", "6", "--joint", "elbow"]) == 0
    lines = capsys.readouterr().out.split("\n\n")[1].splitlines()
    column = next(line for line in lines if line.startswith("unit")).index("twist")
    rows = [line for line in lines if line.startswith(("▶PSA", " PSA"))]
    assert len(rows) == 7
    assert all(row[column - 4:column + 5].strip() == "not rated" for row in rows)


def test_an_infinite_frequency_is_null_in_json_and_inf_in_the_table(shg_result, monkeypatch):
    """A joint that sees no inertia (nothing beyond it) has f_n = sqrt(K1 / 0): the JSON
    never holds Infinity, the table says inf."""
    found = shg_result.precision
    tip = dataclasses.replace(found.joints[-1], lowest_frequency=math.inf,
                              resonance_speed=math.inf)
    frequencies = found.modes.frequencies.copy()
    frequencies[:, -1] = math.inf
    modes = dataclasses.replace(found.modes, frequencies=frequencies)
    result = dataclasses.replace(shg_result, precision=dataclasses.replace(
        found, joints=(*found.joints[:-1], tip), modes=modes))
    document = json.loads(json.dumps(size_json(result), allow_nan=False))["precision"]
    assert document["joints"][-1]["lowest_frequency_hz"] is None
    assert document["joints"][-1]["resonance_speed_rpm"] is None
    assert document["modes"]["frequencies_hz"][-1] is None
    monkeypatch.setenv("COLUMNS", "120")
    row = next(line for line in printed(result).splitlines() if line.startswith("wrist_3"))
    assert " inf " in row
    assert precision_figures(result)["modes"] is not None


def test_a_joint_no_unit_fits_names_no_unit_in_any_precision_output(tmp_path, monkeypatch):
    """Regression: the figures of a joint no unit holds are its strongest candidate's; the
    precision table, notes and JSON named that unit as if it were chosen."""
    monkeypatch.setenv("COLUMNS", "120")
    heavy = size(None, gravity_overload_motion(tmp_path / "heavy.toml"))  # PSA-G: not rated
    (missing,) = [joint for joint in heavy.joints if joint.selected is None]
    assert missing.strongest.unit.id not in printed(heavy)
    # SHG-2UH, rated: no unit twists less than 0.03 arcmin under the shoulder lift's torque
    units = load_catalog(["shg-2uh"], series=["shg-2uh"])
    result = size(None, BENCHTOP, catalog=units, max_torsion={"shoulder_lift": 1e-5})
    (missing,) = [joint for joint in result.joints if joint.selected is None]
    assert missing.name == "shoulder_lift"
    text = printed(result)
    row = next(line for line in text.splitlines() if line.startswith("shoulder_lift"))
    assert row.split()[1] == "none" and missing.strongest.unit.id not in row
    assert "shoulder_lift: no unit holds this joint" in " ".join(text.split())
    entry = size_json(result)["precision"]["joints"][1]
    assert entry["unit"] is None and entry["note"].startswith("no unit holds this joint")


def test_the_review_summary_warns_of_a_target_missed_a_unit_raised_and_no_stiffness(shg_result):
    found = shg_result.precision
    missed = TargetCheck("tool_deflection", 8e-4, 5e-4, False,
                         "cannot be met by this catalog (best reached 0.8 mm against 0.5 mm)")
    met = TargetCheck("arm_frequency", 16.3, 15.0, True)
    raised = Raise("elbow", "SHG-14-80-2UH", "SHG-17-80-2UH", "tool deflection", 0.29)
    result = dataclasses.replace(shg_result, precision=dataclasses.replace(
        found, targets=(missed, met), raised=(raised,)))
    lines = precision_warnings(result)
    assert lines == [
        "target NOT met: tool deflection 0.8 mm, at most 0.5 mm: cannot be met by this "
        "catalog (best reached 0.8 mm against 0.5 mm).",
        "raised for stiffness (tool deflection): elbow SHG-14-80-2UH -> SHG-17-80-2UH, "
        "+0.29 kg."]
    unrated = precision_warnings(size(None, BENCHTOP))
    assert len(unrated) == 1 and "stiffness not rated by the source" in unrated[0]
    assert unrated[0].startswith("PSA-")


@pytest.mark.slow
def test_a_browser_shows_the_precision_section_and_a_phone_scrolls_its_tables(tmp_path):
    """The SHG-2UH report in Chromium: both precision figures decode, no console error, and
    at phone width the page itself never scrolls sideways."""
    from browser import Browser, chromium

    executable = chromium()
    if executable is None:
        pytest.skip("no Chromium here: `apt-get install chromium` (or set HDSELECT_CHROMIUM)")
    out = tmp_path / "report"
    assert main(["size", str(BENCHTOP), "--series", "shg-2uh", "--report", str(out)]) == 0
    assert (out / "precision_tool.png").is_file() and (out / "precision_modes.png").is_file()
    url = (out / "index.html").resolve().as_uri()
    with Browser(executable) as browser:
        browser.load(url)
        sizes = browser.evaluate(
            "Promise.all([...document.querySelectorAll('#precision img')].map(async (i) => {"
            "await i.decode(); return [i.naturalWidth, i.naturalHeight]; }))")
        assert len(sizes) == 2 and all(w > 500 and h > 300 for w, h in sizes)
        heads = browser.evaluate("[...document.querySelectorAll('#precision h3')]"
                                 ".map((h) => h.textContent)")
        assert heads == ["The worst poses"]
        errors = [e for e in browser.events if e.get("method") == "Runtime.exceptionThrown"
                  or (e.get("method") == "Log.entryAdded"
                      and e["params"]["entry"]["level"] in ("error", "warning"))]
        assert errors == []
        browser.send("Emulation.setDeviceMetricsOverride", session=True, width=420,
                     height=900, deviceScaleFactor=1, mobile=True)
        browser.load(url)
        width, inner = browser.evaluate(
            "[document.documentElement.scrollWidth, window.innerWidth]")
        assert width <= inner


def test_a_whole_arm_target_that_could_not_be_judged_says_so(shg_result):
    """TargetCheck.value None (a unit rates no stiffness): null in JSON, words in the notes."""
    unjudged = TargetCheck("arm_frequency", None, 15.0, False, "not rated by the source")
    result = dataclasses.replace(shg_result, precision=dataclasses.replace(
        shg_result.precision, targets=(unjudged,)))
    (entry,) = size_json(result)["precision"]["targets"]
    assert entry == {"name": "arm_frequency", "value": None, "limit": 15.0, "unit": "Hz",
                     "ok": False, "shortfall": "not rated by the source"}
    assert precision_warnings(result)[0] == (
        "target NOT met: lowest arm mode not judged, at least 15 Hz: not rated by the source.")
