"""Read a logged joint trajectory (CSV) for the ``samples`` planner, checked cell by cell.

The file has a header row: ``t`` [s], ``q_<joint>`` for every joint, and
optionally ``qd_<joint>`` and ``qdd_<joint>`` for every joint; other columns
are ignored. Numbers are parsed by numpy's C reader (an 8-hour log at 1 kHz,
29 million rows, reads in well under a minute and in about twice its final
size); a malformed file is then scanned row by row for the first bad cell, so
every message names the data row, the line and the column.

Every log's numbers, a CSV file's or a bag's (`hdselect.motion.bagfile`), are checked
and put in SI units by the one `checked_log`, within the ``[samples]`` window.
"""

from __future__ import annotations

import csv
import io
import itertools
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hdselect.base import bounds
from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_LOG_BYTES, readable
from hdselect.motion.followers import check_logged_followers
from hdselect.robot.model import Robot

TIMESTAMP = bounds.Bound("a time", "s", -1e12, 1e12)
"""A log's time stamp [s]."""
MIN_STEP = 1e-6
"""Shortest time between two log samples [s]: a log is not taken at more than 1 MHz."""
MIN_STEP_FRACTION = 1e-3
"""Shortest time between two log samples as a fraction of the log's median period [-]."""
_KINDS = {"q": bounds.POSITION, "qd": bounds.VELOCITY, "qdd": bounds.ACCELERATION}
_PER_SECOND = {"q": "", "qd": "/s", "qdd": "/s^2"}


@dataclass(frozen=True)
class SampleLog:
    """A logged joint trajectory, in SI units, with time as logged.

    Attributes:
        path: The log it came from: a CSV file, or a ROS bag (a rosbag2 folder's one
            storage file where it has one).
        t: Sample times [s], strictly increasing, shape (n,).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof), or None if not logged.
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof), or None if not logged.
        notes: What reading it left out (a bag's joints the robot does not have), for the
            motion's warnings.
    """

    path: Path
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray | None
    qdd: np.ndarray | None
    notes: tuple[str, ...] = ()


def read_log(log: Path, robot: Robot, scale: np.ndarray, units: Sequence[str],
             angle: tuple[float, str] | None = None, window: Window | None = None) -> SampleLog:
    """Read and check a CSV log for a robot's joints.

    Columns of mimic followers (``q_<follower>``, a ``joint_states`` export has them)
    are read to check that they agree with their leaders.

    Args:
        log: The CSV file.
        robot: The robot: its joint names, and the position limits every logged
            position must respect.
        scale: SI per file unit of each joint's position (pi/180 for degrees).
        units: The file unit of each joint's position, for messages (``deg``, ``rad``, ``m``).
        angle: SI per unit of the file's angles and its label (default: rad).
        window: The part of the log to read (default: all of it).

    Returns:
        The log in SI units.

    Raises:
        InputError: The file cannot be read, a column is missing, unknown or given twice,
            or `checked_log` refuses its numbers. The message names the row and column.
    """
    header, header_line = _header(log)
    seen: set[str] = set()
    follower_columns = []
    for name in header:
        if name in seen:
            raise InputError(f"column '{name}' appears twice in the header; give each column "
                             "once", path=log, field=name)
        seen.add(name)
        for prefix in ("qdd_", "qd_", "q_"):
            if name.startswith(prefix):
                if name[len(prefix):] in robot.mimic:  # a joint_states export lists followers
                    follower_columns.append(name)
                else:
                    robot.joint_index(name[len(prefix):], source=log, field=name)
                break
    kinds = ("q",) + tuple(kind for kind in ("qd", "qdd")
                           if any(f"{kind}_{n}" in seen for n in robot.joint_names))
    wanted = ["t"] + [f"{kind}_{n}" for kind in kinds for n in robot.joint_names]
    for name in wanted:
        if name not in seen:
            raise InputError(f"column '{name}' is missing; columns are: {', '.join(header)}",
                             path=log, field=name)
    columns = [header.index(name) for name in wanted + follower_columns]
    data = _numbers(log, header, header_line, columns)
    table = LogTable(log, kinds, tuple(wanted + follower_columns), data,
                     lambda row: _where(log, header_line, row), str,
                     "a header row and at least two samples")
    return checked_log(table, robot, scale, units, angle, window)


@dataclass(frozen=True)
class LogTable:
    """A log's numbers as read, before any check: what a CSV file and a bag both give.

    Attributes:
        path: The log, for messages.
        kinds: ``("q",)``, and ``"qd"``, ``"qdd"`` where logged, in that order.
        columns: ``t``, then ``<kind>_<joint>`` for each kind and each of the robot's
            joints in its order, then the mimic followers' columns (``q_<follower>``, ...).
        data: The numbers of each row in the log's units, shape (rows, len(columns)).
        where: How a message names a 1-based row (``data row R (line L)``).
        label: The field a message names for a column, in the log's own words.
        needs: What a log needs at least, for the message of one that is too short.
        notes: What reading it left out, for the motion's warnings.
    """

    path: Path
    kinds: tuple[str, ...]
    columns: tuple[str, ...]
    data: np.ndarray
    where: Callable[[int], str]
    label: Callable[[str], str]
    needs: str = "at least two samples"
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class Window:
    """The part of a log to read: ``[samples] start``, ``stop``, in the log's time [s].

    Attributes:
        path: The motion file that gives it, for messages.
        start: The first time kept [s], or None for the log's start.
        stop: The last time kept [s], or None for the log's end.
    """

    path: Path
    start: float | None = None
    stop: float | None = None

    def rows(self, t: np.ndarray) -> np.ndarray:
        """The indices of the samples within the window, at least two.

        Args:
            t: The log's times [s], each finite.

        Raises:
            InputError: Fewer than two samples are within it.
        """
        low = -np.inf if self.start is None else self.start
        high = np.inf if self.stop is None else self.stop
        rows = np.flatnonzero((t >= low) & (t <= high))
        if len(rows) < 2:
            given = ", ".join(f"{key} = {value:g} s" for key, value in
                              (("start", self.start), ("stop", self.stop)) if value is not None)
            raise InputError(f"{given} keeps {len(rows)} of the log's samples (its times run "
                             f"from {t.min():g} to {t.max():g} s); a log needs two or more",
                             path=self.path,
                             field="samples.start" if self.start is not None else "samples.stop")
        return rows


def checked_log(table: LogTable, robot: Robot, scale: np.ndarray, units: Sequence[str],
                angle: tuple[float, str] | None = None,
                window: Window | None = None) -> SampleLog:
    """Check a log's numbers and give them in SI units: every log, a CSV file or a bag.

    Args:
        table: The log as read.
        robot: The robot: the position limits every logged position must respect.
        scale: SI per log unit of each joint's position (pi/180 for degrees).
        units: The log unit of each joint's position, for messages (``deg``, ``rad``, ``m``).
        angle: SI per unit of the log's angles and its label (default: rad).
        window: The part of the log to keep (default: all of it).

    Returns:
        The log (the rows within the window) in SI units.

    Raises:
        InputError: It has fewer than two samples (in the window), a number is not finite
            or out of range, a position is outside its joint's limits (a follower's
            included), a follower disagrees with its leader, or time does not increase
            (or two samples are implausibly close). The message names the row and column.
    """
    log, data = table.path, table.data
    if data.shape[0] < 2:
        raise InputError(f"need {table.needs}", path=log)
    _check_column(table, "t", data[:, 0], TIMESTAMP, 1.0, "s", table.where)
    kept = np.arange(len(data)) if window is None else window.rows(data[:, 0])
    if len(kept) < len(data):
        data = data[kept]

    def where(row: int) -> str:
        return table.where(int(kept[row - 1]) + 1)

    t = data[:, 0]
    dof, wanted = robot.dof, 1 + len(table.kinds) * robot.dof
    arrays: dict[str, np.ndarray] = {}
    for k, kind in enumerate(table.kinds):
        block = data[:, 1 + k * dof:1 + (k + 1) * dof]
        for j, joint in enumerate(robot.joint_names):
            unit = units[j] + _PER_SECOND[kind]
            _check_column(table, f"{kind}_{joint}", block[:, j], _KINDS[kind], float(scale[j]),
                          unit, where)
        block = block * scale
        if kind == "q":
            _check_limits(table, robot, block, scale, units, where)
        arrays[kind] = frozen(block)
    if robot.mimic:
        try:
            check_logged_followers(robot, dict(zip(table.columns[wanted:], data[:, wanted:].T,
                                                   strict=True)), arrays, angle or (1.0, "rad"),
                                   log, where)
        except InputError as err:
            raise InputError(err.reason, path=log, field=table.label(err.field or "")) from err
    steps = np.diff(t)
    back = np.flatnonzero(steps <= 0.0)
    if back.size:
        row = int(back[0]) + 2
        raise InputError(f"time must increase; {where(row)} has t = {t[row - 1]:g} after "
                         f"{t[row - 2]:g}", path=log, field=table.label("t"))
    shortest = max(MIN_STEP, MIN_STEP_FRACTION * float(np.median(steps)))
    close = np.flatnonzero(steps < shortest)
    if close.size:
        row = int(close[0]) + 2
        raise InputError(f"{where(row)} is only {steps[row - 2]:.3g} s after the sample before "
                         f"it, less than {shortest:.3g} s (1e-6 s, or 1e-3 of the log's median "
                         "period): a duplicated or corrupted time stamp?", path=log,
                         field=table.label("t"))
    return SampleLog(path=log, t=frozen(t), q=arrays["q"], qd=arrays.get("qd"),
                     qdd=arrays.get("qdd"), notes=table.notes)


def _header(log: Path) -> tuple[list[str], int]:
    """The header's cells and its line number (1-based)."""
    try:
        with readable(log, MAX_LOG_BYTES).open(newline="", encoding="utf-8-sig") as stream:
            for line_number, line in enumerate(stream, start=1):
                if line.strip():
                    return [cell.strip() for cell in next(csv.reader([line]))], line_number
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise InputError(f"cannot read CSV ({err})", path=log) from err
    raise InputError("need a header row and at least two samples", path=log)


def _numbers(log: Path, header: list[str], header_line: int, columns: list[int]) -> np.ndarray:
    """The wanted columns of every data row as floats, shape (rows, len(columns))."""
    every = sorted(columns) == list(range(len(header)))
    try:
        with readable(log, MAX_LOG_BYTES).open(newline="", encoding="utf-8-sig") as stream:
            for _ in range(header_line):
                stream.readline()
            data = np.loadtxt(stream, delimiter=",", comments=None, ndmin=2, dtype=float,
                              usecols=None if every else columns)
    except (ValueError, UnicodeDecodeError, csv.Error) as err:
        bad = _first_bad_cell(log, header, header_line, columns)
        if bad is not None:
            raise bad from err
        return _read_slowly(log, header_line, columns)  # valid CSV numpy does not read (quotes)
    except OSError as err:
        raise InputError(f"cannot read CSV ({err})", path=log) from err
    if data.size == 0:
        return np.empty((0, len(columns)))
    if every and columns != list(range(len(header))):
        return data[:, columns]  # usecols keeps the order asked for; the whole file does not
    return data


def _rows(log: Path, header_line: int) -> Iterator[tuple[int, int, list[str]]]:
    """(data row, line, cells) of every non-blank row after the header, 1-based."""
    with readable(log, MAX_LOG_BYTES).open(newline="", encoding="utf-8-sig") as stream:
        lines = itertools.islice(stream, header_line, None)
        numbered = ((header_line + 1 + i, line) for i, line in enumerate(lines))
        row = 0
        for line_number, line in numbered:
            if not line.strip():
                continue
            row += 1
            yield row, line_number, [c.strip() for c in next(csv.reader(io.StringIO(line)))]


def _first_bad_cell(log: Path, header: list[str], header_line: int,
                    columns: list[int]) -> InputError | None:
    """The error of the first row that is ragged or has a wanted cell that is not a number."""
    try:
        for row, line, cells in _rows(log, header_line):
            if len(cells) != len(header):
                return InputError(f"data row {row} (line {line}) has {len(cells)} cells, the "
                                  f"header {len(header)}", path=log)
            for column in columns:
                try:
                    float(cells[column])
                except ValueError:
                    return InputError(f"data row {row} (line {line}): not a finite number: "
                                      f"{cells[column]!r}", path=log, field=header[column])
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        return InputError(f"cannot read CSV ({err})", path=log)
    return None


def _read_slowly(log: Path, header_line: int, columns: list[int]) -> np.ndarray:
    """The wanted columns through Python's csv reader, a block of rows at a time."""
    blocks, rows = [], []
    for _, _, cells in _rows(log, header_line):
        rows.append([float(cells[column]) for column in columns])
        if len(rows) == 1 << 16:
            blocks.append(np.array(rows))
            rows = []
    blocks.append(np.array(rows).reshape(-1, len(columns)))
    return np.concatenate(blocks)


def _where(log: Path, header_line: int, row: int) -> str:
    """``data row R (line L)`` of a 1-based data row."""
    for number, line, _ in _rows(log, header_line):
        if number == row:
            return f"data row {row} (line {line})"
    return f"data row {row}"


def _check_column(table: LogTable, name: str, values: np.ndarray, bound: bounds.Bound,
                  scale: float, unit: str, where: Callable[[int], str]) -> None:
    """Every value finite and within `bound` (checked in SI: value x `scale`)."""
    si = values * scale
    bad = np.flatnonzero(~np.isfinite(si) | (si < bound.low) | (si > bound.high))
    if bad.size:
        row = int(bad[0]) + 1
        value = values[row - 1]
        reason = (f"not a finite number: {value}" if not np.isfinite(value) else
                  f"{value:g} is not {bound.describe(scale, unit)}")
        raise InputError(f"{where(row)}: {reason}", path=table.path, field=table.label(name))


def _check_limits(table: LogTable, robot: Robot, q: np.ndarray, scale: np.ndarray,
                  units: Sequence[str], where: Callable[[int], str]) -> None:
    """Every logged position within its joint's limits, as waypoints are checked [rad or m]."""
    outside = (q < robot.lower - 1e-9) | (q > robot.upper + 1e-9)
    if outside.any():
        k, j = (int(i) for i in np.argwhere(outside)[0])
        name = robot.joint_names[j]
        raise InputError(
            f"{where(k + 1)}: {q[k, j] / scale[j]:g} {units[j]} is outside "
            f"the limits of joint '{name}' [{robot.lower[j] / scale[j]:g}, "
            f"{robot.upper[j] / scale[j]:g}] {units[j]}", path=table.path,
            field=table.label(f"q_{name}"))
