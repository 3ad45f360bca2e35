"""Payload events in what consumes tasks beside the core sizing: max-payload, studies, the
envelope, fastest, the precision figures, and every output.

The motion: the two-link arm's pick-and-place with a 1 kg part attached on arrival at
the pick and released at the end of the place's dwell (the gripper, ``[payload]``, is
carried the whole cycle). Each check has an oracle outside the code under test: `size`
itself re-run (bisection, the part's mass written into the motion), inverse dynamics and
the compliance functions with the part put on the robot by hand.
"""

from __future__ import annotations

import json
import re
from dataclasses import replace

import numpy as np
import pytest

import hdselect
from hdselect import InputError, Options, load_case, load_catalog, summarize
from hdselect.catalog.builtin import catalog_file
from hdselect.catalog.stiffness import torsion
from hdselect.cli.main import main
from hdselect.codesign.choice import duty_of
from hdselect.codesign.fastest_cycle import compare_ratios, fastest
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.payloadbounds import duty_bounds
from hdselect.codesign.payloadsizing import scaled
from hdselect.codesign.records import max_payload_json, ratios_json
from hdselect.codesign.trials import EVENTS_NOTE
from hdselect.envelope.torques import carrying_every_part
from hdselect.motion.planning import plan
from hdselect.report.codesign_tables import ratios_table
from hdselect.report.joint_figures import event_times, joint_figure
from hdselect.robot.compliance import arm_frequencies, mass_matrices
from hdselect.robot.dynamics import gravity_torques
from hdselect.sizing.core import added_mass, check_units, size, size_problem
from hdselect.sizing.diagnosis import diagnose, diagnosis_of
from hdselect.sizing.options import options_for
from hdselect.sizing.problem import Problem
from hdselect.sizing.summary import carrying_at, peak_sample
from hdselect.sizing.tasks import task_of
from hdselect.study import load_study, run_study
from hdselect.study.casetasks import Inputs
from hdselect.study.group import build_basis
from hdselect.study.pooled import diagnosed, size_case, slower_events
from hdselect.study.pooled import scaled as slower
from hdselect.study.store import journal_path
from helpers import REPO
from helpers.studies import differences

PART = """[payloads.part]
mass = 1.0
com = [0.05, 0.0, 0.0]
inertia = [[0.001, 0, 0], [0, 0.002, 0], [0, 0, 0.002]]
frame = "tool"
"""


def evented(folder, part: str = PART, attach: str = '"part"', release: str = '"part"') -> str:
    """The planar arm's pick-and-place with the part attached at the pick, released at the place."""
    text = (REPO / "trajectories" / "planar2_pick_place.toml").read_text()
    text = re.sub(r"^\[payloads\.part\].*?\n\n", "", text, flags=re.S | re.M)  # the shipped part
    text = re.sub(r"^(attach|release) = .*\n", "", text, flags=re.M)  # and its events
    text = text.replace('robot = "../robots/planar2.urdf"',
                        f'robot = "{REPO / "robots" / "planar2.urdf"}"')
    text = text.replace("[limits]", part + "\n[limits]")
    text = text.replace("dwell = 0.4\n", f"dwell = 0.4\nattach = {attach}\n", 1)
    text = text.replace("# place on the shelf\ndwell = 0.4\n",
                        f"# place on the shelf\ndwell = 0.4\nrelease = {release}\n")
    path = folder / "events.toml"
    path.write_text(text)
    return str(path)


@pytest.fixture(scope="module")
def pick(tmp_path_factory):
    path = evented(tmp_path_factory.mktemp("events"))
    robot, motion = load_case(path)
    assert [e.part for e in motion.events] == ["part", "part"]
    return path, robot, motion


def with_mass(motion, mass: float):
    """The motion with its part of `mass` [kg] (inertia scaled with it)."""
    return replace(motion, parts={**motion.parts, "part": scaled(motion.parts["part"], mass)})


def test_max_payload_scales_the_moved_part_as_a_bisection_over_size(pick):
    _, robot, motion = pick
    found = max_payload(robot, motion)
    assert found.payload.name == "part" and found.payload.mass == 1.0
    assert found.frame == "tool" and max_payload_json(found)["payload"]["part"] == "part"
    assert 0.5 < found.mass < 20.0

    def fits(mass: float) -> bool:
        return size(robot, with_mass(motion, mass)).feasible

    low, high = 0.5 * found.mass, 1.5 * found.mass
    assert fits(low) and not fits(high)
    for _ in range(16):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if fits(middle) else (low, middle)
    assert found.mass == pytest.approx(low, rel=1e-4)


def test_max_payload_with_fixed_units_checks_the_part_between_its_events(pick):
    _, robot, motion = pick
    free = max_payload(robot, motion)
    units = {j.name: j.selected.unit for j in free.selection.joints}
    fixed = max_payload(robot, motion, units={name: unit.id for name, unit in units.items()})
    trajectory = plan(robot, motion)

    def passes(mass: float) -> bool:
        heavy = with_mass(motion, mass)
        return check_units(robot, trajectory, units,
                           carried=task_of(robot, trajectory, heavy).carried).feasible

    assert passes(0.999 * fixed.mass) and not passes(1.001 * fixed.mass)
    assert fixed.mass == pytest.approx(free.mass, rel=1e-5)  # the same units bind there


def test_a_diagnosis_offers_no_lighter_payload_where_events_move_a_part(pick):
    _, robot, motion = pick
    heavy = size(robot, with_mass(motion, 2.5))
    heavy = replace(heavy, diagnoses=diagnose(heavy, payload_bounds=duty_bounds))
    assert not heavy.feasible
    kinds = {step.kind for joint in heavy.joints if joint.selected is None
             for step in diagnosis_of(heavy, joint.name).steps}
    assert kinds and "payload" not in kinds  # --payload would change the gripper, not the part
    # the same motion without events, its gripper as heavy, is offered one
    plain = replace(motion, events=(), parts={}, payload=replace(motion.payload, mass=2.5))
    whole = size(robot.with_payload(None), plain)
    whole = replace(whole, diagnoses=diagnose(whole, payload_bounds=duty_bounds))
    assert "payload" in {step.kind for joint in whole.joints if joint.selected is None
                         for step in diagnosis_of(whole, joint.name).steps}


def test_a_slowed_problem_keeps_the_samples_that_carry_the_part(pick):
    """A study runs a case s times slower, dwells too: the same samples carry the part
    (re-deriving it from the waypoint times and the file's dwells would not)."""
    path, robot, motion = pick
    task = task_of(robot, plan(robot, motion), motion)
    slowed = replace(task, trajectory=slower(task.trajectory, 1.5),
                     carried=slower_events(task.carried, 1.5))
    problem = Problem(robot, motion, load_catalog(), Options(), {}, (slowed,))
    duty = duty_of(problem, None, None, None, None, what="")[0]
    (planned,) = duty.tasks(Options())
    np.testing.assert_array_equal(planned.carried.mask, task.carried.mask)
    assert [t for t, _, _ in planned.carried.events] == pytest.approx(
        [1.5 * t for t, _, _ in task.carried.events])
    assert max_payload(problem).mass > max_payload(robot, motion).mass  # slower: heavier


def test_max_payload_refuses_events_that_move_two_parts(tmp_path):
    path = evented(tmp_path, PART + '\n[payloads.tray]\nmass = 0.3\nframe = "tool"\n',
                   '["part", "tray"]', '["part", "tray"]')
    robot, motion = load_case(path)
    with pytest.raises(InputError, match=r"part, tray.*scale one part"):
        max_payload(robot, motion)


@pytest.mark.parametrize(("mass", "time_scale"), [(1.2, 1.0), (0.7, 1.3), (2.5, 0.9)])
def test_a_grouped_case_scales_the_part_and_equals_size(pick, mass, time_scale):
    _, robot, motion = pick
    basis = build_basis(robot, motion, motion.parts["part"], part=True)
    assert basis.events is not None and basis.part
    options = Options(stop_time=0.1, life_hours=20000.0, threads=1)
    units = load_catalog()
    grouped = size_case(basis, mass, time_scale, units, options)
    # the oracle: the motion with that part mass (a study keeps its inertia), planned, its
    # task (the samples that carry the part) run s times slower (the dwells too), sized
    heavy = replace(motion, parts={"part": replace(motion.parts["part"], mass=mass)})
    planned = task_of(robot, plan(robot, heavy), heavy)
    task = replace(planned, trajectory=slower(planned.trajectory, time_scale))
    reference = summarize(diagnosed(size_problem(Problem(robot, heavy, units, options, {},
                                                         (task,)))))
    reference = replace(reference, payload_mass=mass)  # a study's payload: the part's
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9


def test_a_study_of_the_part_grouped_equals_each_case_alone(pick, tmp_path):
    path, _, _ = pick
    study = tmp_path / "study.toml"
    study.write_text(f'title = "part"\n[grid]\nmotion = ["{path}"]\n'
                     "payload = [0.4, 0.8, 1.2, 2.5]\ntime_scale = [1.0, 1.2]\n")
    cases = load_study(study)
    grouped = run_study(cases, tmp_path / "grouped.csv", workers=0)
    alone = run_study(cases, tmp_path / "alone.csv", workers=0, grouping=False)
    assert grouped.ran == alone.ran == 8
    methods = {record["method"] for record in journal(tmp_path / "grouped.csv")}
    assert methods == {"grouped"}
    records = journal(tmp_path / "grouped.csv")
    others = {record["key"]: record["result"] for record in journal(tmp_path / "alone.csv")}
    assert all(record["ok"] for record in records) and len(others) == 8
    for record in records:
        assert differences(record["result"], others[record["key"]]) < 1e-9
    # the payload is the part's mass: 0.4 kg fits on every joint, 2.5 kg does not
    by_mass = {record["result"]["payload_mass"]: record["result"]["feasible"]
               for record in records}
    assert by_mass[0.4] and not by_mass[2.5]


def test_a_study_payload_refused_where_the_events_move_two_parts(tmp_path):
    path = evented(tmp_path, PART + '\n[payloads.tray]\nmass = 0.3\nframe = "tool"\n',
                   '["part", "tray"]', '["part", "tray"]')
    (case,) = load_study_text(tmp_path, f'[grid]\nmotion = ["{path}"]\npayload = [0.5]\n')
    with pytest.raises(InputError, match=r"part, tray"):
        Inputs().duty(case)


def journal(csv) -> list[dict]:
    """A study's records, one per case."""
    return [json.loads(line) for line in journal_path(csv).read_text().splitlines()]


def load_study_text(folder, grid: str):
    study = folder / "study.toml"
    study.write_text('title = "t"\n' + grid)
    return load_study(study).cases


def test_the_envelope_states_carry_every_part_and_the_duty_its_events(pick):
    _, robot, motion = pick
    task = task_of(robot, plan(robot, motion), motion)
    states = carrying_every_part(robot, [task])
    assert [p.name for p in states.parts] == ["part"] and states.payload == robot.payload
    q = task.trajectory.q[::200]
    by_hand = gravity_torques(robot.with_parts((motion.parts["part"],)), q)
    np.testing.assert_allclose(gravity_torques(states, q), by_hand, rtol=1e-12, atol=1e-12)
    assert carrying_every_part(robot, [replace(task, carried=None)]) is robot


def test_envelope_with_an_evented_duty(pick, tmp_path):
    path, robot, motion = pick
    spec = tmp_path / "envelope.toml"
    spec.write_text(f'robot = "{REPO / "robots" / "planar2.urdf"}"\nangle_unit = "deg"\n'
                    f'[payload]\nmass = 0.15\ncom = [0.03, 0.0, 0.0]\nframe = "tool"\n'
                    "[limits]\nvelocity = 180\nacceleration = 900\njerk = 9000\n"
                    f'[duty]\nmotion = "{path}"\n')
    result = hdselect.envelope(spec=spec, settings=hdselect.SearchSettings(starts=64,
                                                                            refine=2))
    assert result.duty.tasks[0].carried is not None
    # the duty's own sizing uses the events: it is `size` of the motion
    alone = size(robot, motion)
    for mine, theirs in zip(result.duty_sizing.joints, alone.joints, strict=True):
        assert mine.load.mean_torque == pytest.approx(theirs.load.mean_torque, rel=1e-12)
    # the worst gravity state carries the part: its torque is the robot's with it
    shoulder = result.joints[0]
    carrying = carrying_every_part(robot, result.duty.tasks).with_gearheads(result.masses)
    held = gravity_torques(carrying, shoulder.gravity.q[None])[0, 0]
    assert shoulder.gravity.torque == pytest.approx(held, rel=1e-9)


def test_fastest_bounds_with_every_part_and_checks_with_the_events(pick):
    _, robot, motion = pick
    found = fastest(robot, motion)
    assert found.notes == (EVENTS_NOTE,)
    (item,) = found.tasks
    assert item.task.carried is not None
    times = [t for t, _, _ in item.task.carried.events]
    reached = item.task.trajectory.waypoint_times
    assert times == pytest.approx([reached[1], reached[3] + 0.4])
    # the check is the sizing of that trajectory with its events
    again = size_problem(Problem(robot, motion, found.check.units, found.check.options, {},
                                 (task_of(robot, item.task.trajectory, motion),)))
    for mine, theirs in zip(found.check.joints, again.joints, strict=True):
        assert mine.load.mean_torque == pytest.approx(theirs.load.mean_torque, rel=1e-12)



def test_fastest_slows_until_the_rule_with_the_events_is_at_its_limit(pick):
    """A life the optimum misses: the moves slow until the life with the part carried
    between its events (the sizing of the result's trajectory with them) meets it.

    Not the life with the part carried the whole cycle: that slowed this cycle to 5.0 s,
    where the sizing with the events finds half the life used (issue 31). The check keeps
    the units' stiffness figures (PSA rates no K1: the joints it evaluates), as
    `check_units` gives them for the same samples.
    """
    _, robot, motion = pick
    units = {"shoulder": "PSA-14-100", "elbow": "PSA-14-80"}
    found = fastest(robot, motion, units, options=options_for(motion, life_hours=2e5))
    assert found.reason == ("shoulder", "life") and found.slowdown > 1.0
    (item,) = found.tasks
    assert item.task.carried is not None and item.task.carried.mask.any()
    alone = check_units(robot, item.task.trajectory, found.units, found.check.options,
                        carried=task_of(robot, item.task.trajectory, motion).carried)
    life = alone.joints[0].selected.checks["life"]
    assert 0.99 < life.utilization <= 1.0  # at its limit, by the sizing with the events
    assert found.check.precision is not None and alone.precision is not None
    assert found.check.precision.not_rated == alone.precision.not_rated == ("shoulder", "elbow")
    np.testing.assert_array_equal(found.check.precision.poses, alone.precision.poses)

def test_compare_ratios_says_how_it_carries_the_parts(pick):
    _, robot, motion = pick
    comparison = compare_ratios(robot, motion, joints=["elbow"])
    assert comparison.base.notes == (EVENTS_NOTE,)
    assert ratios_json(comparison)["notes"] == [EVENTS_NOTE]
    (joint,) = comparison.joints
    assert EVENTS_NOTE in " ".join(ratios_table(comparison, joint).notes)
    assert all(row.cycle_time is not None for row in joint.rows if row.unit.id == "PSA-14-80")


def test_precision_poses_carry_their_state(pick):
    _, robot, motion = pick
    options = Options(precision=True, stop_time=0.1, life_hours=20000.0)
    result = size(robot, motion, options=options,
                  catalog=load_catalog([catalog_file("shg-2uh")]))
    modes, tool = result.precision.modes, result.precision.tool
    (task,) = result.tasks
    units = {j.name: (j.selected or j.strongest).unit for j in result.joints}
    gear = task.robot.with_gearheads({j.name: added_mass(j, options) for j in result.joints})
    part, mask = motion.parts["part"], task.carried.mask[:, 0]
    k1 = [units[name].stiffness.k1 for name in modes.joints]
    for carries in (True, False):  # the first evaluated pose carrying the part, not carrying
        p = int(np.flatnonzero(mask[modes.samples] == carries)[0])
        q = task.trajectory.q[modes.samples[p]][None]
        mine, other = (gear.with_parts((part,)), gear) if carries else (
            gear, gear.with_parts((part,)))
        # the arm's modes with this pose's own parts (and not the other state's)
        by_hand = arm_frequencies(mass_matrices(mine, q, modes.joints), k1)[0]
        np.testing.assert_allclose(modes.frequencies[p], by_hand, rtol=1e-9)
        wrong = arm_frequencies(mass_matrices(other, q, modes.joints), k1)[0]
        assert abs(wrong[0] - by_hand[0]) > 1e-3 * by_hand[0]
        # the holding sag: both axes are the base's -y, so the tool turns about it by the
        # joints' twists summed, each under the gravity torque of this state (the bearings'
        # tilt turns it about other axes)
        def turned(robot, q=q):
            held = gravity_torques(robot, q)[0]
            return abs(sum(float(torsion(units[name].stiffness, held[j]))
                           for j, name in enumerate(robot.joint_names)))
        assert abs(tool.holding_rotation[p][1]) == pytest.approx(turned(mine), rel=1e-9)
        assert abs(turned(other) - turned(mine)) > 1e-3 * turned(mine)


def test_outputs_name_the_events_and_what_the_peak_carried(pick, tmp_path, capsys):
    path, robot, motion = pick
    out = tmp_path / "out.json"
    assert main(["size", path, "--json", str(out)]) == 0
    terminal = capsys.readouterr().out
    document = json.loads(out.read_text())
    result = size(robot, motion)
    (task,) = result.tasks
    expected = [{"t": t, "part": name, "event": "attach" if attached else "release"}
                for t, name, attached in task.carried.events]
    assert document["events"] == expected and len(expected) == 2
    assert document["assumptions"]["payload_events"].startswith("part attached at t = ")
    assert [e["event"] for e in expected] == ["attach", "release"]
    for joint, entry in zip(result.joints, document["joints"], strict=True):
        sample = peak_sample(result, joint)
        assert abs(joint.torque[sample]) == pytest.approx(joint.load.peak_torque, rel=1e-12)
        carried = bool(task.carried.mask[sample, 0])
        assert entry["carrying"] == (["payload", "part"] if carried else ["payload"])
        assert tuple(entry["carrying"]) == carrying_at(result, sample)
        assert f"{joint.name} worst at t = {task.trajectory.t[sample]:.3g} s" in \
            " ".join(terminal.split())
    assert "payload events: part attached at t =" in " ".join(terminal.split())
    assert main(["size", path, "--report", str(tmp_path / "report")]) == 0
    page = (tmp_path / "report" / "index.html").read_text()
    assert "payload events</b>: part attached at t = " in page
    assert f"peak: {result.joints[0].name} worst at t = " in page


def test_joint_figures_mark_the_events(pick, tmp_path):
    _, robot, motion = pick
    result = size(robot, motion)
    marks = event_times(result)
    assert [label for _, label in marks] == ["attach part", "release part"]
    assert [t for t, _ in marks] == [t for t, _, _ in result.tasks[0].carried.events]
    figure = joint_figure(result, result.joints[0])
    lines = {round(float(line.get_xdata()[0]), 9) for ax in figure.axes for line in ax.lines
             if len(line.get_xdata()) == 2 and line.get_xdata()[0] == line.get_xdata()[1]}
    assert {round(t, 9) for t, _ in marks} <= lines
    texts = [text.get_text().strip() for text in figure.axes[0].texts]
    assert "attach part" in texts and "release part" in texts
    figure.savefig(tmp_path / "joint.png", dpi=80)
