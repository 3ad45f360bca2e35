"""Read a motion file (TOML): the waypoints, limits and planner a robot's cycle is made of.

Everything is validated here, once, and converted to SI: revolute positions
[rad], prismatic positions [m], times [s]. The file's ``angle_unit`` applies to
revolute positions and every revolute limit (and to a ``samples`` log);
prismatic joints are always in m, m/s, m/s^2 and m/s^3.

A ``samples`` log is a CSV file with a header row: ``t`` [s], ``q_<joint>`` for
every joint, and optionally ``qd_<joint>`` and ``qdd_<joint>`` for every joint;
other columns are ignored.

``[motor]`` gives the motors behind the gearheads: for every rotary joint, and
``[motor.JOINT]`` for one joint (replacing ``[motor]`` there). Each is a fixed motor
(its data inline, or ``id`` from ``catalog``) or ``catalog`` alone, every motor of
which is a candidate; files are relative to the motion file.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base import bounds
from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import check_keys, number, table_of
from hdselect.catalog.motors import Motor
from hdselect.ik.lines import LinePath
from hdselect.motion.bagfile import read_samples
from hdselect.motion.events import Event, payload_table, read_events
from hdselect.motion.limits import (
    JointLists,
    beyond_robot,
    limit_units,
    per_joint,
    vector,
    velocity_limit,
)
from hdselect.motion.logfile import SampleLog
from hdselect.motion.motor_tables import motion_file_motors
from hdselect.motion.option_specs import (
    file_keys,
    file_options,
)
from hdselect.motion.robot_named import (
    load_named,
    named_file,
    read_motion_toml,
    xacro_args_of,
)
from hdselect.motion.sizing_table import bearing_offsets, sizing_joints
from hdselect.motion.toolposes import ToolPoses, ToolSolution, read_base
from hdselect.motion.waypoints import read_waypoints
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import MOUNTINGS, BasePose
from hdselect.robot.payload import Payload

logger = logging.getLogger(__name__)


PLANNERS = ("ruckig", "toppra", "samples")
"""Valid values of the ``planner`` key."""


ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
"""Valid values of ``angle_unit`` and their size [rad]."""


_TOP_KEYS = ("robot", "xacro_args", "planner", "angle_unit", "dt", "mounting", "payload",
             "limits", "safety", "requirements", "precision", "waypoint", "samples", "sizing",
             "motor", "tool", "base", "payloads", "event")


_LIMIT_KEYS = ("velocity", "acceleration", "jerk", "torque")


_NEEDED = {"ruckig": ("velocity", "acceleration", "jerk"), "toppra": ("velocity", "acceleration"),
           "samples": ()}


_ALLOWED = {"ruckig": _NEEDED["ruckig"], "toppra": ("velocity", "acceleration", "torque"),
            "samples": ()}


@dataclass(frozen=True, eq=False)
class Motion:
    """A validated motion file, all in SI units, joints named.

    A Motion is planned against a Robot with the same joints (`hdselect.plan`); it
    does not hold one. What the file says about the robot (its file, payload and
    mounting) is kept here as given, and applied by `robot_for_motion`. Waypoints
    written as tool poses are solved for a robot by `hdselect.motion.planning.solve.solve_motion`
    (which `load_case`, `plan` and `size` call): until then their rows are NaN.

    Attributes:
        path: The motion file.
        joint_names: The joints, in the order of the arrays' columns.
        planner: ``"ruckig"``, ``"toppra"`` or ``"samples"``.
        dt: Sample period of the planned trajectory [s].
        waypoints: Joint positions to pass through [rad or m], shape (k, dof); (0, dof)
            for the samples planner; NaN rows for tool poses not solved yet.
        dwells: Time held at rest after reaching each waypoint [s], shape (k,).
        velocity_limit: Joint speed limit [rad/s or m/s], shape (dof,), or None.
        acceleration_limit: Joint acceleration limit [rad/s^2 or m/s^2], (dof,), or None.
        jerk_limit: Joint jerk limit [rad/s^3 or m/s^3], shape (dof,), or None.
        torque_limit: Joint torque limit for TOPPRA [N m or N], shape (dof,), or None.
        stop_time: Time to stop every joint in an emergency stop [s], or None.
        life_hours: Required gearhead life [h], or None.
        life_basis: The basis of `life_hours`, ``"L10"`` or ``"L50"``, or None if not given.
        margin: Design margin of every rule [-] (``[requirements] margin``), or None.
        samples: The logged trajectory for the samples planner, else None.
        robot_file: The file's ``robot``, relative to the motion file resolved, or None.
        payload: The file's ``[payload]``, or None.
        parts: The file's named parts (``[payloads.NAME]``), and ``"payload"`` (the
            ``[payload]`` table) where an event names it, by name (`hdselect.motion.events`).
        events: Where the parts are attached and released: on waypoints in waypoint order,
            a log's ``[[event]]`` in time order; empty where the file gives none.
        mounting: The file's ``mounting`` (a name or a gravity vector) or its ``base``
            pose, or None when it gives neither.
        angle_unit: The file's ``angle_unit`` (``"deg"`` or ``"rad"``), for messages.
        sized_joints: The file's ``[sizing] joints``, or None when it gives none.
        excluded_joints: The file's ``[sizing] exclude``: joints that move but get no gearhead.
        velocity_from_robot: Joints whose velocity limit the file does not give, so the
            robot file's velocity limit is used.
        warnings: What the file asks beyond the robot file's limits, or how its lists are
            read, one line each.
        motors: The file's ``[motor]``: candidate motors per rotary joint (one for a
            fixed motor), or None when it gives none.
        motor_joints: The joints the file gives a ``[motor.JOINT]`` block of their own.
        tool: The file's tool poses and ``[tool]`` table, or None when every waypoint
            gives joint positions.
        lines: The straight lines, solved into joint samples that the path passes through
            (empty until solved, and for a motion without lines).
        solution: How the tool poses were solved, or None until they are.
        xacro_args: The file's ``xacro_args`` for the ``.xacro`` robot it names.
        bearing_offset: The file's ``[sizing] bearing_offset_m``: where a joint's output
            flange sits along its axis from the joint origin [m], by joint name.
        max_torsion: ``[precision] max_torsion_arcmin``: the largest twist of each
            sized joint's unit [rad], by joint name (``"*"``: every joint); empty
            where the file gives none.
        min_natural_frequency: ``[precision] min_natural_frequency_hz``: each sized
            joint's lowest single-axis natural frequency [Hz], the same way.
        max_tool_deflection: ``[precision] max_tool_deflection_mm`` [m], or None.
        min_arm_frequency: ``[precision] min_arm_frequency_hz`` [Hz], or None.
        allow_flip: ``[tool] allow_flip`` (or ``--allow-flip``): a ``near`` hint the solved
            pose cannot honour is a warning, not an error; None where not given.
    """

    path: Path
    joint_names: tuple[str, ...]
    planner: str
    dt: float
    waypoints: np.ndarray
    dwells: np.ndarray
    velocity_limit: np.ndarray | None = None
    acceleration_limit: np.ndarray | None = None
    jerk_limit: np.ndarray | None = None
    torque_limit: np.ndarray | None = None
    stop_time: float | None = None
    life_hours: float | None = None
    life_basis: str | None = None
    samples: SampleLog | None = None
    robot_file: Path | None = None
    payload: Payload | None = None
    mounting: str | tuple[float, float, float] | BasePose | None = None
    angle_unit: str = "deg"
    sized_joints: tuple[str, ...] | None = None
    excluded_joints: tuple[str, ...] = ()
    velocity_from_robot: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    motors: Mapping[str, tuple[Motor, ...]] | None = None
    motor_joints: tuple[str, ...] = ()
    margin: float | None = None
    tool: ToolPoses | None = None
    lines: tuple[LinePath, ...] = ()
    solution: ToolSolution | None = None
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    bearing_offset: Mapping[str, float] = field(default_factory=dict)
    max_torsion: Mapping[str, float] = field(default_factory=dict)
    min_natural_frequency: Mapping[str, float] = field(default_factory=dict)
    max_tool_deflection: float | None = None
    min_arm_frequency: float | None = None
    allow_flip: bool | None = None
    parts: Mapping[str, Payload] = field(default_factory=dict)
    events: tuple[Event, ...] = ()

    def refuse_motors(self, command: str) -> None:
        """Refuse the file's ``[motor]`` where `command` does not choose motors yet.

        Raises:
            InputError: The file gives motors.
        """
        if self.motors:
            raise InputError(f"{command} does not choose motors yet; the motors given here "
                             "would be left out: remove [motor] (size and compare choose "
                             "motor and gearhead together)", path=self.path, field="motor")

    def check_joints(self, robot: Robot) -> None:
        """Check that the motion was read for this robot's joints.

        Raises:
            InputError: The joints differ.
        """
        if robot.joint_names != self.joint_names:
            raise InputError(f"the motion was read for joints {', '.join(self.joint_names)}; "
                             f"the robot has {', '.join(robot.joint_names)}", path=self.path)


def load_motion(path: str | Path, robot: Robot | str | Path | None = None) -> Motion:
    """Read and validate a motion file.

    The robot is needed to read the file: list-form values follow its joint order,
    ``angle_unit`` applies to its revolute joints only, and waypoints are checked
    against its position limits.

    Args:
        path: The motion file (TOML).
        robot: The robot, a robot file, or None to load the file named by the motion
            file's ``robot`` key (relative to the motion file).

    Returns:
        The motion, in SI units. The file's payload and mounting are recorded, not
        applied: see `robot_for_motion` and `load_case`.

    Raises:
        InputError: The motion file, the robot file or the log is missing, malformed
            or inconsistent; the message names the file and the field.
    """
    path = bounds.file_argument(path, "path")
    bounds.expect_type(robot, (Robot, str, Path, type(None)), "robot",
                       "a Robot, a robot file or None")
    doc = read_motion_toml(path)
    check_keys(doc, _TOP_KEYS, path, "")
    planner = _choice(doc, "planner", PLANNERS, path)
    angle_unit = _choice(doc, "angle_unit", tuple(ANGLE_UNITS), path)
    unit = ANGLE_UNITS[angle_unit]
    dt = number(doc, "dt", path, "", default=0.001, bound=bounds.TIME)
    file_payload = payload_table(doc["payload"], path) if "payload" in doc else None
    file_mounting = mounting_of(doc, path, unit, angle_unit)
    robot_file = named_file(doc, path, must_exist=robot is None)  # a robot given overrides it
    xacro_args = xacro_args_of(doc, path)
    if robot is None:
        if robot_file is None:
            raise InputError("no robot given: set the key or pass a robot file",
                             path=path, field="robot")
        robot = load_named(robot_file, xacro_args, path)
    elif not isinstance(robot, Robot):
        robot = load_robot(robot)
    scale = np.where(robot.revolute, unit, 1.0)
    units = [("deg" if unit != 1.0 else "rad") if r else "m" for r in robot.revolute]
    limits = table_of(doc.get("limits", {}), path, "limits")
    check_keys(limits, _LIMIT_KEYS, path, "limits")
    for key in _NEEDED[planner]:
        if key not in limits and key != "velocity":  # velocity: the robot file's by default
            raise InputError(f"required by planner '{planner}'", path=path, field=f"limits.{key}")
    for key in limits:
        if key not in _ALLOWED[planner]:
            raise InputError(f"not used by planner '{planner}'; remove it (planner "
                             f"'{planner}' takes: {', '.join(_ALLOWED[planner]) or 'no limits'})",
                             path=path, field=f"limits.{key}")
    lists = JointLists(robot)
    lim = {k: frozen(per_joint(v, robot, path, f"limits.{k}", bound=bounds.MOTION_LIMITS[k],
                                scale=np.ones(robot.dof) if k == "torque" else scale,
                                units=limit_units(k, units), lists=lists)
                     * (1.0 if k == "torque" else scale))
           for k, v in limits.items() if k != "velocity"}
    from_robot: tuple[str, ...] = ()
    warnings: list[str] = []
    if "velocity" in _NEEDED[planner]:
        velocity, from_robot = velocity_limit(limits.get("velocity"), robot, path, scale, units,
                                               lists, planner)
        lim["velocity"] = frozen(velocity)
        warnings += beyond_robot(velocity, robot, scale, units, from_robot)
    sizing = sizing_joints(doc, path, robot)
    for table in ("safety", "requirements", "precision"):
        check_keys(table_of(doc.get(table, {}), path, table), file_keys("motion", table), path,
                   table)
    options = file_options(doc, path, "motion", robot.joint_names)
    samples, tool = None, None
    if planner == "samples":
        if "waypoint" in doc:
            raise InputError("planner 'samples' takes its motion from [samples] file; remove "
                             "the waypoints", path=path, field="waypoint")
        waypoints, dwells = np.empty((0, robot.dof)), np.empty(0)
        samples = read_samples(doc.get("samples", {}), path, robot, scale, units,
                               (unit, angle_unit))
    else:
        if "samples" in doc:
            raise InputError(f"only for planner 'samples' (a logged trajectory), not "
                             f"'{planner}': remove [samples], or set planner = \"samples\"",
                             path=path, field="samples")
        waypoints, dwells, tool = read_waypoints(doc, path, robot, scale, units, lists,
                                                 (unit, angle_unit))
        for k in tool.lines if tool is not None and planner != "toppra" else ():
            raise InputError(f"a straight line needs planner \"toppra\" (\"{planner}\" moves "
                             "from rest to rest between waypoints)", path=path,
                             field=f"waypoint[{k}].line")
    parts, events = read_events(doc, path, file_payload,
                                None if samples is None else samples.t)
    warnings += lists.warnings() + list(samples.notes if samples is not None else ())
    for warning in warnings:
        logger.warning("%s: %s", path, warning)
    motors = motion_file_motors(doc["motor"], path, robot) if "motor" in doc else None
    return Motion(
        path=path, joint_names=robot.joint_names, planner=planner, dt=dt,
        waypoints=frozen(waypoints), dwells=frozen(dwells),
        velocity_limit=lim.get("velocity"), acceleration_limit=lim.get("acceleration"),
        jerk_limit=lim.get("jerk"), torque_limit=lim.get("torque"),
        samples=samples,
        robot_file=robot_file, payload=file_payload, mounting=file_mounting,
        angle_unit=angle_unit, sized_joints=sizing.get("joints"),
        excluded_joints=sizing.get("exclude", ()), velocity_from_robot=from_robot,
        warnings=tuple(warnings), motors=motors,
        motor_joints=tuple(key for key, block in doc.get("motor", {}).items()
                           if isinstance(block, dict) and key != "curve"),
        tool=tool, allow_flip=tool is not None and tool.allow_flip, xacro_args=xacro_args,
        bearing_offset=bearing_offsets(doc, path, robot), parts=parts,
        events=events, **options,
    )


def _choice(doc: dict[str, Any], key: str, choices: tuple[str, ...], path: Path) -> str:
    if key not in doc:
        raise InputError(f"required key is missing; choose one of: {', '.join(choices)}",
                         path=path, field=key)
    if doc[key] not in choices:
        raise InputError(f"unknown value {doc[key]!r}; choose one of: {', '.join(choices)}",
                         path=path, field=key)
    return doc[key]


def mounting_of(doc: dict[str, Any], path: Path, unit: float,
                angle_unit: str) -> str | tuple[float, float, float] | BasePose | None:
    """The file's ``mounting`` or ``base``, or None when it gives neither.

    Args:
        doc: The file's table holding them.
        path: The file, for messages.
        unit: Radians per angle unit of the file [rad] (the base's rpy).
        angle_unit: The file's angle unit's name, for messages.
    """
    if "base" in doc:
        if "mounting" in doc:
            raise InputError("give either mounting or base (which sets the mounting), not both",
                             path=path, field="base")
        return read_base(doc["base"], path, unit, angle_unit)
    if "mounting" not in doc:
        return None
    value = doc["mounting"]
    if isinstance(value, str):
        if value not in MOUNTINGS:
            raise InputError(f"unknown mounting {value!r}; choose one of: {', '.join(MOUNTINGS)}"
                             " or a gravity vector [gx, gy, gz] in m/s^2 (or give base = "
                             "{xyz, rpy})", path=path,
                             field="mounting")
        return value
    x, y, z = vector(value, 3, path, "mounting")
    for i, g in enumerate((x, y, z)):
        bounds.GRAVITY.check(g, path=path, field=f"mounting[{i}]")
    return (x, y, z)

