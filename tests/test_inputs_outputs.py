"""Inputs read once (FIFOs, process substitution), outputs that never replace an input, and the
refusals found by the hostile battery: each one line, exit 2, nothing written."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import threading
import warnings
from pathlib import Path

import pytest

import hdselect
from helpers import REPO, run

PLANAR2 = "planar2_pick_place.toml"


def refused(capsys, *argv, says=()) -> str:
    before = {p: p.stat().st_mtime_ns for p in Path(".").rglob("*") if p.is_file()}
    status, out, err = run(capsys, *argv)
    lines = err.strip().splitlines()
    assert status == 2 and out == "" and len(lines) == 1, err
    for text in says:
        assert text in lines[0], (text, lines[0])
    after = {p: p.stat().st_mtime_ns for p in Path(".").rglob("*") if p.is_file()}
    assert after == before
    return lines[0]


# --- outputs --------------------------------------------------------------------------------

@pytest.mark.parametrize(("option", "value", "says"), [
    ("--json", "", "--json: an empty path"),
    ("--report", "", "--report: an empty path"),
    ("--json", "out.json/", "--json: ends in '/'"),
])
def test_an_empty_or_directory_like_output_path_is_refused(work, capsys, option, value, says):
    refused(capsys, "size", f"tr/{PLANAR2}", option, value, says=(says,))


def test_plan_out_with_a_trailing_slash_is_refused(work, capsys):
    refused(capsys, "plan", f"tr/{PLANAR2}", "--out", "traj.csv/", says=("--out: ends in '/'",))
    refused(capsys, "init", "robots/planar2.urdf", "--out", "", says=("--out: an empty path",))


@pytest.mark.slow
@pytest.mark.parametrize("name", ["index.html", "joint_shoulder.png"])
def test_a_report_never_writes_over_an_input_inside_its_directory(work, capsys, name):
    """The motion file named index.html (or the robot file a figure's name) in DIR."""
    Path("rep").mkdir()
    text = Path("tr", PLANAR2).read_text().replace('"../robots/', f'"{REPO}/robots/')
    if name == "index.html":
        Path("rep", name).write_text(text)
        argv = ["size", f"rep/{name}", "--report", "rep"]
    else:
        shutil.copy(REPO / "robots" / "planar2.urdf", Path("rep", name))
        Path("m.toml").write_text(text)
        argv = ["size", f"rep/{name}", "m.toml", "--report", "rep"]
    original = Path("rep", name).read_bytes()
    refused(capsys, *argv, says=("--report", f"would write {name} over the input file"))
    assert Path("rep", name).read_bytes() == original
    assert sorted(p.name for p in Path("rep").iterdir()) == [name]


@pytest.mark.slow
def test_dev_stdout_works_when_stdout_is_a_pipe(work):
    for argv in (["size", f"tr/{PLANAR2}", "--json", "/dev/stdout"],
                 ["plan", f"tr/{PLANAR2}", "--out", "/dev/stdout"]):
        done = subprocess.run([sys.executable, "-m", "hdselect.cli", *argv], capture_output=True,
                              text=True, check=False)
        assert done.returncode == 0, done.stderr
        assert ('"joints"' in done.stdout if "--json" in argv
                else done.stdout.startswith("t,q_shoulder"))


@pytest.mark.slow
def test_a_study_refused_before_its_first_case_writes_nothing(work, capsys):
    study = next(Path("tr/studies").glob("*.toml"))
    refused(capsys, "study", study, "--out", "rows.csv", "--scheduler", "tcp://127.0.0.1:1",
            says=())
    assert not Path("rows.csv").exists() and not Path("rows.jsonl").exists()


def test_a_study_will_not_take_over_a_csv_it_did_not_write(work, capsys):
    study = next(Path("tr/studies").glob("*.toml"))
    Path("mine.csv").write_text("name,value\nkeep,1\n")
    refused(capsys, "study", study, "--out", "mine.csv",
            says=("mine.csv: --out: exists and was not written by a study",))
    assert Path("mine.csv").read_text() == "name,value\nkeep,1\n"


# --- inputs read once -----------------------------------------------------------------------

def fifo_of(path: Path, text: str) -> threading.Thread:
    """A FIFO at `path` that gives `text` to the first reader, once: a second open blocks."""
    os.mkfifo(path)

    def serve():
        with open(path, "w") as stream:  # blocks until a reader opens it
            stream.write(text)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    return thread


@pytest.mark.slow
@pytest.mark.parametrize("which", ["motion", "robot", "log"])
def test_a_fifo_input_is_read_once(work, which):
    """A second read of the FIFO would block: the command must finish, reading it once."""
    text = Path("tr", PLANAR2).read_text().replace('"../robots/', f'"{REPO}/robots/')
    if which == "motion":
        writer = fifo_of(work / "motion.toml", text)
        argv = ["size", "motion.toml", "--json", "r.json"]
    elif which == "robot":
        writer = fifo_of(work / "robot.urdf", (REPO / "robots" / "planar2.urdf").read_text())
        Path("m.toml").write_text(text)
        argv = ["size", "robot.urdf", "m.toml", "--json", "r.json"]
    else:
        logged = Path("tr/pan_tilt_logged.toml").read_text().replace('"../robots/',
                                                                     f'"{REPO}/robots/')
        log = next(line.split('"')[1] for line in logged.splitlines()
                   if line.startswith("file"))
        writer = fifo_of(work / "log.csv", (Path("tr") / log).read_text())
        Path("m.toml").write_text(logged.replace(log, "log.csv"))
        argv = ["size", "m.toml", "--json", "r.json"]
    done = subprocess.run([sys.executable, "-m", "hdselect.cli", *argv], capture_output=True,
                          text=True, check=False, timeout=120)
    assert done.returncode in (0, 1), done.stderr
    assert json.loads(Path("r.json").read_text())["joints"]
    writer.join(timeout=5)
    assert not writer.is_alive()


# --- found by the battery -----------------------------------------------------------------------

def variant(name, base, *changes):
    text = Path("tr", base).read_text()
    for old, new in changes:
        assert old in text, old
        text = text.replace(old, new, 1)
    Path("tr", name).write_text(text)
    return f"tr/{name}"


def test_a_move_longer_than_ruckig_can_plan_is_one_line(work, capsys):
    """limits.velocity 1e-3 deg/s: Ruckig's result -101, which its Python enum lacks."""
    motion = variant("slow.toml", PLANAR2, ("velocity = 180 ", "velocity = 1e-3 "))
    refused(capsys, "size", motion, says=("slow.toml", "longer than Ruckig can plan",
                                          "limits.velocity"))


def test_a_torque_constant_below_any_motor_is_refused(work, capsys):
    text = (REPO / "motors" / "example_motors.toml").read_text()
    Path("kt.toml").write_text(text.replace("torque_constant_nm_per_a = 0.026",
                                            "torque_constant_nm_per_a = 1e-300"))
    refused(capsys, "size", f"tr/{PLANAR2}", "--motor-catalog", "kt.toml",
            says=("kt.toml: motor[EX-16].torque_constant_nm_per_a",))


def test_a_positional_robot_overrides_the_motion_files(work, capsys):
    motion = variant("elsewhere.toml", PLANAR2, ('"../robots/planar2.urdf"', '"gone.urdf"'))
    status, out, err = run(capsys, "size", "robots/planar2.urdf", motion)
    assert status == 0, err
    assert "shoulder" in out
    refused(capsys, "size", motion, says=("elsewhere.toml: robot: robot file not found",))


def test_a_waypoint_on_a_limit_the_robot_file_rounded_is_on_the_limit(work, capsys):
    """90 deg against an upper limit written 1.5707963 rad (pi/2 to 8 digits)."""
    urdf = (REPO / "robots" / "planar2.urdf").read_text()
    assert 'upper="2.0943951"' in urdf
    Path("robots_rounded.urdf").write_text(urdf.replace('upper="2.0943951"',
                                                        'upper="1.5707963"'))
    motion = variant("at90.toml", PLANAR2, ("shoulder = 75", "shoulder = 90"))
    status, _, err = run(capsys, "size", "robots_rounded.urdf", motion)
    assert status in (0, 1), err
    robot, motion_ = hdselect.load_case(motion, "robots_rounded.urdf")
    assert motion_.waypoints.max() == robot.upper[0]  # moved onto the limit, by 2.7e-8 rad
    beyond = variant("at91.toml", PLANAR2, ("shoulder = 75", "shoulder = 90.001"))
    refused(capsys, "size", "robots_rounded.urdf", beyond, says=("outside the limits",))


def test_init_writes_a_starter_size_takes_on_a_robot_of_10000_rad_s(work, capsys):
    """Its moves last 0.044 s: the grid is refined, not refused."""
    urdf = (REPO / "robots" / "planar2.urdf").read_text().replace('velocity="4.0"',
                                                                 'velocity="10000"')
    Path("fast.urdf").write_text(urdf)
    assert run(capsys, "init", "fast.urdf", "--out", "starter.toml")[0] == 0
    status, _, err = run(capsys, "size", "starter.toml", "--json", "s.json")
    assert status in (0, 1), err
    assert json.loads(Path("s.json").read_text())["samples"] > 3 / 0.001


def test_a_refusal_after_a_python_warning_is_still_one_line(work, capsys, monkeypatch):
    """A numpy warning raised before the refusal is held, not printed first."""
    import importlib

    from hdselect.base.errors import InputError

    command = importlib.import_module("hdselect.cli.size")  # main looks it up per run

    def warn_then_refuse(args):
        warnings.warn("overflow encountered in multiply", RuntimeWarning, stacklevel=1)
        raise InputError("refused", field="x")

    monkeypatch.setattr(command, "run_size", warn_then_refuse)
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        refused(capsys, "size", f"tr/{PLANAR2}", says=("error: x: refused",))
