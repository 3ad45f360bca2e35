"""A whole-arm target's verdict as the command line gives it: a result (exit 1) where it is
missed, a refusal (exit 2) where a command does not judge it."""

from __future__ import annotations

import pytest

from helpers import REPO, run

PLANAR2 = REPO / "trajectories" / "planar2_pick_place.toml"
SHG = ("--series", "shg-2uh")


@pytest.mark.parametrize("command", ["size", "compare"])
def test_a_target_the_catalog_cannot_meet_is_a_result_with_exit_1(capsys, command):
    status, out, err = run(capsys, command, PLANAR2, *SHG, "--max-tool-deflection", "1e-6")
    assert status == 1, err
    assert "cannot be met by this catalog" in " ".join(out.split())


def test_a_target_met_exits_0(capsys):
    status, out, err = run(capsys, "size", PLANAR2, *SHG, "--max-tool-deflection", "10")
    assert status == 0, err
    assert "target met" in " ".join(out.split())


@pytest.mark.parametrize("command", [["fastest"], ["fastest", "--compare-ratios"],
                                     ["max-payload"]])
@pytest.mark.parametrize("target", [["--max-tool-deflection", "1"],
                                    ["--min-arm-frequency", "hand-axes"]])
def test_the_solvers_that_raise_no_units_refuse_a_whole_arm_target(capsys, command, target):
    status, out, err = run(capsys, *command, PLANAR2, *SHG, *target)
    assert status == 2 and out == ""
    assert err.startswith(f"hdselect: error: {target[0]} ([precision] ")
    assert "judged by `hdselect size`" in err and len(err.strip().splitlines()) == 1


def test_a_target_on_units_that_rate_no_stiffness_says_not_judged(capsys):
    # PSA-G alone: the figures are not rated, and the target says it could not be judged
    status, out, err = run(capsys, "size", PLANAR2, "--min-arm-frequency", "8")
    assert status == 1, err
    flat = " ".join(out.split())
    assert "Precision: not rated by the source" in flat
    assert "target NOT met: lowest arm mode not judged, at least 8 Hz" in flat


def test_a_class_named_is_flagged_as_a_transcription_in_every_output(capsys, tmp_path):
    import json
    import pickle

    from hdselect import Options
    from hdselect.catalog.stiffness import ClassFrequency

    given = Options(min_natural_frequency={"elbow": "hand-axes"}, min_arm_frequency="scara")
    assert given.min_natural_frequency["elbow"] == 15.0 and given.min_arm_frequency == 15.0
    assert isinstance(given.min_arm_frequency, ClassFrequency)
    assert pickle.loads(pickle.dumps(given)).min_arm_frequency.name == "scara"  # study workers
    out_json = tmp_path / "out.json"
    status, out, err = run(capsys, "size", PLANAR2, *SHG, "--min-natural-frequency",
                           "hand-axes", "--max-torsion", "elbow=2", "--json", out_json)
    assert status in (0, 1), err
    flat = " ".join(out.split())
    assert "precision targets: twist at most 2 arcmin (elbow); f_n at least 15 Hz" in flat
    assert "hand-axes 15 Hz: Harmonic Drive's application classes as publicly transcribed" \
        in flat
    targets = json.loads(out_json.read_text())["assumptions"]["precision_targets"]
    assert targets["max_torsion_arcmin"] == {"elbow": pytest.approx(2.0)}
    assert targets["min_natural_frequency_hz"] == {"*": 15.0}
    assert "publicly transcribed" in targets["classes"]


def test_a_frequency_given_as_a_number_is_the_designers_own(capsys, tmp_path):
    import json

    out_json = tmp_path / "out.json"
    status, out, err = run(capsys, "size", PLANAR2, *SHG, "--min-natural-frequency", "15",
                           "--json", out_json)
    assert status in (0, 1), err
    assert "transcribed" not in " ".join(out.split())
    targets = json.loads(out_json.read_text())["assumptions"]["precision_targets"]
    assert targets["classes"] is None and targets["max_tool_deflection_mm"] is None


def test_fastest_says_when_a_torsion_target_sets_the_torque_limit(capsys):
    status, out, err = run(capsys, "fastest", PLANAR2, *SHG, "--max-torsion", "1")
    assert status == 0, err
    flat = " ".join(out.split())
    assert "the unit's repeated peak, or where a torsion target is tighter, the torque at " \
           "which the unit twists by it" in flat
    status, out, err = run(capsys, "fastest", PLANAR2, *SHG)
    assert "twists by it" not in " ".join(out.split())


def test_the_envelope_prints_its_dutys_precision_section_and_says_whose(capsys):
    spec = REPO / "trajectories" / "envelopes" / "benchtop6_dispensing.toml"
    status, out, err = run(capsys, "envelope", spec, *SHG, "--starts", "64")
    assert status == 0, err
    flat = " ".join(out.split())
    assert "Precision: each unit's twist" in flat and "tool 'tool0': sags" in flat
    assert "The precision figures above are the duty's" in flat


def test_two_targets_given_as_classes_share_one_note():
    from hdselect import Options
    from hdselect.sizing.precision_records import targets_json, targets_text

    given = Options(min_natural_frequency={"elbow": "hand-axes"}, min_arm_frequency="base-axes")
    note = targets_json(given)["classes"]
    assert note.startswith("base-axes 8 Hz, hand-axes 15 Hz: Harmonic Drive's application "
                           "classes as publicly transcribed")
    assert targets_text(given).count("publicly transcribed") == 1
