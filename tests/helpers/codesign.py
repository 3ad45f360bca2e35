"""The one-axis index table of the co-design tests, and the mean speed at which a unit's
mean-torque allowance reaches its repeated peak."""

from __future__ import annotations

import math
from pathlib import Path

from hdselect import load_case
from helpers.robots import write_motion

RPM = 60 / (2 * math.pi)  # rpm per rad/s


def index_table(directory: Path, inertia: float, theta: float, *, stop_time: float = 10.0,
                dt: float = 0.001):
    """A one-axis table of `inertia` [kg m^2] about a vertical axis, moving `theta` [rad].

    The motion's own limits are far beyond any gearhead's; a long stop time keeps the
    emergency stop and the crash far from their limits unless a test wants them. Planned
    at those limits (as `size` would) the move takes about 1 ms: only a fine `dt`
    resolves it.
    """
    (directory / "table.urdf").write_text(
        '<robot name="table"><link name="base"/><link name="disk"><inertial><mass value="1"/>'
        f'<inertia ixx="{inertia}" ixy="0" ixz="0" iyy="{inertia}" iyz="0" izz="{inertia}"/>'
        '</inertial></link><joint name="table" type="continuous"><parent link="base"/>'
        '<child link="disk"/><axis xyz="0 0 1"/><limit effort="1e6" velocity="1e6"/></joint>'
        "</robot>")
    return load_case(write_motion(directory, f"""\
        robot = "table.urdf"
        planner = "toppra"
        angle_unit = "rad"
        dt = {dt!r}
        [limits]
        velocity = 1e4
        acceleration = 1e7
        [safety]
        stop_time = {stop_time}
        [[waypoint]]
        q = [0.0]
        [[waypoint]]
        q = [{theta!r}]
    """))


def mean_speed_allowing_peak(unit) -> float:
    """Mean output speed [rad/s] at which the mean-torque allowance reaches the repeated peak."""
    input_rpm = 1750.0 * (unit.rated_torque / unit.repeated_torque) ** (1.0 / 0.33)
    return input_rpm / unit.ratio / RPM
