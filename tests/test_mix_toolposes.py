"""A mix whose task is a motion of tool poses: solved for that task's own mounting.

Oracles: the tool-pose motion sized alone through `hdselect.size` with the same mounting
(tests/test_toolposes.py checks that path against MuJoCo and forward kinematics), which a
mix of shares (1, 0) must reproduce to the last bit; and forward kinematics of the mix
task's solved waypoints, placed on its base in the world, landing on the file's poses.
A task's mounting re-solves the poses: it does not turn the floor's joint angles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

import hdselect
from hdselect import InputError, size
from hdselect.ik.poses import pose_error
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.mounting import NAMED_BASES
from hdselect.sizing.summary import summarize
from helpers import REPO
from helpers.poses import TOLERANCE, fk, written_pose
from helpers.studies import INSPECT, differences
from helpers.studies import plain_text as plain_text

POSES = REPO / "trajectories" / "benchtop6_pick_place_poses.toml"
PLINTH = {"xyz": [0.02, -0.03, 0.05], "rpy_deg": [10, 0, 30]}
"""A base on a plinth 5 cm high, turned 30 deg and tilted 10 deg (test_toolposes' own)."""


def mix_text(folder: Path, first: str, share: float = 1.0, angle_unit: str | None = None) -> Path:
    """The tool-pose motion (with `first` added to its task table) and the inspection sweep."""
    head = f'angle_unit = "{angle_unit}"\n' if angle_unit else ""
    path = folder / "mix.toml"
    path.write_text(f'{head}[[task]]\nname = "poses"\nmotion = "{POSES}"\nshare = {share}\n'
                    f"{first}\n[[task]]\nname = \"inspect\"\nmotion = \"{INSPECT}\"\n"
                    f"share = {1.0 - share}\n")
    return path


@pytest.mark.slow
@pytest.mark.parametrize("mounting", ["floor", "wall"])
def test_a_task_of_tool_poses_is_its_motion_sized_alone(tmp_path, mounting):
    """Shares (1, 0): the duty is the tool-pose motion on that mounting, to the last bit."""
    mixed = size(None, mix_text(tmp_path, f'mounting = "{mounting}"'))
    alone = size(None, POSES, mounting=mounting)
    assert differences(plain_text(mixed), plain_text(alone)) == 0.0
    task = mixed.tasks[0]
    assert task.motion.solution is not None and task.motion.lines  # the solved motion kept
    np.testing.assert_array_equal(task.motion.waypoints, alone.motion.waypoints)
    np.testing.assert_array_equal(task.trajectory.q, alone.trajectory.q)


@pytest.mark.slow
def test_a_task_mounted_on_the_wall_solves_its_poses_again(tmp_path):
    """The wall task's joint waypoints are new IK solutions that put the tool on the same
    world poses, not the floor's joint angles under another gravity."""
    wall = size(None, mix_text(tmp_path, 'mounting = "wall"', share=0.6))
    floor_motion = hdselect.load_case(POSES)[1]
    task = wall.tasks[0]
    assert np.abs(task.motion.waypoints - floor_motion.waypoints).max() > 0.5  # rad
    base = pin.SE3(np.array(((0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0))),
                   np.zeros(3))  # the wall by its definition: base x up, base z along world x
    np.testing.assert_allclose(task.robot.gravity, base.rotation.T @ [0, 0, -9.80665],
                               atol=1e-12)
    kin = FrameKinematics(task.robot, "tool0")
    for i, q in enumerate(task.motion.waypoints):
        assert TOLERANCE.holds(*pose_error(base * fk(kin, q), written_pose(task.motion, i))), i
    assert wall.tasks[1].robot.base_pose == NAMED_BASES["floor"]  # the other task: its own


@pytest.mark.slow
def test_a_task_base_pose_reads_the_mix_file_angle_unit(tmp_path):
    """``base = {xyz, rpy}`` in a task, rpy in the mix file's angle_unit, is the motion file
    with that base: the same solution and the same sizing."""
    xyz, rpy = PLINTH["xyz"], PLINTH["rpy_deg"]
    radians = [float(np.radians(a)) for a in rpy]
    in_motion = tmp_path / "plinth.toml"
    robot = POSES.parent / ".." / "robots" / "benchtop6.urdf"  # the path the mix reads
    in_motion.write_text(POSES.read_text().replace(
        'mounting = "floor"', f"base = {{xyz = {xyz}, rpy = {rpy}}}").replace(
        '"../robots/benchtop6.urdf"', f'"{robot}"'))
    alone = size(None, in_motion)
    mixed = size(None, mix_text(tmp_path, f"base = {{xyz = {xyz}, rpy = {radians}}}",
                            angle_unit="rad"))
    files = ("motion",)  # the same motion but for its base, in another file
    assert differences({k: v for k, v in plain_text(mixed).items() if k not in files},
                       {k: v for k, v in plain_text(alone).items() if k not in files}) == 0.0
    np.testing.assert_array_equal(mixed.tasks[0].motion.waypoints, alone.motion.waypoints)
    placed = pin.SE3(Rotation.from_euler("xyz", rpy, degrees=True).as_matrix(), np.array(xyz))
    kin = FrameKinematics(mixed.tasks[0].robot, "tool0")
    q = mixed.tasks[0].motion.waypoints[2]  # the pick, straight below the approach
    assert TOLERANCE.holds(*pose_error(placed * fk(kin, q),
                                       written_pose(mixed.tasks[0].motion, 2)))


def test_a_gravity_vector_cannot_place_a_task_of_tool_poses(tmp_path):
    mix = mix_text(tmp_path, "mounting = [0.0, 0.0, -9.81]", share=0.5)
    with pytest.raises(InputError, match="does not place the base") as info:
        size(None, mix)
    assert info.value.path == mix and info.value.field == "task[0].mounting"
    assert "benchtop6_pick_place_poses.toml" in str(info.value)


@pytest.mark.slow
def test_a_mix_with_a_tool_pose_task_says_how_its_poses_were_solved(tmp_path, capsys):
    """Sized beside the inspection sweep: the duty's notes name the task whose poses were
    solved; the study summary lists both tasks; the duty is never less demanding on a
    rule of single samples than the tool-pose task alone with the same units."""
    from hdselect.cli.main import main
    from hdselect.sizing.core import check_units

    mix = mix_text(tmp_path, 'mounting = "wall"', share=0.6)
    assert main(["size", str(mix)]) in (0, 1)
    out = capsys.readouterr().out
    assert "poses: tool poses: 8 waypoints solved for 'tool0' on the wall mounting" in out
    result = size(None, mix)
    assert [t["name"] for t in summarize(result).tasks] == ["poses", "inspect"]
    task = result.tasks[0]
    units = {joint.name: (joint.selected or joint.strongest).unit for joint in result.joints}
    alone = check_units(task.robot, task.trajectory, units, result.options)
    for duty, own in zip(result.joints, alone.joints, strict=True):
        chosen, single = duty.selected or duty.strongest, own.selected or own.strongest
        for rule in ("peak", "speed", "momentary", "static"):
            assert (chosen.checks[rule].utilization
                    >= single.checks[rule].utilization * (1.0 - 1e-9)), (duty.name, rule)
