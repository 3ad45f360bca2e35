"""`hdselect.study.group`: every grouped case against its own separate sizing run.

The oracle is the sizing core run the ordinary way for each case: load, plan, scale
the path, `size_trajectory` (for s = 1, `hdselect.size` itself), every pass of
inverse dynamics done with the case's own payload and carried gearhead masses, each sample
with the parts its payload events carry (the shipped pick-and-place picks its part up).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import hdselect
import hdselect.sizing.core
import hdselect.sizing.problem
from hdselect import Options, load_case, load_catalog, plan, summarize
from hdselect.base.errors import InputError
from hdselect.study.group import build_basis
from hdselect.study.pooled import size_case
from helpers import REPO
from helpers.studies import differences, separate

BENCHTOP = REPO / "trajectories" / "benchtop6_pick_place.toml"
SCARA = REPO / "trajectories" / "scara_wafer_transfer.toml"


@pytest.fixture(scope="module")
def benchtop():
    robot, motion = load_case(BENCHTOP)
    bare = robot.with_payload(None)
    basis = build_basis(bare, motion, motion.payload)
    assert basis.events is not None and not basis.part  # the gripper scales, the part is picked
    return bare, motion, basis


@pytest.mark.slow
@pytest.mark.parametrize(("mass", "time_scale", "given"), [
    (0.5, 1.0, {}),
    (2.0, 0.8, {"stop_time": 0.1}),
    (1.2, 1.3, {"motor_mass": 0.4, "rotor_inertia": 2e-6, "efficiency": 0.8}),
    (0.75, 1.1, {"prefer": "motor-rms", "life_basis": "L10"}),
    (1.6, 0.95, {"prefer": "margin", "stop_time": 0.2}),
    (3.0, 0.6, {}),  # shoulder joints fit nothing: their slow-downs
    (1.0, 1.0, {"margin": 0.2}),
    (2.5, 0.7, {"margin": 0.1, "prefer": "inertia"}),  # no motors: inertia orders as size
])
def test_grouped_cases_equal_their_separate_runs(benchtop, mass, time_scale, given):
    robot, motion, basis = benchtop
    units = load_catalog()
    options = Options(**{"stop_time": 0.15, "life_hours": 20000.0, "threads": 1, **given})
    assert options.mass_coupling
    grouped = size_case(basis, mass, time_scale, units, options)
    reference = separate(robot, motion, mass, time_scale, units, options)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    assert any(joint.carried_mass > 0.0 for joint in grouped.joints)
    if mass == 3.0:
        assert not grouped.feasible and all(j.slowdown for j in grouped.joints if not j.unit)


def test_a_grouped_case_at_speed_one_equals_hdselect_size(benchtop):
    _, _, basis = benchtop
    grouped = size_case(basis, 1.0, 1.0, load_catalog(), Options(stop_time=0.15,
                                                                 life_hours=20000.0))
    payload = replace(basis.payload, mass=1.0)
    reference = summarize(hdselect.size(None, BENCHTOP, payload=payload))
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9


def test_prismatic_joint_ratio_subset_and_no_payload_on_the_scara():
    robot, motion = load_case(SCARA)
    assert motion.payload is None and not all(robot.revolute)
    basis = build_basis(robot, motion, None)
    units = tuple(u for u in load_catalog() if u.ratio == 80)
    for time_scale in (0.7, 1.0):
        options = Options(stop_time=0.1, life_hours=30000.0, threads=1)
        grouped = size_case(basis, None, time_scale, units, options)
        reference = separate(robot, motion, None, time_scale, units, options)
        assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9


def test_dwells_are_kept_once_with_their_length(benchtop):
    _, _, basis = benchtop
    assert basis.weight.sum() == len(basis.trajectory.t)
    assert len(basis.rows) < 0.5 * len(basis.trajectory.t)  # 6 s of the 9.9 s cycle at rest
    assert math.isclose(float(basis.weight.max()) * basis.trajectory.dt, 3.0, rel_tol=0.01)


def grouped_and_direct(motion, payloads=(0.5, 2.0), scales=(0.5, 1.0)):
    """A payload x speed study of `motion` run grouped and direct: outcomes by case index."""
    from hdselect.study import load_study
    from hdselect.study.compute import run_size

    study = motion.parent / "study.toml"
    study.write_text(f'[base]\nmotion = "{motion.name}"\n[grid]\npayload = {list(payloads)}\n'
                     f"time_scale = {list(scales)}\n")
    cases = load_study(study).cases
    grouped = {o.index: o for o in run_size(cases, True)}
    direct = {o.index: o for o in run_size(cases, False)}
    assert {o.method for o in grouped.values()} == {"grouped"}
    assert {o.method for o in direct.values()} == {"direct"}
    for index, outcome in grouped.items():
        assert outcome.ok and direct[index].ok, (outcome.error, direct[index].error)
        assert differences(outcome.result, direct[index].result) < 1e-9
        assert outcome.result["payload_mass"] == cases[index].payload
    return cases, grouped


def starter(robot_file, out, exclude=None, mass=0.5):
    """``hdselect init``'s motion for a robot, with a payload (no frame) and an exclusion."""
    from hdselect.cli.main import main

    assert main(["init", str(robot_file), "--out", str(out)]) == 0
    text = out.read_text()
    if exclude is not None:
        text = text.replace(f'# exclude = ["{exclude}"]', f'exclude = ["{exclude}"]')
    out.write_text(text.replace("# [payload]", f"[payload]\nmass = {mass}\n# ", 1))
    return out


@pytest.mark.slow
def test_a_real_arm_with_sizing_exclude_groups_exactly(tmp_path):
    """TALOS's left arm, its gripper joint excluded by the motion file's ``[sizing]``.

    The default payload frame follows the joints sized; the faster cases leave the robot
    file's velocity limits, so their records carry those warnings. Every grouped record equals
    the direct one (`hdselect size`'s path) but for the method.
    """
    from helpers.robots import ARMS, example_robots

    motion = starter(example_robots() / ARMS["TALOS left arm"], tmp_path / "talos.toml",
                     exclude="gripper_left_joint")
    robot, _ = load_case(motion)
    assert "gripper_left_joint" not in robot.sized_joints
    assert robot.payload_frame == "wrist_left_ft_tool_link"  # the tip without the gripper
    cases, grouped = grouped_and_direct(motion)
    for index, outcome in grouped.items():
        assert outcome.result["payload_frame"] == "wrist_left_ft_tool_link"
        assert [j["name"] for j in outcome.result["joints"]] == list(robot.sized_joints)
        fast = cases[index].time_scale == 0.5
        assert fast == any(w.startswith("cycle: ") and "velocity limit" in w
                           for w in outcome.result["warnings"])


def test_mimic_followers_group_exactly(tmp_path):
    """A gripper leader whose two mimic followers (one reversed, offset) load it."""
    from helpers.robots import gripper

    motion = starter(gripper(tmp_path), tmp_path / "gripper.toml", mass=0.1)
    robot, _ = load_case(motion)
    assert set(robot.mimic) == {"left_inner", "right_outer"}
    assert robot.sized_joints == ("arm_joint", "finger_joint")
    _, grouped = grouped_and_direct(motion, payloads=(0.05, 0.2))
    for outcome in grouped.values():
        assert [j["name"] for j in outcome.result["joints"]] == ["arm_joint", "finger_joint"]


# --- gearhead and motor pairs ---------------------------------------------------------------

EXAMPLE_MOTORS = REPO / "motors" / "example_motors.toml"


@pytest.fixture(scope="module")
def benchtop_pairs():
    """The benchtop basis with the load inertias M_jj, and every example motor per joint."""
    robot, motion = load_case(BENCHTOP)
    bare = robot.with_payload(None)
    basis = build_basis(bare, motion, motion.payload, inertias=True)
    motors = hdselect.load_motors(EXAMPLE_MOTORS)
    return bare, motion, basis, {name: motors for name in robot.sized_joints}


@pytest.mark.slow
@pytest.mark.parametrize(("mass", "time_scale", "given"), [
    (0.5, 1.0, {}),  # prefer None: the lightest pair, as the core resolves it
    (1.5, 0.8, {"prefer": "size", "stop_time": 0.1}),
    (0.8, 1.2, {"prefer": "motor-rms", "efficiency": 0.8}),
    (0.5, 1.0, {"margin": 0.2, "max_inertia_ratio": 10.0}),
    (1.0, 0.9, {"prefer": "inertia", "inertia_target": 5.0, "max_inertia_ratio": 30.0}),
])
def test_grouped_pairs_equal_their_separate_runs(benchtop_pairs, mass, time_scale, given):
    robot, motion, basis, motors = benchtop_pairs
    units = load_catalog()
    options = Options(**{"stop_time": 0.15, "life_hours": 20000.0, "threads": 1, **given})
    grouped = size_case(basis, mass, time_scale, units, options, motors)
    reference = separate(robot, motion, mass, time_scale, units, options, motors)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    assert grouped.options["prefer"] == given.get("prefer", "mass")
    for joint in grouped.joints:  # the pair's figures are there, not only the gearhead's
        assert joint.motor_candidate and joint.motor_binding.startswith("motor_")
        assert joint.inertia_ratio > 0.0 and "motor_rms" in joint.utilization
    # the motors' masses are carried: the shoulder carries more than the gearheads alone
    bare = size_case(basis, mass, time_scale, units, options)
    assert grouped.joints[0].carried_mass > bare.joints[0].carried_mass


@pytest.mark.slow
def test_grouped_pairs_no_pair_fits_and_the_slow_downs_equal_the_core(benchtop_pairs):
    robot, motion, basis, motors = benchtop_pairs
    units = load_catalog()
    two = {name: tuple(m for m in ms if m.id in ("EX-22", "EX-40")) for name, ms in
           motors.items()}  # two motors keep the slow-down search short
    options = Options(stop_time=0.15, life_hours=20000.0, threads=1)
    grouped = size_case(basis, 2.5, 0.6, units, options, two)
    reference = separate(robot, motion, 2.5, 0.6, units, options, two)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    failing = [joint for joint in grouped.joints if joint.unit is None]
    assert failing and all(joint.motor is None and joint.motor_candidate for joint in failing)
    assert any(joint.slowdown and joint.slowdown > 1.0 for joint in failing)


@pytest.mark.slow
def test_a_motion_files_motors_on_some_joints_equal_the_core(benchtop_pairs, tmp_path):
    robot, _, basis, _ = benchtop_pairs
    text = BENCHTOP.read_text().replace('robot = "', 'robot = "' + str(BENCHTOP.parent) + "/")
    path = tmp_path / "with_motors.toml"
    path.write_text(text + f"""
[motor.elbow]
catalog = "{EXAMPLE_MOTORS.as_posix()}"
[motor.wrist_3]
catalog = "{EXAMPLE_MOTORS.as_posix()}"
id = "EX-16"
""")
    motion = hdselect.load_motion(path, robot)
    motors = hdselect.sizing.problem.file_motors(robot, motion)
    assert set(motors) == {"elbow", "wrist_3"} and len(motors["wrist_3"]) == 1
    units = load_catalog()
    options = Options(stop_time=0.15, life_hours=20000.0, threads=1)
    grouped = size_case(replace(basis, motion=motion), 1.0, 1.0, units, options, motors)
    reference = separate(robot, motion, 1.0, 1.0, units, options, motors)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    assert grouped.options["prefer"] == "mass"  # for every joint, as in the core
    assert [j.motor for j in grouped.joints] == [None, None, reference.joints[2].motor, None,
                                                 None, "EX-16"]


def test_grouped_pairs_refuse_what_the_core_refuses(benchtop_pairs):
    _, _, basis, motors = benchtop_pairs
    with pytest.raises(InputError, match="rotor inertia and motor mass"):
        size_case(basis, 1.0, 1.0, load_catalog(), Options(rotor_inertia=1e-6), motors)


@pytest.mark.slow
def test_a_log_of_positions_only_states_the_same_uncertainty_grouped(tmp_path):
    """The peak torque uncertainty of a positions-only log (issue 27) is the case's own,
    grouped or direct: its payload, its units' masses, its time scale."""
    robot, motion = load_case(BENCHTOP)
    trajectory = plan(robot, motion)
    step = 5  # 200 Hz, written to 4 decimals of a degree
    header = ",".join(["t", *(f"q_{n}" for n in robot.joint_names)])
    np.savetxt(tmp_path / "log.csv", np.column_stack([
        trajectory.t[::step], np.round(np.degrees(trajectory.q[::step]), 4)]),
        delimiter=",", header=header, comments="", fmt="%.17g")
    text = BENCHTOP.read_text().replace('"../robots/', f'"{REPO}/robots/')
    head = text[:text.index("[limits]")] + text[text.index("[safety]"):text.index("[[waypoint]]")]
    logged = tmp_path / "logged.toml"
    logged.write_text(head.replace('planner = "ruckig"', 'planner = "samples"')
                      .replace("dt = 0.001", "dt = 0.005") + '[samples]\nfile = "log.csv"\n')
    _, grouped = grouped_and_direct(logged, payloads=(0.5, 2.0), scales=(0.8, 1.0))
    assert all([w for w in o.result["warnings"] if "positions only" in w]
               for o in grouped.values())
