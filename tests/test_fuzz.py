"""Property-based fuzzing of everything a user can hand hdselect (issue 9).

Motion files, logs, catalogs, duty profiles, robot files, motor files (a file for
``--motor-catalog`` and a ``[motor]`` table inline in a motion file), study files
and command lines are generated with random and extreme values (NaN, inf, 0, -0, negative, 1e-300,
1e308, integers too large for a float, wrong types, missing, unknown and
duplicated keys) and run through the command line, in process. Whatever comes
in, the promise holds:

- the exit status is 0, 1 or 2 (3 too for a study: a case failed, its row says why;
  never 70, a bug; never a traceback);
- on 2: exactly one line on standard error, nothing on standard output, and no
  file created, changed or removed;
- on 0 or 1: every number of the JSON written is finite (and the JSON strict);
- no Python warning (pytest turns warnings into errors, which would be status 3).

Profiles: ``ci`` (the default: a fixed seed, a few dozen cases per target, well
under a minute in all) and ``long`` (``HDSELECT_FUZZ=long``: thousands of cases,
random seeds, for local runs). ``pytest --hypothesis-show-statistics`` counts
the cases run.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hdselect
import mujoco_oracle
from helpers import REPO
from helpers.fuzz import (
    MAX_SAMPLES,
    check_run,
    corruptions,
    extreme,
    option_value,
    output_path,
    shuffled_entries,
    toml_text,
    workdir,
)

# --- values -------------------------------------------------------------------------------------


# --- running ------------------------------------------------------------------------------------


# --- motion files -------------------------------------------------------------------------------

angle = st.floats(-80, 110)
elbow = st.floats(-140, 140)


@st.composite
def motions(draw) -> str:
    planner = draw(st.sampled_from(["ruckig", "ruckig", "toppra"]))
    unit = draw(st.sampled_from(["deg", "deg", "deg", "rad"]))
    k = 1.0 if unit == "deg" else math.pi / 180  # file units per degree
    entries: list[tuple[str, object]] = [
        ("robot", "../robots/planar2.urdf"),
        ("planner", planner),
        ("angle_unit", unit),
        ("dt", draw(st.sampled_from([0.001, 0.001, 0.002, 0.005]))),
        ("mounting", draw(st.sampled_from(["floor", "wall", "ceiling", [0, 0, -9.81]]))),
        ("[payload]", None),
        ("mass", draw(st.floats(0.01, 3.0))),
        ("com", draw(st.lists(st.floats(-0.1, 0.1), min_size=3, max_size=3))),
        ("frame", "tool"),
        ("[limits]", None),
        ("velocity", draw(st.floats(30, 400)) * k),
        ("acceleration", draw(st.floats(200, 5000)) * k),
    ]
    if planner == "ruckig":
        entries.append(("jerk", draw(st.floats(2000, 60000)) * k))
    entries += [("[safety]", None), ("stop_time", draw(st.floats(0.01, 0.5))),
                ("[requirements]", None),
                ("life_hours", draw(st.floats(100, 1e6))),
                ("life_basis", draw(st.sampled_from(["L50", "L10"])))]
    for _ in range(draw(st.integers(2, 4))):
        q = {"shoulder": draw(angle) * k, "elbow": draw(elbow) * k}
        entries += [("[[waypoint]]", None), ("q", draw(st.sampled_from([q, list(q.values())])))]
        if draw(st.booleans()):
            entries.append(("dwell", draw(st.floats(0.0, 1.0))))
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@given(motions())
def test_fuzz_motion_files(text):
    with workdir() as work:
        Path("tr/fuzz.toml").write_text(text)
        check_run(work, ["size", "tr/fuzz.toml", "--json", "-", "--max-samples", MAX_SAMPLES],
                  stdout_json=True)


TOOL_POSE_EXAMPLES = 25 if os.environ.get("HDSELECT_FUZZ", "ci") == "ci" else 300
"""Tool-pose motion files: each solves poses and plans lines, so fewer in the ci profile."""
POSES = [((0.26, 0.0, 0.30), (180, 0, -90)), ((0.28, -0.20, 0.16), (180, 0, -135)),
         ((0.28, -0.20, 0.08), (180, 0, -135)), ((0.20, 0.28, 0.16), (180, 0, -45))]
"""Poses of benchtop6_pick_place_poses.toml that the generated ones stay near [m, deg]."""


@st.composite
def tool_pose_motions(draw) -> tuple[str, bool]:
    unit = draw(st.sampled_from(["deg", "deg", "rad"]))
    k = 1.0 if unit == "deg" else math.pi / 180
    entries: list[tuple[str, object]] = [
        ("robot", "../robots/benchtop6.urdf"), ("planner", "toppra"), ("angle_unit", unit),
        ("dt", 0.001),
        draw(st.sampled_from([("mounting", "floor"), ("mounting", "wall"),
                              ("mounting", [0, 0, -9.81]),
                              ("base", {"xyz": [0.0, 0.0, draw(st.floats(-0.1, 0.1))],
                                        "rpy": [0.0, 0.0, draw(st.floats(-30, 30)) * k]})])),
        ("[limits]", None), ("velocity", 120 * k), ("acceleration", 600 * k),
        ("[tool]", None), ("frame", draw(st.sampled_from(["tool0", "tool0", "wrist_3_link"]))),
        ("position_tolerance", draw(st.sampled_from([1e-4, 1e-4, 1e-3, 1e-6]))),
    ]
    lines = False
    for i in range(draw(st.integers(2, 4))):
        xyz, rpy = draw(st.sampled_from(POSES))
        xyz = [x + draw(st.floats(-0.05, 0.05)) for x in xyz]
        entries += [("[[waypoint]]", None),
                    ("pose", {"xyz": xyz, "rpy": [a * k for a in rpy]})]
        if i and draw(st.booleans()):
            entries.append(("line", True))
            lines = True
        elif draw(st.integers(0, 3)) == 0:
            entries.append(("near", {"elbow": draw(st.floats(-150, 150)) * k}))
        if i and draw(st.integers(0, 4)) == 0:
            entries.append(("reconfigure", True))
        if draw(st.booleans()):
            entries.append(("dwell", draw(st.floats(0.0, 0.5))))
    return toml_text(draw(shuffled_entries(entries))), lines


@pytest.mark.slow
@settings(max_examples=TOOL_POSE_EXAMPLES)
@given(tool_pose_motions())
def test_fuzz_tool_pose_motion_files(case):
    text, lines = case
    with workdir() as work:
        Path("tr/fuzz.toml").write_text(text)
        check_run(work, ["plan", "tr/fuzz.toml", "--out", "out.csv", "--waypoints", "solved.csv",
                         *(["--line-errors", "lines.csv"] if lines else []),
                         "--max-samples", MAX_SAMPLES],
                  csv_files=("out.csv", "solved.csv", "lines.csv"))


# --- logs ---------------------------------------------------------------------------------------

@st.composite
def logs(draw) -> tuple[str, float]:
    n = draw(st.integers(2, 120))
    period = draw(st.sampled_from([0.002, 0.005, 0.01]))
    jitter = draw(st.booleans())
    header = ["t", "q_pan", "q_tilt"]
    if draw(st.integers(0, 4)) == 0:
        header.append(draw(st.sampled_from(["q_pan", "qd_pan", "q_elbow", "note", "t", ""])))
    if draw(st.integers(0, 6)) == 0:
        header.remove(draw(st.sampled_from(["t", "q_pan", "q_tilt"])))
    rows = []
    pan_amp, tilt_amp = draw(st.floats(0, 160)), draw(st.floats(0, 55))
    for k in range(n):
        t = k * period * (1 + (0.01 * ((k * 7919) % 13 - 6) / 6 if jitter else 0))
        cells = {"t": repr(t), "q_pan": repr(pan_amp * math.sin(3 * t)),
                 "q_tilt": repr(tilt_amp * math.sin(2 * t))}
        row = [cells.get(name, "0") for name in header]
        rows.append(row)
    for _ in range(draw(corruptions)):
        r = draw(st.integers(0, n - 1))
        c = draw(st.integers(0, len(header) - 1))
        rows[r][c] = draw(st.one_of(extreme.map(repr), st.sampled_from(
            ["", "abc", "nan", "-inf", "1e400", '"5"', "0x10", " 1 "])))
    if draw(st.integers(0, 8)) == 0:
        rows[draw(st.integers(0, n - 1))].append("9")  # ragged
    text = "\n".join(",".join(row) for row in [header, *rows]) + "\n"
    dt = draw(st.sampled_from([period, 0.001, 0.002]))
    return text, dt


@pytest.mark.slow
@given(logs())
def test_fuzz_logs(case):
    text, dt = case
    with workdir() as work:
        Path("tr/logs/fuzz.csv").write_text(text)
        Path("tr/fuzz.toml").write_text(toml_text([
            ("robot", "../robots/pan_tilt.urdf"), ("planner", "samples"),
            ("angle_unit", "deg"), ("dt", dt), ("[samples]", None), ("file", "logs/fuzz.csv")]))
        check_run(work, ["size", "tr/fuzz.toml", "--json", "-", "--max-samples", MAX_SAMPLES],
                  stdout_json=True)


# --- catalogs -----------------------------------------------------------------------------------

@st.composite
def catalogs(draw) -> str:
    entries: list[tuple[str, object]] = [("series", draw(st.just("ACME")))]
    if draw(st.booleans()):
        entries += [("[rules]", None),
                    ("rated_input_speed_rpm", draw(st.floats(500, 3000))),
                    ("rated_life_hours", draw(st.floats(1000, 50000))),
                    ("life_basis", draw(st.sampled_from(["L10", "L50"]))),
                    ("mean_torque_limit", draw(st.sampled_from(["speed-adjusted"]))),
                    ("mean_speed", draw(st.sampled_from(["moving", "whole-cycle"]))),
                    ("max_momentary_events", draw(st.floats(10, 1e5)))]
    for i in range(draw(st.integers(1, 3))):
        rated = draw(st.floats(0.5, 50))
        entries += [
            ("[[unit]]", None),
            ("size", draw(st.just(20 + 2 * i))),
            ("ratio", draw(st.sampled_from([30, 50, 100, 160]))),
            ("rated_torque_nm", draw(st.just(rated))),
            ("repeated_torque_nm", draw(st.just(rated * 1.5))),
            ("momentary_torque_nm", draw(st.just(rated * 3))),
            ("max_input_speed_rpm", draw(st.floats(1000, 8000))),
            ("input_inertia_kg_cm2", draw(st.floats(0.001, 1.0))),
            ("mass_kg", draw(st.floats(0.1, 5.0))),
        ]
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@given(catalogs(), st.sampled_from(["size", "duty", "catalog"]))
def test_fuzz_catalogs(text, command):
    with workdir() as work:
        Path("mine.toml").write_text(text)
        argv = {"size": ["size", "tr/planar2_pick_place.toml", "--json", "-"],
                "duty": ["duty", "tr/duty/conveyor_index.toml", "--json", "-"],
                "catalog": ["catalog", "--json"]}[command]
        check_run(work, [*argv, "--catalog", "mine.toml"], stdout_json=True)


# --- duty profiles ------------------------------------------------------------------------------

@st.composite
def duty_profiles(draw) -> str:
    entries: list[tuple[str, object]] = []
    for _ in range(draw(st.integers(0, 5))):
        entries += [("[[phase]]", None),
                    ("torque", draw(st.floats(-20, 20))),
                    ("time", draw(st.floats(0.01, 2.0))),
                    ("speed", draw(st.floats(-60, 60)))]
        if draw(st.integers(0, 3)) == 0:
            entries.append(("name", draw(st.text(max_size=12))))
    if draw(st.booleans()):
        entries += [("[momentary]", None), ("torque", draw(st.floats(0, 40))),
                    ("speed", draw(st.floats(0, 60))),
                    ("time", draw(st.floats(0.001, 0.5)))]
    if draw(st.booleans()):
        entries += [("[static]", None), ("torque", draw(st.floats(0, 30)))]
    if draw(st.booleans()):
        entries += [("[requirements]", None), ("life_hours", draw(st.floats(1, 1e6))),
                    ("life_basis", draw(st.sampled_from(["L50", "L10"])))]
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@given(duty_profiles())
def test_fuzz_duty_profiles(text):
    with workdir() as work:
        Path("duty.toml").write_text(text)
        check_run(work, ["duty", "duty.toml", "--json", "-"], stdout_json=True)


# --- robot files --------------------------------------------------------------------------------

NUMERIC_ATTRIBUTE = r'(value|ixx|iyy|izz|ixy|lower|upper|xyz|rpy|multiplier|offset)="([^"]*)"'
FUZZ_FINGER = """
  <joint name="finger" type="revolute">
    <parent link="link2"/><child link="finger_link"/>
    <origin xyz="0.25 0 0" rpy="0 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-0.5" upper="0.5" effort="2.0" velocity="4.0"/>
    <mimic joint="elbow" multiplier="0.1" offset="0"/>
  </joint>
  <link name="finger_link">
    <inertial><origin xyz="0.02 0 0" rpy="0 0 0"/><mass value="0.05"/>
      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
</robot>"""
"""A finger on planar2's link2 following the elbow (x 0.1: the shipped motion keeps it in range)."""
UNREADABLE = ["nan", "inf", "", "abc", "1 2", "0 0 1e308", "0.243kg", "${m1}", " 1", "1 ",
              "1e400", "0x10", "+.5"]
"""Values urdfdom reads otherwise than they are written, or refuses."""
AXES = ["0 0 0", "nan 0 0", "0 0", "1e-13 0 0", "0 -2 0", "0.6 0 -0.8", "0 0 1", "1 0 0"]


@st.composite
def robot_files(draw) -> str:
    """planar2 (with a mimic finger or not), 1 to 3 numbers made extreme or unreadable, and
    perhaps a joint axis without direction."""
    import re

    text = (REPO / "robots" / "planar2.urdf").read_text()
    if draw(st.booleans()):
        text = text.replace("</robot>", FUZZ_FINGER)
    matches = list(re.finditer(NUMERIC_ATTRIBUTE, text))
    for _ in range(draw(st.integers(0 if "finger" in text else 1, 3))):
        match = matches[draw(st.integers(0, len(matches) - 1))]
        value = draw(st.one_of(extreme.map(repr), st.sampled_from(UNREADABLE)))
        if match.group(1) in ("xyz", "rpy"):
            value = draw(st.sampled_from([f"{value} 0 0", "nan 0 0", "0 0 1e308", "1 2",
                                          "0 0 0"]))
        start, end = match.span(2)
        text = text[:start] + value + text[end:]
        matches = list(re.finditer(NUMERIC_ATTRIBUTE, text))
    if draw(st.integers(0, 3)) == 0:
        axes = list(re.finditer(r'<axis xyz="([^"]*)"', text))
        start, end = axes[draw(st.integers(0, len(axes) - 1))].span(1)
        text = text[:start] + draw(st.sampled_from(AXES)) + text[end:]
    return text


@pytest.mark.slow
@given(robot_files())
def test_fuzz_robot_files(text):
    """The promise, and more: a file hdselect reads gives MuJoCo's torques (its own reading)."""
    with workdir() as work:
        Path("fuzz.urdf").write_text(text)
        status = check_run(work, ["size", "fuzz.urdf", "tr/planar2_pick_place.toml", "--json",
                                  "-", "--max-samples", MAX_SAMPLES], stdout_json=True)
        if status != 2:
            robot = hdselect.load_robot("fuzz.urdf")
            worst, scale = mujoco_oracle.compare(robot, 2)
            assert worst <= 1e-9 * max(scale, 1e-12), (worst, scale)


# --- motor files --------------------------------------------------------------------------------

MOTOR_SAMPLES = "4000"
"""Motor pairs multiply the candidates: these runs are bounded tighter."""


@st.composite
def motor_entries(draw, header: str) -> list[tuple[str, object]]:
    """One motor's keys under `header` (``[[motor]]``, or ``[motor]`` inline in a motion)."""
    rated = draw(st.floats(0.005, 0.5))
    top = draw(st.floats(2000, 9000))
    entries: list[tuple[str, object]] = [
        (header, None),
        ("rated_torque_nm", rated),
        ("peak_torque_nm", rated * draw(st.floats(1.0, 4.0))),
        ("max_speed_rpm", top),
        ("rated_speed_rpm", top * draw(st.floats(0.3, 1.0))),
        (draw(st.sampled_from(["rotor_inertia_kg_cm2", "rotor_inertia_kg_m2"])),
         draw(st.floats(0.0, 0.05))),
        ("mass_kg", draw(st.floats(0.0, 1.5))),
    ]
    if draw(st.booleans()):
        entries += [("torque_constant_nm_per_a", draw(st.floats(0.01, 0.5))),
                    ("resistance_ohm", draw(st.floats(0.1, 30)))]
    if header == "[[motor]]":
        entries.insert(1, ("id", draw(st.sampled_from(["M1", "M2", "M3", "M1"]))))
    return entries


@st.composite
def motor_files(draw) -> str:
    entries: list[tuple[str, object]] = [("source", "fuzz")]
    for _ in range(draw(st.integers(1, 3))):
        entries += draw(motor_entries("[[motor]]"))
        if draw(st.integers(0, 2)) == 0:  # a torque-speed curve
            top = dict(entries)["max_speed_rpm"]
            entries += [("[motor.curve]", None),
                        ("speed_rpm", [0, draw(st.floats(0, 1)) * top, top * 1.01]),
                        ("peak_torque_nm", [draw(st.floats(0, 1)) for _ in range(3)])]
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@given(motor_files())
def test_fuzz_motor_files(text):
    with workdir() as work:
        Path("motors.toml").write_text(text)
        check_run(work, ["size", "tr/planar2_pick_place.toml", "--motor-catalog", "motors.toml",
                         "--json", "-", "--max-samples", MOTOR_SAMPLES], stdout_json=True)


@st.composite
def motor_tables(draw) -> str:
    """A ``[motor]`` table (every rotary joint) or ``[motor.shoulder]`` (one joint)."""
    entries = draw(motor_entries("[motor]"))
    if draw(st.booleans()):
        entries[0] = ("[motor.shoulder]", None)
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@given(motor_tables())
def test_fuzz_motor_tables_in_motion_files(table):
    with workdir() as work:
        base = Path("tr/planar2_pick_place.toml").read_text()
        Path("tr/fuzz.toml").write_text(base + "\n" + table)
        check_run(work, ["size", "tr/fuzz.toml", "--json", "-", "--max-samples",
                         MOTOR_SAMPLES], stdout_json=True)


# --- study files --------------------------------------------------------------------------------

STUDY_EXAMPLES = 25 if os.environ.get("HDSELECT_FUZZ", "ci") == "ci" else 300
"""Each study case is a whole sizing run: fewer examples than the other targets."""


@st.composite
def study_files(draw) -> str:
    entries: list[tuple[str, object]] = [
        ("title", draw(st.sampled_from(["fuzz", "a study"]))),
        ("compute", draw(st.sampled_from(["size", ["size"]]))),
        ("[base]", None),
        ("motion", draw(st.sampled_from(["tr/planar2_pick_place.toml",
                                         "tr/pan_tilt_logged.toml", "tr/missing.toml"]))),
        ("stop_time", draw(st.floats(0.01, 0.5))),
        ("max_samples", int(MAX_SAMPLES)),
    ]
    if draw(st.booleans()):
        entries.append(("payload", draw(st.one_of(
            st.floats(0.01, 2.0),
            st.fixed_dictionaries({"mass": st.floats(0.01, 2.0),
                                   "com": st.lists(st.floats(-0.1, 0.1), min_size=3,
                                                   max_size=3)})))))
    grid: list[tuple[str, object]] = [("[grid]", None)]
    for key, values in draw(st.lists(st.sampled_from([
            ("time_scale", st.floats(0.5, 3.0)), ("ratio", st.sampled_from([50, 80, 100])),
            ("efficiency", st.floats(0.3, 1.0)), ("mounting", st.sampled_from(
                ["floor", "wall", "ceiling"])), ("life_hours", st.floats(100, 1e5))]),
            max_size=2, unique_by=lambda pair: pair[0])):
        grid.append((key, draw(st.lists(values, min_size=1, max_size=2))))
    entries += grid if len(grid) > 1 else []
    if draw(st.integers(0, 3)) == 0:
        entries += [("[[case]]", None), ("motor_catalog", draw(st.sampled_from(
            ["motors/example_motors.toml", "nowhere.toml"])))]
    return toml_text(draw(shuffled_entries(entries)))


@pytest.mark.slow
@settings(max_examples=STUDY_EXAMPLES)
@given(study_files(), st.sampled_from(["out.csv", "out.csv", os.devnull, "-", "existing_dir",
                                       "none/out.csv", "study.toml", "link.csv"]))
def test_fuzz_study_files(text, out):
    with workdir() as work:
        Path("study.toml").write_text(text)
        if out == "link.csv":  # a symlink: followed, the rows land in its target
            Path("link.csv").symlink_to("target.csv")
        status = check_run(work, ["study", "study.toml", "--out", out, "--workers", "0"],
                           statuses=(0, 2, 3),
                           jsonl_files=("out.jsonl",) if out == "out.csv" else ())
        if status != 2:
            real = Path("target.csv" if out == "link.csv" else out)
            assert real.is_file() and real.with_suffix(".jsonl").is_file()
            assert not Path(out).is_symlink() or out == "link.csv" and Path(out).is_symlink()


# --- command lines ------------------------------------------------------------------------------

OPTIONS = {  # option -> how many values it takes
    "--payload": 1, "--payload-com": 3, "--payload-frame": 1, "--mounting": 1,
    "--stop-time": 1, "--efficiency": 1, "--motor-inertia": 1, "--motor-mass": 1,
    "--life-hours": 1, "--life-basis": 1, "--prefer": 1, "--max-samples": 1,
    "--joints": 1, "--exclude": 1, "--motor-catalog": 1, "--max-torsion": 1,
    "--min-natural-frequency": 1, "--max-tool-deflection": 1, "--min-arm-frequency": 1,
    "--base": 1,
}


@st.composite
def command_lines(draw) -> tuple[list[str], tuple[str, ...]]:
    command = draw(st.sampled_from(["size", "size", "compare", "plan", "duty", "catalog",
                                    "joints", "init"]))
    if command in ("joints", "init"):
        robot = draw(st.sampled_from(["robots/planar2.urdf", "robots/pan_tilt.urdf",
                                      "tr/planar2_pick_place.toml", "none.urdf"]))
        path = draw(output_path)
        option = "--json" if command == "joints" else "--out"
        return [command, robot, *([option, path] if draw(st.booleans()) else [])], (
            (path,) if command == "joints" else ()), ()
    if command == "catalog":
        return ["catalog", *draw(st.sampled_from([[], ["--json"], ["--units", "imperial"],
                                                  ["--units", "si"]]))], (), ()
    if command == "duty":
        path = draw(output_path)
        return ["duty", "tr/duty/conveyor_index.toml", "--json", path], (path,), ()
    motion = draw(st.sampled_from(["tr/planar2_pick_place.toml", "tr/index_table_indexing.toml",
                                   "tr/pan_tilt_logged.toml"]))
    argv = [command, motion]
    written: tuple[str, ...] = ()
    csv: tuple[str, ...] = ()
    if command == "plan":
        out = draw(output_path)
        argv += ["--out", out]
        csv = (out,) if out in ("-", "out.csv") else ()
        if draw(st.booleans()):
            argv += ["--plot", draw(st.sampled_from(["-", "fig.png", "/proc/x.png"]))]
    for option in draw(st.lists(st.sampled_from(list(OPTIONS)), max_size=4, unique=True)):
        if command == "plan" and option not in ("--payload", "--payload-com", "--payload-frame",
                                                "--mounting", "--max-samples", "--joints",
                                                "--exclude", "--motor-catalog", "--motor-mass",
                                                "--base"):
            continue
        if option == "--payload-frame":
            values = [draw(st.sampled_from(["tool", "link1", "base_link", "nowhere", ""]))]
        elif option in ("--joints", "--exclude"):
            values = [draw(st.sampled_from(["shoulder", "elbow", "shoulder,elbow", "pan", ",",
                                            "nope", "tilt,pan", ""]))]
        elif option == "--motor-catalog":
            values = [draw(st.sampled_from(["motors/example_motors.toml", "none.toml",
                                            "tr/planar2_pick_place.toml", "existing_dir"]))]
        elif option == "--mounting":
            values = [draw(st.sampled_from(["floor", "wall", "ceiling", "roof", "nan"]))]
        elif option == "--base":  # --base=: a first number below 0 is no option
            argv.append("--base=" + draw(st.sampled_from(
                ["0,0,0.5,180,0,0", "-0.1,0.2,0,10,-20,30", "nan,0,0,0,0,0", "1e308,0,0,0,0,0",
                 "0,0,0,0,0", "a,b,c,d,e,f", "0,0,0,0,0,inf", ""])))
            continue
        elif option == "--life-basis":
            values = [draw(st.sampled_from(["L10", "L50", "L90"]))]
        elif option == "--prefer":
            values = [draw(st.sampled_from(["size", "margin", "motor-rms", "cheapest"]))]
        elif option in ("--max-torsion", "--min-natural-frequency", "--min-arm-frequency"):
            values = [draw(st.sampled_from(["2", "shoulder=1.5", "table=hand-axes", "nope=2",
                                            "=3", "hand-axes", "nan", "-1", "1e308", "",
                                            "elbow=", "pan=scara", "0"]))]
        else:
            values = [draw(option_value) for _ in range(OPTIONS[option])]
        argv += [option, *values]
    if command == "plan" and draw(st.booleans()):  # the units' masses in the torques
        argv += [*draw(st.sampled_from([[], ["--no-mass-coupling"]])), "--units",
                 draw(st.sampled_from(["shoulder=PSA-14-100", "table=PSA-14-50", "pan=PSA-08-80",
                                       "shoulder=", "elbow=PSA-99", "=PSA-14-100", "nope"]))]
    if command in ("size", "compare") and draw(st.booleans()):
        path = draw(output_path)
        argv += ["--json", path]
        written = (path,)
    if command in ("size", "compare") and draw(st.integers(0, 3)) == 0:
        argv += ["--report", draw(st.sampled_from(["-", "report", "existing_dir", os.devnull,
                                                   "tr/planar2_pick_place.toml"]))]
    if "--max-samples" not in argv:
        argv += ["--max-samples", MAX_SAMPLES]
    return argv, written, csv


@pytest.mark.slow
@given(command_lines())
def test_fuzz_command_lines(case):
    argv, written, csv = case
    stdout_json = argv[:2] == ["catalog", "--json"] or (
        "--json" in argv and argv[argv.index("--json") + 1] == "-")
    with workdir() as work:
        check_run(work, argv, stdout_json=stdout_json,
                  json_files=tuple(p for p in written if p.endswith(".json")), csv_files=csv)
