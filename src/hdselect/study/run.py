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
import multiprocessing
import os
import signal
import sys
import tempfile
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from hdselect.base.errors import HdselectError, InputError
from hdselect.study.compute import COMPUTATIONS, MIN_GROUP, Computation, Outcome
from hdselect.study.spec import Case, Study, _canonical
from hdselect.study.store import Store

logger = logging.getLogger(__name__)

MAX_CHUNK = 200
"""Most cases of a group evaluated by one task."""
DASK_HINT = "pip install 'hdselect[dask]'"
"""How to install the optional Dask executor."""


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
              scheduler: str | None = None, grouping: bool = True, retry_failed: bool = False,
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
            scheduler.
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
    store = out if isinstance(out, Store) or out is None else Store(out, study)
    records: dict[str, dict[str, Any]] = dict(store.records) if store is not None else {}
    todo = [case for case in study.cases
            if store is None or not store.done(case, retry_failed)]
    run = StudyRun(study, records, skipped=len(study.cases) - len(todo))
    tasks = plan_tasks(study, todo, max(workers, 1), grouping)
    start = time.perf_counter()

    def keep(outcome: Outcome) -> None:
        if store is not None:
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

    if store is not None:
        store.open()
    complete = False
    try:
        if scheduler is not None:
            run.executor = _run_dask(tasks, scheduler, workers or 1, keep)
        elif workers == 0:
            run.executor = "this process"
            for task in tasks:
                for outcome in evaluate(task):
                    keep(outcome)
        else:
            run.executor = f"{workers} worker process{'es' if workers > 1 else ''}"
            _run_local(tasks, workers, keep)
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
    assert task.files is not None
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


def _shipped(task: Task) -> Task:
    files = {}
    for case in task.cases:
        for path in case.files:
            try:
                files[str(path.resolve())] = path.read_bytes()
            except OSError:
                pass  # the case fails in the worker, naming the file
    return replace(task, files=files)


# --- local worker processes -------------------------------------------------------------


_DONE = "done"


def _worker_main(connection: Connection) -> None:
    """A worker process: run each task sent, send each outcome, then ``done``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    while True:
        task = connection.recv()
        if task is None:
            return
        for outcome in evaluate(task):
            connection.send(outcome)
        connection.send(_DONE)


class _Worker:
    def __init__(self, context: Any) -> None:
        self.connection, child = context.Pipe()
        self.process = context.Process(target=_worker_main, args=(child,), daemon=True)
        here = str(Path(__file__).resolve().parents[2])  # the hdselect this process runs
        sys.path.insert(0, here)  # first on the worker's path, whatever the working folder
        try:
            self.process.start()
        finally:
            sys.path.remove(here)
        child.close()
        self.task: Task | None = None
        self.received: set[int] = set()
        self.reported = False

    def give(self, task: Task) -> None:
        self.task, self.received = task, set()
        self.connection.send(task)

    def stop(self) -> None:
        if self.process.is_alive():
            try:
                self.connection.send(None)
            except OSError:
                pass
            self.process.join(timeout=1.0)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.connection.close()


def _context() -> Any:
    """Spawned workers: safe with threads (OpenMP, rich), and they import hdselect afresh."""
    return multiprocessing.get_context("spawn")


def _run_local(tasks: Sequence[Task], workers: int, keep: Callable[[Outcome], None]) -> None:
    context = _context()
    queue = deque(tasks)
    pool: list[_Worker] = []
    deaths = 0  # of workers that never reported a case
    try:
        while queue or any(worker.task is not None for worker in pool):
            for worker in pool:
                if worker.task is None and queue:
                    worker.give(queue.popleft())
            while queue and len(pool) < workers:
                pool.append(_Worker(context))
                pool[-1].give(queue.popleft())
            busy = [worker for worker in pool if worker.task is not None]
            wait([w.connection for w in busy] + [w.process.sentinel for w in busy])
            for worker in busy:
                _collect(worker, keep)
                if worker.task is not None and not worker.process.is_alive():
                    deaths += not worker.received
                    if deaths > workers + 2 and not worker.reported:
                        raise HdselectError(
                            f"worker processes die as they start ({_exit(worker.process)}); "
                            "a script that runs a study must do it under "
                            "`if __name__ == \"__main__\":`")
                    queue.extendleft(reversed(_after_death(worker, keep)))
                    worker.stop()
                    pool.remove(worker)
    finally:
        for worker in pool:
            worker.stop()


def _collect(worker: _Worker, keep: Callable[[Outcome], None]) -> None:
    """Everything the worker has sent so far."""
    try:
        while worker.connection.poll():
            message = worker.connection.recv()
            if message == _DONE:
                worker.task = None
            else:
                worker.received.add(message.index)
                worker.reported = True
                keep(message)
    except (EOFError, OSError):
        pass  # the process died; what it sent before is kept


def _after_death(worker: _Worker, keep: Callable[[Outcome], None]) -> list[Task]:
    """The tasks to run again after a worker died: its unfinished cases, one per task.

    A task of one case that killed its worker is recorded as failed instead.
    """
    assert worker.task is not None
    task = worker.task
    left = [case for case in task.cases if case.index not in worker.received]
    worker.process.join()
    if len(left) > 1:
        return [replace(task, cases=(case,)) for case in left]
    if left:
        (case,) = left
        keep(Outcome(case.index, case.key, False,
                     f"the worker process died running this case ({_exit(worker.process)})",
                     None, "grouped" if task.grouped else "direct", None, 0.0, ""))
    return []


def _exit(process: Any) -> str:
    code = process.exitcode
    if code is not None and code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit status {code}"


# --- Dask ------------------------------------------------------------------------------


def _local_cluster(workers: int) -> Any:
    """A Dask LocalCluster on this machine: worker processes of one thread, on 127.0.0.1 only."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR)


def _run_dask(tasks: Sequence[Task], scheduler: str, workers: int,
              keep: Callable[[Outcome], None]) -> str:
    try:
        import dask
        from distributed import Client, as_completed
    except ImportError as err:
        raise InputError(f"needs Dask's distributed scheduler: {DASK_HINT}",
                         field="--scheduler") from err
    cluster = None
    with dask.config.set({"distributed.scheduler.allowed-failures": 1,
                          "distributed.worker.daemon": False}):
        if scheduler == "local":
            cluster = _local_cluster(workers)
            where = f"a Dask LocalCluster of {workers} worker{'s' if workers > 1 else ''}"
        elif scheduler.startswith(("tcp://", "tls://")):
            where = f"the Dask scheduler at {scheduler}"
        else:
            raise InputError(f"expected 'local' or a scheduler address tcp://HOST:PORT, got "
                             f"{scheduler!r}", field="--scheduler")
        try:
            client = Client(cluster if cluster is not None else scheduler, timeout="15s")
        except (OSError, TimeoutError) as err:
            if cluster is not None:
                cluster.close()
            raise InputError(f"cannot reach the Dask scheduler ({err})",
                             field="--scheduler") from err
        try:
            futures = {client.submit(evaluate_all, _shipped(task), pure=False): task
                       for task in tasks}
            pending = as_completed(list(futures))
            for future in pending:
                task = futures.pop(future)
                try:
                    outcomes = future.result()
                except Exception as err:  # noqa: BLE001 - a lost worker, reported per case
                    if len(task.cases) > 1:
                        for case in task.cases:
                            single = replace(task, cases=(case,))
                            again = client.submit(evaluate_all, _shipped(single), pure=False)
                            futures[again] = single
                            pending.add(again)
                    else:
                        (case,) = task.cases
                        keep(Outcome(case.index, case.key, False,
                                     f"the Dask worker died running this case "
                                     f"({type(err).__name__})", None,
                                     "grouped" if task.grouped else "direct", None, 0.0, ""))
                    continue
                for outcome in outcomes:
                    keep(outcome)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    return where
