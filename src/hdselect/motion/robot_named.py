"""The robot a motion file names: its file (relative to the motion file) and xacro arguments.

A motion file's ``robot`` names the robot file, relative to the motion file; its
``xacro_args`` table gives that file's ``xacro:arg`` values when it is a ``.xacro``
(arguments given on the command line, ``--xacro-arg``, override them by name). They
apply to the robot the file names only: a robot given otherwise takes the
arguments given with it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import is_input_file
from hdselect.base.tomlfile import read_toml, table_of
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.xacrofile import xacro_arguments


def read_motion_toml(path: Path) -> dict[str, Any]:
    """A motion file's TOML; a robot file given in its place is told so."""
    return read_toml(path, kind="a motion file", hint=(
        f"; give a motion file (hdselect init {path} --out motion.toml writes one)"))


def named_file(doc: dict[str, Any], path: Path, *, must_exist: bool = True) -> Path | None:
    """The file's ``robot``, resolved against the motion file's folder, if given.

    Args:
        doc: The motion file's document.
        path: The motion file.
        must_exist: Refuse a file that does not exist (not when a robot given instead
            overrides it).
    """
    if "robot" not in doc:
        return None
    if not isinstance(doc["robot"], str):
        raise InputError("expected a file name", path=path, field="robot")
    robot = path.parent / doc["robot"]
    if must_exist and not is_input_file(robot):
        raise InputError(f"robot file not found: {robot}", path=path, field="robot")
    return robot


def xacro_args_of(doc: dict[str, Any], path: Path) -> dict[str, str]:
    """The file's ``xacro_args`` table: arguments for the ``.xacro`` robot it names."""
    if "xacro_args" not in doc:
        return {}
    table = table_of(doc["xacro_args"], path, "xacro_args")
    try:
        return xacro_arguments(table, "xacro_args")
    except InputError as err:
        raise InputError(err.reason, path=path, field=err.field) from err


def robot_source(path: str | Path) -> tuple[Path, dict[str, str]]:
    """The robot file a motion file names, and the xacro arguments it gives that file.

    Raises:
        InputError: The motion file is unreadable or names no robot file that exists.
    """
    path = bounds.file_argument(path, "motion")
    doc = read_motion_toml(path)
    robot = named_file(doc, path)
    if robot is None:
        raise InputError("no robot given: set the key or pass a robot file",
                         path=path, field="robot")
    return robot, xacro_args_of(doc, path)


def robot_file_named(path: str | Path) -> Path:
    """The robot file a motion file names, for loading the robot before the motion.

    Raises:
        InputError: The motion file is unreadable or names no robot file that exists.
    """
    return robot_source(path)[0]


def other_robot(motion: Path, robot: Robot) -> Path | None:
    """The robot file `motion` names when it is not `robot`'s, else None.

    For a motion that does not load on `robot`: its failure is blamed on the other robot
    it was written for; None (no robot named, or `robot`'s own) leaves it the motion's.
    """
    try:
        named = robot_file_named(motion)
    except InputError:
        return None
    return None if named.resolve() == Path(robot.path).resolve() else named


def load_motion_robot(path: str | Path, xacro_args: Mapping[str, str] | None = None, *,
                      given_as: str = "xacro_args") -> Robot:
    """The robot a motion file names, expanded with its ``xacro_args`` (a ``.xacro`` robot).

    Args:
        path: The motion file.
        xacro_args: Arguments overriding the file's, by name (``--xacro-arg``).
        given_as: What `xacro_args` are called in messages (``--xacro-arg``).

    Raises:
        InputError: The motion file or the robot file is missing or invalid.
    """
    robot, arguments = robot_source(path)
    return load_named(robot, arguments, Path(path), xacro_args, given_as)


def load_named(robot: Path, xacro_args: Mapping[str, str], path: Path,
               given: Mapping[str, str] | None = None, given_as: str = "xacro_args") -> Robot:
    """The motion file's robot, its ``xacro_args`` overridden by `given` (called `given_as`)."""
    return load_expanded(robot, ((path, "xacro_args", xacro_args), (None, given_as, given or {})))


def load_expanded(robot: Path, sources: Sequence[tuple[Path | None, str, Mapping[str, str]]]
                  ) -> Robot:
    """A robot file expanded with xacro arguments from several sources, later ones overriding.

    An error about an argument (the file takes none, has no such argument, or its value
    makes a number of the expanded file unreadable) names the source the argument came
    from: its file (None: the command line) and field.

    Args:
        robot: The robot file.
        sources: (file, field, arguments by name) of each source, in order of precedence.

    Raises:
        InputError: As `hdselect.robot.model.load_robot` does.
    """
    merged = {name: value for _, _, given in sources for name, value in given.items()}
    try:
        return load_robot(robot, xacro_args=merged)
    except InputError as err:
        field = str(err.field)
        if err.path != robot or not (field == "xacro_args" or field.startswith("xacro_args.")):
            raise
        name = field.partition(".")[2]
        path, label = next(((p, f) for p, f, given in reversed(sources)
                            if (name in given if name else given)), (robot, "xacro_args"))
        if path is None and not name:  # arguments for a file that takes none: name the file
            path = robot
        raise InputError(err.reason, path=path, field=f"{label}.{name}"
                         if name and not label.startswith("-") else label) from err
