"""The precision figures along a cycle: resonance windows, the poses evaluated, mixes,
joints left rigid and units that rate no stiffness."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.catalog.builtin import catalog_file
from hdselect.catalog.units import Stiffness
from hdselect.robot.payload import frame_id
from hdselect.sizing.core import decimated
from hdselect.sizing.precision import NEAR_RESONANCE, PRECISION_POSES, Window, evaluated_poses
from hdselect.sizing.tasks import pooled, task_rows
from helpers.motions import make_motion
from helpers.robots import BOX, revolute, urdf

ROOT = Path(__file__).resolve().parents[1]
TRAJECTORIES = ROOT / "trajectories"


def shg_units() -> list[hdselect.Unit]:
    """The built-in SHG-2UH series (every unit rates K1)."""
    return [u for u in hdselect.load_catalog([catalog_file("shg-2uh")]) if u.series == "SHG-2UH"]


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True, by a plain walk."""
    found, start = [], None
    for i, value in enumerate(mask):
        if value and start is None:
            start = i
        if not value and start is not None:
            found.append((start, i - 1))
            start = None
    if start is not None:
        found.append((start, len(mask) - 1))
    return found


def test_index_table_runs_near_resonance_where_its_input_speed_is_within_ten_percent() -> None:
    result = hdselect.size(None, TRAJECTORIES / "index_table_indexing.toml", catalog=shg_units())
    (joint,) = result.precision.joints
    trajectory = result.trajectory
    f_n = math.sqrt(joint.unit.stiffness.k1 / 0.061581) / (2 * math.pi)  # J by hand
    rpm = np.abs(trajectory.qd[:, 0]) * joint.unit.ratio * 60.0 / (2 * math.pi)
    near = np.abs(rpm - 30.0 * f_n) <= 0.1 * 30.0 * f_n
    expected = [Window(0, float(trajectory.t[a]), float(trajectory.t[b] + trajectory.dt))
                for a, b in runs(near)]
    assert NEAR_RESONANCE == 0.1 and expected  # the motion crosses it, speeding and slowing
    assert len(joint.near_resonance) == len(expected)
    for got, want in zip(joint.near_resonance, expected, strict=True):
        assert got.task == 0
        assert got.start == pytest.approx(want.start, abs=1e-12)
        assert got.end == pytest.approx(want.end, abs=1e-12)
    assert joint.near_resonance_time == pytest.approx(np.count_nonzero(near) * trajectory.dt)


def test_long_cycles_evaluate_spread_poses_each_tasks_ends_and_each_joints_worst_sample() -> None:
    result = hdselect.size(None, TRAJECTORIES / "mixes" / "benchtop6_pick_inspect.toml",
                           catalog=shg_units())
    precision = result.precision
    samples_task = np.concatenate([np.full(len(task.trajectory.t), k)
                                   for k, task in enumerate(result.counted)])
    n = len(samples_task)
    assert n > PRECISION_POSES
    poses = precision.poses
    assert np.all(np.diff(poses) > 0) and len(poses) <= PRECISION_POSES + 2 * 2 + 6
    assert np.array_equal(precision.tool.samples, poses)
    assert np.array_equal(precision.modes.samples, poses)
    for joint, sized in zip(precision.joints, result.joints, strict=True):
        worst = int(np.argmax(np.abs(sized.torque)))
        assert worst in poses  # the largest torque's pose is one of them
        assert joint.max_torsion_sample == worst
        assert len(joint.frequency) == len(poses)
    first = len(result.counted[0].trajectory.t)
    assert {0, first - 1, first, n - 1} <= set(poses.tolist())  # each task's ends


def test_a_mix_names_the_task_of_every_window_and_worst_pose() -> None:
    result = hdselect.size(None, TRAJECTORIES / "mixes" / "benchtop6_pick_inspect.toml",
                           catalog=shg_units())
    cycles = [task.trajectory.duration + task.trajectory.dt for task in result.counted]
    tasks_seen = set()
    for joint in result.precision.joints:
        for window in joint.near_resonance:
            assert window.task in (0, 1)
            assert 0.0 <= window.start < window.end <= cycles[window.task] + 1e-9
            tasks_seen.add(window.task)
        assert joint.near_resonance_time == pytest.approx(
            sum(w.end - w.start for w in joint.near_resonance))
    lengths = [len(task.trajectory.t) for task in result.counted]
    lowest = result.precision.modes.samples[result.precision.modes.lowest]
    assert 0 <= lowest < sum(lengths)
    assert result.precision.modes.lowest_frequency == pytest.approx(
        result.precision.modes.frequencies.min())


def test_joints_left_out_are_rigid_and_not_springs() -> None:
    result = hdselect.size(None, TRAJECTORIES / "benchtop6_contour.toml", catalog=shg_units(),
                           exclude=["wrist_3"])
    precision = result.precision
    assert precision.rigid == ("wrist_3",)
    assert "wrist_3" not in precision.modes.joints
    assert [j.name for j in precision.joints] == list(result.robot.sized_joints)
    assert precision.tool is not None


def test_a_unit_without_k1_leaves_the_whole_arm_figures_out_and_is_named() -> None:
    robot = hdselect.load_robot(ROOT / "robots" / "planar2.urdf")
    motion = hdselect.load_motion(TRAJECTORIES / "planar2_pick_place.toml", robot)
    robot = robot.with_payload(motion.payload) if motion.payload is not None else robot
    trajectory = hdselect.plan(robot, motion)
    psa = next(u for u in hdselect.load_catalog() if u.id == "PSA-14-100")
    shg = next(u for u in shg_units() if u.id == "SHG-14-100-2UH")
    result = hdselect.check_units(robot, trajectory, {"shoulder": psa, "elbow": shg})
    precision = result.precision
    assert precision.not_rated == ("shoulder",)
    assert precision.tool is None and precision.modes is None
    shoulder, elbow = precision.joints
    assert not shoulder.rated and shoulder.unit is psa and shoulder.max_torsion is None
    assert elbow.rated and elbow.max_torsion > 0.0 and elbow.lowest_frequency > 0.0


def test_evaluated_poses_are_every_sample_of_a_short_cycle() -> None:
    robot = hdselect.load_robot(ROOT / "robots" / "planar2.urdf")
    motion = hdselect.load_motion(TRAJECTORIES / "planar2_pick_place.toml", robot)
    trajectory = decimated(hdselect.plan(robot, motion), 500)
    result = hdselect.size_trajectory(robot, trajectory, shg_units())
    n = len(result.trajectory.t)
    assert n <= PRECISION_POSES
    assert np.array_equal(result.precision.poses, np.arange(n))
    samples = result.precision.tool.samples
    assert np.array_equal(samples, result.precision.poses)
    pooled_samples = pooled(result.tasks)
    assert np.array_equal(evaluated_poses(pooled_samples, [j.torque for j in result.joints]),
                          samples)
    assert task_rows(pooled_samples, 0) == slice(0, n)


def test_a_joint_moving_nothing_has_no_finite_frequency_and_never_runs_near_it(
        tmp_path: Path) -> None:
    # the outer joint turns a point mass on its own axis: M_jj = 0, f_n = inf, nothing rings
    point = ('<inertial><origin xyz="0.05 0 0"/><mass value="0.2"/>'
             '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>')
    urdf(tmp_path, '<link name="base"/>' + revolute("j1", "base", "one", axis="0 0 1")
         + f'<link name="one">{BOX.format(x=0.2, m=1.0, i=2e-3)}</link>'
         + revolute("j2", "one", "two", axis="1 0 0", xyz="0.4 0 0")
         + f'<link name="two">{point}</link>', "arm.urdf")
    robot, motion = make_motion(tmp_path, "ruckig", [(0.0, -1.5), (1.5, 1.8)],
                                velocity=3.0, acceleration=20.0, jerk=200.0)
    result = hdselect.size_trajectory(robot, hdselect.plan(robot, motion), shg_units())
    one, two = result.precision.joints
    assert math.isinf(two.lowest_frequency) and two.near_resonance == ()
    assert two.near_resonance_time == 0.0
    assert math.isfinite(one.lowest_frequency)
    assert math.isfinite(result.precision.modes.lowest_frequency)
    assert np.isinf(result.precision.modes.frequencies[:, 1]).all()


def test_a_mixs_deflections_are_the_jacobian_times_each_tasks_own_twists() -> None:
    units = [replace(u, stiffness=Stiffness(k1=u.stiffness.k1), bearing=None)
             for u in shg_units()]  # K1 alone, no bearing tilt: dx = J(q) (-tau / K1)
    result = hdselect.size(None, TRAJECTORIES / "mixes" / "benchtop6_pick_inspect.toml",
                           catalog=units, mass_coupling=False, bearing_loads=False)
    tool = result.precision.tool
    assert tool.bearing_tilt == ()
    k1 = np.array([j.selected.unit.stiffness.k1 for j in result.joints])
    torque = np.stack([j.torque for j in result.joints], axis=1)
    first = len(result.counted[0].trajectory.t)
    states = set()
    for i in np.linspace(0, len(tool.samples) - 1, 9).astype(int):
        sample = int(tool.samples[i])
        k, row = (0, sample) if sample < first else (1, sample - first)
        task = result.counted[k]  # its own payload, and the parts its events carry there
        held = () if task.carried is None else tuple(
            part for part, on in zip(task.carried.parts, task.carried.mask[row], strict=True)
            if on)
        robot = task.robot.with_parts((*task.robot.parts, *held)) if held else task.robot
        states.add((k, bool(held)))
        model, data = robot.model, robot.model.createData()
        config = robot.configuration(task.trajectory.q[row:row + 1])[:, 0]
        jacobian = pin.computeFrameJacobian(model, data, config, frame_id(model, "tool0"),
                                            pin.LOCAL_WORLD_ALIGNED)
        gravity = pin.computeGeneralizedGravity(model, data, config)
        np.testing.assert_allclose(tool.translation[i], jacobian[:3] @ (-torque[sample] / k1),
                                   atol=1e-12)
        np.testing.assert_allclose(tool.holding_translation[i], jacobian[:3] @ (-gravity / k1),
                                   atol=1e-12)
        np.testing.assert_allclose(tool.holding_rotation[i], jacobian[3:] @ (-gravity / k1),
                                   atol=1e-12)
    assert {(0, True), (0, False)} <= states  # the pick's samples with and without its part
