"""docs/robot-files.md: its counts are the tests', its example robots the same arm.

Its console examples are run with every page's (test_docs).
"""

from __future__ import annotations

import numpy as np

import hdselect
from hdselect.robot.dynamics import inverse_dynamics
from helpers import REPO
from helpers.robots import EXAMPLE_ROBOTS, KNOWN_REFUSALS

DOC = (REPO / "docs" / "robot-files.md").read_text(encoding="utf-8")


def test_the_example_robot_count_is_the_oracle_tests():
    loaded = len(EXAMPLE_ROBOTS) - len(KNOWN_REFUSALS)
    assert f"the {loaded} of example-robot-data hdselect loads" in DOC
    assert f"All {loaded} URDFs of example-robot-data that hdselect loads" in DOC


def test_the_three_formats_of_planar2_give_its_torques():
    """planar2 as URDF, as MJCF (masses from geoms) and as xacro without gripper: the same arm.

    The URDF's inertias are written to 6 significant digits, MuJoCo derives the MJCF's
    from the boxes: they agree to that precision.
    """
    urdf = hdselect.load_robot(REPO / "robots" / "planar2.urdf")
    mjcf = hdselect.load_robot(REPO / "robots" / "planar2.xml")
    xacro = hdselect.load_robot(REPO / "robots" / "planar2_gripper.urdf.xacro",
                                xacro_args={"gripper_mass": "0"})
    rng = np.random.default_rng(11)
    q, qd, qdd = rng.uniform(-1.0, 1.0, (3, 8, 2))
    expected = inverse_dynamics(urdf, q, qd, qdd)
    np.testing.assert_allclose(inverse_dynamics(mjcf, q, qd, qdd), expected, rtol=1e-5)
    np.testing.assert_allclose(inverse_dynamics(xacro, q, qd, qdd), expected, rtol=1e-12)
