"""Read a task-mix file (TOML): the motions a robot runs in its working day, and how often.

A mix file lists tasks, each a motion file with a share of the operating time (or
cycles per hour) and, optionally, its own payload and mounting::

    robot = "../robots/benchtop6.urdf"   # optional: else the motions' own (all one file)
    angle_unit = "deg"                   # optional: of a task's base rpy (default deg)
    [[task]]
    motion = "benchtop6_pick_place.toml"
    share = 0.7
    [[task]]
    motion = "benchtop6_inspect.toml"
    share = 0.3
    payload = {mass = 0.3, com = [0.04, 0, 0.05], frame = "tool0"}

A task's ``mounting`` (a name or a gravity vector) or ``base = {xyz, rpy}`` replaces its
motion file's; a motion of tool poses is solved for its task's own mounting when it is
planned (`hdselect.sizing.mixtasks`). What belongs to the whole duty (the sized joints, the
stop time, the required life, the design margin, the motors, the selection order,
efficiency, mass coupling, catalogs) comes from the command line, else the mix file's
``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]`` tables (which settle it
over the motions', with a note naming them), else the motion files, which must then
agree: two motions that differ are an error naming both files (`Mix.duty_value`).
Files are relative to the mix file.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.bounds import check_shares
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.motion.mixduty import (
    MOTION_FIELD,
    SECTION_OF,
    comparable,
    duty_tables,
    motion_value,
    shown,
)
from hdselect.motion.motionfile import (
    ANGLE_UNITS,
    Motion,
    load_motion,
    mounting_of,
    payload_table,
)
from hdselect.motion.robot_named import other_robot, robot_file_named
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload

_TOP_KEYS = ("robot", "angle_unit", "task", "sizing", "requirements", "safety", "precision",
             "motor")
_TASK_KEYS = ("motion", "name", "share", "cycles_per_hour", "payload", "mounting", "base")
SECONDS_PER_HOUR = 3600.0
"""Seconds in the hour that ``cycles_per_hour`` counts in [s]."""


@dataclass(frozen=True, eq=False)
class MixTask:
    """One task of a mix file.

    Attributes:
        motion: The motion, read for the mix's robot.
        name: What reports call it (default: the motion file's stem).
        share: Its fraction of the operating time [-], or None when `cycles_per_hour`
            is given.
        cycles_per_hour: How many of its cycles run per hour [1/h], or None.
        payload: The mix file's payload for this task (replacing the motion file's), or
            None to keep the motion file's.
        mounting: The mix file's mounting for this task (a name, a gravity vector
            [m/s^2] or a `hdselect.BasePose`), or None for the motion file's.
    """

    motion: Motion
    name: str
    share: float | None
    cycles_per_hour: float | None
    payload: Payload | None = None
    mounting: Mounting | None = None


@dataclass(frozen=True, eq=False)
class Mix:
    """A validated mix file: several motions of one robot, sized as one duty.

    Attributes:
        path: The mix file.
        robot_file: The robot file every task runs.
        joint_names: The robot's joints.
        tasks: The tasks, in the file's order.
        given: The duty-wide values the mix file gives, by `hdselect.Options` field name
            (and ``joints``, ``exclude``, ``motors``).
        catalog: The mix file's ``[sizing] catalog`` files, resolved.
        base_angle_unit: The mix file's own ``angle_unit``: of its tasks' ``base`` rpy and
            of ``--base``'s angles.
    """

    path: Path
    robot_file: Path
    joint_names: tuple[str, ...]
    tasks: tuple[MixTask, ...]
    given: Mapping[str, Any] = field(default_factory=dict)
    catalog: tuple[Path, ...] = ()
    base_angle_unit: str = "deg"

    @property
    def motions(self) -> tuple[Motion, ...]:
        """Every task's motion, in task order."""
        return tuple(task.motion for task in self.tasks)

    @property
    def angle_unit(self) -> str:
        """The first task's angle unit, for tables."""
        return self.tasks[0].motion.angle_unit

    @property
    def warnings(self) -> tuple[str, ...]:
        """The motion files' warnings, led by the file's name, once per file; `overrides`."""
        seen = dict.fromkeys(self.motions)
        return tuple(f"{motion.path.name}: {warning}" for motion in seen
                     for warning in motion.warnings) + self.overrides

    @property
    def overrides(self) -> tuple[str, ...]:
        """Each duty-wide value of the mix file over motion files' others (naming them)."""
        notes = []
        for name, mine in self.given.items():
            others = [f"{m.path.name}'s {shown(v, name)}" for m in dict.fromkeys(self.motions)
                      if name in MOTION_FIELD and (v := motion_value(m, name)) is not None
                      and comparable(v) != comparable(mine)]
            if others:
                notes.append(f"{self.path.name} gives {MOTION_FIELD[name]} {shown(mine, name)} "
                             f"for the whole duty, over {', '.join(others)}")
        return tuple(notes)

    @property
    def shares_given(self) -> bool:
        """The tasks give shares (else cycles per hour)."""
        return self.tasks[0].share is not None

    def with_mounting(self, mounting: Mounting) -> Mix:
        """The mix with one mounting on every task (a command line's ``--mounting``)."""
        return replace(self, tasks=tuple(replace(task, mounting=mounting)
                                         for task in self.tasks))

    def check_joints(self, robot: Robot) -> None:
        """Check that the mix was read for this robot's joints.

        Raises:
            InputError: The joints differ.
        """
        if robot.joint_names != self.joint_names:
            raise InputError(f"the mix was read for joints {', '.join(self.joint_names)}; "
                             f"the robot has {', '.join(robot.joint_names)}", path=self.path)

    def duty_value(self, name: str) -> Any:
        """A duty-wide value: the mix file's, else the one every motion that gives it agrees on.

        The mix file's settles the duty's, whatever its motions give (`overrides` notes
        where they differ): the duty is the mix file's, and its robot has one safety
        system.

        Args:
            name: ``stop_time``, ``life_hours``, ``life_basis``, ``margin``, ``joints``,
                ``exclude`` or ``motors``.

        Returns:
            The value, or None when neither the mix file nor any motion gives it.

        Raises:
            InputError: Two motions' values conflict and the mix file gives none (the
                message names both files).
        """
        if name in self.given:
            return self.given[name]  # over the motions' (`overrides` names them)
        values = [(motion, motion_value(motion, name)) for motion in dict.fromkeys(self.motions)]
        values = [(motion, value) for motion, value in values if value is not None]
        if not values:
            return None
        first_motion, first = values[0]
        for motion, value in values[1:]:
            if comparable(value) != comparable(first):
                raise InputError(
                    f"{first_motion.path} gives {MOTION_FIELD[name]} {shown(first, name)}, "
                    f"{motion.path} gives {shown(value, name)}; the whole duty has one: give it in "
                    f"the mix file ([{SECTION_OF[name]}]) or on the command line",
                    path=self.path, field="task")
        return first


def is_mix_file(path: str | Path) -> bool:
    """Whether a file is a mix file: TOML with ``[[task]]`` tables.

    A file that cannot be read as TOML is not one (reading it as a motion file then
    says what is wrong with it).

    Raises:
        InputError: `path` is not a file name.
    """
    try:
        return "task" in read_toml(bounds.file_argument(path, "motion"))
    except InputError as err:
        if err.field == "motion" and err.path is None:
            raise
        return False


def task_names(path: Path) -> tuple[str, ...] | None:
    """A mix file's task names (``name``, else the motion's stem); None: no mix, or broken."""
    try:
        tables = _task_tables(read_toml(path), path)
    except InputError:
        return None
    return tuple(str(t.get("name", Path(str(t.get("motion", ""))).stem)) for t in tables)


def mix_robot_file(path: str | Path) -> Path:
    """The robot file a mix file runs: its ``robot``, else its motions' (all one file).

    Raises:
        InputError: The file names none, a file is missing, or two motions name different
            robot files.
    """
    path = bounds.file_argument(path, "motion")
    doc = read_toml(path)
    if "robot" in doc:
        if not isinstance(doc["robot"], str):
            raise InputError("expected a file name", path=path, field="robot")
        robot = path.parent / doc["robot"]
        if not robot.is_file():
            raise InputError(f"robot file not found: {robot}", path=path, field="robot")
        return robot
    found: tuple[Path, Path] | None = None
    for i, task in enumerate(_task_tables(doc, path)):
        motion = _motion_path(task, path, i)
        robot = robot_file_named(motion)
        if found is not None and robot.resolve() != found[0].resolve():
            raise InputError(f"{found[1]} runs {found[0]}, {motion} runs {robot}; every task "
                             "runs one robot: set `robot` in the mix file", path=path,
                             field=f"task[{i}].motion")
        found = found or (robot, motion)
    if found is None:
        raise RuntimeError("a mix without tasks passed _task_tables")
    return found[0]


def load_mix(path: str | Path, robot: Robot | str | Path | None = None) -> Mix:
    """Read and validate a mix file and every motion file it names.

    Args:
        path: The mix file (TOML).
        robot: The robot, a robot file, or None for the mix file's ``robot``, else the
            motion files'.

    Returns:
        The mix; payloads and mountings are recorded, not applied.

    Raises:
        InputError: A file is missing, malformed or inconsistent; the message names the
            file and the field.
    """
    path = bounds.file_argument(path, "path")
    bounds.expect_type(robot, (Robot, str, Path, type(None)), "robot",
                       "a Robot, a robot file or None")
    doc = read_toml(path)
    check_keys(doc, _TOP_KEYS, path, "")
    tables = _task_tables(doc, path)
    angle_unit = doc.get("angle_unit", "deg")
    if angle_unit not in ANGLE_UNITS:
        raise InputError(f"unknown value {angle_unit!r}; choose one of: "
                         f"{', '.join(ANGLE_UNITS)}", path=path, field="angle_unit")
    if not isinstance(robot, Robot):
        robot = load_robot(robot if robot is not None else mix_robot_file(path))
    motions: dict[Path, Motion] = {}
    tasks: list[MixTask] = []
    for i, table in enumerate(tables):
        tasks.append(_task(table, path, i, robot, motions, angle_unit))
    names = [task.name for task in tasks]
    for i, name in enumerate(names):
        if name in names[:i]:
            raise InputError(f"task[{names.index(name)}] is called {name!r} too; give each "
                             "task its own `name`", path=path, field=f"task[{i}].name")
    kinds = {task.share is not None for task in tasks}
    if len(kinds) > 1:
        raise InputError("give every task a `share`, or every task `cycles_per_hour`, not "
                         "some of each", path=path, field="task")
    if tasks[0].share is not None:
        try:
            check_shares([task.share for task in tasks if task.share is not None])
        except InputError as err:
            raise InputError(err.reason, path=path, field="task.share") from err
    given, catalog = duty_tables(doc, path, robot)
    return Mix(path, robot.path, robot.joint_names, tuple(tasks), given, catalog, angle_unit)


def _task_tables(doc: dict[str, Any], path: Path) -> list[dict[str, Any]]:
    tasks = doc.get("task")
    if not isinstance(tasks, list) or not tasks:
        raise InputError("expected one or more [[task]] tables", path=path, field="task")
    return [table_of(task, path, f"task[{i}]") for i, task in enumerate(tasks)]


def _motion_path(table: dict[str, Any], path: Path, i: int) -> Path:
    value = table.get("motion")
    if not isinstance(value, str) or not value:
        raise InputError("required: the motion file, relative to this file", path=path,
                         field=f"task[{i}].motion")
    motion = path.parent / value
    if not motion.is_file():
        raise InputError(f"motion file not found: {motion}", path=path,
                         field=f"task[{i}].motion")
    if motion.resolve() == path.resolve() or "task" in read_toml(motion):
        raise InputError("names a mix file; a task's motion is a motion file", path=path,
                         field=f"task[{i}].motion")
    return motion


def _other_robot(err: InputError, name: object, motion: Path, path: Path, i: int,
                 robot: Robot) -> None:
    """Blame a task's motion that does not load on the mix's robot on its other robot.

    Names the mix file, the task and both robots; returns where the motion names the
    mix's robot file, or none.

    Raises:
        InputError: The motion names another robot file than the one the mix runs.
    """
    named = other_robot(motion, robot)
    if named is not None:
        raise InputError(f"task {name!r} runs {motion.name}, written for {named}, but the mix "
                         f"runs {robot.path}: the motion does not fit it ({err}); give the "
                         "task a motion of this robot", path=path,
                         field=f"task[{i}].motion") from err


def _task(table: dict[str, Any], path: Path, i: int, robot: Robot,
          motions: dict[Path, Motion], angle_unit: str) -> MixTask:
    where = f"task[{i}]"
    check_keys(table, _TASK_KEYS, path, where)
    file = _motion_path(table, path, i)
    key = file.resolve()
    if key not in motions:
        try:
            motions[key] = load_motion(file, robot)
        except InputError as err:
            _other_robot(err, table.get("name", file.stem), file, path, i, robot)
            raise
    motion = motions[key]
    name = table.get("name", file.stem)
    if not isinstance(name, str) or not name.strip():
        raise InputError(f"expected a name, got {name!r}", path=path, field=f"{where}.name")
    if ("share" in table) == ("cycles_per_hour" in table):
        raise InputError("give `share` (a fraction of the operating time) or "
                         "`cycles_per_hour`, one of them", path=path, field=where)
    share = cycles = None
    if "share" in table:
        share = as_number(table["share"], path, f"{where}.share", minimum=0.0)
        if share > 1.0:
            raise InputError(f"a share is a fraction of the operating time, at most 1, got "
                             f"{share:g}", path=path, field=f"{where}.share")
    else:
        cycles = as_number(table["cycles_per_hour"], path, f"{where}.cycles_per_hour",
                           minimum=0.0)
    payload = payload_table(table["payload"], path) if "payload" in table else None
    if payload is not None and payload.frame is not None:
        try:
            robot.with_payload(payload)
        except InputError as err:
            raise InputError(err.reason, path=path, field=f"{where}.{err.field}") from err
    try:
        mounting = mounting_of(table, path, ANGLE_UNITS[angle_unit], angle_unit)
    except InputError as err:
        raise InputError(err.reason, path=path, field=f"{where}.{err.field}") from err
    return MixTask(motion, name.strip(), share, cycles, payload, mounting)
