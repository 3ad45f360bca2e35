"""Run a study's cases: in worker processes here, or on a Dask distributed cluster.

Cases are cut into tasks: the cases of one robot, path, mounting and payload shape
that are many enough (`MIN_GROUP`) go together, in at most one chunk per worker
(`hdselect.study.group`); every other case is a task of its own. Each worker runs its
dynamics on one thread. Results come back case by case and are kept as they arrive
(`hdselect.study.store`). A worker process that dies takes no other case with it:
its task's unfinished cases are run again one by one, and the one that kills its
worker again is recorded as failed, with the exit status.
"""

from __future__ import annotations

import logging
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hdselect.base.errors import InputError
from hdselect.base.scheduler import DEFAULT_TIMEOUT, scheduler_address, timeout_seconds
from hdselect.study.case import Case
from hdselect.study.cluster import run_dask
from hdselect.study.compute import COMPUTATIONS, MIN_GROUP, Outcome
from hdselect.study.jobs import MAX_CHUNK, Task, evaluate
from hdselect.study.local import run_local
from hdselect.study.spec import Study, _canonical
from hdselect.study.store import Store

logger = logging.getLogger(__name__)


@dataclass
class StudyRun:
    """What a study run did.

    Attributes:
        study: The study.
        records: The record of every case done so far, by key.
        ran: Cases run now.
        skipped: Cases already done before (their records are kept).
        failed: Cases whose record says they failed, now or before.
        seconds: Wall time of this run [s].
        executor: Where the cases ran, in words.
    """

    study: Study
    records: dict[str, dict[str, Any]]
    ran: int = 0
    skipped: int = 0
    failed: int = 0
    seconds: float = 0.0
    executor: str = ""
    methods: dict[str, int] = field(default_factory=dict)


def default_workers() -> int:
    """The cores this process may use."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def run_study(study: Study, out: str | Path | Store | None = None, *,
              workers: int | None = None,
              scheduler: str | None = None, timeout: float = DEFAULT_TIMEOUT,
              grouping: bool = True, retry_failed: bool = False,
              progress: Callable[[int, int, dict[str, Any]], None] | None = None) -> StudyRun:
    """Run every case of a study not yet done, keeping each result as it arrives.

    Args:
        study: The study.
        out: The CSV file (its journal beside it), or its `Store`; None keeps the results
            in memory only.
        workers: Worker processes (default: the cores here); 0 runs the cases in this
            process, without isolation. With ``scheduler="local"``: Dask workers.
        scheduler: None for local worker processes; ``"local"`` for a Dask ``LocalCluster``
            on this machine (localhost only); ``"tcp://HOST:PORT"`` for a running Dask
            scheduler (checked before any case runs, and asked for Dask's greeting first).
        timeout: The time limit of connecting to the scheduler [s], at most a day.
        grouping: Evaluate the cases of one robot and path from a shared basis.
        retry_failed: Run again the cases recorded as failed.
        progress: Called with (done, to do, record) after each case.

    Returns:
        What ran, and the records.

    Raises:
        InputError: A bad argument, an output that cannot be written, no Dask installed,
            or a scheduler that cannot be reached.
    """
    workers = default_workers() if workers is None else workers
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise InputError(f"expected a whole number of workers, 0 or more; got {workers!r}",
                         field="--workers")
    if scheduler is not None:
        scheduler = scheduler_address(scheduler, "--scheduler")
    timeout = timeout_seconds(timeout, "--timeout")
    store = out if isinstance(out, Store) or out is None else Store(out, study)
    records: dict[str, dict[str, Any]] = dict(store.records) if store is not None else {}
    todo = [case for case in study.cases
            if store is None or not store.done(case, retry_failed)]
    run = StudyRun(study, records, skipped=len(study.cases) - len(todo))
    tasks = plan_tasks(study, todo, max(workers, 1), grouping)
    used = max(1, min(workers, len(tasks)))  # no more processes than tasks to give them
    start = time.perf_counter()

    def keep(outcome: Outcome) -> None:
        if store is not None:
            if not store.opened:  # first result: a study refused before any writes nothing
                store.open()
            record = store.add(outcome)
        else:
            record = {"key": outcome.key, "case": outcome.index, "ok": outcome.ok,
                      "error": outcome.error, "result": outcome.result,
                      "method": outcome.method, "note": outcome.note}
        records[outcome.key] = record
        run.ran += 1
        run.methods[outcome.method] = run.methods.get(outcome.method, 0) + 1
        if progress is not None:
            progress(run.ran, len(todo), record)

    complete = False
    try:
        if scheduler is not None:
            run.executor = run_dask(tasks, scheduler, used, keep, timeout)
        elif workers == 0:
            run.executor = "this process"
            for task in tasks:
                for outcome in evaluate(task):
                    keep(outcome)
        else:
            run.executor = f"{used} worker process{'es' if used > 1 else ''}"
            run_local(tasks, used, keep)
        complete = all(case.key in records for case in study.cases)
    finally:
        if store is not None:
            store.close(complete)
    run.seconds = time.perf_counter() - start
    run.failed = sum(1 for case in study.cases if not records[case.key]["ok"])
    return run


def plan_tasks(study: Study, todo: Sequence[Case], workers: int, grouping: bool) -> list[Task]:
    """Cut the cases to run into tasks; the biggest first.

    Whether a case is evaluated from its group's basis depends on the whole study's
    group, never on what is left to run or on the workers, so a case gets the same
    answer whichever way the study runs.
    """
    def group(case: Case) -> str:
        return _canonical([case.compute, str(case.motion), str(case.robot),
                           case.values.get("mounting"), case.payload_shape])

    sizes: dict[str, int] = {}
    for case in study.cases:
        sizes[group(case)] = sizes.get(group(case), 0) + 1
    groups: dict[str, list[Case]] = {}
    for case in todo:
        groups.setdefault(group(case), []).append(case)
    tasks = []
    for name, cases in groups.items():
        compute = COMPUTATIONS[cases[0].compute]
        if grouping and sizes[name] >= MIN_GROUP:
            count = max(math.ceil(len(cases) / MAX_CHUNK),
                        min(workers, max(1, len(cases) // MIN_GROUP)))
            step = len(cases) / count
            for k in range(count):
                chunk = tuple(cases[round(k * step):round((k + 1) * step)])
                tasks.append(Task(compute, chunk, True))
        else:
            tasks += [Task(compute, (case,), False) for case in cases]
    tasks.sort(key=lambda task: -len(task.cases))
    return tasks
