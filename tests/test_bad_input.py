"""Every case of issue 9 (hostile input), end to end through the command line.

The promise: exit status 0 (every joint has a unit), 1 (some joint has none) or 2
(bad input: one line on standard error naming the file and the field, no output
written); 3 for a bug in hdselect, 130/143 when interrupted. Never a silently
wrong answer, never a traceback, never a half-written or replaced output.
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from hdselect.cli.output import EXIT_BAD_INPUT, EXIT_BUG, EXIT_CASES_FAILED, EXIT_NO_FIT
from helpers import REPO, run

TRAJECTORIES = REPO / "trajectories"


def variant(name: str, base: str, *changes: tuple[str, str]) -> str:
    """A copy of a shipped motion (in tr/) with text replaced; returns its path."""
    text = Path("tr", base).read_text()
    for old, new in changes:
        assert old in text, old
        text = text.replace(old, new, 1)
    Path("tr", name).write_text(text)
    return f"tr/{name}"


def refused(capsys, *argv, says: tuple[str, ...] = ()) -> str:
    """Run a command that must be refused: status 2, one line, no output, no new file."""
    before = set(Path(".").rglob("*"))
    status, out, err = run(capsys, *argv)
    lines = err.strip().splitlines()
    assert status == 2, err
    assert out == "" and len(lines) == 1 and lines[0].startswith("hdselect: error: "), err
    for text in says:
        assert text in lines[0], (text, lines[0])
    assert set(Path(".").rglob("*")) == before
    return lines[0]


def table_units(out: str) -> dict[str, str]:
    """Joint -> unit id of a ``size`` table."""
    units = {}
    for line in out.splitlines():
        cells = line.split()
        if len(cells) > 1 and cells[1].rstrip("*").startswith("PSA-"):
            units[cells[0]] = cells[1].rstrip("*")
    return units


PLANAR2 = "planar2_pick_place.toml"
SCAN = "pan_tilt_scan.toml"
LOGGED = "pan_tilt_logged.toml"


# --- silent wrong results ----------------------------------------------------------------------

@pytest.mark.parametrize("dt", ["100", "0.5"])
def test_a_dt_coarser_than_a_move_is_refined_and_sizes_as_the_file_fine(work, capsys, dt):
    """dt is the period the file asks for; a cycle it does not resolve is sampled finer."""
    fine = run(capsys, "size", f"tr/{PLANAR2}", "--json", "fine.json")
    motion = variant("coarse.toml", PLANAR2, ("dt = 0.001", f"dt = {dt}"))
    coarse = run(capsys, "size", motion, "--json", "coarse.json")
    assert fine[0] == coarse[0] == 0
    a, b = (json.loads(Path(name).read_text()) for name in ("fine.json", "coarse.json"))
    assert b["samples"] > 3.8 / float(dt) + 1  # a grid finer than the file's
    for x, y in zip(a["joints"], b["joints"], strict=True):
        assert x["selected"] == y["selected"]
        assert y["peak_torque_nm"] == pytest.approx(x["peak_torque_nm"], rel=0.01)


def test_the_move_the_sampling_resolves_sizes_as_before(work, capsys):
    status, out, _ = run(capsys, "size", f"tr/{PLANAR2}")
    assert status == 0 and table_units(out)["shoulder"] == "PSA-14-100"


@pytest.mark.slow
def test_toppra_with_limits_too_high_is_refused(work, capsys):
    motion = variant("fast.toml", SCAN, ("velocity = 150", "velocity = 1e308"))
    refused(capsys, "size", motion, says=("limits.velocity", "between"))
    motion = variant("fast.toml", SCAN, ("velocity = 150", "velocity = 5e7"),
                     ("acceleration = 1200", "acceleration = 5e10"))
    refused(capsys, "size", motion, "--max-samples", "10000",
            says=("dt", "is refined to", "to resolve the path piece", "--max-samples"))


def write_log(name: str, rows: list[str], header: str = "t,q_pan,q_tilt") -> str:
    Path("tr", "logs", name).write_text("\n".join([header, *rows]) + "\n")
    return variant(name.replace(".csv", ".toml"), LOGGED,
                   ("logs/pan_tilt_log.csv", f"logs/{name}"))


def logged_rows() -> list[str]:
    return Path("tr/logs/pan_tilt_log.csv").read_text().splitlines()[1:]


def test_a_log_past_the_joint_limits_is_refused(work, capsys):
    rows = logged_rows()
    t, pan, tilt = rows[500].split(",")
    rows[500] = f"{t},500,{tilt}"  # the pan joint stops at +-170 deg
    motion = write_log("over.csv", rows)
    refused(capsys, "size", motion, says=("over.csv: q_pan: data row 501 (line 502)",
                                          "500 deg is outside the limits of joint 'pan'"))


def test_a_duplicated_log_column_is_refused(work, capsys):
    rows = [row + "," + row.split(",")[1] for row in logged_rows()]
    motion = write_log("dup.csv", rows, header="t,q_pan,q_tilt,q_pan")
    refused(capsys, "size", motion, says=("dup.csv: q_pan: column 'q_pan' appears twice",))


@pytest.mark.parametrize(("lower", "upper", "says"), [
    ("1.5707963", "-1.0471976", "is above the upper limit"),
    ("0.5", "0.5", "equals the upper limit"),
])
def test_urdf_limits_that_cross_are_refused_naming_the_joint(work, capsys, lower, upper, says):
    text = (REPO / "robots" / "pan_tilt.urdf").read_text()
    old = 'lower="-1.0471976" upper="1.5707963"'
    assert old in text
    Path("crossed.urdf").write_text(text.replace(old, f'lower="{lower}" upper="{upper}"'))
    refused(capsys, "size", "crossed.urdf", f"tr/{SCAN}",
            says=("crossed.urdf: joint[tilt].limit", "joint 'tilt'", says))


def size_json(capsys, *argv) -> dict:
    status, out, err = run(capsys, "size", *argv, "--json", "-")
    assert status in (0, 1), err
    return json.loads(out)


def shoulder(document: dict) -> dict:
    return next(joint for joint in document["joints"] if joint["name"] == "shoulder")


def test_payload_mass_override_keeps_the_files_centre_of_mass_inertia_and_frame(work, capsys):
    plain = shoulder(size_json(capsys, f"tr/{PLANAR2}"))
    same = shoulder(size_json(capsys, f"tr/{PLANAR2}", "--payload", "0.15"))
    assert same == plain  # 0.15 kg is the file's own [payload] (the gripper): nothing changes
    assert plain["selected"] == "PSA-14-100"
    heavier = shoulder(size_json(capsys, f"tr/{PLANAR2}", "--payload", "0.8"))
    assert heavier["max_gravity_torque_nm"] > plain["max_gravity_torque_nm"]


def test_payload_com_or_frame_alone_change_the_files_payload(work, capsys):
    plain = shoulder(size_json(capsys, f"tr/{PLANAR2}"))
    # the file's 0.4 kg at 0.03 m from the tool frame's origin, moved out to 0.30 m
    moved = shoulder(size_json(capsys, f"tr/{PLANAR2}", "--payload-com", "0.30", "0", "0"))
    assert moved["max_gravity_torque_nm"] > plain["max_gravity_torque_nm"]
    # carried on the upper arm instead of the tool: less torque at the shoulder
    upper = shoulder(size_json(capsys, f"tr/{PLANAR2}", "--payload-frame", "link1"))
    assert upper["max_gravity_torque_nm"] < plain["max_gravity_torque_nm"]


@pytest.mark.parametrize("option", [["--payload-com", "0", "0", "0.1"],
                                    ["--payload-frame", "table_top"]])
def test_payload_com_or_frame_without_a_payload_anywhere_is_refused(work, capsys, option):
    refused(capsys, "size", "tr/index_table_indexing.toml", *option,
            says=(option[0], "gives no payload", "--payload KG"))


@pytest.mark.parametrize("value", ["1e308", "inf", "-inf", "nan", "0", "-1"])
def test_a_payload_mass_out_of_range_is_refused(work, capsys, value):
    refused(capsys, "size", f"tr/{PLANAR2}", f"--payload={value}", says=("--payload",))


@pytest.mark.parametrize("command", ["size", "max-payload"])
def test_a_payload_frame_of_undecodable_bytes_is_an_unknown_frame(work, capsys, command):
    # found by the hostile battery: UnicodeEncodeError in Pinocchio (exit 70); the shell
    # passes bytes that are not UTF-8 as surrogates (os.fsdecode)
    refused(capsys, command, f"tr/{PLANAR2}", "--payload-frame", os.fsdecode(b"\xff"),
            says=("--payload-frame: unknown frame", "links are: base_link, link1"))


def test_nan_in_a_payload_com_is_refused(work, capsys):
    refused(capsys, "size", f"tr/{PLANAR2}", "--payload-com", "nan", "0", "0",
            says=("--payload-com: ", "finite"))
    motion = variant("nancom.toml", PLANAR2, ("com = [0.03, 0.0, 0.0]", "com = [nan, 0, 0]"))
    refused(capsys, "size", motion, says=("nancom.toml: payload.com[0]", "finite"))


def catalog_file(**values: float) -> str:
    unit = {"size": 20, "ratio": 50, "rated_torque_nm": 30.0, "repeated_torque_nm": 40.0,
            "max_input_speed_rpm": 4000, "input_inertia_kg_cm2": 0.1, "mass_kg": 1.0}
    unit.update(values)
    Path("mine.toml").write_text('series = "ACME"\n[[unit]]\n' + "".join(
        f"{key} = {value!r}\n" for key, value in unit.items()))
    return "mine.toml"


@pytest.mark.parametrize(("key", "value"), [
    ("ratio", 1e300), ("rated_torque_nm", 1e308), ("rated_torque_nm", 1e-300),
    ("repeated_torque_nm", 1e308), ("mass_kg", 1e308), ("input_inertia_kg_cm2", 1e300),
])
def test_a_catalog_value_out_of_range_is_refused_by_every_command(work, capsys, key, value):
    catalog = catalog_file(**{key: value})
    for command in (["size", f"tr/{PLANAR2}"], ["duty", "tr/duty/conveyor_index.toml"],
                    ["catalog"]):
        refused(capsys, *command, "--catalog", catalog, says=("mine.toml", key))


def test_a_urdf_mass_of_1e308_is_refused(work, capsys):
    text = (REPO / "robots" / "planar2.urdf").read_text()
    first = re.search(r'<mass value="([0-9.]+)"', text)
    assert first is not None
    Path("heavy.urdf").write_text(text.replace(first.group(0), '<mass value="1e308"', 1))
    refused(capsys, "size", "heavy.urdf", f"tr/{PLANAR2}", says=("heavy.urdf", "mass"))


@pytest.mark.parametrize("value", ["-1", "0", "nan", "inf", "1e308"])
def test_life_hours_out_of_range_is_refused_as_in_the_file(work, capsys, value):
    refused(capsys, "size", f"tr/{PLANAR2}", f"--life-hours={value}", says=("--life-hours",))
    motion = variant("life.toml", PLANAR2, ("life_hours = 20000", f"life_hours = {value}"))
    refused(capsys, "size", motion, says=("life.toml: requirements.life_hours",))


def test_identical_waypoints_without_a_dwell_take_no_time_and_are_refused(work, capsys):
    home = "{shoulder = 40, elbow = -80}"
    motion = variant("still.toml", PLANAR2, ("{shoulder = -30, elbow = 20}", home),
                     ("{shoulder = 75, elbow = -45}", home), ("dwell = 0.3", "dwell = 0"),
                     ("dwell = 0.4", "dwell = 0"), ("dwell = 0.4", "dwell = 0"))
    refused(capsys, "size", motion, says=("still.toml: waypoint", "takes no time"))


def test_a_hold_is_sized_on_its_static_check_and_says_so(work, capsys):
    home = "{shoulder = 40, elbow = -80}"
    motion = variant("hold.toml", PLANAR2, ("{shoulder = -30, elbow = 20}", home),
                     ("{shoulder = 75, elbow = -45}", home))
    status, out, err = run(capsys, "size", motion)
    assert status == 0 and err == ""
    assert "hold only: nothing moves in this cycle" in " ".join(out.split())
    document = size_json(capsys, motion)
    assert document["hold_only"] is True and document["cycle_time_s"] == pytest.approx(1.1)
    for joint in document["joints"]:
        chosen = next(c for c in joint["candidates"] if c["unit"] == joint["selected"])
        assert chosen["checks"]["static"]["value"] == pytest.approx(
            joint["max_gravity_torque_nm"], rel=1e-9)
        assert chosen["checks"]["peak"]["value"] == 0.0


# --- crashes that become one line --------------------------------------------------------------

@pytest.mark.parametrize(("change", "says"), [
    (("dwell = 0.3", "dwell = 1e308"), ("waypoint[0].dwell",)),
    (("dwell = 0.3", "dwell = 1e9"), ("dt", "more than the limit of 30,000,000",
                                       "--max-samples", "GB")),
    (("velocity = 180", "velocity = 1e-300"), ("limits.velocity",)),
    (("jerk = 9000", "jerk = 1e-300"), ("limits.jerk",)),
])
def test_extreme_motion_values_are_one_line(work, capsys, change, says):
    refused(capsys, "size", variant("extreme.toml", PLANAR2, change), says=says)


def test_toppra_limits_of_1e_300_are_one_line(work, capsys):
    motion = variant("slow.toml", SCAN, ("velocity = 150", "velocity = 1e-300"),
                     ("acceleration = 1200", "acceleration = 1e-300"))
    refused(capsys, "size", motion, says=("slow.toml: limits.", "got 1e-300"))


def test_a_1e308_cell_in_a_log_is_one_line(work, capsys):
    rows = logged_rows()
    rows[99] = rows[99].split(",")[0] + ",1e308,0"
    refused(capsys, "size", write_log("big.csv", rows),
            says=("big.csv: q_pan: data row 100 (line 101)",))


def test_a_long_gap_in_a_log_is_refused_before_allocating(work, capsys):
    motion = write_log("gap.csv", logged_rows()[:3] + ["1000000,0,0"])
    refused(capsys, "size", motion, says=("gap.toml: dt", "500,000,001 samples",
                                          "--max-samples"))


def test_a_duty_speed_of_1e308_is_one_line(work, capsys):
    Path("duty.toml").write_text("[[phase]]\ntorque = 1.0\ntime = 0.1\nspeed = 1e308\n")
    refused(capsys, "duty", "duty.toml", says=("duty.toml: phase[0].speed",))


def prismatic_robot() -> tuple[str, str]:
    Path("slide.urdf").write_text(
        '<robot name="slide"><link name="base"/><link name="carriage"><inertial>'
        '<mass value="2.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
        '</inertial></link><joint name="x" type="prismatic"><parent link="base"/>'
        '<child link="carriage"/><axis xyz="1 0 0"/>'
        '<limit lower="0" upper="0.5" effort="100" velocity="1"/></joint></robot>')
    Path("slide.toml").write_text(
        'robot = "slide.urdf"\nplanner = "ruckig"\nangle_unit = "rad"\n[limits]\n'
        "velocity = 0.5\nacceleration = 2\njerk = 20\n[[waypoint]]\nq = [0]\n"
        "[[waypoint]]\nq = [0.4]\n")
    return "slide.urdf", "slide.toml"


def test_a_robot_with_no_rotary_joint_is_refused_with_report(work, capsys):
    robot, motion = prismatic_robot()
    refused(capsys, "size", motion, "--report", "report", "--json", "out.json",
            says=("slide.urdf: joints", "no rotary joint"))
    status, _, _ = run(capsys, "plan", motion, "--out", "slide.csv")  # planning it is fine
    assert status == 0 and Path("slide.csv").stat().st_size > 0


def cli_process(*argv: str, cwd: Path, env: dict | None = None, text: bool = True):
    return subprocess.Popen(
        [sys.executable, "-c", "import sys; from hdselect.cli.main import main; sys.exit(main())",
         *argv], cwd=cwd, env={**os.environ, "PYTHONPATH": str(REPO / "src"), **(env or {})},
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=text)


@pytest.mark.slow
def test_an_ascii_terminal_gets_the_table_not_a_traceback(work):
    for argv in (["size", f"tr/{PLANAR2}"], ["catalog"], ["duty", "tr/duty/conveyor_index.toml"]):
        process = cli_process(*argv, cwd=work, env={"PYTHONIOENCODING": "ascii"})
        out, err = process.communicate(timeout=120)
        assert process.returncode == 0, err
        assert err == "" and "PSA-" in out


def test_ctrl_c_anywhere_is_one_line_and_leaves_nothing(work, capsys, monkeypatch):
    import hdselect.motion.planning

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(hdselect.motion.planning, "plan_motion", interrupted)
    status, out, err = run(capsys, "size", f"tr/{PLANAR2}", "--json", "out.json",
                           "--report", "report")
    assert status == 130 and out == ""
    assert err.strip().splitlines() == ["hdselect: interrupted; no output was written"]
    assert not Path("out.json").exists() and not Path("report").exists()
    assert [p.name for p in Path(".").iterdir() if p.name.startswith(".")] == []


def test_a_bug_is_its_own_status_one_line_and_no_output(work, capsys, monkeypatch):
    import hdselect.sizing.core

    def broken(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(hdselect.sizing.core, "size_tasks", broken)
    status, out, err = run(capsys, "size", f"tr/{PLANAR2}", "--json", "out.json")
    lines = err.strip().splitlines()
    assert status == EXIT_BUG == 70 and out == "" and len(lines) == 1
    assert status not in (EXIT_NO_FIT, EXIT_BAD_INPUT, EXIT_CASES_FAILED)
    assert "internal error (a bug in hdselect" in lines[0] and "-v" in lines[0]
    assert "ZeroDivisionError" in lines[0] and not Path("out.json").exists()
    status, _, err = run(capsys, "size", f"tr/{PLANAR2}", "-v")  # -v anywhere
    assert status == EXIT_BUG and "Traceback" in err


def test_found_by_fuzzing_a_subnormal_dwell_is_one_line(work, capsys):
    motion = variant("tiny.toml", PLANAR2, ("dwell = 0.3", "dwell = 5e-324"))
    refused(capsys, "size", motion, says=("tiny.toml: dt", "to resolve the dwell at waypoint[0]",
                                          "lengthen that dwell"))


def test_found_by_fuzzing_log_samples_1e_300_s_apart_are_one_line(work, capsys):
    motion = write_log("close.csv", ["0,0,0", "1e-300,0,0.004", "0.004,0,0.008"])
    refused(capsys, "size", motion, says=("close.csv: t: data row 2 (line 3)",
                                          "duplicated or corrupted time stamp"))


# --- memory and size ---------------------------------------------------------------------------

def test_a_tiny_dt_on_the_six_axis_arm_is_refused_before_allocating(work, capsys):
    """Refused up front: the refusal allocates nothing near one array of the grid.

    98,550,001 samples x 6 joints x 8 bytes is 4.7 GB per array; numpy reports its
    allocations to tracemalloc, so the peak while refusing counts the work done.
    """
    motion = variant("fine.toml", "benchtop6_pick_place.toml", ("dt = 0.001", "dt = 1e-7"))
    tracemalloc.start()
    try:
        refused(capsys, "size", motion, says=("fine.toml: dt", "98,550,001 samples", "GB",
                                              "limit of 30,000,000", "--max-samples"))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1e9, f"{peak / 1e6:.0f} MB allocated before refusing"


def test_max_samples_is_an_option_of_every_planning_command(work, capsys):
    for command in ("size", "compare", "plan"):
        extra = ["--out", "x.csv"] if command == "plan" else []
        refused(capsys, command, f"tr/{PLANAR2}", "--max-samples", "1000", *extra,
                says=("3,826 samples", "limit of 1,000"))
    status, _, _ = run(capsys, "size", f"tr/{PLANAR2}", "--max-samples", "3826")
    assert status == 0


@pytest.mark.parametrize("value", ["0", "-5", "1"])
def test_max_samples_must_be_a_whole_number_of_two_or_more(work, capsys, value):
    refused(capsys, "size", f"tr/{PLANAR2}", f"--max-samples={value}",
            says=("--max-samples", "whole number"))


# --- outputs -----------------------------------------------------------------------------------

def test_an_unwritable_output_leaves_no_other_output(work, capsys):
    refused(capsys, "plan", f"tr/{PLANAR2}", "--out", "/proc/x.csv", "--plot", "fig.png",
            says=("/proc/x.csv: --out",))
    refused(capsys, "size", f"tr/{PLANAR2}", "--report", "report", "--json", "/proc/x.json",
            says=("/proc/x.json: --json",))


@pytest.mark.slow
def test_a_failing_commit_puts_back_what_it_replaced(work, capsys, monkeypatch):
    Path("report").mkdir()
    Path("report/index.html").write_text("old report")
    Path("report/notes.txt").write_text("mine")
    Path("out.json").write_text("old json")
    real_replace = os.replace
    report = Path("report").resolve()
    moved = []

    def flaky(source, target):
        if Path(target).parent == report:
            moved.append(target)
            if len(moved) == 2:  # the JSON and one figure are in place: the disk fills up
                raise OSError(28, "No space left on device")
        real_replace(source, target)

    monkeypatch.setattr(os, "replace", flaky)
    status, out, err = run(capsys, "size", f"tr/{PLANAR2}", "--json", "out.json",
                           "--report", "report")
    assert status == 2 and out == "" and "nothing was changed" in err and len(moved) >= 2
    assert Path("out.json").read_text() == "old json"
    assert sorted(p.name for p in Path("report").iterdir()) == ["index.html", "notes.txt"]
    assert Path("report/index.html").read_text() == "old report"
    assert [p for p in Path(".").rglob(".*")] == []


def test_a_symlink_is_followed_and_its_target_replaced(work, capsys):
    Path("target.json").write_text("old")
    Path("link.json").symlink_to("target.json")
    status, _, _ = run(capsys, "size", f"tr/{PLANAR2}", "--json", "link.json")
    assert status == 0
    assert Path("link.json").is_symlink()
    assert json.loads(Path("target.json").read_text())["feasible"] is True


def test_dev_null_and_a_fifo_are_written_into_never_replaced(work, capsys):
    status, _, _ = run(capsys, "size", f"tr/{PLANAR2}", "--json", os.devnull)
    assert status == 0 and Path(os.devnull).is_char_device()
    os.mkfifo("pipe")
    received = []
    reader = threading.Thread(target=lambda: received.append(Path("pipe").read_text()))
    reader.start()
    status, _, _ = run(capsys, "size", f"tr/{PLANAR2}", "--json", "pipe")
    reader.join(timeout=60)
    assert status == 0 and json.loads(received[0])["feasible"] is True
    assert Path("pipe").is_fifo()


@pytest.mark.slow
def test_a_dash_is_standard_output_for_every_output_option(work, capsys):
    status, out, _ = run(capsys, "plan", f"tr/{PLANAR2}", "--out", "-")
    assert status == 0 and out.startswith("t,q_shoulder,qd_shoulder")
    status, out, _ = run(capsys, "size", f"tr/{PLANAR2}", "--report", "-")
    assert status == 0 and out.startswith("<!DOCTYPE html>") and "data:image/png;base64," in out
    assert "PSA-14-100" in out and "┃" not in out  # the page, not the table
    for command, extra in (("size", ["--json"]), ("duty", ["--json"])):
        target = f"tr/{PLANAR2}" if command == "size" else "tr/duty/conveyor_index.toml"
        status, out, _ = run(capsys, command, target, *extra, "-")
        assert json.loads(out)
    refused(capsys, "plan", f"tr/{PLANAR2}", "--out", "-", "--plot", "-",
            says=("--plot", "only one output"))


@pytest.mark.slow
def test_the_plot_goes_to_standard_output_as_png(work):
    process = cli_process("plan", f"tr/{PLANAR2}", "--out", "p.csv", "--plot", "-", cwd=work,
                          text=False)
    out, err = process.communicate(timeout=120)
    assert process.returncode == 0, err
    assert out.startswith(b"\x89PNG") and Path("p.csv").stat().st_size > 0


@pytest.mark.slow
def test_sigterm_removes_every_temporary(work):
    t = np.arange(1_200_000) * 0.002  # long enough that the signal lands during the work
    np.savetxt("tr/logs/long.csv", np.column_stack([t, 20 * np.sin(t), 5 * np.sin(2 * t)]),
               fmt=("%.3f", "%.4f", "%.4f"), delimiter=",", header="t,q_pan,q_tilt",
               comments="")
    motion = variant("long.toml", LOGGED, ("logs/pan_tilt_log.csv", "logs/long.csv"))
    process = cli_process("size", motion, "--json", "out.json", "--report", "report", cwd=work)
    deadline = time.monotonic() + 120
    while not list(Path(".").glob(".out.json.*")) and time.monotonic() < deadline:
        time.sleep(0.05)  # until the outputs are reserved (temporaries exist)
    assert list(Path(".").glob(".out.json.*")), "the run never reserved its outputs"
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 143
    assert err.strip().splitlines() == ["hdselect: terminated; no output was written"]
    assert sorted(p.name for p in Path(".").iterdir()) == ["robots", "tr"]


# --- the inputs and outputs of issues 11 to 14: motors, studies, joints, init -----------------

MOTORS = REPO / "motors" / "example_motors.toml"


def motor_file(old: str, new: str) -> str:
    text = MOTORS.read_text()
    assert old in text, old
    Path("motors.toml").write_text(text.replace(old, new, 1))
    return "motors.toml"


@pytest.mark.parametrize(("old", "new", "says"), [
    ("rated_torque_nm = 0.004", "rated_torque_nm = nan", "rated_torque_nm: must be finite"),
    ("peak_torque_nm = 0.014", "peak_torque_nm = 1e308", "peak_torque_nm: must be a torque"),
    ("max_speed_rpm = 7000", "max_speed_rpm = inf", "max_speed_rpm: must be finite"),
    ("rotor_inertia_kg_cm2 = 0.0012", "rotor_inertia_kg_cm2 = 1e-320",
     "rotor_inertia_kg_cm2: must be 0 or at least"),
    ("mass_kg = 0.06", "mass_kg = -1", "mass_kg: must be a mass of at least 0"),
])
def test_a_bad_number_in_a_motor_file_is_one_line_and_no_output(work, capsys, old, new, says):
    path = motor_file(old, new)
    for argv in (["size", f"tr/{PLANAR2}", "--json", "out.json", "--report", "report"],
                 ["compare", f"tr/{PLANAR2}", "--json", "out.json"]):
        refused(capsys, *argv, "--motor-catalog", path, says=(f"{path}: motor[EX-16].", says))


def test_nan_in_a_motion_files_motor_table_is_one_line(work, capsys):
    motion = Path("tr", PLANAR2).read_text() + (
        "\n[motor.shoulder]\nrated_torque_nm = 0.1\npeak_torque_nm = nan\n"
        "max_speed_rpm = 6000\nrated_speed_rpm = 3000\nrotor_inertia_kg_cm2 = 0.01\n"
        "mass_kg = 0.2\n")
    Path("tr/motor.toml").write_text(motion)
    refused(capsys, "size", "tr/motor.toml", "--json", "out.json",
            says=("motor.toml: motor.shoulder.peak_torque_nm: must be finite",))


def test_a_robot_files_velocity_limit_used_as_a_default_is_range_checked(work, capsys):
    text = (REPO / "robots" / "planar2.urdf").read_text()
    assert 'velocity="4.0"' in text
    Path("fast.urdf").write_text(text.replace('velocity="4.0"', 'velocity="1e300"', 1))
    motion = variant("nolimit.toml", PLANAR2, ("robot = ", "# robot = "))
    lines = Path(motion).read_text().splitlines()
    Path(motion).write_text("\n".join(line for line in lines
                                       if not line.startswith("velocity")) + "\n")
    refused(capsys, "size", "fast.urdf", motion, says=(
        "fast.urdf: joint[", "].limit.velocity: must be a speed limit", "limits.velocity"))


def small_study(text: str = "") -> str:
    Path("s.toml").write_text(f"""title = "small"
[base]
motion = "tr/{PLANAR2}"
[grid]
stop_time = [0.05, 0.1, 0.15]
{text}""")
    return "s.toml"


@pytest.mark.parametrize(("out", "says"), [
    (os.devnull, "is a device or a named pipe"),
    ("-", "--out: a study keeps its rows in a file"),
    ("existing", "is a directory"),
    ("nowhere/rows.csv", "does not exist"),
    ("s.toml", "is an input file"),
])
def test_a_study_output_that_cannot_hold_its_rows_is_refused_before_any_case(work, capsys, out,
                                                                              says):
    Path("existing").mkdir()
    refused(capsys, "study", small_study(), "--out", out, "--workers", "0", says=(says,))
    assert Path(os.devnull).is_char_device()


def test_a_bad_study_file_writes_nothing(work, capsys):
    study = small_study("time_scale = [1.0, nan]")
    refused(capsys, "study", study, "--out", "rows.csv", "--plot", "rows.png",
            says=("s.toml: grid.time_scale[1]: must be finite",))


def test_a_study_follows_a_symlink_and_keeps_its_journal_beside_the_target(work, capsys):
    Path("store").mkdir()
    Path("rows.csv").symlink_to("store/real.csv")
    status, out, _ = run(capsys, "study", small_study(), "--out", "rows.csv", "--workers", "0")
    assert status == 0
    assert Path("rows.csv").is_symlink() and Path("store/real.csv").is_file()
    assert len(Path("store/real.jsonl").read_text().splitlines()) == 3
    assert "store/real.csv; records:" in " ".join(out.split())


@pytest.mark.slow
def test_sigterm_during_a_study_keeps_the_finished_cases_and_resumes(work):
    study = small_study("efficiency = [0.5, 0.6, 0.7]")  # 9 cases: the signal lands among them
    process = cli_process("study", study, "--out", "rows.csv", "--workers", "1",
                          "--no-grouping", "--plot", "rows.png", cwd=work)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (
            Path("rows.jsonl").is_file() and Path("rows.jsonl").read_text().count("\n")):
        time.sleep(0.02)  # until the first case is kept
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 143, err
    assert err.strip().splitlines() == [
        "hdselect: terminated; the cases done are kept in rows.csv and its journal "
        "rows.jsonl; run the same command to resume"]
    kept = [json.loads(line) for line in Path("rows.jsonl").read_text().splitlines()]
    assert 1 <= len(kept) < 9 and not Path("rows.png").exists()
    assert [p.name for p in Path(".").iterdir() if p.name.startswith(".")] == []
    again = cli_process("study", study, "--out", "rows.csv", "--workers", "0",
                        "--plot", "rows.png", cwd=work)
    out, err = again.communicate(timeout=120)
    assert again.returncode == 0, err
    assert f"{len(kept)} already done" in " ".join(out.split())
    assert len(Path("rows.jsonl").read_text().splitlines()) == 9 and Path("rows.png").is_file()


def test_init_never_replaces_a_file_even_through_a_symlink(work, capsys):
    Path("mine.toml").write_text("keep")
    Path("link.toml").symlink_to("mine.toml")
    for target in ("mine.toml", "link.toml"):
        refused(capsys, "init", "robots/planar2.urdf", "--out", target,
                says=(f"{target}: --out: exists",))
    assert Path("mine.toml").read_text() == "keep"
    refused(capsys, "init", "robots/planar2.urdf", "--out", "robots/planar2.urdf",
            says=("is an input file",))


def test_a_file_that_appears_while_init_runs_is_not_replaced(work, capsys, monkeypatch):
    import hdselect.motion.starter

    real = hdselect.motion.starter.starter_motion

    def racing(*args, **kwargs):
        Path("new.toml").write_text("someone else's")
        return real(*args, **kwargs)

    monkeypatch.setattr(hdselect.motion.starter, "starter_motion", racing)
    status, out, err = run(capsys, "init", "robots/planar2.urdf", "--out", "new.toml")
    assert status == 2 and out == "" and "new.toml" in err and "not replaced" in err
    assert Path("new.toml").read_text() == "someone else's"
    assert [p.name for p in Path(".").iterdir() if p.name.startswith(".")] == []


@pytest.mark.slow
@pytest.mark.parametrize("command", [["compare", f"tr/{PLANAR2}"], ["joints",
                                                                    "robots/planar2.urdf"]])
def test_compare_and_joints_outputs_are_one_transaction(work, capsys, command):
    extra = ["--report", "report"] if command[0] == "compare" else []
    refused(capsys, *command, *extra, "--json", "/proc/x/out.json",
            says=("/proc/x/out.json: --json",))
    status, out, _ = run(capsys, *command, *extra, "--json", "-")
    assert status == 0
    json.loads(out, parse_constant=lambda constant: pytest.fail(constant))


# --- the Python API ----------------------------------------------------------------------------

PLANAR2_PATH = TRAJECTORIES / PLANAR2


def api_error(call, *args, **kwargs):
    from hdselect import InputError

    with pytest.raises(InputError) as info:
        call(*args, **kwargs)
    return info.value


def test_size_refuses_wrong_arguments_naming_the_parameter():
    import hdselect

    cases = [
        ((None, PLANAR2_PATH), {"units": ()}, "units"),
        ((123, PLANAR2_PATH), {}, "robot"),
        ((None, 42), {}, "motion"),
        ((None, PLANAR2_PATH), {"catalog": "mine.toml"}, "catalog"),
        ((None, PLANAR2_PATH), {"joints": "elbow"}, "joints"),
        ((None, PLANAR2_PATH), {"payload": 0.5}, "payload"),
        ((None, PLANAR2_PATH), {"units": ["PSA-14-100"]}, "units"),
        ((None, PLANAR2_PATH), {"life_hours": -1}, "life_hours"),
        ((None, PLANAR2_PATH), {"max_samples": 10}, "dt"),
        ((None, PLANAR2_PATH), {"max_samples": 1.5}, "max_samples"),
        ((None, PLANAR2_PATH), {"threads": 10**9}, "threads"),
        ((None, PLANAR2_PATH), {"mounting": [0, 0, float("nan")]}, "mounting"),
    ]
    for args, kwargs, field in cases:
        assert api_error(hdselect.size, *args, **kwargs).field == field, (args, kwargs)


def test_the_other_entry_points_refuse_wrong_arguments_naming_the_parameter():
    import hdselect
    from hdselect.sizing.options import options_for

    robot, motion = hdselect.load_case(PLANAR2_PATH)
    trajectory = hdselect.plan(robot, motion)
    cases = [
        (hdselect.load_robot, (123,), {}, "path"),
        (hdselect.load_robot, (REPO / "robots" / "planar2.urdf",), {"payload": 1}, "payload"),
        (hdselect.load_motion, (None,), {}, "path"),
        (hdselect.load_case, (PLANAR2_PATH,), {"robot": 3}, "robot"),
        (hdselect.load_catalog, ("mine.toml",), {}, "catalog"),
        (hdselect.load_duty, (5,), {}, "path"),
        (hdselect.size_duty, ("cycle", ()), {}, "cycle"),
        (hdselect.plan, ("robot", motion), {}, "robot"),
        (hdselect.plan, (robot, "motion"), {}, "motion"),
        (hdselect.plan, (robot, motion), {"max_samples": 0}, "max_samples"),
        (hdselect.size_trajectory, (robot, "trajectory", ()), {}, "trajectory"),
        (hdselect.size_trajectory, (robot, trajectory, hdselect.load_catalog(), {}), {},
         "options"),
        (hdselect.summarize, (None,), {}, "result"),
        (hdselect.Payload, (-1,), {}, "payload.mass"),
        (hdselect.Payload, (float("inf"),), {}, "payload.mass"),
        (hdselect.Payload, ("1",), {}, "payload.mass"),
        (hdselect.Options, (), {"life_hours": -1}, "life_hours"),
        (hdselect.Options, (), {"prefer": ["size"]}, "prefer"),
        (robot.with_payload, (0.5,), {}, "payload"),
        (robot.with_gearheads, ({"elbow": -1.0},), {}, "masses.elbow"),
        (robot.with_gearheads, ({"elbo": 1.0},), {}, "masses"),
        (robot.with_sized_joints, ("elbow",), {}, "joints"),
        (robot.with_mounting, ([0, 0, 1e308],), {}, "mounting[2]"),
        (options_for, ("motion",), {}, "motion"),
    ]
    for call, args, kwargs, field in cases:
        assert api_error(call, *args, **kwargs).field == field, (call, args, kwargs)


def test_a_robot_given_with_a_loaded_motion_is_used_not_ignored():
    import hdselect

    motion = hdselect.load_motion(PLANAR2_PATH)
    error = api_error(hdselect.size, REPO / "robots" / "benchtop6.urdf", motion)
    assert "the motion was read for joints shoulder, elbow" in str(error)


def test_json_is_strict():
    from hdselect.report.export import write_json

    with pytest.raises(ValueError, match="JSON compliant"):
        write_json(os.devnull, {"x": math.nan})
