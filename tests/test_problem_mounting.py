"""A mounting given over a mix's (or a motion's) reaches every task, and is blamed as given.

Oracles: gravity in the base frame from `Robot.with_mounting` of the robot file alone
(each task must run on the mounting given, whatever its mix or motion file says); and
the input that gave a mounting (the parameter), which a tool pose it cannot place must
name instead of the mix file's ``task[k].mounting`` or the motion file's ``mounting``.
"""

from __future__ import annotations

import numpy as np
import pytest

from hdselect import InputError, load_case, load_robot, resolve, size
from hdselect.sizing.problem import problem_of
from helpers.mixes import PLANAR2, PLANAR2_MOTION, POSES, poses_mix, two_mountings

GRAVITY = (0.0, 0.0, -9.81)
"""A mounting as a gravity vector: it places no base, so tool poses cannot be solved."""


def gravity_on(mounting: str) -> np.ndarray:
    return load_robot(PLANAR2).with_mounting(mounting).gravity


def test_a_mounting_given_for_a_mix_reaches_every_task(tmp_path):
    """resolve and problem_of alike: the given mounting over the mix's and the motions'."""
    mix = two_mountings(tmp_path)
    own = resolve(None, mix)
    np.testing.assert_array_equal(own.tasks[0].robot.gravity, gravity_on("floor"))
    np.testing.assert_array_equal(own.tasks[1].robot.gravity, gravity_on("ceiling"))
    assert not np.allclose(gravity_on("wall"), gravity_on("ceiling"))
    robot, loaded = load_case(mix)
    for problem in (resolve(None, mix, mounting="wall"),
                    problem_of(robot, loaded, mounting="wall")):
        assert problem.mounting == "wall" and len(problem.tasks) == 2
        for task in problem.tasks:
            np.testing.assert_array_equal(task.robot.gravity, gravity_on("wall"))
        assert problem.mix is not None
        assert [task.mounting for task in problem.mix.tasks] == ["wall", "wall"]


def test_a_mounting_given_to_problem_of_mounts_a_motion():
    robot, motion = load_case(PLANAR2_MOTION)
    problem = problem_of(robot, motion, mounting="wall")
    np.testing.assert_array_equal(problem.robot.gravity, gravity_on("wall"))
    np.testing.assert_array_equal(problem.tasks[0].robot.gravity, gravity_on("wall"))
    alone = resolve(None, PLANAR2_MOTION, mounting="wall")
    np.testing.assert_array_equal(problem.tasks[0].trajectory.q, alone.tasks[0].trajectory.q)


def test_a_tool_pose_a_given_mounting_cannot_place_names_the_parameter(tmp_path):
    """Not the mix file's task[k].mounting, nor the motion file's mounting: the caller's."""
    for given in (poses_mix(tmp_path), POSES):
        with pytest.raises(InputError, match="does not place the base") as info:
            size(None, given, mounting=GRAVITY)
        assert info.value.path is None and info.value.field == "mounting", given
        assert "benchtop6_pick_place_poses.toml" in str(info.value)
