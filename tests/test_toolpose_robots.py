"""Tool poses on robots read from MJCF (compiled by MuJoCo) and from xacro (with arguments).

Oracles that do not come from the code under test: MuJoCo's own forward kinematics of
planar2.xml, whose tool site sits where planar2.urdf's tool link and
planar2_gripper.urdf.xacro's gripper link sit (0.25 m along link2); the poses are
written from it at known joint angles, so the solved joints must be those angles
(with the orientation fixed, a planar two-link arm reaches a pose one way only).
A .xacro's arguments that move a link are checked against Pinocchio's model of the
same file written out by hand as plain URDF.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.cli.main import main
from hdselect.ik.poses import Tolerance, pose_error
from hdselect.motion.planning.solve import solve_motion
from helpers.poses import ANGLES, ROBOTS, SHORT, pose_motion, written_pose
from helpers.robots import finger_arm

WITHIN = 0.05
"""How close the solved angles must come [deg]: the solver stops within 0.1 mm and
0.01 deg of a pose, and 0.1 mm across the shorter link (0.25 m) is 0.023 deg."""


@pytest.mark.parametrize(("robot", "frame", "extra"), [
    ("planar2.xml", "tool", ""),
    ("planar2_gripper.urdf.xacro", "gripper", 'xacro_args = {gripper_mass = "1.0"}'),
])
def test_tool_poses_solve_on_robots_read_from_mjcf_and_xacro(robot, frame, extra, tmp_path):
    motion_path = pose_motion(tmp_path, str(ROBOTS / robot), frame, extra)
    loaded, motion = hdselect.load_case(motion_path)
    np.testing.assert_allclose(np.degrees(motion.waypoints), ANGLES, atol=WITHIN)
    assert motion.solution is not None and motion.solution.frame == frame
    if robot.endswith(".xacro"):  # the motion file's arguments reached the robot
        assert dict(loaded.xacro_args) == {"gripper_mass": "1.0"}
        assert loaded.moved_mass("shoulder") == pytest.approx(0.243 + 0.16875 + 1.0)
    trajectory = hdselect.plan(loaded, motion)
    np.testing.assert_allclose(np.degrees(trajectory.q[[0, -1]]), [ANGLES[0], ANGLES[-1]],
                               atol=WITHIN)


@pytest.mark.slow
def test_the_command_line_plans_tool_poses_on_a_xacro_robot_with_its_arguments(
        tmp_path, capsys):
    """--xacro-arg overrides the file's argument on the tool-pose path too."""
    motion_path = pose_motion(tmp_path, str(ROBOTS / "planar2_gripper.urdf.xacro"), "gripper",
                              'xacro_args = {gripper_mass = "1.0"}')
    out = tmp_path / "out.csv"
    assert main(["plan", str(motion_path), "--xacro-arg", "gripper_mass:=7.5", "--out",
                 str(out)]) == 0
    rows = np.genfromtxt(out, delimiter=",", names=True)
    assert np.degrees([rows["q_shoulder"][0], rows["q_elbow"][0]]) == pytest.approx(
        ANGLES[0], abs=WITHIN)
    assert main(["size", str(motion_path), "--xacro-arg", "gripper_mass:=7.5", "--json",
                 str(tmp_path / "heavy.json")]) in (0, 1)
    assert main(["size", str(motion_path), "--json", str(tmp_path / "light.json")]) in (0, 1)
    capsys.readouterr()
    heavy, light = (hdselect.load_case(motion_path, hdselect.load_robot(
        ROBOTS / "planar2_gripper.urdf.xacro", xacro_args={"gripper_mass": m}))[0]
        for m in ("7.5", "1.0"))
    assert heavy.moved_mass("shoulder") - light.moved_mass("shoulder") == pytest.approx(6.5)
    assert (tmp_path / "heavy.json").read_text() != (tmp_path / "light.json").read_text()


def test_a_pose_that_takes_a_mimic_follower_past_its_limits_is_refused_naming_it(tmp_path):
    """planar2 with a finger following the elbow 3:1 within +-0.5 rad: the elbow may turn
    +-0.5 / 3 rad = +-9.549 deg. A pose at elbow -80 deg is refused when solved, naming the
    finger; poses at elbow -8 and -3 deg solve to those angles."""
    arm = finger_arm(tmp_path)
    with pytest.raises(hdselect.InputError) as info:
        hdselect.load_case(pose_motion(tmp_path, str(arm), "tool"))
    assert str(info.value).endswith(
        "waypoint[0].pose: the tool frame 'tool' cannot reach this pose on the floor "
        "mounting: the closest it comes is 295 mm and 7.02 deg from it; in the way: the lower "
        "limit of elbow (-9.549 deg, where mimic follower 'finger' reaches its own limit)")
    inside = ([40.0, -8.0], [20.0, -3.0])
    _, motion = hdselect.load_case(pose_motion(tmp_path, str(arm), "tool", angles_each=inside))
    np.testing.assert_allclose(np.degrees(motion.waypoints), inside, atol=WITHIN)


TOOL_ORIGIN = '<origin xyz="0 0.01 0" rpy="-1.5707963 0 0"/>'
"""benchtop6.urdf's flange-to-tool0 offset, which a xacro argument sets below."""


def benchtop6_xacro(folder) -> tuple[object, str]:
    """benchtop6 with its tool offset [m] a xacro argument (default 0.01, as the URDF)."""
    text = (ROBOTS / "benchtop6.urdf").read_text()
    assert text.count(TOOL_ORIGIN) == 1
    path = folder / "benchtop6.urdf.xacro"
    path.write_text(text.replace(
        '<robot name="benchtop6">', '<robot name="benchtop6" '
        'xmlns:xacro="http://www.ros.org/wiki/xacro">\n<xacro:arg name="tool" default="0.01"/>'
    ).replace(TOOL_ORIGIN, TOOL_ORIGIN.replace("0.01", "$(arg tool)")))
    return path, text


@pytest.mark.slow
def test_a_motion_solved_for_one_set_of_xacro_arguments_is_solved_again_for_another(tmp_path):
    """The same .xacro file with a longer tool is another arm: its poses need other joints."""
    path, text = benchtop6_xacro(tmp_path)
    motion_path = tmp_path / "motion.toml"
    motion_path.write_text(SHORT.format(robot=path))
    short, solved = hdselect.load_case(motion_path)
    longer = hdselect.load_robot(path, xacro_args={"tool": 0.05})
    again = solve_motion(longer, solved)
    assert again is not solved
    by_hand = tmp_path / "longer.urdf"  # the oracle: the same arm written out by hand
    by_hand.write_text(text.replace(TOOL_ORIGIN, TOOL_ORIGIN.replace("0.01", "0.05")))
    model = pin.buildModelFromUrdf(str(by_hand))
    data = model.createData()
    tool0 = model.getFrameId("tool0")

    def error(q: np.ndarray, i: int) -> tuple[float, float]:
        pin.framesForwardKinematics(model, data, q)
        return pose_error(data.oMf[tool0], written_pose(solved, i))

    for i in range(len(solved.waypoints)):
        assert Tolerance().holds(*error(again.waypoints[i], i)), i
        assert error(solved.waypoints[i], i)[0] > 0.03  # the short tool's joints miss by 4 cm
