"""Co-design's one output path for a motion and a mix: a motion is a duty of one task.

A one-task mix writes the motion's JSON for every key the motion has; a mix of several
tasks names each task's cycle, limits and binding (no first task standing in for the
duty), its binding shares weighted by how often each task runs; a study's ``fastest``
and ``max-payload`` rows of a mix are the commands' own answers on it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.codesign.fastest_cycle import fastest
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.records import fastest_json, max_payload_json
from hdselect.motion.loading import load_case
from helpers.studies import workspace

REPO = Path(__file__).resolve().parents[1]
PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
INSPECT = REPO / "trajectories" / "benchtop6_inspect.toml"
MIX_NAME = "benchtop6_pick_inspect.toml"
PICK_INSPECT = REPO / "trajectories" / "mixes" / MIX_NAME


def _same(ours, theirs, where="document"):
    """JSON values equal, floats to 1e-9 relative."""
    if isinstance(theirs, dict):
        assert isinstance(ours, dict) and set(ours) >= set(theirs), where
        for key, value in theirs.items():
            _same(ours[key], value, f"{where}.{key}")
    elif isinstance(theirs, list):
        assert isinstance(ours, list) and len(ours) == len(theirs), where
        for k, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            _same(a, b, f"{where}[{k}]")
    elif isinstance(theirs, float) and not isinstance(theirs, bool):
        assert ours == pytest.approx(theirs, rel=1e-9, abs=1e-12), where
    else:
        assert ours == theirs, where


def _one_task_mix(folder: Path) -> Path:
    """The pick-and-place alone, as a mix (the inspection counted for nothing)."""
    path = folder / "mix.toml"
    path.write_text(f'[[task]]\nname = "pick"\nmotion = "{PICK}"\nshare = 1.0\n'
                    f'[[task]]\nname = "inspect"\nmotion = "{INSPECT}"\nshare = 0.0\n')
    return path


@pytest.mark.slow
def test_a_one_task_mix_writes_the_motions_fastest_json(tmp_path):
    robot, motion = load_case(PICK)
    mixed_robot, mix = load_case(_one_task_mix(tmp_path))
    alone = fastest_json(fastest(robot, motion))
    mixed = fastest_json(fastest(mixed_robot, mix))
    _same(mixed, alone)  # every key the motion has, the same value
    assert mixed["mix"] == str(mix.path) and [t["name"] for t in mixed["tasks"]] == ["pick"]
    (task,) = mixed["tasks"]
    assert task["cycle_time_s"] == mixed["cycle_time_s"] and task["motion"] == str(PICK)
    assert task["binding"] == alone["binding"]


@pytest.mark.slow
def test_a_one_task_mix_writes_the_motions_max_payload_json(tmp_path):
    robot, motion = load_case(PICK)
    mixed_robot, mix = load_case(_one_task_mix(tmp_path))
    alone = max_payload_json(max_payload(robot, motion), motion)
    mixed = max_payload_json(max_payload(mixed_robot, mix))
    # the motion's answer is a mass on its payload's shape, the mix's a factor on the
    # payload as given: the same masses, to the bisection's and rounding's accuracy
    assert mixed["max_payload_kg"] == pytest.approx(alone["max_payload_kg"], rel=1e-9)
    _same(mixed["ranges_kg"], alone["ranges_kg"], "ranges_kg")
    for key in ("motion", "unlimited", "binding", "payload"):
        _same(mixed[key], alone[key], key)
    assert mixed["selection"]["joints"][1]["selected"] == \
        alone["selection"]["joints"][1]["selected"]
    assert mixed["factor"] * mixed["given_kg"]["pick"] == pytest.approx(
        alone["max_payload_kg"], rel=1e-9)


@pytest.fixture(scope="module")
def duty():
    robot, mix = load_case(PICK_INSPECT)
    return robot, mix, fastest(robot, mix)


@pytest.mark.slow
def test_a_mix_has_each_tasks_cycle_limits_and_binding_and_no_first_task(duty):
    robot, mix, result = duty
    assert [item.task.label for item in result.tasks] == ["pick", "inspect"]
    for item in result.tasks:
        assert item.motion.path.resolve() == {"pick": PICK, "inspect": INSPECT}[item.task.label]
        assert set(item.limits) == set(robot.joint_names)
        assert item.binding and {b.task for b in item.binding} == {item.task.label}
        assert item.binding[-1].end <= item.cycle_time + 1e-9
        assert sum(share for _, _, share in item.binding_shares()) == pytest.approx(1.0)
    for what in ("motion", "trajectory", "limits"):
        with pytest.raises(InputError, match="one per task"):
            getattr(result, what)
    # the duty's shares: each task's stretches for the time they take in the duty, as
    # often as the task runs (share / cycle), by hand
    rate = {item.task.label: item.task.share / item.cycle_time for item in result.tasks}
    total: dict[tuple[str, str], float] = {}
    for item in result.tasks:
        for b in item.binding:
            key = (b.joint, b.limit)
            total[key] = total.get(key, 0.0) + rate[item.task.label] * (b.end - b.start)
    by_hand = {key: value / sum(total.values()) for key, value in total.items()}
    ours = {(joint, limit): share for joint, limit, share in result.binding_shares()}
    assert ours == pytest.approx(by_hand, rel=1e-12)
    shares = [item.task.share for item in result.tasks]
    weighted = sum(s * item.cycle_time for s, item in zip(shares, result.tasks, strict=True))
    assert result.cycle_time == pytest.approx(weighted / sum(shares))


@pytest.mark.slow
def test_a_mixs_json_gives_each_task_and_the_duty(duty, tmp_path):
    robot, mix, result = duty
    document = fastest_json(result)
    assert document["motion"] is None and document["payload"] is None
    assert document["samples"] == sum(len(item.task.trajectory.t) for item in result.tasks)
    assert {b["task"] for b in document["binding"]} == {"pick", "inspect"}
    for joint in document["joints"]:
        assert joint["velocity_limit"] is None and joint["binding_share"] is not None
    for task, item in zip(document["tasks"], result.tasks, strict=True):
        assert task["cycle_time_s"] == item.cycle_time
        assert task["moving_time_s"] + task["dwell_time_s"] == pytest.approx(item.cycle_time)
        limits = {j["name"]: j["velocity_limit"] for j in task["joints"]}
        assert limits == {name: item.limits[name].velocity for name in robot.sized_joints}
        assert task["payload"]["mass_kg"] == item.task.robot.payload.mass
    # the command line writes the same document with the same units
    units = [arg for name, unit in result.units.items() for arg in ("--units", f"{name}={unit.id}")]
    out = tmp_path / "mix.json"
    assert main(["fastest", str(PICK_INSPECT), *units, "--json", str(out)]) == 0
    written = json.loads(out.read_text())
    assert set(written) == set(document)
    assert written["cycle_time_s"] == pytest.approx(document["cycle_time_s"], rel=1e-12)
    assert written["tasks"][0]["binding"] == document["tasks"][0]["binding"]


@pytest.mark.slow
def test_a_study_of_a_mix_computes_fastest_and_max_payload_as_the_commands(tmp_path):
    root = workspace(tmp_path)
    path = root / "mix_codesign.toml"
    path.write_text("""compute = ["fastest", "max-payload"]
[base]
motion = "trajectories/mixes/benchtop6_pick_inspect.toml"
[grid]
shares = [[0.7, 0.3], [0.5, 0.5]]
""")
    rows = hdselect.study(path, workers=0)
    assert {row["status"] for row in rows} == {"ok"}, [row["error"] for row in rows]
    mix_file = root / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
    robot, mix = load_case(mix_file)
    assert [task.share for task in mix.tasks] == [0.7, 0.3]  # the first case is the file's
    first = [row for row in rows if row["shares"] == [0.7, 0.3]]
    direct = fastest(robot, mix)
    mine = [row for row in first if row["compute"] == "fastest"]
    assert [(r["joint"], r["unit"]) for r in mine] == [(n, u.id) for n, u in
                                                       direct.units.items()]
    assert [r["cycle_time_s"] for r in mine] == pytest.approx(
        [direct.cycle_time] * len(mine), rel=1e-9)
    assert [r["optimum_s"] for r in mine] == pytest.approx([direct.optimum] * len(mine),
                                                           rel=1e-9)
    longest = {}
    for joint, limit, share in direct.binding_shares():
        longest.setdefault(joint, (limit, share))
    for row in mine:
        limit, share = longest.get(row["joint"], (None, None))  # a joint that never binds
        assert row["binds_longest"] == limit
        assert row["binds_share"] == (None if share is None else pytest.approx(share, rel=1e-9))
    assert any(row["binds_longest"] for row in mine)
    largest = max_payload(robot, mix)
    mine = [row for row in first if row["compute"] == "max-payload"]
    assert [r["joint"] for r in mine] == list(robot.sized_joints)
    assert [r["payload_factor"] for r in mine] == pytest.approx(
        [largest.factor] * len(mine), rel=1e-12)
    assert all(r["max_payload_kg"] is None for r in mine)  # two payloads scale
    assert [r["unit"] for r in mine] == [j.selected.unit.id for j in largest.selection.joints]
    assert [r["payload_limit"] for r in mine if r["payload_limit"]] == [
        f"{largest.unit.id} {largest.rule}"]
    # the shares matter: another day, another answer
    other = [row for row in rows if row["shares"] == [0.5, 0.5]
             and row["compute"] == "fastest"]
    assert other and other[0]["cycle_time_s"] != pytest.approx(direct.cycle_time, rel=1e-6)
    assert not math.isnan(other[0]["cycle_time_s"])


def test_the_mixs_old_writers_warn_and_are_the_one_writer():
    from hdselect.codesign import records

    for old, new in (("mix_fastest_json", records.fastest_json),
                     ("mix_payload_json", records.max_payload_json)):
        with pytest.warns(DeprecationWarning, match=f"records.{new.__name__}"):
            assert getattr(records, old) is new
    with pytest.raises(AttributeError):
        records.mix_nothing  # noqa: B018


@pytest.mark.slow
def test_a_mixs_tables_show_each_tasks_binding_and_the_duty(duty):
    from hdselect.cli.output import rendered
    from hdselect.report.codesign_tables import binding_table, fastest_tables

    _, mix, result = duty
    tables = fastest_tables(result)
    text = rendered(*tables)
    assert "pick       70%" in text and f"fastest cycle {result.cycle_time:.3f} s" in text
    binds = binding_table(result)
    assert binds.columns[0].header == "task"
    assert [row[0] for row in binds.rows] == [b.task for b in result.binding]
    longest = {}
    for joint, limit, _ in result.binding_shares():
        longest.setdefault(joint, limit)
    joints = tables[2]
    shown = {row[0]: row[5] for row in joints.rows}
    assert any(value != "-" for value in shown.values())
    assert all((shown[name] == "-") == (name not in longest) for name in shown)


def test_a_study_of_a_logged_mix_fails_fastest_alone_and_finds_its_payload(tmp_path):
    """Logged tasks have no path to run faster (that case fails alone, saying so); their
    payloads still scale, to the factor `max_payload` of the mix finds."""
    from helpers.studies import write_index_mix

    mix_file = write_index_mix(tmp_path, shares=[0.6, 0.4])
    path = tmp_path / "logged.toml"
    path.write_text(f'compute = ["fastest", "max-payload"]\n[base]\nmotion = "{mix_file}"\n'
                    "[grid]\nshares = [[0.6, 0.4]]\n")
    rows = hdselect.study(path, workers=0)
    (failed,) = [row for row in rows if row["compute"] == "fastest"]
    assert failed["status"] == "failed"
    assert "has no path to run faster; give motions with waypoints" in failed["error"]
    found = [row for row in rows if row["compute"] == "max-payload"]
    assert {row["status"] for row in found} == {"ok"}
    robot, mix = load_case(mix_file)
    largest = max_payload(robot, mix)
    assert math.isfinite(largest.factor)
    assert [row["payload_factor"] for row in found] == pytest.approx([largest.factor],
                                                                     rel=1e-12)
    assert {"robot", "mix", "factor", "unlimited", "scaled", "payloads_kg", "given_kg",
            "ranges", "binding", "selection"} <= set(max_payload_json(largest))


@pytest.mark.slow
def test_a_mixs_ratio_rows_say_what_binds_longest_over_the_duty(duty):
    from hdselect.codesign.fastest_cycle import compare_ratios
    from hdselect.report.codesign_tables import ratios_table

    robot, mix, result = duty
    catalog = list(dict.fromkeys(result.units.values()))
    comparison = compare_ratios(robot, mix, result.units, catalog=catalog, joints=["wrist_3"])
    (joint,) = comparison.joints
    (mine,) = [row for row in joint.rows if row.unit is result.units["wrist_3"]]
    joint_name, limit, _ = result.binding_shares()[0]
    assert mine.binding == (joint_name, limit)
    assert all(row.binding is not None for row in joint.rows if row.cycle_time is not None)
    table = ratios_table(comparison, joint)
    assert all(row[3] != "-" for row in table.rows if "none" not in row[1])
    with pytest.raises(InputError, match="one per task"):
        comparison.motion  # noqa: B018


@pytest.mark.slow
def test_a_mixs_documents_keep_every_key_they_had(duty):
    _, mix, result = duty
    document = fastest_json(result)
    assert {"robot", "mix", "units", "motors", "tasks", "idle_share", "slowdown",
            "lengthened_by", "feasible", "check"} <= set(document)
    for task in document["tasks"]:
        assert {"name", "share", "planned_cycle_s", "optimum_s", "cycle_time_s",
                "cycles_per_hour"} <= set(task)


@pytest.mark.slow
def test_a_study_of_a_mix_run_slower_takes_sizes_units_there(tmp_path):
    """``time_scale`` runs every task slower: `fastest` takes the units `size` selects for
    the slower duty, `max-payload` carries the payloads along it."""
    from dataclasses import replace

    from hdselect.study.pooled import scaled

    root = workspace(tmp_path)
    path = root / "slower.toml"
    path.write_text("""compute = ["fastest", "max-payload"]
[base]
motion = "trajectories/mixes/benchtop6_pick_inspect.toml"
[grid]
time_scale = [1.6]
""")
    rows = hdselect.study(path, workers=0)
    assert {row["status"] for row in rows} == {"ok"}, [row["error"] for row in rows]
    problem = hdselect.resolve(None, root / "trajectories" / "mixes" / MIX_NAME)
    slower = replace(problem, tasks=tuple(replace(task, trajectory=scaled(task.trajectory, 1.6))
                                          for task in problem.tasks))
    sized = hdselect.size_problem(slower)
    units = {joint.name: joint.selected.unit.id for joint in sized.joints}
    at_speed = {joint.name: joint.selected.unit.id
                for joint in hdselect.size_problem(problem).joints}
    assert units != at_speed  # the slower duty takes another unit somewhere
    direct = fastest(problem, units=units)
    mine = [row for row in rows if row["compute"] == "fastest"]
    assert {row["joint"]: row["unit"] for row in mine} == units
    assert [r["cycle_time_s"] for r in mine] == pytest.approx(
        [direct.cycle_time] * len(mine), rel=1e-9)
    largest = max_payload(slower)
    mine = [row for row in rows if row["compute"] == "max-payload"]
    assert [r["payload_factor"] for r in mine] == pytest.approx(
        [largest.factor] * len(mine), rel=1e-12)
    assert largest.factor > max_payload(problem).factor  # slower: a heavier payload
