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
planned (`hdselect.sizing.duty`). What belongs to the whole duty (the sized joints, the
stop time, the required life, the design margin, the motors, the selection order,
efficiency, mass coupling, catalogs) comes from the command line, else the mix file's
``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]`` tables, else the motion
files, which must then agree: a motion whose value differs from the mix file's, or from
another motion's, is an error naming both files (`Mix.duty_value`). Files are relative
to the mix file.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.bounds import SHARE_TOLERANCE, check_shares  # noqa: F401  (re-exported)
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.catalog.select import PREFERENCES
from hdselect.motion.motionfile import (
    ANGLE_UNITS,
    LIFE_BASES,
    Motion,
    load_motion,
    mounting_of,
    payload_table,
    robot_file_named,
)
from hdselect.motion.motor_tables import motion_file_motors
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload

_TOP_KEYS = ("robot", "angle_unit", "task", "sizing", "requirements", "safety", "motor")
_TASK_KEYS = ("motion", "name", "share", "cycles_per_hour", "payload", "mounting", "base")
_SIZING_KEYS = ("joints", "exclude", "catalog", "prefer", "efficiency", "mass_coupling",
                "rotor_inertia", "motor_mass")
_SECTION_OF = {"stop_time": "safety", "life_hours": "requirements",
               "life_basis": "requirements", "margin": "requirements", "joints": "sizing",
               "exclude": "sizing", "motors": "motor"}
"""Where each duty-wide value a motion file may also give lives in the mix file."""
_MOTION_FIELD = {"stop_time": "safety.stop_time", "life_hours": "requirements.life_hours",
                 "life_basis": "requirements.life_basis", "margin": "requirements.margin",
                 "joints": "sizing.joints",
                 "exclude": "sizing.exclude", "motors": "motor"}
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
    """

    path: Path
    robot_file: Path
    joint_names: tuple[str, ...]
    tasks: tuple[MixTask, ...]
    given: Mapping[str, Any] = field(default_factory=dict)
    catalog: tuple[Path, ...] = ()

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
        """The motion files' warnings, each led by its file's name, once per file."""
        seen = dict.fromkeys(self.motions)
        return tuple(f"{motion.path.name}: {warning}" for motion in seen
                     for warning in motion.warnings)

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

        Args:
            name: ``stop_time``, ``life_hours``, ``life_basis``, ``margin``, ``joints``,
                ``exclude`` or ``motors``.

        Returns:
            The value, or None when neither the mix file nor any motion gives it.

        Raises:
            InputError: A motion's value conflicts with the mix file's or another
                motion's (the message names both files).
        """
        values = [(motion, _motion_value(motion, name)) for motion in dict.fromkeys(self.motions)]
        values = [(motion, value) for motion, value in values if value is not None]
        where = _MOTION_FIELD[name]
        if name in self.given:
            mine = self.given[name]
            for motion, value in values:
                if _comparable(value) != _comparable(mine):
                    raise InputError(
                        f"{motion.path} gives {where} {_shown(value)}, {self.path.name} gives "
                        f"{_shown(mine)}; the whole duty has one: make them agree, or remove "
                        "it from the motion file", path=self.path,
                        field=f"{_SECTION_OF[name]}" + ("" if name == "motors" else f".{name}"))
            return mine
        if not values:
            return None
        first_motion, first = values[0]
        for motion, value in values[1:]:
            if _comparable(value) != _comparable(first):
                raise InputError(
                    f"{first_motion.path} gives {where} {_shown(first)}, {motion.path} gives "
                    f"{_shown(value)}; the whole duty has one: give it in the mix file "
                    f"([{_SECTION_OF[name]}]) or on the command line", path=self.path,
                    field="task")
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
    assert found is not None  # _task_tables gives one at least
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
    given, catalog = _duty_tables(doc, path, robot)
    return Mix(path, robot.path, robot.joint_names, tuple(tasks), given, catalog)


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


def _task(table: dict[str, Any], path: Path, i: int, robot: Robot,
          motions: dict[Path, Motion], angle_unit: str) -> MixTask:
    where = f"task[{i}]"
    check_keys(table, _TASK_KEYS, path, where)
    file = _motion_path(table, path, i)
    key = file.resolve()
    if key not in motions:
        motions[key] = load_motion(file, robot)
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


def _duty_tables(doc: dict[str, Any], path: Path,
                 robot: Robot) -> tuple[dict[str, Any], tuple[Path, ...]]:
    """The duty-wide values of ``[sizing]``, ``[requirements]``, ``[safety]`` and ``[motor]``."""
    given: dict[str, Any] = {}
    safety = table_of(doc.get("safety", {}), path, "safety")
    check_keys(safety, ("stop_time",), path, "safety")
    if "stop_time" in safety:
        given["stop_time"] = as_number(safety["stop_time"], path, "safety.stop_time",
                                       bound=bounds.STOP_TIME)
    needs = table_of(doc.get("requirements", {}), path, "requirements")
    check_keys(needs, ("life_hours", "life_basis", "margin"), path, "requirements")
    for key, bound in (("life_hours", bounds.LIFE), ("margin", bounds.MARGIN)):
        if key in needs:
            given[key] = as_number(needs[key], path, f"requirements.{key}", bound=bound)
    if "life_basis" in needs:
        if needs["life_basis"] not in LIFE_BASES:
            raise InputError(f"unknown value {needs['life_basis']!r}; choose one of: "
                             f"{', '.join(LIFE_BASES)}", path=path,
                             field="requirements.life_basis")
        given["life_basis"] = needs["life_basis"]
    sizing = table_of(doc.get("sizing", {}), path, "sizing")
    check_keys(sizing, _SIZING_KEYS, path, "sizing")
    for key in ("joints", "exclude"):
        if key in sizing:
            value = sizing[key]
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise InputError(f"expected a list of joint names, got {value!r}", path=path,
                                 field=f"sizing.{key}")
            given[key] = tuple(value)
    if "joints" in given or "exclude" in given:
        try:
            robot.with_sized_joints(given.get("joints"), given.get("exclude", ()))
        except InputError as err:
            raise InputError(err.reason, path=path, field=f"sizing.{err.field}") from err
    if "prefer" in sizing:
        if sizing["prefer"] not in PREFERENCES:
            raise InputError(f"unknown order {sizing['prefer']!r}; choose one of: "
                             f"{', '.join(PREFERENCES)}", path=path, field="sizing.prefer")
        given["prefer"] = sizing["prefer"]
    if "mass_coupling" in sizing:
        if not isinstance(sizing["mass_coupling"], bool):
            raise InputError(f"expected true or false, got {sizing['mass_coupling']!r}",
                             path=path, field="sizing.mass_coupling")
        given["mass_coupling"] = sizing["mass_coupling"]
    for key, bound in (("efficiency", bounds.EFFICIENCY), ("rotor_inertia", bounds.ROTOR_INERTIA),
                       ("motor_mass", bounds.ADDED_MASS)):
        if key in sizing:
            given[key] = as_number(sizing[key], path, f"sizing.{key}", bound=bound)
    catalog: list[Path] = []
    if "catalog" in sizing:
        files = sizing["catalog"] if isinstance(sizing["catalog"], list) else [sizing["catalog"]]
        for i, file in enumerate(files):
            if not isinstance(file, str) or not (path.parent / file).is_file():
                raise InputError(f"catalog file not found: {file!r}", path=path,
                                 field=f"sizing.catalog[{i}]")
            catalog.append(path.parent / file)
    if "motor" in doc:
        given["motors"] = motion_file_motors(doc["motor"], path, robot)
        given["motor_joints"] = tuple(key for key, block in doc["motor"].items()
                                      if isinstance(block, dict) and key != "curve")
    return given, tuple(catalog)


def _motion_value(motion: Motion, name: str) -> Any:
    if name == "joints":
        return motion.sized_joints
    if name == "exclude":
        return motion.excluded_joints or None
    return getattr(motion, name)


def _comparable(value: Any) -> Any:
    """A duty-wide value in a form two files' values compare in (motors by id and file)."""
    if isinstance(value, Mapping):
        return {joint: tuple((m.id, str(m.source)) for m in motors)
                for joint, motors in value.items()}
    if isinstance(value, list | tuple):
        return tuple(value)
    return value


def _shown(value: Any) -> str:
    if isinstance(value, Mapping):
        return "motors " + "; ".join(f"{joint}: {', '.join(m.id for m in motors)}"
                                     for joint, motors in value.items())
    if isinstance(value, list | tuple):
        return "[" + ", ".join(map(str, value)) + "]"
    return f"{value:g}" if isinstance(value, float) else str(value)
