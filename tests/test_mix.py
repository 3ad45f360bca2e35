"""Tests of a robot's working day sized as one duty: mix files (hdselect.motion.mixfile,
hdselect.sizing.mixtasks) through the core (hdselect.sizing.core.size_tasks).

Oracles: a two-task index-table mix computed by hand from its bang-bang samples (the
table's inertia summed from the URDF's own numbers, independently of Pinocchio); each
motion sized alone (shares 1 and 0 must reproduce it to the last bit); a motion mixed
with itself; and `check_units` of each task alone with the mix's units (a rule of
single samples over the mix is the worst task's, never less).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import replace

import pytest

from hdselect import InputError, load_catalog, size
from hdselect.catalog.rules import PER_SAMPLE_CHECKS, RPM_PER_RAD_S
from hdselect.cli.main import main
from hdselect.sizing.core import check_units
from hdselect.sizing.summary import summarize
from helpers import REPO
from helpers.studies import (
    BANG_BANG,
    DT,
    INSPECT,
    PICK,
    PICK_INSPECT,
    TABLE,
    differences,
    mix_text,
    plain_text,
    write_index_mix,
)

# ------------------------------------------------------------------ the index table by hand

def table_inertia() -> float:
    """The index table's inertia about its vertical axis [kg m^2], from the URDF's numbers.

    The disk's izz plus, for each fixture block fixed to it, its own izz and m r^2 with r
    its centre of mass's distance from the axis (mount origin plus inertial origin, in x
    and y; every frame is unrotated).
    """
    root = ET.parse(TABLE).getroot()
    offset = {j.find("child").get("link"): [float(v) for v in j.find("origin").get("xyz").split()]
              for j in root.iter("joint") if j.get("type") == "fixed"}
    total = 0.0
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass = float(inertial.find("mass").get("value"))
        izz = float(inertial.find("inertia").get("izz"))
        x, y, _ = offset.get(link.get("name"), (0.0, 0.0, 0.0))
        cx, cy, _ = (float(v) for v in inertial.find("origin").get("xyz").split())
        total += izz + mass * ((x + cx) ** 2 + (y + cy) ** 2)
    return total


def hand_figures(rates: dict[str, float], idle_time: float = 0.0):
    """T_av [N m], moving mean speed [rad/s] and whole-cycle mean speed [rad/s] of the mix.

    Task k runs r_k cycles per unit time. Its moving samples carry torque
    tau_k = (J_table + J_k) a_k in magnitude and speed |qd_i|; summed over one cycle,
    sum |qd_i| DT = a DT^2 (sum_{i<n} i + sum_{i=1..n} i) = a n^2 DT^2 (the travel),
    sum |qd_i| |tau|^3 DT = tau_k^3 a n^2 DT^2, and the moving time is 2 n DT. So

        T_av^3 = sum r_k tau_k^3 a_k n_k^2 DT^2 / sum r_k a_k n_k^2 DT^2,
        N_av (moving) = sum r_k a_k n_k^2 DT^2 / sum r_k 2 n_k DT,
        N_av (whole cycle) = sum r_k a_k n_k^2 DT^2 / (sum r_k (2 n_k + m_k) DT + idle),

    the last with the idle time per unit time, where the pauses count.
    """
    table = table_inertia()
    travel = {k: a * n * n * DT * DT for k, (a, n, _, _) in BANG_BANG.items()}
    tau = {k: (table + inertia) * a for k, (a, _, _, inertia) in BANG_BANG.items()}
    cubes = sum(rates[k] * tau[k] ** 3 * travel[k] for k in BANG_BANG)
    moved = sum(rates[k] * travel[k] for k in BANG_BANG)
    moving = sum(rates[k] * 2 * BANG_BANG[k][1] * DT for k in BANG_BANG)
    whole = sum(rates[k] * (2 * BANG_BANG[k][1] + BANG_BANG[k][2]) * DT for k in BANG_BANG)
    return math.cbrt(cubes / moved), moved / moving, moved / (whole + idle_time)


def l50(unit, mean_torque: float, mean_speed: float) -> float:
    """The catalog page's L50 = 35000 (1750 / N_av,in) (T_N / T_av)^3 [h], N_av,in in rpm."""
    rules = unit.rules
    speed_in = mean_speed * RPM_PER_RAD_S * unit.ratio
    return (rules.rated_l50_hours * (rules.rated_input_speed / speed_in)
            * (unit.rated_torque / mean_torque) ** 3)


def test_index_table_mix_by_hand(tmp_path):
    shares = {"fast": 0.35, "slow": 0.65}
    mix = write_index_mix(tmp_path, shares=list(shares.values()))
    result = size(None, mix)
    (joint,) = result.joints
    cycle = {k: (2 * n + m) * DT for k, (_, n, m, _) in BANG_BANG.items()}
    mean_torque, mean_speed, _ = hand_figures({k: shares[k] / cycle[k] for k in shares})
    assert joint.load.mean_torque == pytest.approx(mean_torque, rel=1e-9)
    assert joint.load.mean_speed == pytest.approx(mean_speed, rel=1e-9)
    chosen = joint.selected
    assert chosen is not None
    assert chosen.life_hours == pytest.approx(l50(chosen.unit, mean_torque, mean_speed),
                                              rel=1e-9)
    # each task alone with the same unit: its own T_av and speed, by the same formulas
    for task, alone in zip(result.counted, joint.per_task, strict=True):
        torque, speed, _ = hand_figures({k: float(k == task.label) for k in BANG_BANG})
        assert alone.life_hours == pytest.approx(l50(chosen.unit, torque, speed), rel=1e-9)
    # the peak is the faster task's, (J_table + J_fast) a_fast, and it sets the rule
    a, _, _, inertia = BANG_BANG["fast"]
    assert joint.load.peak_torque == pytest.approx((table_inertia() + inertia) * a, rel=1e-9)
    assert result.counted[joint.setting_task("peak")].label == "fast"


def test_idle_hours_count_only_where_the_mean_speed_takes_the_whole_cycle(tmp_path):
    """Cycles per hour leave the rest of the hour idle: a pause in a whole-cycle mean speed."""
    per_hour = {"fast": 900.0, "slow": 1200.0}
    mix = write_index_mix(tmp_path, cycles_per_hour=list(per_hour.values()))
    moving_rules = load_catalog()
    whole_rules = tuple(replace(u, rules=replace(u.rules, mean_speed="whole-cycle"))
                        for u in moving_rules)
    rates = {k: per_hour[k] / 3600.0 for k in per_hour}  # cycles per second
    busy = sum(rates[k] * (2 * n + m) * DT for k, (_, n, m, _) in BANG_BANG.items())
    assert busy < 1.0
    mean_torque, moving_speed, whole_speed = hand_figures(rates, idle_time=1.0 - busy)
    for units, speed in ((moving_rules, moving_speed), (whole_rules, whole_speed)):
        result = size(None, mix, catalog=units)
        (joint,) = result.joints
        assert result.idle == pytest.approx(1.0 - busy, rel=1e-12)
        assert [t.share for t in result.tasks] == pytest.approx(
            [rates[k] * (2 * n + m) * DT for k, (_, n, m, _) in BANG_BANG.items()], rel=1e-12)
        assert joint.load.mean_torque == pytest.approx(mean_torque, rel=1e-9)
        chosen = joint.selected
        assert chosen is not None
        assert chosen.life_hours == pytest.approx(l50(chosen.unit, mean_torque, speed),
                                                  rel=1e-9)
    assert whole_speed < moving_speed  # the pauses (dwells and idle) dilute it


def test_cycles_per_hour_cannot_overfill_the_hour(tmp_path):
    mix = write_index_mix(tmp_path, cycles_per_hour=[4000.0, 2000.0])
    with pytest.raises(InputError, match="the cycles take .* s of every hour") as info:
        size(None, mix)
    assert info.value.path == mix and info.value.field == "task.cycles_per_hour"


# ------------------------------------------------------------ mixes of the shipped motions


@pytest.mark.parametrize("shares", [(1.0, 0.0), (0.0, 1.0)])
def test_a_share_of_one_is_the_motion_sized_alone(tmp_path, shares):
    mix = mix_text(tmp_path, ("pick", PICK, shares[0]), ("inspect", INSPECT, shares[1]))
    mixed = size(None, mix)
    alone = size(None, PICK if shares[0] == 1.0 else INSPECT)
    assert differences(plain_text(mixed), plain_text(alone)) == 0.0  # to the last bit
    assert len(mixed.tasks) == 2 and len(mixed.counted) == 1
    assert all(not joint.per_task for joint in mixed.joints)
    assert [(t["name"], t["share"]) for t in summarize(mixed).tasks] == [
        ("pick", shares[0]), ("inspect", shares[1])]


def test_a_motion_mixed_with_itself_is_the_motion(tmp_path):
    mix = mix_text(tmp_path, ("a", PICK, 0.4), ("b", PICK, 0.6))
    mixed, alone = size(None, mix), size(None, PICK)
    for a, b in zip(alone.joints, mixed.joints, strict=True):
        assert a.selected.unit.id == b.selected.unit.id
        for name, check in a.selected.checks.items():
            assert b.selected.checks[name].utilization == pytest.approx(
                check.utilization, rel=1e-12, abs=1e-15), (a.name, name)
        if a.selected.life_hours is not None:
            assert b.selected.life_hours == pytest.approx(a.selected.life_hours, rel=1e-12)


@pytest.fixture(scope="module")
def pick_inspect():
    return size(None, PICK_INSPECT)


@pytest.fixture(scope="module")
def pick_inspect_rated():
    """The same day on the example catalog that rates its output bearings."""
    return size(None, PICK_INSPECT, catalog=[REPO / "catalogs" / "example_rated_bearing.toml"])


def test_a_mix_is_never_less_demanding_on_a_rule_of_single_samples(pick_inspect):
    _never_less_demanding(pick_inspect)


def test_a_mix_takes_the_worse_tasks_bearing_loads(pick_inspect_rated):
    """The bearing's largest moment and forces are rules of single samples too; the task
    that sets them is named."""
    _never_less_demanding(pick_inspect_rated)
    rated = [joint for joint in pick_inspect_rated.joints
             if joint.selected.unit.bearing is not None]
    assert rated and all(joint.setting_task("bearing_moment") is not None for joint in rated)
    assert all("bearing_moment" in joint.selected.checks for joint in rated)


def _never_less_demanding(result) -> None:
    """Each task alone, checked with the mix's units by `check_units` (another path)."""
    units = {joint.name: joint.selected.unit for joint in result.joints}
    for k, task in enumerate(result.counted):
        alone = check_units(task.robot, task.trajectory, units, result.options,
                            carried=task.carried)
        for mixed, own in zip(result.joints, alone.joints, strict=True):
            for rule in PER_SAMPLE_CHECKS:
                if rule not in own.selected.checks or own.selected.checks[rule].value is None:
                    continue
                worst = mixed.selected.checks[rule].utilization
                mine = own.selected.checks[rule].utilization
                assert worst >= mine * (1.0 - 1e-12), (task.label, mixed.name, rule)
                # and the core's own check of that task alone agrees with `check_units`
                assert mixed.per_task[k].checks[rule].utilization == pytest.approx(
                    mine, rel=1e-9, abs=1e-12), (task.label, mixed.name, rule)
    for joint in result.joints:
        for rule in PER_SAMPLE_CHECKS:
            if rule in joint.selected.checks:
                assert joint.selected.checks[rule].utilization == max(
                    c.checks[rule].utilization for c in joint.per_task)


def test_the_pooled_mean_torque_lies_between_the_tasks_alone(pick_inspect):
    for joint in pick_inspect.joints:
        alone = [c.checks["mean"].value for c in joint.per_task
                 if c.checks["mean"].value is not None]
        if joint.load.mean_torque is not None and alone:
            assert min(alone) * (1 - 1e-12) <= joint.load.mean_torque <= max(alone) * (1 + 1e-12)


def test_the_report_names_the_task_that_sets_each_rule(pick_inspect):
    from hdselect.sizing.records import size_json

    document = size_json(pick_inspect)
    assert [t["name"] for t in document["tasks"]] == ["pick", "inspect"]
    assert [t["share"] for t in document["tasks"]] == [0.7, 0.3]
    assert document["tasks"][0]["payload"]["mass_kg"] == 0.2  # the mix's, over the file's 0.3
    assert document["tasks"][1]["payload"]["com_m"] == [0.04, 0.0, 0.05]
    for joint, sized in zip(document["joints"], pick_inspect.joints, strict=True):
        assert joint["set_by"]["mean"] == "pooled"
        assert joint["set_by"]["peak"] in ("pick", "inspect")
        k = sized.setting_task("momentary")
        assert joint["set_by"]["momentary"] == pick_inspect.counted[k].label
        assert [entry["task"] for entry in joint["per_task"]] == ["pick", "inspect"]


# ------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("body, field, message", [
    ('[[task]]\nmotion = "{pick}"\nshare = 0.6\n[[task]]\nmotion = "{inspect}"\nshare = 0.3\n',
     "task.share", "the shares sum to 0.9"),
    ('[[task]]\nmotion = "{pick}"\nshare = -0.5\n', "task[0].share", "at least 0"),
    ('[[task]]\nmotion = "{pick}"\nshare = 1\ncycles_per_hour = 3\n', "task[0]", "one of them"),
    ('[[task]]\nmotion = "{pick}"\nshare = 0.5\n[[task]]\nmotion = "{inspect}"\n'
     "cycles_per_hour = 3\n", "task", "not some of each"),
    ('[[task]]\nmotion = "nowhere.toml"\nshare = 1\n', "task[0].motion", "not found"),
    ('[[task]]\nmotion = "{pick}"\nshare = 0.5\n[[task]]\nmotion = "{pick}"\nshare = 0.5\n',
     "task[1].name", "give each task its own `name`"),
    ('[[task]]\nmotion = "{pick}"\nshare = 1\npayload = {{mass = 0.3, frame = "nowhere"}}\n',
     "task[0].payload.frame", "nowhere"),
    ("title = 1\n[[task]]\nmotion = \"{pick}\"\nshare = 1\n", "title", "unknown key"),
])
def test_bad_mix_files_name_the_file_and_the_field(tmp_path, body, field, message):
    path = tmp_path / "mix.toml"
    path.write_text(body.format(pick=PICK, inspect=INSPECT))
    with pytest.raises(InputError, match=message) as info:
        size(None, path)
    assert info.value.path == path and info.value.field == field


def test_a_mix_of_another_robot_names_the_mix_the_task_and_both_robots(tmp_path, capsys):
    """The mix runs the two-link arm; its task's motion is the benchtop arm's: the error is
    the mix file's, not the motion file's waypoint that names a joint planar2 lacks."""
    planar = REPO / "robots" / "planar2.urdf"
    path = mix_text(tmp_path, ("pick", PICK, 1.0))
    path.write_text(f'robot = "{planar}"\n' + path.read_text())
    with pytest.raises(InputError) as info:
        size(None, path)
    assert info.value.path == path and info.value.field == "task[0].motion"
    reason = info.value.reason
    assert "task 'pick' runs benchtop6_pick_place.toml" in reason
    assert "benchtop6.urdf" in reason and f"the mix runs {planar}" in reason
    assert main(["size", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"hdselect: error: {path}: task[0].motion: ")


def test_motions_that_disagree_on_the_duty_are_named_both(tmp_path):
    other = tmp_path / "other.toml"
    other.write_text(INSPECT.read_text().replace("life_hours = 20000", "life_hours = 9000")
                     .replace('"../robots/', f'"{REPO}/robots/'))
    path = mix_text(tmp_path, ("pick", PICK, 0.5), ("other", other, 0.5))
    with pytest.raises(InputError) as info:
        size(None, path)
    assert str(PICK) in info.value.reason and str(other) in info.value.reason
    assert "9000" in info.value.reason and "20000" in info.value.reason
    # the command line settles it
    assert size(None, path, life_hours=15000.0).options.life_hours == 15000.0


@pytest.mark.slow
def test_the_mix_files_stop_time_settles_the_duty_over_its_motions(tmp_path):
    """[safety] stop_time = 0.05 s in the mix, 0.15 s in both motions: the mix file's holds
    (as the same mix given --stop-time 0.05), with a note naming both motions. The stop
    time is the robot's safety system's, one for the duty, which the mix file describes."""
    path = mix_text(tmp_path, ("pick", PICK, 0.7), ("inspect", INSPECT, 0.3))
    path.write_text("[safety]\nstop_time = 0.05\n" + path.read_text())
    (tmp_path / "plain").mkdir()
    plain = mix_text(tmp_path / "plain", ("pick", PICK, 0.7), ("inspect", INSPECT, 0.3))
    result = size(None, path)
    assert result.options.stop_time == 0.05
    assert ("motion file: mix.toml gives safety.stop_time 0.05 for the whole duty, over "
            "benchtop6_pick_place.toml's 0.15, benchtop6_inspect.toml's 0.15") in result.warnings
    given = size(None, plain, stop_time=0.05)
    assert plain_text(result) == plain_text(given)
    assert plain_text(result) != plain_text(size(None, plain))  # 0.15 s: the stop time took effect
    path.write_text(path.read_text().replace("0.05", "0.15"))
    assert not any("stop_time" in warning for warning in size(None, path).warnings)
    # every duty-wide value alike: the required life
    path.write_text("[requirements]\nlife_hours = 30000\n" + path.read_text())
    result = size(None, path)
    assert result.options.life_hours == 30000.0
    assert ("motion file: mix.toml gives requirements.life_hours 30000 for the whole duty, "
            "over benchtop6_pick_place.toml's 20000, benchtop6_inspect.toml's 20000"
            ) in result.warnings


def test_the_command_line_takes_a_mix(tmp_path, capsys):
    status = main(["size", str(PICK_INSPECT), "--json", str(tmp_path / "out.json")])
    out = capsys.readouterr().out
    assert status == 0
    assert "peak 95% (inspect)" in out and "Which task sets each rule" in out
    assert (tmp_path / "out.json").is_file()
    status = main(["size", str(PICK_INSPECT), "--payload", "1.0"])
    err = capsys.readouterr().err
    assert status == 2 and "--payload: a mix's tasks carry their own payloads" in err
    assert err.count("\n") == 1


# ------------------------------------------------------------------------------- studies

STUDY = """compute = "size"
[base]
motion = "{mix}"
[[case]]
shares = [0.7, 0.3]
[[case]]
shares = [0.2, 0.8]
payloads = {{pick = 0.8}}
time_scale = 0.9
[[case]]
shares = [1.0, 0.0]
time_scale = 1.2
stop_time = 0.2
prefer = "margin"
[[case]]
payloads = {{pick = 3.0, inspect = 1.5}}
time_scale = 0.6
[[case]]
shares = [0.5, 0.5]
payloads = {{inspect = 0.9}}
life_hours = 40000
"""


@pytest.mark.slow
def test_grouped_mix_cases_equal_the_direct_core(tmp_path):
    """One basis per task, pooled with each case's shares: the core's answer to 1e-9."""
    from hdselect.study.casetasks import Inputs
    from hdselect.study.compute import size_direct
    from hdselect.study.pooled import group_cases
    from hdselect.study.spec import load_study

    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(mix=PICK_INSPECT))
    study = load_study(path)
    inputs = Inputs()
    grouped = group_cases(study.cases, inputs, "here")
    outcomes = []
    try:
        while True:
            outcomes.append(next(grouped))
    except StopIteration as done:
        assert done.value == []  # none left to size direct
    assert [o.index for o in outcomes] == list(range(len(study.cases)))
    for case, outcome in zip(study.cases, outcomes, strict=True):
        assert outcome.ok, outcome.error
        direct = size_direct(case, inputs)
        assert differences(outcome.result, direct.to_dict()) < 1e-9, case.values
    last = outcomes[3].result  # 3 kg and 1.5 kg, 1.67 times faster: slow-downs
    assert not last["feasible"] and any(j["slowdown"] for j in last["joints"])
    assert outcomes[0].result["tasks"][0]["share"] == 0.7
    assert outcomes[1].result["tasks"][0]["payload_mass"] == 0.8
    assert {j["binding_task"] for j in outcomes[0].result["joints"]} <= {"pick", "inspect",
                                                                           "pooled"}


def test_a_mix_study_names_its_parameters(tmp_path):
    from hdselect.study.spec import load_study

    path = tmp_path / "study.toml"
    path.write_text(f'[base]\nmotion = "{PICK_INSPECT}"\n[grid]\nshares = [[0.6, 0.3]]\n')
    with pytest.raises(InputError, match="sum to 0.9") as info:
        load_study(path)
    assert info.value.field == "grid.shares[0]"


# ----------------------------------------------------------------------------- co-design

@pytest.mark.slow
def test_max_payload_of_a_mix_is_where_the_duty_stops_fitting(tmp_path):
    """The factor found: the duty sized just below fits, just above some joint has no unit."""
    from hdselect.codesign.maxpayload import max_payload
    from hdselect.codesign.payloadsizing import at_factor
    from hdselect.motion.loading import load_case
    from hdselect.sizing.core import size_tasks

    robot, mix = load_case(PICK_INSPECT)
    result = max_payload(robot, mix)
    assert result.scaled == ("pick", "inspect") and 1.0 < result.factor < math.inf
    # what scales: the pick's 0.2 kg part (its events move it; the mix's 0.2 kg payload is
    # the gripper), the inspect's 0.3 kg camera
    assert result.masses() == pytest.approx({"pick": 0.2 * result.factor,
                                             "inspect": 0.3 * result.factor}, rel=1e-12)
    units = load_catalog()
    for factor, fits in ((0.999 * result.factor, True), (1.001 * result.factor, False)):
        tasks = at_factor(result.tasks, result.scaled, factor)
        assert size_tasks(tasks, units, result.selection.options).feasible is fits
    assert result.selection.feasible and result.selection.mix is mix
    binding = next(j for j in result.selection.joints if j.name == result.joint)
    assert binding.selected.checks[result.rule].utilization == pytest.approx(1.0, abs=2e-3)


@pytest.mark.slow
def test_max_payload_of_a_mix_of_one_task_is_its_motions(tmp_path):
    from hdselect.codesign.maxpayload import max_payload
    from hdselect.motion.loading import load_case

    path = mix_text(tmp_path, ("pick", PICK, 1.0), ("inspect", INSPECT, 0.0))
    robot, mix = load_case(path)
    mixed = max_payload(robot, mix, tasks=["pick"])
    assert mixed.scaled == ("pick",)
    alone = max_payload(*load_case(PICK))
    assert mixed.masses()["pick"] == pytest.approx(alone.mass, rel=1e-9)
    assert (mixed.joint, mixed.unit.id, mixed.rule) == (alone.joint, alone.unit.id, alone.rule)


@pytest.mark.slow
def test_fastest_of_a_mix_of_one_task_is_its_motions(tmp_path):
    from hdselect.codesign.fastest_cycle import fastest
    from hdselect.motion.loading import load_case

    path = mix_text(tmp_path, ("pick", PICK, 1.0), ("inspect", INSPECT, 0.0))
    mixed = fastest(*load_case(path))
    alone = fastest(*load_case(PICK), {name: unit.id for name, unit in mixed.units.items()})
    assert alone.reason is None and mixed.reason is None and mixed.slowdown == 1.0
    (task,) = mixed.tasks
    assert task.cycle_time == pytest.approx(alone.cycle_time, rel=1e-9)
    assert task.task.trajectory.qd == pytest.approx(alone.trajectory.qd, rel=1e-9, abs=1e-12)


@pytest.mark.slow
def test_fastest_of_a_mix_holds_the_pooled_rules_at_the_shares():
    """A required life the optima miss: every task slowed by one factor until it holds.

    The pick task's part is carried between its events: the slow-down is where the life
    with the part carried only there (the core's check, and the search's own figures on
    the same events) reaches the requirement, not the life with it carried throughout.
    """
    from functools import partial

    from hdselect.codesign.cyclerules import check_scaled
    from hdselect.codesign.fastest_cycle import fastest
    from hdselect.codesign.fastpath import PathModel
    from hdselect.codesign.trials import retimed, run_trial
    from hdselect.motion.loading import load_case
    from hdselect.sizing.mixtasks import mix_options
    from hdselect.sizing.tasks import every_part

    robot, mix = load_case(PICK_INSPECT)
    units = {"shoulder_pan": "PSA-10-80", "shoulder_lift": "PSA-14-100", "elbow": "PSA-10-80",
             "wrist_1": "PSA-08-80", "wrist_2": "PSA-08-80", "wrist_3": "PSA-08-80"}
    options = mix_options(mix, life_hours=6e5)  # shoulder_lift: 3.8e5 h at the optima
    result = fastest(robot, mix, units, options=options)
    assert result.slowdown > 1.0 and result.reason == ("shoulder_lift", "life")
    assert result.feasible
    check = next(j for j in result.check.joints
                 if j.name == "shoulder_lift").selected.checks["life"]
    assert 0.99 < check.utilization <= 1.0  # at the limit, by the core's own check
    for item in result.tasks:
        assert item.optimum < item.cycle_time
    # the search's pooled figures: failing just faster than the slow-down, passing at it
    masses = {name: unit.mass for name, unit in result.units.items()}
    assert result.tasks[0].task.carried is not None  # the pick's part: between its events
    held = [() if item.task.carried is None else item.task.carried.parts
            for item in result.tasks]
    models = [PathModel.build(every_part(item.task.robot, item.task.motion, parts),
                              item.task.motion, robot.sized_joints)
              for item, parts in zip(result.tasks, held, strict=True)]  # the search's paths
    paths = run_trial(models, [model.robot.with_gearheads(masses) for model in models],
                      [item.task.share for item in result.tasks], result.units, masses, {},
                      options, tasks=[partial(retimed, item.task) for item in result.tasks]).legs
    unit = result.units["shoulder_lift"]
    faster = check_scaled(paths, "shoulder_lift", unit, result.slowdown / 1.001, options)
    assert not faster.checks["life"].ok
    assert check_scaled(paths, "shoulder_lift", unit, result.slowdown,
                        options).checks["life"].ok


def test_the_duty_life_is_the_tasks_lives_combined_by_miners_rule(pick_inspect):
    """L50 = c / (N_av T_av^3) with N_av T_av^3 = sum |n| |T|^3 t / (moving time): damage
    per moving hour adds over the tasks, so 1 / L = sum_k w_k / L_k with w_k task k's share
    of the moving time, w_k ~ share_k / cycle_k x (its moving time per cycle). The
    share-weighted mean of the lives is then optimistic, the shortest life pessimistic.
    """
    from hdselect.catalog.rules import at_rest
    from hdselect.sizing.tasks import cycle_of

    result = pick_inspect
    for joint in result.joints:
        j = result.robot.joint_index(joint.name)
        moving = []
        for task in result.counted:
            traj = task.trajectory
            still = at_rest(traj.qd[:, j], traj.qdd[:, j])
            moving.append(task.share / cycle_of(traj) * traj.dt * float((~still).sum()))
        weights = [m / sum(moving) for m in moving]
        lives = [math.inf if c.life_hours is None else c.life_hours for c in joint.per_task]
        duty = joint.selected.life_hours
        assert duty == pytest.approx(1.0 / sum(w / life for w, life in zip(weights, lives,
                                                                            strict=True)),
                                     rel=1e-9), joint.name
        if math.inf in lives:  # a task where the joint does not move: no damage there
            continue
        shares = [task.share for task in result.counted]
        assert sum(s * life for s, life in zip(shares, lives, strict=True)) > duty * (1 - 1e-12) \
            or math.isclose(min(lives), max(lives), rel_tol=1e-9)
        assert min(lives) <= duty * (1 + 1e-12)


def test_the_share_weighted_mean_of_the_lives_weighs_the_operating_time():
    """A day of cycles per hour: shares 0.2 and 0.1 of the hour, the rest idle. Lives
    alone of 1,000 h and 4,000 h, duty 1,500 h: weighted over the operating time the
    mean is (0.2 x 1000 + 0.1 x 4000) / 0.3 = 2,000 h (+33 %), the shortest -33 %;
    weighing by the shares of the hour would give 600 h, below the shortest life."""
    from types import SimpleNamespace

    from hdselect.report.task_tables import spread_notes

    def unit(life):
        return SimpleNamespace(life_hours=life)

    joint = SimpleNamespace(name="elbow", selected=unit(1500.0), strongest=unit(1500.0),
                            per_task=(unit(1000.0), unit(4000.0)))
    result = SimpleNamespace(counted=(SimpleNamespace(share=0.2), SimpleNamespace(share=0.1)),
                             joints=(joint,))
    assert spread_notes(result)[1] == ("elbow: duty L50 1,500 h; the share-weighted mean of "
                                       "the lives alone (2,000 h) is +33%, the shortest "
                                       "(1,000 h) -33%")


@pytest.mark.slow
def test_a_day_in_cycles_per_hour_prints_a_mean_between_the_lives(tmp_path, capsys):
    """The index table at 900 and 1200 cycles an hour (53 % idle): the note's mean, in the
    terminal and the HTML report, is the lives alone weighted by the operating time."""
    from hdselect.report.report_files import write_report

    mix = write_index_mix(tmp_path, cycles_per_hour=[900.0, 1200.0])
    result = size(None, mix)
    assert result.idle > 0.5
    (joint,) = result.joints
    lives = [c.life_hours for c in joint.per_task]
    shares = [task.share for task in result.counted]
    mean = sum(s * life for s, life in zip(shares, lives, strict=True)) / sum(shares)
    assert min(lives) < mean < max(lives)
    assert main(["size", str(mix)]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert f"the share-weighted mean of the lives alone ({mean:,.0f} h)" in out
    write_report(tmp_path / "report", result)
    page = (tmp_path / "report" / "index.html").read_text()
    assert f"the share-weighted mean of the lives alone ({mean:,.0f} h)" in page


@pytest.mark.slow
def test_a_slowdown_of_a_mix_runs_every_task_that_much_slower():
    """Heavy parts, 1.67x faster: a joint no unit fits, and its slow-down s. Every task's
    trajectory run s times slower (the shares kept) must let that unit fit."""
    from hdselect.codesign.payloadsizing import at_factor
    from hdselect.codesign.trials import check_tasks
    from hdselect.motion.loading import load_case
    from hdselect.sizing.core import size_tasks
    from hdselect.sizing.mixtasks import mix_options, mix_tasks
    from hdselect.sizing.records import size_json
    from hdselect.study.pooled import scaled

    robot, mix = load_case(PICK_INSPECT)
    tasks, _ = mix_tasks(robot, mix)
    tasks = at_factor(tasks, ("pick", "inspect"), 5.0)
    fast = tuple(replace(t, trajectory=scaled(t.trajectory, 0.6)) for t in tasks)
    units, options = load_catalog(), mix_options(mix)
    result = size_tasks(fast, units, options)
    stuck = [joint for joint in result.joints if joint.selected is None]
    assert stuck and all(joint.slowdown.factor > 1.0 for joint in stuck)
    document = size_json(result)
    for joint in stuck:
        factor, unit = joint.slowdown.factor, joint.slowdown.unit
        entry = next(j for j in document["joints"] if j["name"] == joint.name)
        assert entry["slowdown"]["task_cycle_times_s"] == pytest.approx(
            {t.label: factor * t.trajectory.duration for t in fast}, rel=1e-12)
        slower = tuple(replace(t, trajectory=scaled(t.trajectory, factor)) for t in fast)
        fixed = {j.name: (j.selected or j.strongest).unit for j in result.joints}
        fixed[joint.name] = next(u for u in units if u.id == unit)
        again = check_tasks(slower, fixed, options)  # the units further out as chosen
        assert next(j for j in again.joints if j.name == joint.name).selected is not None


@pytest.mark.slow
def test_the_html_report_of_a_mix_has_its_tasks(pick_inspect, tmp_path):
    from hdselect.report.report_files import write_report

    write_report(tmp_path / "report", pick_inspect)
    page = (tmp_path / "report" / "index.html").read_text()
    assert "<section id=tasks>" in page and "Which task sets each rule" in page
    assert "benchtop6_pick_place.toml" in page and "benchtop6_inspect.toml" in page
    assert "repeated peak torque, 95 % of its limit (inspect)" in page and "pooled" in page
    assert "One duty of 2 tasks: pick (cycle 9.855 s, 70% of the time)" in page
    for joint in pick_inspect.joints:
        assert (tmp_path / "report" / f"joint_{joint.name}.png").stat().st_size > 10_000


def test_the_tables_of_a_mix_fit_a_narrow_terminal(pick_inspect, monkeypatch):
    import io

    from hdselect.report.size_tables import size_table
    from hdselect.report.tables import console_for
    from hdselect.report.task_tables import task_tables

    buffer = io.StringIO()
    monkeypatch.setenv("COLUMNS", "60")
    out = console_for(buffer)
    for item in [size_table(pick_inspect), *task_tables(pick_inspect)]:
        out.print(item)
    lines = buffer.getvalue().splitlines()
    assert max(len(line) for line in lines) <= 60
    assert any("peak 95% (inspect)" in line for line in lines)
    assert sum(line.startswith("shoulder_lift") for line in lines) >= 4  # tables moved below


@pytest.mark.slow
def test_both_task_sections_mark_exactly_the_failing_rules(monkeypatch):
    """The terminal's and the HTML's "which task sets each rule" mark a cell failing
    exactly where the chosen unit's check fails (their rows are built once)."""
    import io

    from hdselect.report.html_tasks import task_section
    from hdselect.report.tables import console_for
    from hdselect.report.task_tables import rules_table

    result = size(None, PICK_INSPECT, margin=0.8)
    failing = sum(not check.ok for joint in result.joints
                  for check in (joint.selected or joint.strongest).checks.values()
                  if check.value is not None)
    assert failing > 0
    section = task_section(result).split("<h3>Which task sets each rule</h3>", 1)[1]
    assert section.split("<h3>", 1)[0].count("class=fail") == failing
    buffer = io.StringIO()
    monkeypatch.setenv("COLUMNS", "300")
    console_for(buffer).print(rules_table(result))
    assert buffer.getvalue().count("✗") == failing


@pytest.mark.parametrize("argv, flag", [
    (["--joints", "elbo"], "--joints: unknown joint 'elbo'"),
    (["--mounting", "sideways"], "--mounting: unknown mounting 'sideways'"),
    (["--payload-com", "0", "0", "0.1"], "--payload-com: a mix's tasks carry their own"),
])
def test_bad_flags_with_a_mix_name_the_flag(argv, flag, capsys):
    assert main(["size", str(PICK_INSPECT), *argv]) == 2
    err = capsys.readouterr().err
    assert flag in err and err.count("\n") == 1


def test_a_flag_mounting_goes_on_every_task(tmp_path):
    from hdselect.sizing.records import size_json

    document = size_json(size(None, PICK_INSPECT, mounting="wall"))
    gravity = [task["gravity_m_s2"] for task in document["tasks"]]
    assert gravity[0] == gravity[1] and gravity[0] != [0.0, 0.0, -9.80665]
