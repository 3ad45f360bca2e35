"""A study's unit of work: the cases of one group, evaluated wherever a worker runs.

A task carries what its cases need; `shipped` puts the cases' input files inside it
for a worker that does not share our file system.
"""

from __future__ import annotations

import logging
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path

from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_LOG_BYTES, read_input
from hdselect.study.case import Case
from hdselect.study.compute import Computation, Outcome

logger = logging.getLogger(__name__)

MAX_CHUNK = 200
"""Most cases of a group evaluated by one task."""


@dataclass(frozen=True)
class Task:
    """Cases a worker evaluates together.

    Attributes:
        compute: What to compute.
        cases: The cases, of one group.
        grouped: Evaluate them from one shared basis.
        files: Contents of the files the cases read, by absolute path, for workers on
            other machines; None to read them where they are.
    """

    compute: Computation
    cases: tuple[Case, ...]
    grouped: bool
    files: dict[str, bytes] | None = None


def evaluate(task: Task) -> Iterator[Outcome]:
    """Run a task where this is called (a worker); yield each case's outcome as it completes.

    Shipped files are written to a temporary folder laid out as on the submitting
    machine, and the cases read them there. An unexpected error fails the task's
    remaining cases with its message instead of ending the worker.
    """
    with tempfile.TemporaryDirectory(prefix="hdselect-study-") as folder:
        cases = task.cases if task.files is None else _moved(task, Path(folder))
        done: set[int] = set()
        try:
            for outcome in task.compute.run(cases, task.grouped):
                done.add(outcome.index)
                yield outcome if task.files is None else _unmoved(outcome, folder)
        except Exception as err:  # a bug must not cost the study: record it per case
            logger.exception("unexpected error in a study task")
            for case in cases:
                if case.index not in done:
                    yield Outcome(case.index, case.key, False,
                                  f"unexpected error: {type(err).__name__}: {err}", None,
                                  "grouped" if task.grouped else "direct", None, 0.0, "")


def evaluate_all(task: Task) -> list[Outcome]:
    """`evaluate`, all outcomes at once (what a Dask task returns)."""
    return list(evaluate(task))


def _moved(task: Task, folder: Path) -> tuple[Case, ...]:
    if task.files is None:
        raise RuntimeError("a task to move has no files")
    for name, content in task.files.items():
        target = folder / Path(name).relative_to(Path(name).anchor)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(content)

    def moved(path: Path) -> Path:
        return folder / path.resolve().relative_to(path.resolve().anchor)

    return tuple(replace(case, motion=moved(case.motion),
                         robot=None if case.robot is None else moved(case.robot),
                         catalog=tuple(moved(f) for f in case.catalog),
                         motor_catalog=None if case.motor_catalog is None
                         else moved(case.motor_catalog))
                 for case in task.cases)


def _unmoved(outcome: Outcome, folder: str) -> Outcome:
    """The outcome with the temporary folder taken out of its paths and messages."""
    result = outcome.result
    if result is not None:
        result = {**result, **{k: result[k].replace(folder, "") for k in ("robot", "motion")
                               if isinstance(result.get(k), str)}}
    error = None if outcome.error is None else outcome.error.replace(folder, "")
    return replace(outcome, result=result, error=error)


def shipped(task: Task) -> Task:
    """The task with its cases' input files carried inside, for a worker without our files."""
    files = {}
    for case in task.cases:
        for path in case.files:
            try:
                files[str(path.resolve())] = read_input(path, MAX_LOG_BYTES)
            except InputError:
                pass  # the case fails in the worker, naming the file
    return replace(task, files=files)
