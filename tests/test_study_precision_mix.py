"""Mix files and the precision targets: duty-wide keys, their conflicts, a study of a mix.

A mix file's ``[precision]`` table and its motions' settle as every other duty-wide
value does (the mix file's over its motions', else the one they agree on, a conflict
refused naming both files), shown in the units of the file's keys. A grouped study case
of a mix has the precision figures of `hdselect.size` of the same mix.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import hdselect
from hdselect import load_catalog, summarize
from hdselect.base.errors import InputError
from hdselect.catalog.units import RAD_PER_ARCMIN
from hdselect.study import load_study, run_study
from helpers import REPO
from helpers.studies import differences, workspace

SHG = load_catalog(["shg-2uh"], series=["SHG-2UH"])


def _motion(folder: Path, name: str, precision: str) -> Path:
    source = REPO / "trajectories" / f"benchtop6_{name}.toml"
    text = source.read_text().replace('"../robots/', f'"{REPO}/robots/')
    path = folder / f"{name}.toml"
    path.write_text(text + (f"\n[precision]\n{precision}\n" if precision else ""))
    return path


def _mix(folder: Path, pick: str = "", inspect: str = "", mine: str = "") -> Path:
    _motion(folder, "pick_place", pick)
    _motion(folder, "inspect", inspect)
    path = folder / "mix.toml"
    path.write_text(f"""robot = "{REPO}/robots/benchtop6.urdf"
{f"[precision]{chr(10)}{mine}" if mine else ""}
[[task]]
name = "pick"
motion = "pick_place.toml"
share = 0.7
[[task]]
name = "inspect"
motion = "inspect.toml"
share = 0.3
""")
    return path


def test_motions_that_agree_give_the_duty_its_targets(tmp_path):
    both = "max_torsion_arcmin = {elbow = 2.5}\nmin_arm_frequency_hz = \"hand-axes\""
    mix = hdselect.load_mix(_mix(tmp_path, both, both))
    assert math.isclose(mix.duty_value("max_torsion")["elbow"], 2.5 * RAD_PER_ARCMIN)
    assert mix.duty_value("min_arm_frequency") == 15.0
    assert not mix.overrides


@pytest.mark.slow
def test_motions_that_disagree_are_refused_naming_both_in_arcmin(tmp_path):
    path = _mix(tmp_path, "max_torsion_arcmin = 3.0", "max_torsion_arcmin = {elbow = 2.0}")
    with pytest.raises(InputError) as caught:
        hdselect.size(None, path, catalog=SHG)
    reason = caught.value.reason
    assert caught.value.path == path and caught.value.field == "task"
    assert "pick_place.toml gives precision.max_torsion_arcmin 3," in reason
    assert "inspect.toml gives {elbow = 2}" in reason and "[precision]" in reason
    # the command line settles it, as any duty-wide value
    sized = hdselect.size(None, path, catalog=SHG, max_torsion={"*": 4.0 * RAD_PER_ARCMIN})
    assert math.isclose(sized.options.joint_value("max_torsion", "wrist_1"),
                        4.0 * RAD_PER_ARCMIN)


@pytest.mark.slow
def test_the_mix_files_table_settles_the_duty_with_a_note(tmp_path):
    path = _mix(tmp_path, "max_tool_deflection_mm = 0.5", "max_tool_deflection_mm = 0.7",
                mine="max_tool_deflection_mm = 0.4")
    sized = hdselect.size(None, path, catalog=SHG)
    assert math.isclose(sized.options.max_tool_deflection, 0.4e-3)
    assert ("motion file: mix.toml gives precision.max_tool_deflection_mm 0.4 for the whole "
            "duty, over pick_place.toml's 0.5, inspect.toml's 0.7") in sized.warnings


@pytest.mark.parametrize(("line", "field"), [
    ("max_torsion_arcmin = {wrist = 2.0}", "precision.max_torsion_arcmin"),
    ("min_natural_frequency_hz = \"hands\"", "precision.min_natural_frequency_hz"),
    ("resolution = 1", "precision.resolution"),
])
def test_a_bad_key_of_the_mix_files_table_is_refused_naming_it(tmp_path, line, field):
    path = _mix(tmp_path, mine=line)
    with pytest.raises(InputError) as caught:
        hdselect.size(None, path, catalog=SHG)
    assert caught.value.path == path and str(caught.value.field).startswith(field)


@pytest.mark.slow
def test_a_grouped_study_of_a_mix_has_size_s_figures(tmp_path):
    root = workspace(tmp_path)
    study = root / "study.toml"
    study.write_text("""[base]
motion = "trajectories/mixes/benchtop6_pick_inspect.toml"
series = "SHG-2UH"
[grid]
shares = [[0.7, 0.3], [0.5, 0.5], [0.3, 0.7], [0.9, 0.1]]
""")
    done = run_study(load_study(study), workers=0)
    records = sorted(done.records.values(), key=lambda record: record["case"])
    assert [record["method"] for record in records] == ["grouped"] * 4
    reference = summarize(hdselect.size(None, root / "trajectories" / "mixes" /
                                        "benchtop6_pick_inspect.toml", catalog=SHG))
    assert reference.precision is not None and reference.precision["tool_holding"] > 0.0
    assert differences(records[0]["result"]["precision"], reference.to_dict()["precision"]) < 1e-9
