"""A mix under the review's rules: the design margin, the inertia ratio, the summary, --bom.

Oracles: the motion sized alone with the same margin, motors and largest inertia ratio (a
mix of shares (1, 0) must reproduce it to the last bit); the load inertia M_jj computed
here by Pinocchio's composite rigid body algorithm (`pinocchio.crba`, a second method
beside the core's RNEA columns) on each task's poses; the utilizations of the same mix
sized without a margin (a margin changes the verdicts, never the demands); each task's
cycle, payload and share as the result holds them, read back from the rendered summary
and the parts list; and a study's grouped cases against the direct core.
"""

from __future__ import annotations

import csv

import numpy as np
import pinocchio as pin
import pytest

from hdselect import size
from hdselect.catalog.motors import load_motors
from hdselect.catalog.rules import holds
from hdselect.catalog.select import select
from hdselect.cli.main import main
from hdselect.sizing.torques import GRAVITY_SAMPLES
from helpers import REPO
from helpers.dynamics import part_rows, with_body
from helpers.studies import INSPECT, PICK, PICK_INSPECT, differences, write_index_mix
from helpers.studies import mix_text as mix_text
from helpers.studies import plain_text as plain_text

MOTORS = REPO / "motors" / "example_motors.toml"


@pytest.fixture(scope="module")
def catalog_motors():
    return load_motors(MOTORS)


def _every_joint(result_or_robot, motors):
    robot = getattr(result_or_robot, "robot", result_or_robot)
    return {name: motors for name in robot.sized_joints}


# ----------------------------------------------------------------------- the design margin

def test_shares_of_one_and_zero_keep_the_margin_and_the_inertia_rule(tmp_path, catalog_motors):
    """Margin, motors, largest inertia ratio and the inertia preference: the motion alone."""
    mix = mix_text(tmp_path, ("pick", PICK, 1.0), ("inspect", INSPECT, 0.0))
    given = {"margin": 0.15, "max_inertia_ratio": 8.0, "prefer": "inertia",
             "inertia_target": 3.0}
    robot = size(None, PICK).robot
    motors = _every_joint(robot, catalog_motors)
    mixed = size(None, mix, motors=motors, **given)
    alone = size(None, PICK, motors=motors, **given)
    assert mixed.options.margin == 0.15 and mixed.options.max_inertia_ratio == 8.0
    assert differences(plain_text(mixed), plain_text(alone)) == 0.0  # to the last bit


def test_a_margin_changes_the_verdicts_over_a_mix_not_the_demands():
    """Without mass coupling every joint sees the same torques with or without a margin:
    each rule's utilization over the duty (pooled or worst task) and against each task
    alone is the same, its verdict is `holds(u, m)`, and the selection is the catalog's
    order over the units that hold every rule at (1 - m) of its limits."""
    margin = 0.3
    plain = size(None, PICK_INSPECT, mass_coupling=False)
    held = size(None, PICK_INSPECT, mass_coupling=False, margin=margin)
    changed = 0
    for a, b in zip(plain.joints, held.joints, strict=True):
        rejudged = []
        for x, y in zip(a.candidates, b.candidates, strict=True):
            assert x.unit.id == y.unit.id and x.checks.keys() == y.checks.keys()
            for name, check in x.checks.items():
                assert y.checks[name].utilization == check.utilization, (a.name, name)
                assert y.checks[name].ok == holds(check.utilization, margin), (a.name, name)
            rejudged.append(y)
        assert b.selected is select(rejudged, "size")
        chosen = b.selected or b.strongest
        assert len(b.per_task) == 2
        for alone in b.per_task:
            assert alone.unit is chosen.unit and alone.required_margin == margin
            for check in alone.checks.values():
                assert check.ok == holds(check.utilization, margin)
        changed += (a.selected or a.strongest).unit.id != chosen.unit.id
    assert changed >= 1  # the shoulder lift's peak at 77 %: a larger unit with 30 % held back


def test_the_margin_of_a_mix_file_and_of_its_motions(tmp_path):
    text = PICK_INSPECT.read_text().replace("life_hours = 20000",
                                             "life_hours = 20000\nmargin = 0.2")
    mix = PICK_INSPECT.parent / "margin_test.toml"  # its motions' paths are relative
    try:
        mix.write_text(text)
        assert size(None, mix).options.margin == 0.2
        assert size(None, mix, margin=0.05).options.margin == 0.05  # the caller's first
        motion = tmp_path / "pick.toml"
        motion.write_text(PICK.read_text().replace('"../robots/', f'"{REPO}/robots/').replace(
            "life_hours = 20000", "life_hours = 20000\nmargin = 0.1"))
        mix.write_text(text.replace('"../benchtop6_pick_place.toml"', f'"{motion}"'))
        result = size(None, mix)  # the mix file's settles it over its motion's, noted
        assert result.options.margin == 0.2
        assert ("motion file: margin_test.toml gives requirements.margin 0.2 for the whole "
                "duty, over pick.toml's 0.1") in result.warnings
    finally:
        mix.unlink()


# ------------------------------------------------------------------------ the inertia ratio

def _crba_inertias(task, masses, name):
    """M_jj of joint `name` at the task's gravity poses, by `pinocchio.crba` [kg m^2]; the
    pick-and-place's part written into the model at the poses between its events."""
    robot = task.robot.with_gearheads(masses)
    models = [robot.model, robot.model]
    traj = task.trajectory
    rides = np.zeros(len(traj.t), dtype=bool)
    if task.motion.events:
        part = task.motion.parts["part"]
        models[1] = with_body(robot.model, part, part.frame or robot.payload_frame)
        rides = part_rows(task.motion, traj)
    v = robot.model.joints[robot.model.getJointId(name)].idx_v
    poses = np.unique(np.linspace(0, len(traj.t) - 1, GRAVITY_SAMPLES).astype(int))
    chosen = [models[int(rides[i])] for i in poses]
    return np.array([pin.crba(model, model.createData(), traj.q[i])[v, v]
                     for model, i in zip(chosen, poses, strict=True)])


@pytest.fixture(scope="module")
def matched(catalog_motors):
    """The day with the example motors, at most 10:1 inertia and a 10 % margin."""
    robot = size(None, INSPECT).robot
    return size(None, PICK_INSPECT, motors=_every_joint(robot, catalog_motors),
                max_inertia_ratio=10.0, margin=0.1)


def test_the_load_inertia_of_a_mix_is_its_largest_tasks(matched):
    """Per joint: M_jj of each task by crba with the chosen units' and motors' masses; the
    duty's load inertia is the larger, each task alone has its own ratio, and the task
    with the larger M_jj sets the duty's inertia-ratio rule."""
    masses = {joint.name: joint.selected.unit.mass + joint.selected.motor_unit.mass
              for joint in matched.joints}
    inspect_sets = 0
    for joint in matched.joints:
        chosen = joint.selected
        own = [float(_crba_inertias(task, masses, joint.name).max()) for task in matched.counted]
        assert joint.load_inertia == pytest.approx(max(own), rel=1e-9)
        unit, motor = chosen.unit, chosen.motor_unit
        for inertia, alone in zip(own, joint.per_task, strict=True):
            ratio = (inertia / unit.ratio**2 + unit.input_inertia) / motor.rotor_inertia
            assert alone.inertia_ratio == pytest.approx(ratio, rel=1e-9)
            assert alone.checks["inertia_ratio"].utilization == pytest.approx(ratio / 10.0,
                                                                              rel=1e-9)
        assert chosen.checks["inertia_ratio"].utilization <= 1.0  # no margin on a choice
        setter = matched.counted[int(np.argmax(own))].label
        assert matched.set_by(joint, "inertia_ratio") == setter
        inspect_sets += setter == "inspect"
    assert inspect_sets >= 1  # the camera off-centre, the arm reaching out
    blocked = [c for joint in matched.joints for c in joint.candidates
               if not c.checks["inertia_ratio"].ok
               and all(check.ok for name, check in c.checks.items() if name != "inertia_ratio")]
    assert blocked  # pairs that only the inertia rule turns down


# --------------------------------------------------------- the review summary and --bom

def _summary(page: str) -> str:
    start = page.index("<section id=summary")
    return page[start:page.index("</section>", start)]


@pytest.mark.slow
def test_the_review_summary_lists_each_task_of_a_mix(matched, tmp_path):
    from hdselect.report.report_files import write_report

    write_report(tmp_path / "report", matched)
    summary = _summary((tmp_path / "report" / "index.html").read_text())
    for task in matched.tasks:
        payload = task.robot.payload
        row = (f"<span class=id>{task.label} ({task.motion.planner})</span></td>"
               f'<td data-h="cycle">{task.trajectory.duration:.3f} s</td>'
               f'<td data-h="payload" class=t>{payload.mass:g} kg on {task.robot.payload_frame}'
               f'</td><td data-h="share of the time">{task.share * 100:g} %</td>')
        assert row in summary, task.label
    assert "<td class=t>floor</td>" in summary  # the mounting fact: both tasks' one
    for joint in matched.joints:
        words = summary.split(f">{joint.name}</a>", 1)[1].split("</tr>", 1)[0]
        rule = joint.selected.gearhead_binding
        assert f"({matched.set_by(joint, rule)})" in words, joint.name
    assert "load-to-rotor inertia ratio, 89 % of largest allowed (inspect)" in summary
    assert "10 %: every rule must hold at up to 90 % of its limit" in summary


@pytest.mark.slow
def test_the_summary_of_a_day_in_cycles_per_hour_shows_its_idle_time(tmp_path):
    """The index table's two tasks at 900 and 1200 cycles an hour, one on the wall: each
    task's share, the idle rest of the hour, and each task's mounting."""
    from hdselect.report.report_files import write_report

    mix = write_index_mix(tmp_path, cycles_per_hour=[900.0, 1200.0])
    mix.write_text(mix.read_text().replace('name = "slow"', 'name = "slow"\nmounting = "wall"'))
    result = size(None, mix)
    write_report(tmp_path / "report", result)
    summary = _summary((tmp_path / "report" / "index.html").read_text())
    for task in result.tasks:
        assert f'<td data-h="share of the time">{task.share * 100:g} %</td>' in summary
    assert result.idle > 0.1
    assert (f'idle (no task runs)</span></td><td data-h="cycle">-</td><td data-h="payload" '
            f'class=t>-</td><td data-h="share of the time">{result.idle * 100:.3g} %</td>'
            in summary)
    assert "each task&#x27;s own (under Motion)" in summary
    assert '<td data-h="mounting" class=t>wall</td>' in summary


def test_the_parts_list_of_a_mix(matched, tmp_path, capsys):
    """``--bom`` of a mix: the units, motors and masses the duty chose, the margin held."""
    bom = tmp_path / "parts.csv"
    assert main(["size", str(PICK_INSPECT), "--motor-catalog", str(MOTORS),
                 "--max-inertia-ratio", "10", "--margin", "0.1", "--bom", str(bom)]) == 0
    assert "wrote " + str(bom) in capsys.readouterr().out.replace("\n  ", " ")
    with bom.open(newline="") as file:
        rows = list(csv.DictReader(file))
    assert [row["joint"] for row in rows] == [j.name for j in matched.joints] + ["total"]
    for row, joint in zip(rows[:-1], matched.joints, strict=True):
        chosen = joint.selected
        assert (row["gearhead"], row["motor"]) == (chosen.unit.id, chosen.motor_unit.id)
        assert float(row["mass_kg"]) == pytest.approx(chosen.unit.mass + chosen.motor_unit.mass,
                                                      abs=5e-6)
        assert row["binding"] == chosen.binding and float(row["margin_required"]) == 0.1
    total = sum(j.selected.unit.mass + j.selected.motor_unit.mass for j in matched.joints)
    assert float(rows[-1]["mass_kg"]) == pytest.approx(total, abs=5e-6)


# ------------------------------------------------------------------------------- studies

STUDY = """compute = "size"
[base]
motion = "{mix}"
[[case]]
shares = [0.6, 0.4]
margin = 0.2
[[case]]
shares = [0.7, 0.3]
motor_catalog = "{motors}"
max_inertia_ratio = 10.0
margin = 0.1
[[case]]
payloads = {{pick = 0.8}}
motor_catalog = "{motors}"
prefer = "inertia"
inertia_target = 5.0
max_inertia_ratio = 30.0
time_scale = 0.9
[[case]]
shares = [0.3, 0.7]
motor_catalog = "{motors}"
max_inertia_ratio = 4.0
"""


@pytest.mark.slow
def test_grouped_mix_cases_with_margins_and_inertia_ratios_equal_the_direct_core(tmp_path):
    """One basis per task (with its inertias), pooled with each case's shares: the core's
    answer to 1e-9, margins and inertia ratios included."""
    from hdselect.study.casetasks import Inputs
    from hdselect.study.compute import size_direct
    from hdselect.study.pooled import group_cases
    from hdselect.study.spec import load_study

    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(mix=PICK_INSPECT, motors=MOTORS))
    study = load_study(path)
    inputs = Inputs()
    grouped = group_cases(study.cases, inputs, "here")
    outcomes = []
    try:
        while True:
            outcomes.append(next(grouped))
    except StopIteration as done:
        assert done.value == []
    assert [o.index for o in outcomes] == list(range(len(study.cases)))
    for case, outcome in zip(study.cases, outcomes, strict=True):
        assert outcome.ok, outcome.error
        direct = size_direct(case, inputs)
        assert differences(outcome.result, direct.to_dict()) < 1e-9, case.values
    bindings = {(j["binding"], j["binding_task"]) for o in outcomes[1:]
                for j in o.result["joints"]}
    assert ("inertia_ratio", "inspect") in bindings  # the rule bites, set by one task
    for joint in outcomes[3].result["joints"]:  # at most 4:1
        assert joint["inertia_ratio"] <= 4.0 or not joint["feasible"]
