"""The precision figures along a cycle: resonance windows, the poses evaluated, mixes,
joints left rigid and units that rate no stiffness."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.catalog.builtin import catalog_file
from hdselect.sizing.core import decimated
from hdselect.sizing.precision import NEAR_RESONANCE, PRECISION_POSES, Window, evaluated_poses
from hdselect.sizing.tasks import pooled, task_rows

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
