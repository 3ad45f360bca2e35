"""The ``catalog`` and ``duty`` commands: output, JSON shape, exit status, error lines."""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from hdselect.cli.main import main
from helpers import REPO, run

CONVEYOR = REPO / "trajectories" / "duty" / "conveyor_index.toml"
UNIT_IDS = ["PSA-08-80", "PSA-08-100", "PSA-10-50", "PSA-10-80", "PSA-14-50", "PSA-14-80",
            "PSA-14-100"]
BASE_CHECKS = ["peak", "mean", "speed", "average_speed", "momentary", "static"]
NM_PER_LB_IN = 0.1129848

LIGHT = [  # (torque [N m], time [s], output speed [rpm]): the size-10 units fit
    (3.0, 0.1, 15.0),
    (1.0, 0.2, 30.0),
    (2.0, 0.1, 15.0),
    (0.5, 0.4, 0.0),
]


def write_profile(tmp_path: Path, phases: list[tuple[object, object, object]] | None = None,
                  extra: str = "", name: str = "profile.toml") -> Path:
    """A duty-cycle profile: phases as (torque, time, speed), values written as given."""
    phases = LIGHT if phases is None else phases
    text = extra + "\n" + "".join(
        f"[[phase]]\ntorque = {torque!r}\ntime = {time!r}\nspeed = {speed!r}\n\n"
        for torque, time, speed in phases)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def table_rows(out: str) -> dict[str, tuple[str, list[str]]]:
    """Rows of a printed table keyed by unit id: (the whole line, the cells after the id)."""
    rows = {}
    for line in out.splitlines():
        tokens = line.replace("│", " ").replace("▶", " ").split()
        if tokens and tokens[0] in UNIT_IDS:  # caption notes read "PSA-08-80: ..."
            rows[tokens[0]] = (line, tokens[1:])
    return rows


def assert_one_error_line(err: str, *needles: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("hdselect: error: ")
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])


# ----------------------------------------------------------------------------- catalog


def test_catalog_table(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "catalog")
    assert status == 0 and err == ""
    rows = table_rows(out)
    assert list(rows) == UNIT_IDS
    by_id = {unit_id: line for unit_id, (line, _) in rows.items()}
    assert "2.6*" in by_id["PSA-08-80"]  # momentary and static stand-ins
    assert "0.0062*" in by_id["PSA-08-80"]  # input inertia stand-in, the PSA-10 value
    assert "7.91†" in by_id["PSA-10-80"]  # 70 lb-in = 7.909 N m
    assert "33.9†" in by_id["PSA-14-100"]  # 300 lb-in = 33.895 N m
    for unit_id in ("PSA-10-50", "PSA-14-50", "PSA-14-80"):
        assert "*" not in by_id[unit_id] and "†" not in by_id[unit_id]
    text = " ".join(out.split())  # the notes may wrap
    assert "PSA-10-80: static limit: the source's 9 N m and 70 lb-in disagree" in text
    assert "PSA-14-100: static limit: the source's 34.6 N m and 300 lb-in disagree" in text
    assert text.count("not rated by the source") == 4  # momentary + static, two PSA-08s
    assert text.count("input inertia not given by the source") == 2


def test_catalog_imperial(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "catalog", "--units", "imperial")
    assert status == 0
    assert "lb-in" in out
    by_id = {unit_id: cells for unit_id, (_, cells) in table_rows(out).items()}
    assert list(by_id) == UNIT_IDS
    # columns: rated, repeated, momentary, static, max input, input inertia, mass
    cells = by_id["PSA-10-80"]
    assert cells[3] == "70†"  # the corrected static limit, back in lb-in
    assert cells[6] == "0.88"  # 0.4 kg / 0.45359237 = 0.8818 lb
    assert by_id["PSA-14-100"][3] == "300†"
    # 15.8 N m / 0.1129848 = 139.84 lb-in -> 140 (seed: 140)
    assert by_id["PSA-14-80"][1] == "140"


def test_catalog_json(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "catalog", "--json")
    assert status == 0
    units = json.loads(out)["units"]
    assert [u["unit"] for u in units] == UNIT_IDS
    by_id = {u["unit"]: u for u in units}
    assert {(f["field"], f["kind"]) for f in by_id["PSA-08-80"]["flags"]} == {
        ("momentary_torque", "fallback"), ("static_torque", "fallback"),
        ("input_inertia", "fallback")}
    assert [(f["field"], f["kind"]) for f in by_id["PSA-10-80"]["flags"]] == [
        ("static_torque", "corrected")]
    assert by_id["PSA-10-80"]["static_torque_nm"] == pytest.approx(70 * NM_PER_LB_IN)
    assert by_id["PSA-08-100"]["input_inertia_kg_m2"] == pytest.approx(6.2e-7)
    assert by_id["PSA-14-50"]["flags"] == []
    assert all(f["note"] for u in units for f in u["flags"])


def test_catalog_with_a_user_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "mine.toml"
    path.write_text('series = "ACME"\n[[unit]]\nsize = 20\nratio = 30\nrated_torque_nm = 40\n'
                    "repeated_torque_nm = 50\nmax_input_speed_rpm = 4000\n"
                    "input_inertia_kg_cm2 = 0.2\nmass_kg = 1.5\n", encoding="utf-8")
    status, out, _ = run(capsys, "catalog", "--json", "--catalog", path)
    assert status == 0
    units = json.loads(out)["units"]
    assert [u["unit"] for u in units] == UNIT_IDS + ["ACME-20-30"]
    # no momentary or static figure: both fall back to the repeated-peak limit, flagged
    assert units[-1]["momentary_torque_nm"] == 50
    assert {f["kind"] for f in units[-1]["flags"]} == {"fallback"}


def test_catalog_with_a_bad_user_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "mine.toml"
    path.write_text('series = "ACME"\n[[unit]]\nsize = 20\nratio = 30\nrated_torque_nm = 40\n'
                    "repeated_torque_nm = 50\nmax_input_speed_rpm = 4000\nmass_kg = -1.5\n",
                    encoding="utf-8")
    status, out, err = run(capsys, "catalog", "--catalog", path)
    assert status == 2
    assert out == ""
    assert_one_error_line(err, str(path), "unit[ACME-20-30].mass_kg", "a mass between 0.001 and")


# ----------------------------------------------------------------------------- duty


def test_duty_json_shape(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "duty", write_profile(tmp_path), "--json", "-")
    assert status == 0 and err == ""
    document = json.loads(out)  # nothing but JSON on stdout
    assert {"mean_torque_nm", "mean_output_speed_rpm", "peak_torque_nm", "selected",
            "candidates"} <= set(document)
    # T_av = cbrt((1.5 x 27 + 6 x 1 + 1.5 x 8) / (1.5 + 6 + 1.5)) = cbrt(58.5 / 9) = cbrt(6.5)
    assert document["mean_torque_nm"] == pytest.approx(6.5 ** (1 / 3))
    assert document["mean_output_speed_rpm"] == pytest.approx(9.0 / 0.4)  # 22.5 rpm
    assert document["peak_torque_nm"] == 3.0
    assert document["selected"] == "PSA-10-80"
    candidates = document["candidates"]
    assert [c["unit"] for c in candidates] == UNIT_IDS
    for c in candidates:
        size, ratio = c["unit"].split("-")[1:]
        assert (c["size"], c["ratio"]) == (int(size), int(ratio))
        assert isinstance(c["feasible"], bool)
        assert isinstance(c["life_hours"], float)
        assert isinstance(c["flags"], list)
        assert list(c["checks"]) == BASE_CHECKS  # no required life: no life check
        for check in c["checks"].values():
            assert {"value", "limit", "ok"} <= set(check)
        assert c["feasible"] == all(check["ok"] for check in c["checks"].values())
        # no momentary event given: the check does not apply
        assert c["checks"]["momentary"]["value"] is None
        assert c["checks"]["momentary"]["ok"] is True
        # speed is input rpm: 30 output rpm x ratio
        assert c["checks"]["speed"]["value"] == pytest.approx(30.0 * c["ratio"])
    # PSA-08-80: peak 3.0 > 2.6 N m. PSA-08-100: mean input speed 22.5 x 100 = 2250 rpm,
    # allowable (1750 / 2250)^0.33 x 2.0 = 1.8408 N m < 1.8663 N m. All larger units fit.
    assert [c["feasible"] for c in candidates] == [False, False] + [True] * 5
    assert candidates[0]["checks"]["peak"]["ok"] is False
    assert candidates[1]["checks"]["mean"]["ok"] is False


def test_duty_required_life_adds_a_check(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    profile = write_profile(tmp_path, extra="[requirements]\nlife_hours = 1e12\n")
    status, out, _ = run(capsys, "duty", profile, "--json", "-")
    assert status == 1  # no gearhead lives 1e12 h
    document = json.loads(out)
    assert document["selected"] is None
    for c in document["candidates"]:
        assert list(c["checks"]) == BASE_CHECKS + ["life"]
        assert c["checks"]["life"]["ok"] is False
        assert c["checks"]["life"]["limit"] == 1e12
        assert c["feasible"] is False


def test_duty_nothing_fits_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # 25 N m exceeds the largest repeated-peak limit, PSA-14-100's 20.3 N m
    profile = write_profile(tmp_path, [(25.0, 0.1, 10.0)])
    status, out, err = run(capsys, "duty", profile)
    assert status == 1
    assert err == ""
    rows = table_rows(out)
    assert list(rows) == UNIT_IDS
    assert not any("▶" in line for line, _ in rows.values())


def test_duty_table(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "duty", CONVEYOR)
    assert status == 0 and err == ""
    rows = table_rows(out)
    assert list(rows) == UNIT_IDS
    marked = [unit_id for unit_id, (line, _) in rows.items() if "▶" in line]
    assert marked == ["PSA-14-80"]
    text = " ".join(out.split())  # the title may wrap
    assert "mean torque 4.89 N m" in text  # cbrt(515.1384 / 4.4) = 4.892 N m
    assert "mean output speed 14.7 rpm" in text  # 4.4 / 0.3 = 14.67 rpm


def test_duty_json_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "out.json"
    status, out, _ = run(capsys, "duty", CONVEYOR, "--json", target)
    assert status == 0
    assert "PSA-14-80" in out  # the table is still printed
    assert json.loads(target.read_text(encoding="utf-8"))["selected"] == "PSA-14-80"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]  # no temporary left


def test_duty_json_into_a_missing_directory(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "absent" / "out.json"
    status, _, err = run(capsys, "duty", CONVEYOR, "--json", target)
    assert status == 2
    assert_one_error_line(err, str(target))
    assert list(tmp_path.iterdir()) == []


def test_duty_json_onto_a_directory(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "a_directory"
    target.mkdir()
    status, _, err = run(capsys, "duty", CONVEYOR, "--json", target)
    assert status == 2
    assert_one_error_line(err, str(target))
    assert [p.name for p in tmp_path.iterdir()] == ["a_directory"]  # no temporary left
    assert list(target.iterdir()) == []


@pytest.mark.parametrize(("phases", "extra", "field", "reason"), [
    ([(3.0, -0.1, 10.0)], "", "phase[0].time", "between 1e-06 and 1e+09 s"),
    ([(3.0, math.inf, 10.0)], "", "phase[0].time", "finite"),
    ([(3.0, math.nan, 10.0)], "", "phase[0].time", "finite"),
    ([(3.0, 0.1, 1e308)], "", "phase[0].speed", "between -100000 and 100000 rpm"),
    ([(1e308, 0.1, 10.0)], "", "phase[0].torque", "between -1e+07 and 1e+07 N m"),
    ([], 'description = "empty"\n', "phase", "no [[phase]] entries"),
    ([], "phase = []\n", "phase", "no [[phase]] entries"),
    ([(3.0, 0.1, 10.0)], "[static]\ntorqe = 2.0\n", "static.torqe", "did you mean 'torque'"),
])
def test_duty_bad_profile(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                          phases: list, extra: str, field: str, reason: str) -> None:
    profile = write_profile(tmp_path, phases, extra=extra)
    status, out, err = run(capsys, "duty", profile)
    assert status == 2
    assert out == ""
    assert_one_error_line(err, f"{profile}: {field}: ", reason)


def test_duty_hold_only_is_sized_and_says_so(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    profile = write_profile(tmp_path, [(3.0, 0.1, 0.0), (1.0, 0.2, -0.0)])
    status, out, err = run(capsys, "duty", profile)
    assert status == 0 and err == ""
    assert "hold only: nothing moves in this cycle" in " ".join(out.split())
    status, out, _ = run(capsys, "duty", profile, "--json", "-")
    document = json.loads(out)
    assert document["hold_only"] is True
    # held with the input locked: 3 N m against each unit's static limit, nothing else
    chosen = next(c for c in document["candidates"] if c["unit"] == document["selected"])
    assert chosen["checks"]["static"]["value"] == 3.0
    assert chosen["checks"]["peak"]["value"] == 0.0 and chosen["checks"]["mean"]["value"] is None


@pytest.mark.parametrize(("text", "field", "reason"), [
    ("[[phase]]\ntime = 0.1\nspeed = 10\n", "phase[0].torque", "required key is missing"),
    ("[[phase]]\ntorque = 1.0\ntime = 0.1\nspeed = 10\n[[phase]]\ntorqe = 1.0\ntime = 0.1\n"
     "speed = 10\n", "phase[1].torqe", "did you mean 'torque'"),
    ("[[phase]]\ntorque = 1.0\ntime = 0.1\nsped = 10\n", "phase[0].sped", "did you mean 'speed'"),
    ('[[phase]]\ntorque = "high"\ntime = 0.1\nspeed = 10\n', "phase[0].torque",
     "expected a number"),
])
def test_duty_bad_phase_keys(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                             text: str, field: str, reason: str) -> None:
    profile = tmp_path / "p.toml"
    profile.write_text(text, encoding="utf-8")
    status, out, err = run(capsys, "duty", profile)
    assert status == 2 and out == ""
    assert_one_error_line(err, f"{profile}: {field}: ", reason)


def test_duty_missing_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    profile = tmp_path / "absent.toml"
    status, out, err = run(capsys, "duty", profile)
    assert status == 2 and out == ""
    assert_one_error_line(err, str(profile), "file not found")


def test_duty_malformed_toml(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    profile = tmp_path / "broken.toml"
    profile.write_text("[[phase]\ntorque = 1.0\n", encoding="utf-8")
    status, out, err = run(capsys, "duty", profile)
    assert status == 2 and out == ""
    assert_one_error_line(err, str(profile), "not valid TOML")


@pytest.mark.slow
def test_duty_error_in_a_real_process(tmp_path: Path) -> None:
    """The installed entry point: one line on stderr, exit 2, no traceback."""
    profile = write_profile(tmp_path, [(3.0, math.nan, 10.0)])
    completed = subprocess.run(
        [sys.executable, "-c", "from hdselect.cli.main import main; raise SystemExit(main())",
         "duty", str(profile)],
        capture_output=True, text=True, timeout=60, check=False)
    assert completed.returncode == 2
    assert completed.stdout == ""
    assert_one_error_line(completed.stderr, str(profile), "phase[0].time", "finite")


@pytest.mark.slow
@pytest.mark.parametrize("module", ["hdselect", "hdselect.cli"])
def test_python_dash_m_runs_the_command_line(module: str) -> None:
    """``python -m hdselect`` said "'hdselect' is a package and cannot be directly executed"."""
    completed = subprocess.run([sys.executable, "-m", module, "joints", "robots/planar2.urdf"],
                               capture_output=True, text=True, timeout=60, check=False,
                               cwd=Path(__file__).resolve().parents[1])
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.startswith("planar2.urdf: 2 joints")


# --- the help texts (issue 27) -----------------------------------------------------------------

def help_text(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    return capsys.readouterr().out


def test_every_command_says_in_one_line_what_it_does(capsys: pytest.CaptureFixture[str]) -> None:
    from hdselect.cli.main import _parser

    commands = next(a for a in _parser()._actions
                    if isinstance(a, argparse._SubParsersAction))
    listing = " ".join(help_text(capsys).split())
    for name, parser in commands.choices.items():
        summary = next(a.help for a in commands._choices_actions if a.dest == name)
        assert summary and f"{name} {summary}" in listing, name
        assert parser.description == f"{summary[:1].upper()}{summary[1:]}.", name
        assert parser.description in " ".join(help_text(capsys, name).split()), name


def test_the_top_help_says_how_to_begin(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert ("A first run on your own robot: hdselect joints ROBOT (its joints as read), hdselect "
            "init ROBOT --out motion.toml (a starter motion), hdselect size motion.toml.") in text


def test_help_promises_only_what_the_input_takes(capsys: pytest.CaptureFixture[str]) -> None:
    duty = " ".join(help_text(capsys, "duty").split())
    assert "[requirements]" not in duty and "(default: 0)" in duty  # a profile has no margin
    for command in ("joints", "init"):  # a robot file alone: no motion file, no xacro_args
        text = help_text(capsys, command)
        assert "--xacro-arg" in text and "xacro_args" not in text
    assert "overrides the motion file's xacro_args" in " ".join(help_text(capsys, "size").split())


@pytest.mark.parametrize(("command", "joint"), [("compare", "shown"), ("fastest", "compared")])
def test_joints_sized_and_the_joint_shown_are_told_apart(capsys: pytest.CaptureFixture[str],
                                                         command: str, joint: str) -> None:
    text = help_text(capsys, command)
    group = text[text.index(f"joints sized (--joints, --exclude) and {joint} (--joint):"):]
    group = " ".join(group.split("\n\n")[0].split())
    assert "--joints A,B size only these joints" in group and "--joint JOINT" in group
    assert "the joints --joints names are all sized" in group
