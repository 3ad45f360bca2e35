"""A commented starter motion file for a robot: `hdselect init`.

The file plans and sizes as written: the robot file's velocity limits, an
acceleration and jerk derived from them (a robot file gives neither), and a
cycle from a start pose to a second pose and back, every joint well inside its
limits. Everything the user should look at is a commented key.

With tool poses, the waypoints are the tool's poses in the world at two joint
configurations away from singularities (`regular_pair`): the first carries a ``near``
hint of its joints, so the file solves back to them, and the second lies a small move
away on the same branch. A commented ``line = true`` is offered where the arm can follow
the straight line between them, and the planner is TOPPRA, which lines need.

Every change a comment suggests plans too: uncommenting a key, or switching the planner
the way its comment says (``tests/test_starter.py`` carries each one out).
"""

from __future__ import annotations

import json
import math
import re
import textwrap

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.ik.branches import check_branch, path_crossing
from hdselect.ik.lines import LinePath, solve_line
from hdselect.ik.poses import Tolerance, pose_error, pose_from_xyz_rpy, xyz_rpy
from hdselect.ik.solver import solve_pose
from hdselect.ik.targets import Target
from hdselect.robot.joints import describe_joints
from hdselect.robot.kinematics import FrameKinematics, leader_range
from hdselect.robot.model import Robot

DEG_PER_RAD = 180.0 / math.pi

ACCELERATION_TIME = 0.5
"""The starter's acceleration reaches the velocity limit in this time [s]."""
JERK_TIME = 0.1
"""The starter's jerk reaches the acceleration limit in this time [s]."""
GUESSED_SPEED = {"deg": 90.0, "m": 0.1}
"""Speed limit where the robot file gives none [deg/s or m/s]."""
MOVE = {"deg": 30.0, "m": 0.05}
"""Largest move of a joint in the starter cycle [deg or m] ..."""
MOVE_FRACTION = 0.25
"""... and at most this fraction of its range [-]."""
INSIDE = 0.1
"""The start pose keeps this fraction of a joint's range from each limit [-]."""


def starter_motion(robot: Robot, robot_file: str, *, tool_poses: bool = False) -> str:
    """The text of a starter motion file (TOML) for a robot.

    Args:
        robot: The loaded robot.
        robot_file: The robot file as the motion file's ``robot`` key gives it
            (relative to the motion file).
        tool_poses: Write the waypoints as poses of the robot's payload frame in the
            world (the robot on the floor), not as joint positions.

    Returns:
        The motion file, commented.

    Raises:
        InputError: An argument is of the wrong type.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_robot)")
    expect_type(robot_file, (str,), "robot_file", "the robot file's name, a string")
    expect_type(tool_poses, (bool,), "tool_poses", "True or False")
    infos = [i for i in describe_joints(robot) if i.index is not None]
    units = ["deg" if i.kind != "prismatic" else "m" for i in infos]
    scale = [DEG_PER_RAD if u == "deg" else 1.0 for u in units]
    ranges = [leader_range(robot, i.name, i.lower, i.upper) for i in infos]
    start, second = _poses(ranges, units, scale)
    if tool_poses:
        pair = regular_pair(robot, np.array(start) / scale, np.array(second) / scale)
        start, second = ([_inside(v * k, i.lower * k, i.upper * k, 4)
                          for v, k, i in zip(q, scale, infos, strict=True)] for q in pair)
    speeds, guessed = [], []
    for info, unit, k in zip(infos, units, scale, strict=True):
        if math.isfinite(info.velocity_limit):
            speeds.append(_floor4(info.velocity_limit * k))
        else:
            speeds.append(GUESSED_SPEED[unit])
            guessed.append(info.name)
    grippers = [i.name for i in infos if i.sized and i.gripper_like]
    arguments = ", ".join(f"{_key(k)} = {json.dumps(v)}" for k, v in robot.xacro_args.items())
    lines = [
        f"# Starter motion for {robot.path.name}, written by `hdselect init`: it plans and sizes"
        " as it is.",
        "# Edit the waypoints, limits and payload to your cycle, then: hdselect size THIS_FILE",
        "# Joints are keyed by name here; a list (q = [...]) follows the model's order instead:",
        *textwrap.wrap(", ".join(i.name for i in infos), 96, initial_indent="#   ",
                       subsequent_indent="#   ", break_on_hyphens=False),
        "# `hdselect joints ROBOT` prints every joint with its limits.",
        "",
        f"robot = {json.dumps(robot_file)}   # relative to this file (or absolute)",
        *([f"xacro_args = {{{arguments}}}   # the .xacro robot's arguments"] if arguments else []),
        *_planner_lines(tool_poses),
        'angle_unit = "deg"      # revolute angles in degrees; prismatic joints in m',
        "dt = 0.001              # sample period [s]",
        'mounting = "floor"      # "floor", "wall", "ceiling" or '
        + ("base = {xyz = [m], rpy = [deg]} instead" if tool_poses
           else "[gx, gy, gz] in m/s^2"),
        "",
        "# [payload]             # what the tool carries: uncomment and set",
        "# mass = 1.0            # kg",
        "# com = [0.0, 0.0, 0.05]   # m, in the frame below",
        f"# frame = {json.dumps(robot.default_payload_frame)}   # the default: the tip of the "
        "longest chain of joints not excluded",
        "",
        "[sizing]                # every revolute joint gets a gearhead unless excluded here",
        (f"# exclude = {json.dumps(grippers)}   # named like a gripper's: exclude to size the "
         "arm alone" if grippers else "# exclude = []          # joints that move but get no "
         "gearhead"),
        "",
        "# Velocity: the robot file's <limit velocity>. A robot file gives no acceleration or "
        "jerk:",
        f"# these reach full speed in {ACCELERATION_TIME:g} s and full acceleration in "
        f"{JERK_TIME:g} s. Set your own.",
    ]
    for key, unit_suffix, factor in (("velocity", "/s", 1.0),
                                     ("acceleration", "/s^2", 1.0 / ACCELERATION_TIME),
                                     ("jerk", "/s^3", 1.0 / (ACCELERATION_TIME * JERK_TIME))):
        off = "# " if key == "jerk" and tool_poses else ""  # TOPPRA refuses a jerk limit
        lines += ["", f"{off}[limits.{key}]   # deg{unit_suffix} (m{unit_suffix} for prismatic "
                  "joints)" + ('; for planner = "ruckig"' if off else "")]
        for info, speed in zip(infos, speeds, strict=True):
            note = "   # not in the robot file: a guess" if key == "velocity" and \
                info.name in guessed else ""
            lines.append(f"{off}{_key(info.name)} = {_number(speed * factor)}{note}")
    lines += [
        "",
        "[safety]",
        "stop_time = 0.1         # s: an emergency stop brings every joint to rest this fast",
        "",
        "[requirements]",
        "life_hours = 20000      # required gearhead life [h]",
        'life_basis = "L50"      # "L50" (average life) or "L10" (90 % survive it)',
        "",
    ]
    if tool_poses:
        return "\n".join(lines + _tool_waypoints(robot, infos, scale, start, second)) + "\n"
    lines += [
        "# The cycle: a start pose inside every joint's limits, a second pose and back, resting",
        "# 0.5 s at each. Positions in deg (m for prismatic joints), keyed by joint name.",
    ]
    for pose in (start, second, start):
        lines += ["", "[[waypoint]]", "dwell = 0.5", "[waypoint.q]"]
        lines += [f"{_key(i.name)} = {_number(v)}" for i, v in zip(infos, pose, strict=True)]
    return "\n".join(lines) + "\n"


def _planner_lines(tool_poses: bool) -> list[str]:
    """The ``planner`` key and how to switch to the other planner, a change that plans too.

    A joint starter moves with Ruckig (its jerk limits written); a tool-pose starter with
    TOPPRA, which straight lines need and which takes no jerk limit.
    """
    if tool_poses:
        return ['planner = "toppra"      # time-optimal along the path; straight lines '
                "(line = true) need it.",
                '#   "ruckig": jerk-limited moves waypoint to waypoint, with [limits.jerk] '
                "below uncommented"]
    return ['planner = "ruckig"      # jerk-limited moves waypoint to waypoint.',
            '#   "toppra": time-optimal along the path, without [limits.jerk] (delete that '
            "table)"]


def _tool_waypoints(robot: Robot, infos, scale, start, second) -> list[str]:
    """The ``[tool]`` table and the cycle as tool poses of the payload frame [m, deg]."""
    kin = FrameKinematics(robot, robot.payload_frame)
    joints = [np.array(q) / scale for q in (start, second)]
    form = pose_form(kin)
    poses = [_rounded(kin.placement(q)) for q in joints]
    targets = [pose_from_xyz_rpy(xyz, [math.radians(a) for a in rpy]) for xyz, rpy in poses]
    written = [_written(kin, form, q) for q in joints]
    goals = targets if form == "rpy" else [goal for goal, _ in written]
    follows = isinstance(solve_line(kin, 1, goals[0], goals[1], joints[0], Tolerance()),
                         LinePath)
    near = ", ".join(f"{_key(i.name)} = {_number(v)}" for i, v in zip(infos, start, strict=True))
    lines = [
        "",
        "[tool]",
        f"frame = {json.dumps(robot.payload_frame)}   # the frame the poses place (the default: "
        "the payload's frame)",
        "# position_tolerance = 0.0001   # m: how close a solved pose must come (0.1 mm)",
        "# orientation_tolerance = 0.01  # deg (0.01 deg)",
        *(['approach = "z"          # the tool axis `axis` gives (x, y, z, -x, -y, -z)']
          if form == "axis" else []),
        "",
        "# The cycle as tool poses in the world (z up; the robot on the floor at the origin),",
        "# resting 0.5 s at each. `--mounting wall` or `ceiling` solves these same poses for",
        "# the arm hung there, where they are often out of reach: write poses for it there.",
        *FORM_WORDS[form],
        "# The first pose starts the solver at `near`, which picks the arm's branch (elbow up",
        "# or down, ...); each next pose starts from the one before. The last repeats the",
        "# first `near`, so the cycle ends where it starts (a redundant arm could end elsewhere).",
    ]
    texts = ([f"rpy = [{', '.join(_number(v) for v in rpy)}]" for _, rpy in poses]
             if form == "rpy" else [text for _, text in written])
    for k, ((xyz, _), text) in enumerate(zip((poses[0], poses[1], poses[0]),
                                             (texts[0], texts[1], texts[0]), strict=True)):
        lines += ["", "[[waypoint]]", "dwell = 0.5",
                  f"pose = {{xyz = [{', '.join(_number(v) for v in xyz)}]"
                  + (f", {text}}}" if text else "}")]
        if k != 1:  # the return too: a redundant arm solves the same pose elsewhere
            lines.append(f"near = {{{near}}}")
        if k == 1 and follows:  # only where the arm can follow the line
            lines.append("# line = true          # reach it along a straight line")
    return lines


FORM_WORDS = {
    "rpy": ["# xyz in m, rpy (roll, pitch, yaw about fixed x, y, z) in deg: the full pose."],
    "axis": ["# xyz in m, and the direction the tool's z axis points (axis): an arm of five",
             "# joints cannot take every orientation; the roll about that axis is left to it."],
    "yaw": ["# xyz in m, and the yaw of the tool about the vertical in deg: the arm keeps its",
            "# tool's tilt by its build (a SCARA); the tilt is left to it."],
    "xyz": ["# xyz in m alone: an arm of so few joints places the tool's origin; its",
            "# orientation is left to it."],
}
"""What each form of pose gives, in the starter's comment."""


def pose_form(kin: FrameKinematics) -> str:
    """The form of tool pose that fits an arm: what its joints can place.

    6 joints or more: ``"rpy"`` (the full pose); 5: ``"axis"`` (position and approach
    axis); 4 with a vertical first axis (a SCARA, a palletiser): ``"yaw"``; fewer (or 4
    otherwise): ``"xyz"``, the position alone.
    """
    if kin.dof >= 6:
        return "rpy"
    if kin.dof == 5:
        return "axis"
    if kin.dof == 4:
        first = kin.jacobian(kin.middle, aligned=True)[:, 0]
        axis = first[3:] if kin.robot.revolute[0] else first[:3]
        size = float(np.linalg.norm(axis))
        if size > 0.0 and abs(axis[2]) > 0.999 * size:
            return "yaw"
    return "xyz"


def _written(kin: FrameKinematics, form: str, q: np.ndarray) -> tuple[Target, str]:
    """The tool pose at `q` in a form fixing less than the full pose, rounded as written.

    Returns:
        The target as the file gives it (world = base: the floor), and its key beside
        ``xyz`` in the file (``""`` for a position alone).
    """
    placement = kin.placement(q)
    xyz = np.array(_rounded(placement)[0])
    if form == "axis":
        axis = [round(float(v), 5) + 0.0 for v in placement.rotation[:, 2]]
        unit = np.array(axis) / np.linalg.norm(axis)
        return (Target("axis", xyz, unit),
                f"axis = [{', '.join(_number(v) for v in axis)}]")
    if form == "yaw":
        x = placement.rotation[:, 0]
        yaw = round(math.degrees(math.atan2(x[1], x[0])), 4) + 0.0
        return Target("yaw", xyz, yaw=math.radians(yaw)), f"yaw = {_number(yaw)}"
    return Target("position", xyz), ""


def _rounded(pose) -> tuple[list[float], list[float]]:
    """A pose's xyz [m] to 10 um and rpy [deg] to 1e-4 deg, as the starter writes them."""
    xyz, rpy = xyz_rpy(pose)
    return [round(float(v), 5) + 0.0 for v in xyz], [round(float(v) * DEG_PER_RAD, 4) + 0.0
                                                      for v in rpy]


CANDIDATES = 64
"""Joint configurations tried for a starter's tool poses [-]."""


def regular_pair(robot: Robot, start: np.ndarray, second: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Two joint configurations [rad or m] whose tool poses solve back to them, on one branch.

    Candidates are the starter's own pair, then pairs drawn (seeded) around it, ever
    further, inside the middle 80 % of every range, with the same moves; the first whose
    rounded poses solve, from a `near` hint of the first, to within the default
    tolerance, without a change of branch and away from singularities, wins; else the
    most regular candidate.
    """
    kin = FrameKinematics(robot, robot.payload_frame)
    rng = np.random.default_rng(0)
    lower = np.where(np.isfinite(kin.lower), kin.lower, -np.pi)
    upper = np.where(np.isfinite(kin.upper), kin.upper, np.pi)
    margin = INSIDE * (upper - lower)
    move = second - start
    best, best_sigma = (start, second), -1.0
    for k in range(CANDIDATES):
        first = start if k == 0 else np.clip(start + rng.normal(0.0, 0.2 * (1 + k / 4), kin.dof),
                                             lower + margin, upper - margin)
        pair = (first, np.clip(first + move, lower, upper))
        sigma = min(kin.sigma_min(q) for q in pair)
        if sigma > best_sigma:
            best, best_sigma = pair, sigma
        if sigma > 0.02 and _solves_back(kin, *pair):
            return pair
    return best


def _solves_back(kin: FrameKinematics, first: np.ndarray, second: np.ndarray) -> bool:
    """The rounded poses of `first` and `second` solve from `first` on one branch.

    The move between them (straight in joint space: both rest) passes no singularity.
    """
    targets = [pose_from_xyz_rpy(xyz, [math.radians(a) for a in rpy])
               for xyz, rpy in (_rounded(kin.placement(q)) for q in (first, second))]
    one = solve_pose(kin, targets[0], first)
    two = solve_pose(kin, targets[1], one.q)
    return (one.converged and two.converged
            and not check_branch(kin, one.q, two.q).flipped
            and pose_error(kin.placement(two.q), targets[1])[0] < 1e-4
            and path_crossing(kin, np.vstack([one.q, two.q])) is None)


def _poses(ranges, units, scale) -> tuple[list[float], list[float]]:
    """A start pose near zero but inside every range, and a second pose a move away [file units].

    Each range [rad or m] is the joint's own, narrowed to keep its mimic followers within
    theirs. Values are rounded towards the inside of the range (0.1 deg, 0.1 mm).
    """
    start, second = [], []
    for (lower, upper), unit, k in zip(ranges, units, scale, strict=True):
        lo, hi = lower * k, upper * k
        step = MOVE[unit]
        if math.isfinite(lo) and math.isfinite(hi):
            margin = INSIDE * (hi - lo)
            a = float(np.clip(0.0, lo + margin, hi - margin))
            step = min(step, MOVE_FRACTION * (hi - lo))
            b = a + step if hi - a >= a - lo else a - step
        else:
            a, b = 0.0, step
        digits = 1 if unit == "deg" else 4
        start.append(_inside(a, lo, hi, digits))
        second.append(_inside(b, lo, hi, digits))
    return start, second


def _inside(value: float, lo: float, hi: float, digits: int) -> float:
    """`value` rounded to `digits` decimals, moved inside [lo, hi] if rounding left it."""
    rounded = round(value, digits)
    unit = 10.0 ** -digits
    if rounded < lo:
        rounded = math.ceil(lo / unit) * unit
    if rounded > hi:
        rounded = math.floor(hi / unit) * unit
    return round(rounded, digits)


def _floor4(value: float) -> float:
    """`value` > 0 rounded down to four significant digits: never above a file's limit."""
    unit = 10.0 ** (math.floor(math.log10(value)) - 3)
    return round(math.floor(value / unit * (1 + 1e-12)) * unit, 12)


def _number(value: float) -> str:
    """A float for TOML, without trailing noise."""
    text = f"{value:.6g}"
    return text if re.fullmatch(r"-?\d+(\.\d+)?", text) else repr(float(value))


def _key(name: str) -> str:
    """A joint name as a TOML key: bare when it can be, else quoted."""
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else json.dumps(name)
