"""The ``size``, ``compare`` and ``plan`` commands, in-process: output, exit status, errors.

Exit status: 0 every joint has a unit, 1 some joint has none (the table and JSON are
still printed), 2 bad input: one line on stderr, no traceback, no file left behind.
"""

from __future__ import annotations

import base64
import csv
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from hdselect.catalog.motors import load_motors
from hdselect.cli.main import main
from hdselect.motion.loading import load_case
from helpers import REPO, run
from helpers.dynamics import (
    J_TABLE,
    L1,
    L2,
    G,
    composite_link2,
    part_rows,
    planned,
    two_link,
)
from helpers.motions import PLANAR2, gravity_overload_motion, overload_motion, slow_planar2_motion

PLANAR2_MOTION = REPO / "trajectories" / "planar2_pick_place.toml"
INDEX = REPO / "trajectories" / "index_table_indexing.toml"
BENCHTOP6 = REPO / "trajectories" / "benchtop6_pick_place.toml"
SCARA = REPO / "trajectories" / "scara_wafer_transfer.toml"


def assert_one_line_error(err: str, *fragments: str):
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert re.match(r"hdselect( [a-z-]+)?: error: ", lines[0]), err  # argparse: its command
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


def files_in(directory: Path) -> set[str]:
    return {str(p.relative_to(directory)) for p in directory.rglob("*")}


# --- size ------------------------------------------------------------------------------------

@pytest.mark.parametrize("motion, joints", [
    (PLANAR2_MOTION, ["shoulder", "elbow"]),
    (SCARA, ["shoulder", "elbow", "wrist"]),
    (INDEX, ["table"]),
])
def test_size_prints_every_joint_and_exits_0(capsys, motion, joints):
    status, out, err = run(capsys, "size", motion)
    assert status == 0, err
    assert err == ""
    sizing, loads = out.split("Every joint over the cycle")
    rows = {line.split()[0] for line in sizing.splitlines() if line.strip()}
    for joint in joints:
        assert joint in rows
    assert "PSA-" in out
    assert "lift" not in rows  # prismatic: reported by the model, never sized
    load_rows = {cells[0]: cells[1:3] for cells in map(str.split, loads.splitlines())
                 if len(cells) > 2 and cells[0] in (*joints, "lift")
                 and cells[1] in ("revolute", "continuous", "prismatic")}
    assert load_rows == {**{j: [load_rows[j][0], "yes"] for j in joints},
                         **({"lift": ["prismatic", "no"]} if "lift" in load_rows else {})}
    assert ("lift" in load_rows) == (motion == SCARA)
    if motion == SCARA:
        assert "lift: not sized: the catalog is rotary" in loads


def test_size_json_to_stdout_parses(capsys):
    status, out, _ = run(capsys, "size", PLANAR2_MOTION, "--json", "-")
    assert status == 0
    document = json.loads(out)  # nothing but the JSON document on stdout
    assert [j["name"] for j in document["joints"]] == ["shoulder", "elbow"]
    assert document["motion"] == str(PLANAR2_MOTION)
    assert all(j["selected"] for j in document["joints"])


def test_size_json_to_a_file_and_the_table(capsys, tmp_path):
    target = tmp_path / "result.json"
    status, out, _ = run(capsys, "size", REPO / "robots" / "planar2.urdf", PLANAR2_MOTION,
                         "--json", target)
    assert status == 0
    assert "shoulder" in out and "elbow" in out
    document = json.loads(target.read_text())
    assert document["robot"] == str(REPO / "robots" / "planar2.urdf")
    assert files_in(tmp_path) == {"result.json"}  # no temporary file left beside it


def test_size_options_reach_the_result(capsys):
    status, out, _ = run(capsys, "size", PLANAR2_MOTION, "--json", "-", "--stop-time", "0.3",
                         "--efficiency", "0.8", "--no-mass-coupling", "--motor-mass", "0.1")
    assert status == 0
    assumptions = json.loads(out)["assumptions"]
    assert assumptions["stop_time_s"] == 0.3 and assumptions["efficiency"] == 0.8
    assert assumptions["mass_coupling"] is False and assumptions["motor_mass_kg"] == 0.1


def test_overloaded_motion_exits_1_with_table_and_json(capsys, tmp_path):
    motion = overload_motion(tmp_path, payload=2.5, velocity=300, acceleration=3000,
                             jerk=60000, stop_time=0.5)
    status, out, err = run(capsys, "size", motion)
    assert status == 1
    assert err == ""
    assert "shoulder" in out and "none" in out and "slower" in out
    status, out, err = run(capsys, "size", motion, "--json", "-")
    assert status == 1 and err == ""
    document = json.loads(out)
    shoulder = document["joints"][0]
    assert shoulder["selected"] is None
    assert shoulder["slowdown"]["factor"] > 1.0
    assert not any(c["feasible"] for c in shoulder["candidates"])


def test_gravity_overload_says_no_slowdown_helps(capsys, tmp_path):
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    status, out, _ = run(capsys, "size", motion)
    assert status == 1
    assert "no slow-down or lower speed/acceleration limit helps" in " ".join(out.split())


# --- compare ---------------------------------------------------------------------------------

def test_compare_one_joint(capsys):
    status, out, err = run(capsys, "compare", PLANAR2_MOTION, "--joint", "elbow")
    assert status == 0, err
    assert "Joint elbow" in out and "Joint shoulder" not in out
    for unit in ("PSA-08-80", "PSA-10-50", "PSA-14-100"):
        assert unit in out


@pytest.mark.slow
def test_compare_every_joint_by_default(capsys):
    status, out, _ = run(capsys, "compare", PLANAR2_MOTION)
    assert status == 0
    assert "Joint elbow" in out and "Joint shoulder" in out


# --- bad input: exit 2, one line --------------------------------------------------------------

def test_unknown_joint_names_the_valid_ones(capsys):
    status, out, err = run(capsys, "compare", PLANAR2_MOTION, "--joint", "elbo")
    assert status == 2
    assert out == ""
    assert_one_line_error(err, "elbo", "shoulder", "elbow", "--joint")


@pytest.mark.parametrize("value", ["-0.1", "0", "nan"])
def test_bad_stop_time(capsys, value):
    status, out, err = run(capsys, "size", PLANAR2_MOTION, f"--stop-time={value}")
    assert status == 2
    assert out == ""
    assert_one_line_error(err, "--stop-time")


@pytest.mark.parametrize("option, value", [("--efficiency", "1.5"), ("--efficiency", "0"),
                                           ("--motor-mass", "-1"), ("--motor-inertia", "-1e-6")])
def test_bad_sizing_options(capsys, option, value):
    status, _, err = run(capsys, "size", PLANAR2_MOTION, f"{option}={value}")
    assert status == 2
    assert_one_line_error(err, option)


BAD_CATALOG = """\
series = "BAD"
[[unit]]
size = 14
ratio = 100
rated_torque_nm = 12.0
repeated_torque_nm = 10.0
max_input_speed_rpm = 6000
input_inertia_kg_cm2 = 0.03
mass_kg = 0.5
"""


def test_user_catalog_that_fails_validation(capsys, tmp_path):
    catalog = tmp_path / "bad.toml"
    catalog.write_text(BAD_CATALOG)  # repeated-peak limit below the rated torque
    status, out, err = run(capsys, "size", PLANAR2_MOTION, "--catalog", catalog)
    assert status == 2
    assert out == ""
    assert_one_line_error(err, str(catalog), "repeated")


def test_user_catalog_missing_file(capsys, tmp_path):
    status, _, err = run(capsys, "compare", PLANAR2_MOTION, "--catalog", tmp_path / "no.toml")
    assert status == 2
    assert_one_line_error(err, "no.toml")


def test_user_catalog_units_are_sized(capsys, tmp_path):
    catalog = tmp_path / "good.toml"
    catalog.write_text(BAD_CATALOG.replace("12.0", "9.0").replace('"BAD"', '"XYZ"'))
    status, out, _ = run(capsys, "size", PLANAR2_MOTION, "--catalog", catalog, "--json", "-")
    assert status == 0
    units = [c["unit"] for c in json.loads(out)["joints"][0]["candidates"]]
    assert "XYZ-14-100" in units and "PSA-14-100" in units


# --- plan: the CSV -----------------------------------------------------------------------------

def read_csv(path: Path):
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    return rows[0], np.array(rows[1:], dtype=float)


def test_plan_csv_header_rows_and_torques_by_hand(capsys, tmp_path):
    """The index table's torque column is J qdd of its own qdd column."""
    out_file = tmp_path / "index.csv"
    status, _, err = run(capsys, "plan", INDEX, "--out", out_file)
    assert status == 0, err
    header, data = read_csv(out_file)
    assert header == ["t", "q_table", "qd_table", "qdd_table", "tau_table"]
    # one row per sample: t_k = k dt up to the cycle time (4 moves and 4 dwells)
    dt = 0.001
    np.testing.assert_allclose(data[:, 0], np.arange(len(data)) * dt, atol=1e-9)
    assert data[-1, 0] >= 4 * 0.6
    np.testing.assert_allclose(data[:, 4], J_TABLE * data[:, 3], rtol=1e-8, atol=1e-9)
    assert data[0, 1] == 0.0 and data[-1, 1] == pytest.approx(2 * math.pi, rel=1e-9)
    assert files_in(tmp_path) == {"index.csv"}


def test_plan_csv_two_link_closed_form(capsys, tmp_path):
    out_file = tmp_path / "planar2.csv"
    status, _, _ = run(capsys, "plan", PLANAR2_MOTION, "--out", out_file)
    assert status == 0
    header, data = read_csv(out_file)
    assert header == ["t", "q_shoulder", "qd_shoulder", "qdd_shoulder", "tau_shoulder",
                      "q_elbow", "qd_elbow", "qdd_elbow", "tau_elbow"]
    q, qd, qdd, tau = (data[:, [1 + k, 5 + k]] for k in range(4))
    # the motion's 0.15 kg gripper, and its 0.25 kg part between the pick and the place
    _, motion, trajectory = planned(PLANAR2_MOTION)
    rides = part_rows(motion, trajectory)
    assert len(rides) == len(tau) and rides.any() and not rides.all()
    for rows, mass in ((~rides, 0.15), (rides, 0.4)):
        m2, lc2, i2 = composite_link2(mass, L2 + 0.03)
        # CSV values have 10 significant digits
        np.testing.assert_allclose(tau[rows], two_link(q[rows], qd[rows], qdd[rows], m2=m2,
                                                       lc2=lc2, i2=i2), rtol=0, atol=1e-7)


def test_plan_csv_lists_every_joint_the_prismatic_one_in_newtons(capsys, tmp_path):
    out_file = tmp_path / "scara.csv"
    assert run(capsys, "plan", SCARA, "--out", out_file)[0] == 0
    header, data = read_csv(out_file)
    assert header == ["t"] + [f"{kind}_{joint}" for joint in ("shoulder", "elbow", "lift", "wrist")
                              for kind in ("q", "qd", "qdd", "tau")]
    robot, _ = load_case(SCARA)
    lift = robot.joint_index("lift")
    # the lift holds the quill, end effector and wafer against gravity: m g, in N
    held = sum(robot.model.inertias[j].mass for j in range(lift + 1, robot.model.njoints))
    at_rest = (data[:, header.index("qd_lift")] == 0) & (data[:, header.index("qdd_lift")] == 0)
    np.testing.assert_allclose(data[at_rest, header.index("tau_lift")], held * 9.80665,
                               rtol=1e-6)


MOTOR_FILE = REPO / "motors" / "example_motors.toml"


@pytest.mark.slow
@pytest.mark.parametrize("motors", [(), ("--motor-catalog", MOTOR_FILE)])
def test_plan_with_units_writes_the_torques_size_computes(capsys, tmp_path, motors):
    """Issue 27: plan --units carries the units' (and motors') masses, as size does."""
    from hdselect import size

    result = size(None, BENCHTOP6, motors=None if not motors else {
        name: load_motors(MOTOR_FILE) for name in load_case(BENCHTOP6)[0].sized_joints})
    chosen = {j.name: j.selected.unit.id for j in result.joints}
    pairs = [f"{name}={unit}" for name, unit in chosen.items()]
    status, out, err = run(capsys, "plan", BENCHTOP6, "--out", tmp_path / "u.csv",
                           *[a for pair in pairs for a in ("--units", pair)], *motors)
    assert status == 0, err
    assert "as size computes it" in out and f"shoulder_lift {chosen['shoulder_lift']}" in out
    header, data = read_csv(tmp_path / "u.csv")
    np.testing.assert_allclose(data[:, 0], result.trajectory.t, rtol=0, atol=1e-9)
    for joint in result.joints:
        np.testing.assert_allclose(data[:, header.index(f"tau_{joint.name}")], joint.torque,
                                   rtol=1e-9, atol=1e-9)
    # without units: the robot alone, a smaller holding torque at the shoulder
    status, out, _ = run(capsys, "plan", BENCHTOP6, "--out", tmp_path / "bare.csv")
    assert status == 0 and "without gearhead or motor masses" in out
    bare_header, bare = read_csv(tmp_path / "bare.csv")
    lift = result.joints[[j.name for j in result.joints].index("shoulder_lift")]
    bare_lift = np.abs(bare[:, bare_header.index("tau_shoulder_lift")]).max()
    assert bare_lift < np.abs(lift.torque).max() - 1.0
    if motors:  # --motor-catalog alone: the units and motors size selects
        status, _, err = run(capsys, "plan", BENCHTOP6, "--out", tmp_path / "m.csv", *motors)
        assert status == 0, err
        header, data = read_csv(tmp_path / "m.csv")
        for joint in result.joints:
            np.testing.assert_allclose(data[:, header.index(f"tau_{joint.name}")],
                                       joint.torque, rtol=1e-9, atol=1e-9)


@pytest.mark.slow
def test_plan_with_units_but_no_mass_coupling_is_the_robot_alone(capsys, tmp_path):
    run(capsys, "plan", PLANAR2_MOTION, "--out", tmp_path / "bare.csv")
    status, out, err = run(capsys, "plan", PLANAR2_MOTION, "--out", tmp_path / "off.csv",
                           "--units", "shoulder=PSA-14-100", "--no-mass-coupling")
    assert status == 0, err
    assert "--no-mass-coupling" in out
    np.testing.assert_array_equal(read_csv(tmp_path / "off.csv")[1],
                                  read_csv(tmp_path / "bare.csv")[1])


@pytest.mark.slow
def test_plan_units_of_a_catalog_file_carry_their_mass(capsys, tmp_path):
    """A heavier elbow unit from --catalog: the shoulder carries m g r more (the elbow's
    unit sits on the elbow's axis, so its weight acts at the shoulder's link length)."""
    catalog = tmp_path / "heavy.toml"
    catalog.write_text('series = "HVY"\n[[unit]]\nsize = 20\nratio = 100\n'
                       "rated_torque_nm = 40\nrepeated_torque_nm = 50\n"
                       "max_input_speed_rpm = 4000\ninput_inertia_kg_cm2 = 0.2\n"
                       "mass_kg = 2.5\n")
    tau, q = {}, None
    for unit, extra in (("PSA-08-100", ()), ("HVY-20-100", ("--catalog", catalog))):
        out_file = tmp_path / f"{unit}.csv"
        status, _, err = run(capsys, "plan", PLANAR2_MOTION, "--out", out_file, "--units",
                             "shoulder=PSA-14-100", "--units", f"elbow={unit}", *extra)
        assert status == 0, err
        header, data = read_csv(out_file)
        tau[unit] = data[:, header.index("tau_shoulder")]
        rest = np.all(data[:, [header.index(f"{k}_{j}") for k in ("qd", "qdd")
                               for j in ("shoulder", "elbow")]] == 0, axis=1)
        q = data[:, header.index("q_shoulder")]
    status, _, err = run(capsys, "plan", PLANAR2_MOTION, "--out", tmp_path / "x.csv",
                         "--units", "elbow=HVY-20-100")
    assert status == 2 and "unknown unit 'HVY-20-100'" in err
    # at rest, by hand: 2.2 kg more (2.5 kg against the catalog's 0.3 kg) at L1 from the axis
    np.testing.assert_allclose((tau["HVY-20-100"] - tau["PSA-08-100"])[rest],
                               (2.5 - 0.3) * G * L1 * np.cos(q[rest]), rtol=1e-8, atol=1e-8)
    assert rest.sum() > 100


@pytest.mark.parametrize(("argv", "says"), [
    (("--motor-mass", "1"), ("--motor-mass", "only with --units")),
    (("--no-mass-coupling",), ("--no-mass-coupling", "only with --units")),
    (("--units", "shoulder=PSA-99"), ("--units", "unknown unit 'PSA-99'")),
    (("--units", "wrist=PSA-14-100"), ("--units", "wrist")),
    (("--units", "shoulder"), ("--units", "JOINT=UNIT")),
])
def test_plan_refuses_bad_units_in_one_line(capsys, tmp_path, argv, says):
    status, _, err = run(capsys, "plan", PLANAR2_MOTION, "--out", tmp_path / "x.csv", *argv)
    assert status == 2
    assert_one_line_error(err, *says)
    assert files_in(tmp_path) == set()


def test_failing_plan_leaves_no_csv(capsys, tmp_path):
    motion = slow_planar2_motion(tmp_path / "outside.toml", (0, 0), (150, 0))
    out_file = tmp_path / "never.csv"
    status, out, err = run(capsys, "plan", motion, "--out", out_file)
    assert status == 2
    assert_one_line_error(err, "outside.toml", "waypoint[1]", "shoulder")
    assert files_in(tmp_path) == {"outside.toml"}


def test_plan_into_a_missing_directory_is_one_line(capsys, tmp_path):
    status, _, err = run(capsys, "plan", INDEX, "--out", tmp_path / "no" / "such" / "x.csv")
    assert status == 2
    assert_one_line_error(err, "x.csv")
    assert files_in(tmp_path) == set()


# --- size --report -----------------------------------------------------------------------------

@pytest.mark.slow
def test_report_writes_html_and_pngs(capsys, tmp_path):
    pytest.importorskip("hdselect.report.figures")
    report = tmp_path / "report"
    status, out, err = run(capsys, "size", PLANAR2_MOTION, "--report", report)
    assert status == 0, err
    names = files_in(report)
    assert "index.html" in names
    pngs = sorted(n for n in names if n.endswith(".png"))
    assert len(pngs) >= 2  # at least one figure per joint
    for name in pngs:
        assert (report / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    page = (report / "index.html").read_text()
    embedded = [base64.b64decode(data) for data in
                re.findall(r"src='data:image/png;base64,([A-Za-z0-9+/=]+)'", page)]
    # self-contained: every figure is in the page, the same as the file beside it
    assert sorted(embedded) == sorted((report / name).read_bytes() for name in pngs)
    targets = re.findall(r"""(?:src|href)=["']([^"']*)""", page)
    assert targets and all(t.startswith(("data:image/png;base64,", "#")) for t in targets)
    assert "shoulder" in page and "elbow" in page
    assert "base: &#x27;base_link&#x27; held fixed; payload: 0.15 kg on" in page  # the gripper
    assert files_in(tmp_path) == {"report"} | {f"report/{n}" for n in names}
    assert f"wrote {report / 'index.html'}" in " ".join(out.split())  # may wrap


def test_report_dir_that_cannot_be_written(capsys, tmp_path):
    pytest.importorskip("hdselect.report.figures")
    blocker = tmp_path / "file.txt"
    blocker.write_text("a regular file")
    target = blocker / "report"
    json_out = tmp_path / "result.json"
    status, out, err = run(capsys, "size", PLANAR2_MOTION, "--report", target, "--json",
                           json_out)
    assert status == 2
    assert out == ""
    assert_one_line_error(err, "report")
    assert files_in(tmp_path) == {"file.txt"}  # no report, no JSON, no temporary files
    assert blocker.read_text() == "a regular file"


def test_report_onto_an_existing_file(capsys, tmp_path):
    pytest.importorskip("hdselect.report.figures")
    target = tmp_path / "report.html"
    target.write_text("keep me")
    status, _, err = run(capsys, "size", PLANAR2_MOTION, "--report", target)
    assert status == 2
    assert_one_line_error(err, "report.html")
    assert target.read_text() == "keep me" and files_in(tmp_path) == {"report.html"}


@pytest.mark.parametrize(("command", "given", "message"), [
    ("size", "--joint", "--joint elbow; size takes no --joint; did you mean --joints? (see "
                        "hdselect size --help)"),
    ("compare", "--payloda", "--payloda elbow; did you mean --payload? (see hdselect compare "
                             "--help)"),
    ("plan", "--xyz", "--xyz elbow (see hdselect plan --help)"),
])
def test_an_unknown_or_shortened_option_is_refused_by_its_command(capsys, command, given,
                                                                 message):
    """Never read as an abbreviation (size --joint J sized J alone, as --joints J)."""
    with pytest.raises(SystemExit) as exit:
        main([command, str(PLANAR2_MOTION), given, "elbow",
              *(["--out", "x.csv"] if command == "plan" else [])])
    assert exit.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == f"hdselect {command}: error: unrecognized arguments: {message}\n"


@pytest.mark.parametrize("command", ["size", "compare", "plan"])
def test_bad_files_are_one_line_errors(capsys, tmp_path, command):
    broken = tmp_path / "broken.toml"
    broken.write_text("planner = [\n")
    extra = ["--out", str(tmp_path / "x.csv")] if command == "plan" else []
    cases = [
        ([tmp_path / "missing.toml"], "missing.toml"),
        ([broken], "broken.toml"),
        ([PLANAR2, PLANAR2_MOTION, PLANAR2_MOTION], "unrecognized arguments"),
        ([tmp_path / "missing.urdf", PLANAR2_MOTION], "missing.urdf"),
    ]
    for files, fragment in cases:
        try:
            status, out, err = run(capsys, command, *files, *extra)
        except SystemExit as exit:  # argparse's own errors exit from inside main()
            status, (out, err) = exit.code, capsys.readouterr()
        assert status == 2, (files, err)
        assert out == ""
        assert_one_line_error(err, fragment)
    assert files_in(tmp_path) == {"broken.toml"}


@pytest.mark.parametrize("option", ["--out", "--plot"])
def test_plan_never_writes_over_its_inputs(capsys, tmp_path, option):
    motion = tmp_path / "m.toml"
    text = (REPO / "trajectories" / "planar2_pick_place.toml").read_text()
    motion.write_text(text.replace('"../robots/planar2.urdf"', repr(str(PLANAR2))))
    outputs = {"--out": tmp_path / "x.csv", "--plot": tmp_path / "x.png", option: motion}
    code, out, err = run(capsys, "plan", motion, "--out", outputs["--out"],
                         "--plot", outputs["--plot"])
    assert code == 2
    assert_one_line_error(err, "m.toml", "input file")
    assert motion.read_text() == text.replace('"../robots/planar2.urdf"', repr(str(PLANAR2)))


def test_size_json_never_writes_over_the_robot(capsys):
    code, out, err = run(capsys, "size", str(REPO / "trajectories" / "planar2_pick_place.toml"),
                         "--json", str(PLANAR2))
    assert code == 2
    assert_one_line_error(err, "planar2.urdf", "input file")
    assert PLANAR2.read_text().startswith("<?xml")


def test_payload_frame_missing_from_the_robot_names_the_motion_file(capsys, tmp_path):
    """A planar2 motion carrying its payload on `tool0`, a link planar2 does not have."""
    text = PLANAR2_MOTION.read_text().replace('robot = "../robots/planar2.urdf"', "")
    motion = tmp_path / "tool0.toml"
    motion.write_text(text.replace('frame = "tool"', 'frame = "tool0"'))
    code, out, err = run(capsys, "size", PLANAR2, motion)
    assert code == 2 and out == ""
    assert_one_line_error(err, "tool0.toml", "payload.frame", "tool0",
                          "links are: base_link, link1, link2, tool")


@pytest.mark.slow
def test_joints_and_exclude_options_choose_the_sized_joints(capsys, tmp_path):
    report = tmp_path / "r.json"
    status, out, err = run(capsys, "size", BENCHTOP6, "--exclude", "wrist_1,wrist_3",
                           "--json", report)
    assert status == 0, err
    document = json.loads(report.read_text())
    assert [j["name"] for j in document["joints"]] == ["shoulder_pan", "shoulder_lift", "elbow",
                                                       "wrist_2"]
    assert "wrist_1: not sized: excluded" in out
    status, out, err = run(capsys, "size", BENCHTOP6, "--joints", "elbow", "--joints",
                           "wrist_2", "--json", report)
    assert [j["name"] for j in json.loads(report.read_text())["joints"]] == ["elbow", "wrist_2"]
    assert "wrist_1: not sized: not among the joints asked for" in out  # not "excluded"
    assert "The dynamics include them." in " ".join(out.split())


@pytest.mark.parametrize(("args", "text"), [
    (["--joints", "elbo"], "--joints: unknown joint 'elbo'; joints are: shoulder_pan"),
    (["--exclude", "shoulder_pan,shoulder_lift,elbow,wrist_1,wrist_2,wrist_3"],
     "--exclude: no joint left to size"),
])
def test_bad_joint_options_are_one_line(capsys, args, text):
    status, out, err = run(capsys, "size", BENCHTOP6, *args)
    assert status == 2 and out == "" and err.count("\n") == 1
    assert text in err


# --- what the commands say, compare's outputs, -v anywhere -------------------------------------

@pytest.mark.slow
def test_plan_says_what_it_planned_and_wrote(capsys, tmp_path):
    out_file, plot = tmp_path / "scara.csv", tmp_path / "scara.png"
    status, out, err = run(capsys, "plan", SCARA, "--out", out_file, "--plot", plot)
    assert status == 0 and err == ""
    text = " ".join(out.split())
    assert "not sized: lift (prismatic" in text
    assert (f"wrote {out_file}: t, then q_, qd_, qdd_, tau_ of shoulder, elbow, lift, wrist "
            "(SI); tau_ without gearhead or motor masses (--units adds them)") in text
    assert f"wrote {plot}" in text


def test_compare_json_is_the_size_document_for_the_joints_shown(capsys):
    status, out, err = run(capsys, "compare", PLANAR2_MOTION, "--joint", "elbow", "--json", "-")
    assert status == 0 and err == ""
    shown = json.loads(out)
    status, out, _ = run(capsys, "size", PLANAR2_MOTION, "--json", "-")
    whole = json.loads(out)
    assert set(shown) == set(whole)
    assert [j["name"] for j in shown["joints"]] == ["elbow"]
    assert shown["joints"][0] == next(j for j in whole["joints"] if j["name"] == "elbow")


@pytest.mark.slow
def test_compare_report_has_the_joints_shown(capsys, tmp_path):
    status, out, err = run(capsys, "compare", PLANAR2_MOTION, "--joint", "shoulder", "--report",
                           tmp_path / "r", "--json", tmp_path / "r.json")
    assert status == 0, err
    assert files_in(tmp_path / "r") == {"index.html", "joint_shoulder.png",
                                        "bearing_shoulder.png"}
    page = (tmp_path / "r" / "index.html").read_text()
    assert "id='joint-shoulder'" in page and "id='joint-elbow'" not in page
    text = " ".join(out.split())
    assert "Joint shoulder" in text and f"wrote {tmp_path / 'r.json'}" in text


@pytest.mark.slow
def test_written_files_go_to_stderr_when_stdout_is_json(capsys, tmp_path):
    status, out, err = run(capsys, "size", PLANAR2_MOTION, "--json", "-", "--report",
                           tmp_path / "r")
    assert status == 0
    json.loads(out)
    assert "wrote" in err and "index.html" in " ".join(err.split())


@pytest.mark.parametrize("where", ["before", "after"])
def test_verbose_goes_anywhere(capsys, tmp_path, where):
    argv = ["catalog", "--json"]
    argv = ["-v", *argv] if where == "before" else [*argv, "-v"]
    status, out, _ = run(capsys, *argv)
    assert status == 0 and json.loads(out)["units"]
    from hdselect.cli.main import _parser

    assert _parser().parse_args(argv).verbose is True
    assert _parser().parse_args(["catalog"]).verbose is False


def test_a_robot_file_given_as_the_motion_is_told_to_write_a_motion_file(capsys):
    status, out, err = run(capsys, "size", REPO / "robots" / "scara.urdf")
    assert status == 2 and out == ""
    assert_one_line_error(err, "scara.urdf: this is a robot file (XML), not a motion file",
                          "hdselect init")
    assert "TOML" not in err


def test_help_says_what_each_command_does_with_its_options(capsys):
    for command, absent, present in (("max-payload", "--payload ", "puts a point mass"),
                                     ("plan", "size only", "plot only these joints")):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        assert absent not in text and present in text, command


def test_fastest_states_the_selection_order_that_chose_its_units(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    status, out, _ = run(capsys, "fastest", REPO / "trajectories" / "benchtop6_fast_pick.toml")
    assert status == 0
    assert "selection: size;" in out and "None" not in out


@pytest.mark.slow
def test_the_mass_carried_for_a_joint_without_a_unit_is_stated(capsys):
    """No unit fits shoulder_lift under 30 kg: the joints below carry the strongest unit's
    mass there, which the assumptions now say (they spoke of chosen units only)."""
    status, out, err = run(capsys, "size", BENCHTOP6, "--payload", "30")
    assert status == 1, err
    text = " ".join(out.split())
    assert ("mass coupling: on: each chosen unit's mass is carried by the joints nearer the "
            "base; where none fits, the strongest unit's;") in text
    status, out, err = run(capsys, "size", BENCHTOP6)
    assert status == 0 and "where none fits" not in " ".join(out.split())
