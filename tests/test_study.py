"""`hdselect study`: study files, executors, resuming, failures kept per case."""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.base.scheduler import local_cluster as _local_cluster
from hdselect.cli.main import main
from hdselect.study import COMPUTATIONS, Computation, compute, load_study, run_study
from hdselect.study.compute import SIZE, Outcome, run_size
from hdselect.study.store import journal_path
from helpers import REPO
from helpers.motions import whole_cycle
from helpers.studies import small_study, workspace

SRC = REPO / "src"


def journal(csv: Path) -> list[dict]:
    return [json.loads(line) for line in journal_path(csv).read_text().splitlines()]


# --- the study file ----------------------------------------------------------------------


def test_grid_cases_and_list_cross_the_grid(tmp_path):
    root = workspace(tmp_path)
    study = load_study(small_study(root))
    assert len(study.cases) == 12 and study.varied == ("motion", "payload", "time_scale")
    assert [c.values["payload"] for c in study.cases[:6]] == [0.2, 0.2, 0.4, 0.4, 0.6, 0.6]
    assert study.cases[0].motion == root / "trajectories" / "planar2_pick_place.toml"
    assert len({case.key for case in study.cases}) == 12
    listed = root / "listed.toml"
    listed.write_text("""[base]
motion = "trajectories/planar2_pick_place.toml"
stop_time = 0.2
[[case]]
payload = {mass = 0.3, com = [0.05, 0, 0], frame = "tool"}
[[case]]
mounting = "wall"
[grid]
time_scale = [1.0, 2.0]
""")
    study = load_study(listed)
    assert len(study.cases) == 4 and study.varied == ("payload", "mounting", "time_scale")
    assert study.cases[0].payload == 0.3 and study.cases[0].payload_shape[2] == "tool"
    assert study.cases[2].payload is None and study.cases[2].mounting == "wall"
    assert all(case.options == {"stop_time": 0.2} for case in study.cases)


@pytest.mark.parametrize(("text", "field", "words"), [
    ("compute = 'duty'\n[base]\nmotion = 'm.toml'", "compute",
     "it computes: size, fastest, max-payload"),
    ("[base]\nmotion = 'm.toml'\npayloda = 1", "base.payloda", "did you mean 'payload'"),
    ("[grid]\nmotion = []", "grid.motion", "non-empty list"),
    ("[grid]\nmotion = ['m.toml']\npayload = [1, -2]", "grid.payload[1]", "positive"),
    ("[grid]\nmotion = ['m.toml']\nstop_time = [0]", "grid.stop_time[0]",
     "a time between 0.0001 and 1000 s"),
    ("[grid]\nmotion = ['m.toml']\ntime_scale = [1, 1e308]", "grid.time_scale[1]",
     "a time scale between 0.001 and 1000"),
    ("[grid]\nmotion = ['m.toml']\ntime_scale = [nan]", "grid.time_scale[0]", "finite"),
    ("[grid]\nmotion = ['m.toml']\nratio = [1000000]", "grid.ratio[0]",
     "a ratio between 1 and 100000"),
    ("[grid]\nmotion = ['m.toml']\nmounting = [[0, 0, inf]]", "grid.mounting[0][2]",
     "finite"),
    ("[grid]\nmotion = ['m.toml']\npayload = [1e308]", "grid.payload[0]", "at most 100000 kg"),
    ("[grid]\nmotion = ['m.toml']\nlife_hours = [-1]", "grid.life_hours[0]", "positive"),
    ("[grid]\nmotion = ['m.toml']\nmax_samples = [1]", "grid.max_samples[0]", "at least 2"),
    ("[grid]\nmotion = ['m.toml']\nstop_time = " + str([0.1] * 1000)
     + "\nefficiency = " + str([0.5] * 1001), "grid", "more than 1,000,000"),
    ("[grid]\nmotion = ['m.toml']\nratio = [1.5]", "grid.ratio[0]", "whole ratio"),
    ("[grid]\npayload = [1.0]", "base.motion", "needs a motion"),
])
def test_a_bad_study_file_names_the_field(tmp_path, text, field, words):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(InputError) as error:
        load_study(path)
    assert error.value.field == field and words in str(error.value)
    assert main(["study", str(path), "--out", str(tmp_path / "r.csv")]) == 2
    assert not (tmp_path / "r.csv").exists()


# --- executors and determinism ----------------------------------------------------------


@pytest.mark.slow
def test_rows_are_identical_with_1_worker_2_workers_and_a_dask_local_cluster(tmp_path):
    study = load_study(small_study(workspace(tmp_path)))
    outputs = {}
    for name, options in {"one": {"workers": 1}, "two": {"workers": 2},
                          "dask": {"workers": 2, "scheduler": "local"},
                          "alone": {"workers": 1, "grouping": False}}.items():
        done = run_study(study, tmp_path / f"{name}.csv", **options)
        assert done.ran == 12 and done.failed == 0
        outputs[name] = (tmp_path / f"{name}.csv").read_text()
    assert outputs["one"] == outputs["two"] == outputs["dask"] == outputs["alone"]
    lines = outputs["one"].splitlines()
    assert len(lines) == 1 + 6 * 2 + 6 * 1  # planar2: two joints; index table: one
    assert {record["method"] for record in journal(tmp_path / "one.csv")} == {"grouped"}
    assert {record["method"] for record in journal(tmp_path / "alone.csv")} == {"direct"}


def test_workers_beyond_the_tasks_start_no_more_processes_than_tasks(tmp_path):
    # found by the hostile battery: --workers 99999999 said "on 99999999 worker processes"
    study = load_study(small_study(workspace(tmp_path)))
    done = run_study(study, tmp_path / "r.csv", workers=99_999_999)
    assert done.ran == 12 and done.failed == 0
    count = int(done.executor.split()[0])
    assert 1 <= count <= 12 and done.executor.endswith(("worker process", "worker processes"))


@pytest.mark.slow
def test_the_local_dask_cluster_listens_on_localhost_only():
    cluster = _local_cluster(1)
    try:
        addresses = [cluster.scheduler_address, *cluster.scheduler_info["workers"],
                     *(nanny.address for nanny in cluster.workers.values())]
        assert len(addresses) == 3
        assert all(a.startswith("tcp://127.0.0.1:") for a in addresses), addresses
        assert "127.0.0.1" in cluster.dashboard_link
    finally:
        cluster.close()


def test_without_dask_one_line_says_how_to_install_it(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)
    path = small_study(workspace(tmp_path))
    assert main(["study", str(path), "--out", str(tmp_path / "r.csv"),
                 "--scheduler", "local"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "pip install 'hdselect[dask]'" in error


# --- nothing lost: resume, failures, changed inputs -------------------------------------


@pytest.mark.slow
def test_a_study_stopped_after_k_cases_resumes_and_has_every_case_once(tmp_path):
    study = load_study(small_study(workspace(tmp_path)))
    out = tmp_path / "r.csv"

    def stop_after_5(done, total, record):
        if done == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, workers=0, grouping=False, progress=stop_after_5)
    assert len(journal(out)) == 5 and len(out.read_text().splitlines()) > 5
    with journal_path(out).open("a") as stream:
        stream.write('{"key": "half-writ')  # a kill in the middle of a line
    again = run_study(study, out, workers=0, grouping=False)
    assert (again.skipped, again.ran) == (5, 7)
    keys = [record["key"] for record in journal(out)]
    assert sorted(keys) == sorted(case.key for case in study.cases)
    once = run_study(study, tmp_path / "fresh.csv", workers=0, grouping=False)
    assert once.ran == 12 and out.read_text() == (tmp_path / "fresh.csv").read_text()
    finished = run_study(study, out, workers=0)
    assert (finished.ran, finished.skipped) == (0, 12)


@pytest.mark.slow
def test_a_killed_command_resumes_where_it_stopped(tmp_path):
    path = small_study(workspace(tmp_path))
    out = tmp_path / "r.csv"
    command = [sys.executable, "-m", "hdselect.cli", "study", str(path), "--out", str(out),
               "--workers", "1", "--no-grouping"]
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if journal_path(out).exists() and len(journal(out)) >= 3:
                break
            time.sleep(0.05)
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    first = len(journal(out))
    assert 3 <= first < 12
    done = subprocess.run(command, env=env, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert "already done" in done.stdout and f"{12 - first} run now" in done.stdout
    assert sorted(r["case"] for r in journal(out)) == list(range(12))


def test_a_broken_robot_file_fails_its_cases_only(tmp_path, capsys):
    root = workspace(tmp_path)
    (root / "robots" / "index_table.urdf").write_text("<robot name='x'><link name=")
    out = tmp_path / "r.csv"
    assert main(["study", str(small_study(root)), "--out", str(out), "--workers", "2"]) == 3
    printed = capsys.readouterr().out
    assert "6 failed" in printed
    records = journal(out)
    failed = [r for r in records if not r["ok"]]
    assert len(failed) == 6 and all("index_table.urdf" in r["error"] for r in failed)
    assert all(r["ok"] for r in records if r["values"]["motion"].endswith("planar2_pick_place"
                                                                          ".toml"))
    rows = [line for line in out.read_text().splitlines() if ",failed," in line]
    assert len(rows) == 6 and all("not a valid URDF" in row for row in rows)


def dies_on_04(cases, grouped):
    """A computation whose worker process dies on the cases with a 0.4 kg payload."""
    for case in cases:
        if case.payload == 0.4:
            os._exit(7)
        yield from run_size([case], False)


@pytest.mark.slow
def test_a_case_that_kills_its_worker_is_recorded_and_the_rest_run(tmp_path, monkeypatch):
    monkeypatch.setitem(COMPUTATIONS, "dies", Computation("dies", "test", dies_on_04,
                                                          SIZE.rows, SIZE.columns))
    path = small_study(workspace(tmp_path), extra="")
    path.write_text("compute = 'dies'\n" + path.read_text())
    done = run_study(load_study(path), tmp_path / "r.csv", workers=2)
    assert done.ran == 12 and done.failed == 4
    failed = [r for r in journal(tmp_path / "r.csv") if not r["ok"]]
    assert {r["values"]["payload"] for r in failed} == {0.4}
    assert all(r["error"] == "the worker process died running this case (exit status 7)"
               for r in failed)


def test_changing_one_input_file_reruns_only_its_cases(tmp_path):
    root = workspace(tmp_path)
    path = small_study(root)
    out = tmp_path / "r.csv"
    assert run_study(load_study(path), out, workers=0).ran == 12
    motion = root / "trajectories" / "index_table_indexing.toml"
    motion.write_text(motion.read_text().replace("dt = 0.001", "dt = 0.002"))
    again = run_study(load_study(path), out, workers=0)
    assert (again.ran, again.skipped) == (6, 6)
    assert len(journal(out)) == 12  # the old records of the changed cases are gone


def test_outcome_fields_are_what_the_journal_keeps(tmp_path):
    study = load_study(small_study(workspace(tmp_path)))
    run_study(study, tmp_path / "r.csv", workers=0)
    record = journal(tmp_path / "r.csv")[0]
    assert set(Outcome.__dataclass_fields__) - {"index"} <= set(record)
    assert record["result"]["joints"][0]["name"] == "shoulder"


# --- the command and the Python API -----------------------------------------------------


@pytest.mark.slow
def test_the_command_prints_the_pivot_and_draws_the_plot(tmp_path, capsys):
    path = small_study(workspace(tmp_path))
    out, plot = tmp_path / "r.csv", tmp_path / "r.png"
    assert main(["study", str(path), "--out", str(out), "--plot", str(plot)]) == 0
    printed = capsys.readouterr().out
    assert "small: 12 cases: 12 run now (12 grouped), 0 already done, 0 failed" in printed
    assert plot.stat().st_size > 10_000
    assert main(["study", str(path), "--out", str(out)]) == 0
    assert "12 cases: 0 run now, 12 already done, 0 failed" in capsys.readouterr().out


def test_python_api_returns_rows_as_dicts(tmp_path):
    rows = hdselect.study(small_study(workspace(tmp_path)), workers=0)
    assert len(rows) == 18 and rows[0]["joint"] == "shoulder" and rows[0]["status"] == "ok"
    assert isinstance(rows[0]["life_l50_h"], float) and rows[0]["payload"] == 0.2
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(InputError, match="pip install pandas"):
            hdselect.study(small_study(tmp_path), workers=0, frame=True)


# --- motors -------------------------------------------------------------------------------


@pytest.mark.slow
def test_a_study_with_motors_sizes_pairs_the_same_grouped_or_alone(tmp_path):
    root = workspace(tmp_path)
    shutil.copytree(REPO / "motors", root / "motors")
    path = root / "pairs.toml"
    path.write_text("""[base]
motion = "trajectories/planar2_pick_place.toml"
motor_catalog = "motors/example_motors.toml"
[grid]
payload = [0.2, 0.6]
time_scale = [1.0, 1.5]
""")
    study = load_study(path)
    motors = root / "motors" / "example_motors.toml"
    assert all(case.motor_catalog == motors and motors in case.files for case in study.cases)
    outputs = {}
    for name, grouping in (("grouped", True), ("alone", False)):
        done = run_study(study, tmp_path / f"{name}.csv", workers=0, grouping=grouping)
        assert done.ran == 4 and done.failed == 0
        outputs[name] = (tmp_path / f"{name}.csv").read_text()
    assert outputs["grouped"] == outputs["alone"]
    assert {r["method"] for r in journal(tmp_path / "grouped.csv")} == {"grouped"}
    rows = hdselect.study(path, out=tmp_path / "grouped.csv")  # all done: read back
    assert len(rows) == 4 * 2 and all(row["motor"].startswith("EX-") for row in rows)
    assert all(row["inertia_ratio"] > 0 and row["motor_binding"].startswith("motor_")
               for row in rows)
    records = journal(tmp_path / "grouped.csv")
    assert all(r["result"]["options"]["prefer"] == "mass" for r in records)
    # the key hashes the motor file: a changed motor re-runs the cases
    keys = {case.key for case in study.cases}
    motors.write_text(motors.read_text().replace("mass_kg = 0.06", "mass_kg = 0.07", 1))
    assert not keys & {case.key for case in load_study(path).cases}


def test_a_motion_files_motor_files_are_inputs_of_its_cases(tmp_path):
    root = workspace(tmp_path)
    shutil.copytree(REPO / "motors", root / "motors")
    motion = root / "trajectories" / "planar2_pick_place.toml"
    motion.write_text(motion.read_text() + '\n[motor]\ncatalog = "../motors/example_motors.toml"\n')
    (case,) = load_study(small_study(root, "")).cases[:1]
    assert root / "trajectories" / ".." / "motors" / "example_motors.toml" in case.files
    outcome = next(iter(run_size([case], False)))
    assert outcome.ok and all(joint["motor"] for joint in outcome.result["joints"])


# --- fastest and max-payload -----------------------------------------------------------------


@pytest.mark.slow
def test_fastest_and_max_payload_rows_equal_the_direct_calls(tmp_path, capsys):
    root = workspace(tmp_path)
    # the part carried the whole cycle: at s = 0.8 it is what makes the elbow's unit bigger
    whole = whole_cycle(root / "trajectories" / "planar2_pick_place.toml", root)
    path = root / "codesign.toml"
    path.write_text("""compute = ["fastest", "max-payload"]
[base]
motion = "planar2_pick_place.toml"
ratio = 100
[grid]
time_scale = [1.0, 0.8]
""")
    study = load_study(path)
    assert [(c.compute, c.time_scale) for c in study.cases] == [
        ("fastest", 1.0), ("max-payload", 1.0), ("fastest", 0.8), ("max-payload", 0.8)]
    out = root / "codesign.csv"
    assert main(["study", str(path), "--out", str(out), "--workers", "0"]) == 0
    printed = " ".join(capsys.readouterr().out.split())
    rows = hdselect.study(path, out=out, workers=0)  # every case already done: read back
    assert {row["status"] for row in rows} == {"ok"}

    robot, motion = hdselect.load_case(whole)
    assert not motion.events and robot.parts  # the direct calls below see no events
    options = hdselect.sizing.options.options_for(motion)
    units = [u for u in hdselect.load_catalog() if u.ratio == 100]
    for s in (1.0, 0.8):
        trajectory = compute.scaled(hdselect.plan(robot, motion), s)
        # fastest: the units `size` selects for the motion run s times slower, then the
        # shortest cycle they allow (at s = 1: hdselect.fastest's own default units)
        sized = hdselect.size_trajectory(robot, trajectory, units, options)
        chosen = {j.name: j.selected.unit for j in sized.joints}
        direct = hdselect.fastest(robot, motion, chosen if s != 1.0 else None, options,
                                  catalog=units)
        mine = [r for r in rows if r["compute"] == "fastest" and r["time_scale"] == s]
        assert [(r["joint"], r["unit"]) for r in mine] == [(n, u.id) for n, u in
                                                           direct.units.items()]
        assert [r["cycle_time_s"] for r in mine] == pytest.approx(
            [direct.cycle_time] * len(mine), rel=1e-9)
        assert all(r["feasible"] for r in mine) and direct.feasible
        assert f"{direct.cycle_time:.3f}" in printed
        # max-payload: the largest payload on the motion run s times slower
        largest = hdselect.max_payload(robot, motion, options, catalog=units,
                                       trajectory=trajectory if s != 1.0 else None)
        mine = [r for r in rows if r["compute"] == "max-payload" and r["time_scale"] == s]
        assert [r["joint"] for r in mine] == list(robot.sized_joints)
        assert [r["max_payload_kg"] for r in mine] == pytest.approx(
            [largest.mass] * len(mine), rel=1e-12)
        assert [r["unit"] for r in mine] == [j.selected.unit.id
                                             for j in largest.selection.joints]
        limit = [r["payload_limit"] for r in mine if r["payload_limit"]]
        assert limit == [f"{largest.unit.id} {largest.rule}"]
        assert f"{largest.mass:.3g}" in printed
    assert "fastest cycle s (time_scale down)" in printed
    assert "largest payload kg (time_scale down)" in printed
    # the time scale is used: 1.25 times faster, `size` picks a bigger elbow unit, and the
    # arm carries less
    elbow = [r["unit"] for r in rows if r["compute"] == "fastest" and r["joint"] == "elbow"]
    assert elbow == ["PSA-08-100", "PSA-14-100"]
    payloads = [r["max_payload_kg"] for r in rows if r["compute"] == "max-payload"]
    assert payloads[-1] < payloads[0]


@pytest.mark.slow
def test_fastest_of_a_log_and_max_payload_under_toppra_torque_limits_fail_alone(tmp_path):
    root = workspace(tmp_path)
    contour = (root / "trajectories" / "benchtop6_contour.toml").read_text()
    (root / "trajectories" / "torque.toml").write_text(contour.replace(
        "[limits]", "[limits]\ntorque = 50", 1))
    path = root / "fails.toml"
    path.write_text("""compute = ["fastest", "max-payload"]
[grid]
motion = ["trajectories/pan_tilt_logged.toml", "trajectories/torque.toml"]
""")
    rows = hdselect.study(path, workers=0)
    status = {(row["motion"], row["compute"]): (row["status"], row["error"]) for row in rows}
    logged = status["trajectories/pan_tilt_logged.toml", "fastest"]
    assert logged[0] == "failed" and "has no path to run faster" in logged[1]
    # the pan-tilt's default payload frame, the laser, sits on both axes: a point mass
    # there loads neither joint, so one row says there is no limit
    (unlimited,) = [row for row in rows if row["compute"] == "max-payload"
                    and row["motion"] == "trajectories/pan_tilt_logged.toml"]
    assert unlimited["status"] == "ok" and unlimited["max_payload_kg"] == math.inf
    assert unlimited["payload_frame"] == "laser" and unlimited.get("joint") is None
    assert unlimited["payload_limit"] == "no rule depends on the payload mass"
    torque = status["trajectories/torque.toml", "max-payload"]
    assert torque[0] == "failed" and "limits.torque" in torque[1]
