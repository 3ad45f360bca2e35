"""Co-design on a mix, on the one path a motion takes: motors, ratios compared, a Problem.

What a mix was refused before issue 28 (motors in `fastest` and `max-payload`,
`fastest --compare-ratios`), each checked against the sizing core's own verdict on the
tasks at the answer (every rule holds there, one fails just beyond it), and a one-task
mix against its motion.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import load_motors
from hdselect.cli.main import main
from hdselect.codesign.fastest_cycle import compare_ratios, fastest
from hdselect.codesign.fastpath import PathModel, cycle
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.payloadsizing import at_factor
from hdselect.codesign.trials import check_tasks, run_trial
from hdselect.motion.loading import load_case
from hdselect.sizing.core import size_tasks
from hdselect.sizing.mixtasks import mix_options
from helpers.motions import whole_cycle

REPO = Path(__file__).resolve().parents[1]
PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
INSPECT = REPO / "trajectories" / "benchtop6_inspect.toml"
PICK_INSPECT = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
MOTORS = REPO / "motors" / "example_motors.toml"


def _motors(robot):
    catalog = load_motors(MOTORS)
    return {name: catalog for name in robot.sized_joints}


def _whole_cycle_mix(folder: Path) -> Path:
    """The shipped mix with the pick's part carried the whole cycle (no payload events)."""
    (folder / "mixes").mkdir()
    whole_cycle(PICK, folder)
    whole_cycle(INSPECT, folder)
    return whole_cycle(PICK_INSPECT, folder / "mixes")


def _one_task_mix(folder: Path) -> Path:
    path = folder / "mix.toml"
    path.write_text(f'[[task]]\nname = "pick"\nmotion = "{PICK}"\nshare = 1.0\n'
                    f'[[task]]\nname = "inspect"\nmotion = "{INSPECT}"\nshare = 0.0\n')
    return path


def test_fastest_of_a_mix_with_motors_is_where_the_core_stops_passing(tmp_path):
    """The shipped mix with the example motors: the pooled motor RMS slows every task.

    The pick's part is carried the whole cycle (0.4 kg at the tool, the mix before payload
    events): with it carried only between the pick and the place no pooled rule binds.

    At the answer the core's check of the tasks (their units and paired motors) passes
    every rule, the one that set the slow-down at its limit; every task's moves 1 %
    faster (TOPPRA's profiles of the answer, resampled) fail it in the same check. (A
    motor's RMS torque moves slowly with speed, its dwells kept: +2e-4 for 1 %.)
    """
    robot, mix = load_case(_whole_cycle_mix(tmp_path))
    result = fastest(robot, mix, motors=_motors(robot))
    assert set(result.motors) == set(robot.sized_joints) and result.feasible
    assert result.reason is not None and result.slowdown > 1.0
    joint, rule = result.reason
    options = result.options
    tasks = tuple(item.task for item in result.tasks)
    assert [task.label for task in tasks] == ["pick", "inspect"]
    at = check_tasks(tasks, result.units, options, result.idle, result.motors)
    assert at.feasible
    binding = next(j for j in at.joints if j.name == joint).selected
    assert 0.99 < binding.checks[rule].utilization <= 1.0
    masses = {name: unit.mass + result.motors[name].mass for name, unit in result.units.items()}
    models = [PathModel.build(task.robot, task.motion, robot.sized_joints) for task in tasks]
    trial = run_trial(models, [m.robot.with_gearheads(masses) for m in models],
                      [task.share for task in tasks], result.units, masses, {}, options,
                      result.motors)
    faster = tuple(
        type(task)(task.robot, cycle(task.motion, leg.profiles,
                                     [r * result.slowdown / 1.01 for r in leg.kinematic],
                                     max_samples=options.max_samples)[0],
                   task.share, task.motion, task.name)
        for task, leg in zip(tasks, trial.legs, strict=True))
    below = check_tasks(faster, result.units, options, result.idle, result.motors)
    failing = next(j for j in below.joints if j.name == joint).candidates[0]
    assert not failing.checks[rule].ok
    for item, task in zip(result.tasks, faster, strict=True):
        assert task.trajectory.duration < item.cycle_time  # the faster run is shorter


def test_max_payload_of_a_mix_with_motors_is_where_the_duty_stops_fitting():
    """Motors only add rules: a factor no larger than without them, and the core sizing
    the duty with the motors fits just below it and not just above."""
    robot, mix = load_case(PICK_INSPECT)
    motors = _motors(robot)
    result = max_payload(robot, mix, motors=motors)
    free = max_payload(robot, mix)
    assert 0.0 < result.factor <= free.factor * (1.0 + 1e-9)
    assert result.scaled == ("pick", "inspect") and result.mix is mix
    units = load_catalog()
    for factor, fits in ((0.999 * result.factor, True), (1.001 * result.factor, False)):
        tasks = at_factor(result.tasks, result.scaled, factor)
        sizing = size_tasks(tasks, units, result.selection.options, motors=motors,
                            idle=result.idle)
        assert sizing.feasible is fits, factor
    assert result.selection.feasible and result.selection.mix is mix
    assert all(joint.selected.motor_unit is not None for joint in result.selection.joints)


def test_max_payload_of_a_mix_with_fixed_units_checks_them_over_the_duty():
    robot, mix = load_case(PICK_INSPECT)
    units = dict.fromkeys(robot.sized_joints, "PSA-14-100")
    result = max_payload(robot, mix, units=units)
    by_id = {unit.id: unit for unit in load_catalog()}
    fixed = {name: by_id[unit] for name, unit in units.items()}
    options = mix_options(mix)
    for factor, fits in ((0.999 * result.factor, True), (1.001 * result.factor, False)):
        tasks = at_factor(result.tasks, result.scaled, factor)
        assert check_tasks(tasks, fixed, options, result.idle).feasible is fits, factor


def test_compare_ratios_of_a_one_task_mix_is_its_motions(tmp_path):
    robot, mix = load_case(_one_task_mix(tmp_path))
    mixed = compare_ratios(robot, mix, joints=["elbow"])
    alone = compare_ratios(*load_case(PICK), joints=["elbow"])
    assert mixed.mix is mix and alone.mix is None
    assert {n: u.id for n, u in mixed.units.items()} == {n: u.id for n, u in alone.units.items()}
    (ours,), (theirs,) = mixed.joints, alone.joints
    assert ours.selected == theirs.selected
    assert [row.unit.id for row in ours.rows] == [row.unit.id for row in theirs.rows]
    for row, other in zip(ours.rows, theirs.rows, strict=True):
        assert (row.cycle_time is None) is (other.cycle_time is None), row.unit.id
        if row.cycle_time is not None:
            assert row.cycle_time == pytest.approx(other.cycle_time, rel=1e-9), row.unit.id
        assert (row.gravity, row.lengthened_by) == (other.gravity, other.lengthened_by)


def test_compare_ratios_of_a_mix_equals_fastest_unit_by_unit():
    """Each row is `fastest` of the mix with that unit: the tasks' cycles at their shares."""
    robot, mix = load_case(PICK_INSPECT)
    comparison = compare_ratios(robot, mix, joints=["elbow"])
    (joint,) = comparison.joints
    rows = {row.unit.id: row for row in joint.rows}
    assert rows[joint.selected].cycle_time == comparison.base.mean_cycle_time
    for unit in ("PSA-10-50", "PSA-14-100"):
        alone = fastest(robot, mix, {**comparison.units, "elbow": unit})
        cycles = [item.cycle_time for item in alone.tasks]
        shares = [item.task.share for item in alone.tasks]
        mean = sum(s * c for s, c in zip(shares, cycles, strict=True)) / sum(shares)
        assert rows[unit].cycle_time == pytest.approx(mean, rel=1e-12)
        assert rows[unit].cycle_time == alone.mean_cycle_time
    assert rows["PSA-08-80"].cycle_time is None  # too weak at any speed, as for the motions


def test_a_problem_runs_as_its_robot_and_motion_do():
    problem = hdselect.resolve(None, PICK)  # planned: its plan is the one sized
    by_problem = fastest(problem)
    by_case = fastest(*load_case(PICK))
    assert by_problem.cycle_time == by_case.cycle_time
    np.testing.assert_array_equal(by_problem.trajectory.qd, by_case.trajectory.qd)
    assert max_payload(problem).mass == max_payload(*load_case(PICK)).mass
    with pytest.raises(InputError) as info:
        fastest(problem, options=problem.options)
    assert info.value.field == "options"


def test_the_old_mix_names_warn_and_are_the_one_path():
    import hdselect.codesign as codesign

    for old, new in (("mix_fastest", fastest), ("mix_max_payload", max_payload),
                     ("MixFastestResult", codesign.FastestResult),
                     ("MixPayloadResult", codesign.MaxPayloadResult)):
        with pytest.warns(DeprecationWarning, match=f"hdselect.codesign.{old} is deprecated"):
            assert getattr(codesign, old) is new
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert codesign.fastest is fastest
    with pytest.raises(AttributeError):
        codesign.mix_nothing  # noqa: B018


def test_the_command_line_takes_motors_and_ratios_on_a_mix(tmp_path, capsys):
    """The pick's part carried the whole cycle, so that the pooled motor RMS binds."""
    mix = str(_whole_cycle_mix(tmp_path))
    assert main(["fastest", mix, "--motor-catalog", str(MOTORS), "--json",
                 str(tmp_path / "f.json")]) == 0
    document = json.loads((tmp_path / "f.json").read_text())
    assert set(document["motors"]) == set(document["units"]) and document["feasible"]
    assert document["lengthened_by"] == {"joint": "elbow", "rule": "motor_rms"}
    assert main(["fastest", mix, "--compare-ratios", "--joint", "elbow", "--json",
                 str(tmp_path / "r.json")]) == 0
    ratios = json.loads((tmp_path / "r.json").read_text())
    assert ratios["mix"] == mix and [t["name"] for t in ratios["tasks"]] == ["pick", "inspect"]
    out = capsys.readouterr().out
    assert "Joint elbow: the shortest cycle with each unit" in out
    assert "tasks' cycles weighted by their shares" in " ".join(out.split())
    assert main(["max-payload", mix, "--motor-catalog", str(MOTORS), "--units",
                 "shoulder_lift=PSA-14-100", "--json", str(tmp_path / "p.json")]) == 2
    assert "give a unit for every sized joint" in capsys.readouterr().err
    assert not (tmp_path / "p.json").exists()
    for flag, value in (("--out", "t.csv"), ("--plot", "t.png")):
        assert main(["fastest", mix, flag, str(tmp_path / value)]) == 2
        err = capsys.readouterr().err
        assert err.strip().count("\n") == 0 and flag in err
        assert not (tmp_path / value).exists()
