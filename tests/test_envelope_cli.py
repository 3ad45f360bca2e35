"""``hdselect envelope`` and its envelope file: output, JSON, limits' sources, bad input.

Exit status: 0 every joint has a unit for any motion within the spec, 1 some joint has
none, 2 bad input (one line, no output file written).
"""

from __future__ import annotations

import html
import json
import math

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.envelope import SearchSettings, envelope
from hdselect.envelope.records import envelope_json
from hdselect.envelope.torques import BEARING_NOTE
from hdselect.report.envelope_tables import note_lines
from helpers import REPO, run
from helpers.options import (
    ENVELOPE_EFFECTS,
    ENVELOPE_OUTPUTS,
    PLANAR2,
    PLANAR2_MOTION,
    one_line_error,
)

MIX = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
DEG = math.pi / 180.0
QUICK = ("--starts", "256", "--moves", "4")


def test_envelope_prints_every_joint_and_writes_json_that_matches_the_api(capsys, tmp_path):
    out_file = tmp_path / "envelope.json"
    status, out, _ = run(capsys, "envelope", PLANAR2, "--velocity", "180", "--acceleration",
                         "900", "--stop-time", "0.1", "--json", out_file, *QUICK)
    assert status == 0
    for text in ("shoulder", "elbow", "duty alone", "default duty: 4 random moves",
                 "Worst states", "v given, a given"):
        assert text in out
    document = json.loads(out_file.read_text())
    result = envelope(PLANAR2, velocity=180 * DEG, acceleration=900 * DEG, stop_time=0.1,
                      moves=4, settings=SearchSettings(starts=256))
    assert document["feasible"] is True and document["duty"]["default"] is True
    assert document["search"]["states_evaluated"] == result.states
    for entry, joint in zip(document["joints"], result.joints, strict=True):
        assert entry["selected"] == joint.selected.unit.id
        assert entry["worst"]["peak"]["torque"] == joint.worst["peak"].torque
        assert entry["worst"]["peak"]["q"] == list(joint.worst["peak"].q)
        assert len(entry["convergence"]["demands"]["peak"]["by_starts"]) >= 2
    assert document["limits"]["elbow"]["velocity"] == pytest.approx(math.pi)
    assert document["limits"]["elbow"]["sources"]["velocity"] == "given"
    assert document["duty_sizing"]["joints"][0]["name"] == "shoulder"


@pytest.mark.slow
def test_every_output_says_what_the_bearing_loads_are_over(capsys, tmp_path):
    """The search bounds torques, not the bearing's force and moment: the terminal, the
    JSON and the page say so, and the JSON gives each joint's loads as the API has them."""
    out_file = tmp_path / "envelope.json"
    status, out, _ = run(capsys, "envelope", PLANAR2, "--velocity", "180", "--acceleration",
                         "900", "--json", out_file, "--report", tmp_path / "report", *QUICK)
    assert status == 0
    assert BEARING_NOTE in " ".join(out.split())  # the note, wrapped at 80 columns
    document = json.loads(out_file.read_text())
    assert document["bearing_note"] == BEARING_NOTE
    result = envelope(PLANAR2, velocity=180 * DEG, acceleration=900 * DEG, moves=4,
                      settings=SearchSettings(starts=256))
    for entry, joint in zip(document["joints"], result.joints, strict=True):
        bearing = entry["bearing"]
        assert bearing["max_moment_nm"] == joint.sizing.bearing.max_moment
        assert bearing["mean_radial_n"] == joint.sizing.bearing.mean_radial
        assert bearing["largest_over"] == "the duty and the worst states"
        assert bearing["means_over"] == "the duty"
        assert bearing["rated"] is False
    page = (tmp_path / "report" / "index.html").read_text()
    assert html.escape(BEARING_NOTE) in page
    off = envelope(PLANAR2, velocity=180 * DEG, acceleration=900 * DEG, moves=4,
                   settings=SearchSettings(starts=256), bearing_loads=False)
    assert all(joint.sizing.bearing is None for joint in off.joints)
    assert envelope_json(off)["bearing_note"] is None  # no loads, nothing to say of them
    assert not any(BEARING_NOTE in line for line in note_lines(off))


def test_an_envelope_file_gives_limits_the_flags_and_the_robot_file_complete(capsys, tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(f'robot = "{PLANAR2}"\nangle_unit = "deg"\n'
                    "[limits]\nvelocity = {elbow = 120}\nacceleration = [600, 700]\n"
                    "[safety]\nstop_time = 0.2\n[sizing]\nbearing_offset_m = {elbow = 0.02}\n"
                    "[duty]\nmoves = 3\nseed = 5\n")
    status, out, _ = run(capsys, "envelope", spec, "--acceleration", "shoulder=500",
                         "--json", "-", "--starts", "256")
    assert status == 0
    document = json.loads(out)
    limits = document["limits"]
    assert limits["shoulder"]["velocity"] == pytest.approx(4.0)  # the robot file's
    assert limits["shoulder"]["sources"] == {"velocity": "robot file", "acceleration": "given",
                                             "jerk": "default"}
    assert limits["elbow"]["velocity"] == pytest.approx(120 * DEG)
    assert limits["shoulder"]["acceleration"] == pytest.approx(500 * DEG)
    assert limits["elbow"]["acceleration"] == pytest.approx(700 * DEG)
    assert limits["elbow"]["duty_jerk"] == pytest.approx(700 * DEG / 0.05)
    assert document["assumptions"]["stop_time_s"] == 0.2
    assert document["duty"]["moves"] == 3 and document["duty"]["seed"] == 5
    assert document["spec_file"] == str(spec)
    assert [j["bearing"]["offset_m"] for j in document["joints"]] == [0.0, 0.02]


def test_a_motion_file_as_the_duty_is_sized_alone_beside_the_envelope(capsys):
    status, out, _ = run(capsys, "envelope", PLANAR2, "--duty", PLANAR2_MOTION,
                         "--velocity", "180", "--acceleration", "900", "--json", "-",
                         "--starts", "256")
    assert status == 0
    document = json.loads(out)
    alone = hdselect.size(PLANAR2, PLANAR2_MOTION)
    assert document["duty"]["label"] == "planar2_pick_place.toml"
    assert [j["duty_selected"] for j in document["joints"]] == [
        j.selected.unit.id for j in alone.joints]
    assert document["assumptions"]["stop_time_s"] == 0.1  # the motion file's [safety]
    assert document["payload"]["mass_kg"] == 0.15  # the motion file's [payload], the gripper
    status, out, _ = run(capsys, "envelope", PLANAR2, "--duty", PLANAR2_MOTION, "--payload",
                         "0.9", "--velocity", "180", "--acceleration", "900", "--json", "-",
                         "--starts", "64")
    payload = json.loads(out)["payload"]  # --payload changes the duty's mass, keeps the rest
    assert payload["mass_kg"] == 0.9 and payload["com_m"] == [0.03, 0.0, 0.0]
    assert payload["frame"] == "tool"


@pytest.mark.slow
def test_report_writes_the_page_and_the_duty_report_beside_it(capsys, tmp_path):
    status, out, _ = run(capsys, "envelope", PLANAR2, "--velocity", "180", "--acceleration",
                         "900", "--report", tmp_path / "report", *QUICK)
    assert status == 0 and "wrote" in out
    page = (tmp_path / "report" / "index.html").read_text()
    for text in ("Worst states", "worst by starts", "duty/index.html", "PSA-"):
        assert text in page
    assert (tmp_path / "report" / "duty" / "index.html").stat().st_size > 0
    assert (tmp_path / "report" / "duty" / "joint_elbow.png").stat().st_size > 0
    status, out, _ = run(capsys, "envelope", PLANAR2, "--velocity", "180", "--acceleration",
                         "900", "--report", "-", *QUICK)
    assert status == 0 and out.startswith("<!DOCTYPE html>") and "duty/index.html" not in out


def test_no_unit_for_every_motion_exits_1_with_the_table(capsys):
    status, out, _ = run(capsys, "envelope", PLANAR2, "--velocity", "180", "--acceleration",
                         "20000", *QUICK)
    assert status == 1
    text = " ".join(out.split())
    assert "none" in text and "shoulder: no unit holds it: repeated peak torque" in text
    assert "shoulder: lower the velocity and acceleration limits" in text  # dynamics fail


@pytest.mark.parametrize(("argv", "fragments"), [
    (["--velocity", "180"], ["acceleration", "no acceleration limit for shoulder, elbow"]),
    (["--acceleration", "900", "--velocity", "wrist=3"], ["--velocity", "unknown joint 'wrist'"]),
    (["--acceleration", "fast"], ["--acceleration", "expected a number or JOINT=NUMBER"]),
    (["--acceleration", "-5"], ["--acceleration", "must be an acceleration limit"]),
    (["--acceleration", "900", "--starts", "1000"], ["--starts", "power of 2"]),
    (["--acceleration", "900", "--motor-catalog", "x.toml"], ["--motor-catalog"]),
    (["--acceleration", "900", "--velocity", "90", "--duty", PLANAR2_MOTION],
     ["planar2_pick_place.toml", "limits.velocity", "above the spec's velocity limit"]),
    (["--acceleration", "900", "--workers", "0"], ["--workers"]),
    # a mix duty of another robot: blamed on the mix file's task and both robots
    (["--acceleration", "900", "--duty", MIX], ["benchtop6_pick_inspect.toml", "task[0].motion",
                                                "written for", "but the mix runs",
                                                "planar2.urdf"]),
    # the default duty's options beside a motion duty: refused, naming both options
    *[(["--acceleration", "1000", "--duty", PLANAR2_MOTION, flag, value],
       [flag, "default duty of random moves only", "--duty"])
      for flag, value in (("--moves", "3"), ("--seed", "1"), ("--jerk", "9000"))],
    (["--acceleration", "900", "--payload", "1", "--payload-frame", "tool8"],
     ["--payload-frame", "unknown frame 'tool8'", "planar2.urdf"]),
    (["--acceleration", "900", "--joints", "knee"], ["--joints", "unknown joint 'knee'"]),
    # a duty of another robot: blamed on --duty and both robots, not on its first waypoint
    (["--acceleration", "900", "--duty", REPO / "trajectories" / "benchtop6_pick_place.toml"],
     ["--duty", "benchtop6_pick_place.toml is written for", "benchtop6.urdf",
      "but the envelope runs", "planar2.urdf", "give a duty motion of this robot"]),
])
def test_bad_input_is_one_line_and_exit_2_with_no_output(capsys, tmp_path, argv, fragments):
    out_file = tmp_path / "out.json"
    status, out, err = run(capsys, "envelope", PLANAR2, *argv, "--json", out_file)
    assert status == 2 and out == ""
    one_line_error(err, *fragments)
    assert not out_file.exists()


@pytest.mark.parametrize(("text", "fragments"), [
    ('angle_unit = "deg"\n[limits]\nacceleration = 900\n', ["robot", "no robot given"]),
    ('robot = "{robot}"\n[limits]\nacceleration = 900\n', ["angle_unit"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limit]\n', ["limit", "did you mean 'limits'"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = {{knee = 3}}\n',
     ["limits.acceleration.knee", "unknown joint 'knee'"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = 900\n'
     '[duty]\nmoves = 0\n', ["duty.moves"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = 900\n'
     '[duty]\nmotion = "nowhere.toml"\n', ["duty.motion", "not found"]),
    # what the robot lacks, blamed on the envelope file's key, not on the robot file
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nvelocity = 90\n',
     ["limits.acceleration", "no acceleration limit for shoulder, elbow"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[payload]\nmass = 0.3\nframe = "tool9"\n'
     '[limits]\nacceleration = 900\n',
     ["payload.frame", "unknown frame 'tool9'", "links are: ", "(robot file planar2.urdf)"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = 900\n'
     '[sizing]\njoints = ["j9"]\n', ["sizing.joints", "unknown joint 'j9'", "planar2.urdf"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = 900\n'
     '[sizing]\nexclude = ["shoulder", "elbow"]\n', ["sizing.exclude", "no joint left"]),
    ('robot = "{robot}"\nangle_unit = "deg"\n[limits]\nacceleration = 900\n'
     '[duty]\nmotion = "{motion}"\n', ["--moves", "spec.toml's [duty] motion"]),
])
def test_a_bad_envelope_file_names_the_file_and_the_field(capsys, tmp_path, text, fragments):
    spec = tmp_path / "spec.toml"
    spec.write_text(text.format(robot=PLANAR2, mix=MIX, motion=PLANAR2_MOTION))
    status, _, err = run(capsys, "envelope", spec,
                         *(["--moves", "3"] if "motion = " in text else []))
    assert status == 2
    one_line_error(err, "spec.toml", *fragments)


def test_the_python_api_is_callable_from_the_package_and_checks_its_arguments():
    assert callable(hdselect.envelope) and "envelope" in hdselect.__all__
    with pytest.raises(InputError, match="give a robot file"):
        hdselect.envelope()
    with pytest.raises(InputError, match="acceleration"):
        hdselect.envelope(PLANAR2, velocity=1.0)
    with pytest.raises(InputError, match="missing|unknown joint"):
        hdselect.envelope(PLANAR2, acceleration={"shoulder": 1.0, "hand": 2.0})
    result = hdselect.envelope(PLANAR2, acceleration={"shoulder": 5.0, "elbow": 6.0},
                               velocity=[2.0, 3.0], moves=2,
                               settings=SearchSettings(starts=128))
    assert np.allclose(result.spec.box.acceleration, [5.0, 6.0])
    assert np.allclose(result.spec.box.velocity, [2.0, 3.0])


@pytest.mark.slow
def test_states_computed_in_worker_processes_are_the_same():
    """The quasi-random states split over two spawned workers (each on one thread) give
    the same worst states, bit for bit, as the batched passes here."""
    kwargs = {"velocity": 180 * DEG, "acceleration": 900 * DEG, "moves": 2,
              "settings": SearchSettings(starts=256)}
    here = envelope(PLANAR2, **kwargs)
    spread = envelope(PLANAR2, workers=2, **kwargs)
    assert spread.executor == "2 worker processes" and here.executor == "this process"
    for a, b in zip(here.joints, spread.joints, strict=True):
        for figure in a.worst:
            assert a.worst[figure].torque == b.worst[figure].torque
            assert np.array_equal(a.worst[figure].q, b.worst[figure].q)
    assert here.states == spread.states


@pytest.mark.slow
def test_states_computed_on_a_dask_cluster_are_the_same():
    """The same split on a Dask LocalCluster (one worker, one thread) gives the same states."""
    pytest.importorskip("distributed")
    kwargs = {"velocity": 180 * DEG, "acceleration": 900 * DEG, "moves": 2,
              "settings": SearchSettings(starts=128)}
    here = envelope(PLANAR2, **kwargs)
    cluster = envelope(PLANAR2, scheduler="local", workers=1, **kwargs)
    assert cluster.executor == "a Dask LocalCluster of 1 worker"
    assert [j.worst["peak"].torque for j in here.joints] == [
        j.worst["peak"].torque for j in cluster.joints]
    with pytest.raises(InputError, match="scheduler"):
        envelope(PLANAR2, scheduler="udp://nowhere", **kwargs)


ACME = ('series = "ACME"\n[[unit]]\nsize = 20\nratio = 30\nrated_torque_nm = 40\n'
        "repeated_torque_nm = 50\nmax_input_speed_rpm = 4000\ninput_inertia_kg_cm2 = 0.2\n"
        "mass_kg = 1.5\n")


def _answer(document):
    """The JSON without what echoes the options or varies from run to run."""
    if isinstance(document, dict):
        return {k: _answer(v) for k, v in document.items()
                if k not in ("assumptions", "seconds")}
    if isinstance(document, list):
        return [_answer(v) for v in document]
    return document


@pytest.mark.slow
@pytest.mark.parametrize(("option", "values"), ENVELOPE_EFFECTS, ids=lambda x: str(x)[:20])
def test_every_envelope_option_changes_the_answer_or_is_refused(capsys, tmp_path, monkeypatch,
                                                                 option, values):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "acme.toml").write_text(ACME)
    base = ["envelope", PLANAR2, "--velocity", "180", "--acceleration", "900",
            "--life-hours", "20000", "--starts", "64", "--moves", "2", "--json", "-"]
    status, out, err = run(capsys, *base)
    assert status in (0, 1), err
    before = _answer(json.loads(out))
    status, out, err = run(capsys, *base, option, *values)
    if status == 2:
        one_line_error(err, option)
        return
    assert status in (0, 1), err
    assert _answer(json.loads(out)) != before, f"{option} took no effect"


def test_the_effects_table_covers_every_option_of_envelope():
    from hdselect.cli.main import _parser
    from helpers.options import NO_FIGURES, OTHER, STIFFNESS_TARGETS
    from helpers.options import effect_options as effect_options

    options = effect_options(_parser())["envelope"]
    # --xacro-arg needs a .xacro robot: test_xacro.test_the_envelope_takes_xacro_arguments;
    # the precision targets act on stiffness-rated units: test_precision_rules
    assert options == {row[0] for row in ENVELOPE_EFFECTS} | set(ENVELOPE_OUTPUTS) | {
        "--xacro-arg", *NO_FIGURES, *STIFFNESS_TARGETS}
    assert set(OTHER["envelope"]) == options


@pytest.mark.parametrize("parameter", ["robot", "spec", "velocity", "acceleration", "jerk",
                                       "payload", "mounting", "joints", "exclude", "duty",
                                       "moves", "seed", "catalog", "units", "settings",
                                       "workers", "scheduler", "timeout"])
def test_the_function_names_a_parameter_of_a_wrong_type(parameter):
    """Each parameter in turn of no type it takes, the others valid: an InputError naming it."""
    valid = {"robot": PLANAR2, "acceleration": 5.0, "moves": 2,
             "settings": SearchSettings(starts=64)}
    numbers = ("velocity", "acceleration", "jerk", "moves", "seed", "workers", "timeout")
    for wrong in ("x" if parameter in numbers else 42, object()):
        with pytest.raises(InputError) as raised:
            envelope(**{**valid, parameter: wrong})
        assert str(raised.value.field).split(".")[0].split("[")[0] == parameter, raised.value


def test_an_envelope_file_places_its_base_as_a_motion_file_does(capsys, tmp_path):
    """``base = {xyz, rpy}`` with the wall's pose gives the answer ``mounting = "wall"``
    gives (gravity the same in the base frame); both at once are refused by field."""
    from pinocchio import rpy

    from hdselect.robot.mounting import NAMED_BASES

    turn = [float(v) for v in np.degrees(rpy.matrixToRpy(NAMED_BASES["wall"].matrix))]
    head = f'robot = "{PLANAR2}"\nangle_unit = "deg"\n'
    rest = "\n[limits]\nvelocity = 180\nacceleration = 900\n"
    answers = []
    for name, placing in (("named", 'mounting = "wall"\n'),
                          ("pose", f"base = {{xyz = [0, 0, 0.2], rpy = {turn}}}\n")):
        spec = tmp_path / f"{name}.toml"
        spec.write_text(head + placing + rest)
        status, out, err = run(capsys, "envelope", spec, *QUICK, "--json", "-")
        assert status in (0, 1), err
        answers.append(_answer(json.loads(out)))
    # the same worst torques and units; the states that reach them may differ within the
    # search's tolerance (the pose's rpy round trip moves gravity by 1e-16), and with
    # them the bearing's loads at those states
    assert _close(answers[0]["joints"], answers[1]["joints"], skip=("q", "qd", "qdd",
                                                                   "bearing"))
    both = tmp_path / "both.toml"
    both.write_text(head + 'mounting = "wall"\nbase = {xyz = [0, 0, 0], rpy = [0, 0, 0]}\n'
                    + rest)
    status, _, err = run(capsys, "envelope", both, *QUICK)
    assert status == 2
    one_line_error(err, "both.toml", "base")


def _close(a, b, skip=()) -> bool:
    """The same JSON but for the keys skipped, numbers within 1e-9 relative."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_close(a[k], b[k], skip) for k in a
                                            if k not in skip)
    if isinstance(a, list):
        return len(a) == len(b) and all(_close(x, y, skip) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9)
    return a == b


@pytest.mark.parametrize(("name", "value"), [("moves", 2), ("seed", 1), ("jerk", 100.0)])
def test_the_default_duty_arguments_are_refused_beside_a_motion_duty(name, value):
    """Python's `envelope` refuses them as the command line does: they would act on nothing."""
    with pytest.raises(InputError) as raised:
        envelope(PLANAR2, acceleration=15.0, duty=PLANAR2_MOTION, **{name: value})
    assert raised.value.field == name and "default duty" in raised.value.reason
