"""Keep a study's results: a CSV of rows and a JSON Lines journal beside it, resumable.

Each case's record is appended to ``NAME.jsonl`` and its rows to ``NAME.csv`` and
both are flushed as soon as the case completes, so a study killed at any moment
keeps everything finished before. On the next run the journal says which keys are
done (a half-written last line is dropped) and only the rest run. When every case is
done, both files are rewritten atomically in study order with the study's current
cases only: the CSV is then the same whichever executor ran the study, and a journal
record carries what differs between runs (time taken, host, when).
"""

from __future__ import annotations

import csv
import errno
import io
import json
import math
import os
import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, TextIO

from hdselect.base.errors import InputError
from hdselect.base.outputs import check_output_path, writable_target, write_file
from hdselect.study.case import Case
from hdselect.study.compute import COMPUTATIONS, Outcome
from hdselect.study.spec import Study

STATUS_COLUMNS = ("case", "compute", "status", "error")
"""Columns before the case's parameters."""


def journal_path(out: str | Path) -> Path:
    """The JSON Lines file beside a CSV: the same name, ``.jsonl``."""
    return Path(out).with_suffix(".jsonl")


def columns(study: Study) -> tuple[str, ...]:
    """The CSV header of a study: status, the parameters it sets, the per-joint results."""
    results: list[str] = []
    for name in study.compute:
        results += [c for c in COMPUTATIONS[name].columns if c not in results]
    return (*STATUS_COLUMNS, *study.keys, *results)


def rows(study: Study, case: Case, record: dict[str, Any]) -> list[dict[str, Any]]:
    """The rows of one case (one per joint; one with the error if it failed), typed values."""
    head: dict[str, Any] = {"case": case.index, "compute": case.compute,
                            "status": "ok" if record["ok"] else "failed",
                            "error": record["error"]}
    head.update({key: case.values.get(key) for key in study.keys})
    if not record["ok"]:
        return [head]
    return [{**head, **fields} for fields in COMPUTATIONS[case.compute].rows(record["result"])]


def cell(value: Any) -> str:
    """A CSV cell: 10 significant digits for numbers, empty for none, JSON for lists.

    A table (a mix's ``payloads``) is ``name=value`` pairs joined by ``;``.
    """
    if value is None:
        return ""
    if isinstance(value, dict):
        return ";".join(f"{key}={cell(item)}" for key, item in value.items())
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.10g}" if math.isfinite(value) else str(value)
    if isinstance(value, tuple | list | dict):
        return ";".join(map(str, value)) if all(isinstance(v, str) for v in value) else (
            json.dumps(value))
    return str(value)


class Store:
    """The CSV and the journal of one study, opened for appending.

    Both are regular files, read back to resume and rewritten when the study is
    complete: a symlink is followed (the journal goes beside the file it points to),
    and standard output, a device or a FIFO is refused.
    """

    def __init__(self, out: str | Path, study: Study) -> None:
        """Check both paths and read what the journal already holds.

        Args:
            out: The CSV file; the journal is `journal_path(out)`.
            study: The study the files are for.

        Raises:
            InputError: A file cannot be read or written, is not a regular file, or is an
                input.
        """
        self.csv_path = _regular(out)
        self.journal_path = _regular(journal_path(self.csv_path))
        self.study = study
        inputs = {f.resolve() for case in study.cases for f in case.files} | {
            study.path.resolve()}
        for path in (self.csv_path, self.journal_path):
            if path.resolve() in inputs:
                raise InputError("is an input file; choose another output path", path=path,
                                 field="--out")
        _check_ours(self.csv_path, out)
        for path in (self.csv_path, self.journal_path):
            _check_appendable(path)
        self.records: dict[str, dict[str, Any]] = {}
        if self.journal_path.exists():
            for record in _read_journal(self.journal_path):
                self.records[record["key"]] = record
        self._csv: TextIO | None = None
        self._journal: TextIO | None = None
        self._writer: Any = None

    @property
    def paths(self) -> tuple[Path, Path]:
        """The CSV and the journal."""
        return self.csv_path, self.journal_path

    def done(self, case: Case, retry_failed: bool = False) -> bool:
        """The case's key has a record (a failed one counts unless `retry_failed`)."""
        record = self.records.get(case.key)
        return record is not None and (record["ok"] or not retry_failed)

    @property
    def opened(self) -> bool:
        """`open` was called (and `close` not yet)."""
        return self._csv is not None

    def open(self) -> None:
        """Rewrite the CSV from the journal's records of this study, then append to both."""
        write_file(self.csv_path, lambda stream: self._write_csv(stream))
        try:
            self._csv = self.csv_path.open("a", encoding="utf-8", newline="")
            self._journal = self.journal_path.open("a", encoding="utf-8")
        except OSError as err:
            raise InputError(f"cannot write here ({err.strerror})", path=self.csv_path) from err
        self._writer = csv.DictWriter(self._csv, columns(self.study), lineterminator="\n")

    def add(self, outcome: Outcome) -> dict[str, Any]:
        """Append and flush one case's record and rows; returns the record."""
        if self._csv is None or self._journal is None:
            raise RuntimeError("the store is not open")
        case = self.study.cases[outcome.index]
        record = {"key": outcome.key, "case": outcome.index, "compute": case.compute,
                  "values": dict(case.values), **asdict(outcome),
                  "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        del record["index"]
        self._journal.write(json.dumps(record, allow_nan=False) + "\n")
        self._journal.flush()
        self.records[outcome.key] = record
        self._writer.writerows({k: cell(v) for k, v in row.items()}
                               for row in rows(self.study, case, record))
        self._csv.flush()
        return record

    def close(self, complete: bool) -> None:
        """Close both files; when every case is done, rewrite them in study order."""
        for stream in (self._csv, self._journal):
            if stream is not None:
                stream.close()
        self._csv = self._journal = None
        if complete:
            current = [self.records[case.key] for case in self.study.cases]
            write_file(self.journal_path, lambda stream: stream.writelines(
                json.dumps(record, allow_nan=False) + "\n" for record in current))
            write_file(self.csv_path, lambda stream: self._write_csv(stream))

    def _write_csv(self, stream: TextIO) -> None:
        stream.write(csv_text(self.study, self.records))


def _read_journal(path: Path) -> Iterable[dict[str, Any]]:
    """The journal's records; a last line cut short by a kill is dropped."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"cannot read the study's journal ({err})", path=path) from err
    for number, line in enumerate(lines, 1):
        try:
            record = json.loads(line)
        except json.JSONDecodeError as err:
            if number == len(lines):
                return  # written when the study was killed
            raise InputError(f"line {number} is not JSON; delete the file to start over",
                             path=path) from err
        if not isinstance(record, dict) or not {"key", "ok"} <= set(record):
            raise InputError(f"line {number} is not a study record; delete the file to start "
                             "over", path=path)
        yield record


def _check_ours(csv_path: Path, given: str | Path) -> None:
    """Refuse to take over a CSV a study did not write (its header is not a study's).

    Raises:
        InputError: The file exists, is not empty, and does not start with a study's columns.
    """
    try:
        with csv_path.open(encoding="utf-8", newline="") as stream:
            first = stream.readline()
    except FileNotFoundError:
        return
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"cannot read it to check it is a study's ({err})", path=given,
                         field="--out") from err
    if first.strip() and not first.startswith(",".join(STATUS_COLUMNS)):
        raise InputError(f"exists and was not written by a study (its first line is not "
                         f"'{','.join(STATUS_COLUMNS)},...'); choose another file, or remove "
                         "it", path=given, field="--out")


def _check_appendable(path: Path) -> None:
    """Refuse, before any case runs, a study file that cannot be appended to or created.

    An existing file is opened for appending and closed (nothing written); a new one
    needs a directory it can be created in.

    Raises:
        InputError: It is read-only, or its directory is.
    """
    try:
        if path.exists():
            path.open("a", encoding="utf-8").close()
        elif not os.access(path.parent, os.W_OK | os.X_OK):
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror}); a study appends its cases to "
                         "it", path=path, field="--out") from err


def _regular(out: str | Path) -> Path:
    """Where a study file goes: a regular file (symlinks followed), whose directory exists.

    Raises:
        InputError: It is ``-``, a directory, a device, a FIFO or another special file.
    """
    check_output_path(out, "--out")
    if str(out) == "-":
        raise InputError("a study keeps its rows in a file it reads back to resume; standard "
                         "output cannot be one", field="--out")
    real, kind = writable_target(out, "--out")
    if kind != "file":
        raise InputError("is a device or a named pipe; a study keeps its rows in a regular "
                         "file it reads back to resume", path=out, field="--out")
    return real


def table(study: Study, records: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """Every row of the study's done cases, in study order, values typed (for Python)."""
    out: list[dict[str, Any]] = []
    for case in study.cases:
        record = records.get(case.key)
        if record is not None:
            out += rows(study, case, record)
    return out


def csv_text(study: Study, records: dict[str, dict[str, Any]]) -> str:
    """The CSV the store writes when the study is complete, as a string."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns(study), lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: cell(v) for k, v in row.items()} for row in table(study, records))
    return buffer.getvalue()


@dataclass(frozen=True)
class Pivot:
    """The unit selected for one joint against the first two varied parameters.

    Attributes:
        joint: The joint.
        rows: The parameter down the side (the first varied one).
        columns: The parameter across (the second varied one), or None.
        row_values: Its values, in study order (as CSV cells).
        column_values: Its values, in study order (as CSV cells); ``[""]`` when None.
        cells: (row value, column value) -> the units selected there, in catalog order of
            first appearance: ``none`` where no unit fits, ``failed`` for a failed case.
    """

    joint: str
    rows: str
    columns: str | None
    row_values: list[str]
    column_values: list[str]
    cells: dict[tuple[str, str], list[str]]


def pivots(study: Study, records: dict[str, dict[str, Any]],
           compute: str = "size") -> tuple[list[Pivot], dict[str, str]]:
    """Pivot tables of the selected units, and the joints whose unit never changes.

    Returns:
        One pivot per joint whose selection varies, and joint -> unit for the others.
    """
    first = study.varied[0] if study.varied else "case"
    second = study.varied[1] if len(study.varied) > 1 else None
    done = [(case, records[case.key]) for case in study.cases
            if case.compute == compute and case.key in records]
    by_joint: dict[str, dict[tuple[str, str], list[str]]] = {}
    row_values: list[str] = []
    column_values: list[str] = []
    failed: list[tuple[str, str]] = []
    for case, record in done:
        row = cell(case.index if first == "case" else case.values.get(first))
        column = "" if second is None else cell(case.values.get(second))
        row_values += [row] if row not in row_values else []
        column_values += [column] if column not in column_values else []
        if not record["ok"]:
            failed.append((row, column))
            continue
        for joint in record["result"]["joints"]:
            cells = by_joint.setdefault(joint["name"], {}).setdefault((row, column), [])
            unit = joint["unit"] or "none"
            cells += [unit] if unit not in cells else []
    out, constant = [], {}
    for joint, grid in by_joint.items():
        for place in failed:
            grid.setdefault(place, []).append("failed")
        units = {u for values in grid.values() for u in values}
        if len(units) == 1:
            constant[joint] = units.pop()
        else:
            out.append(Pivot(joint, first, second, row_values, column_values, grid))
    return out, constant


def value_pivot(study: Study, records: dict[str, dict[str, Any]], compute: str,
                value: Callable[[dict[str, Any]], str]) -> Pivot | None:
    """One number per case of a computation against the first two varied parameters.

    Args:
        study: The study.
        records: The records done, by key.
        compute: The computation (``fastest``, ``max-payload``).
        value: A case's result -> its cell text.

    Returns:
        The pivot (its ``joint`` is the computation), or None when no case of it is done.
    """
    first = study.varied[0] if study.varied else "case"
    second = study.varied[1] if len(study.varied) > 1 else None
    cells: dict[tuple[str, str], list[str]] = {}
    row_values: list[str] = []
    column_values: list[str] = []
    for case in study.cases:
        record = records.get(case.key)
        if case.compute != compute or record is None:
            continue
        row = cell(case.index if first == "case" else case.values.get(first))
        column = "" if second is None else cell(case.values.get(second))
        row_values += [row] if row not in row_values else []
        column_values += [column] if column not in column_values else []
        text = value(record["result"]) if record["ok"] else "failed"
        place = cells.setdefault((row, column), [])
        place += [text] if text not in place else []
    if not cells:
        return None
    return Pivot(compute, first, second, row_values, column_values, cells)
