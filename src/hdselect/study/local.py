"""Worker processes on this machine: each task in a child process, a dead one reported.

Workers are forked from a fork server that imported hdselect (and the numerical
libraries a case needs) once, when this process first started a worker: a worker is
ready in milliseconds, not after the second or so a fresh interpreter takes to import
them. The server is a clean, single-threaded process, so forking it is safe where
forking this one (OpenMP and rich threads) would not be.
"""

from __future__ import annotations

import multiprocessing
import signal
import sys
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import replace
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from hdselect.base.errors import HdselectError
from hdselect.study.compute import Outcome
from hdselect.study.jobs import Task, evaluate

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


PRELOAD = ("hdselect.study.local", "hdselect.study.compute",
           "hdselect.motion.planning.constraints", "scipy.interpolate")
"""Modules the fork server imports once for every worker it forks."""


def _context() -> Any:
    """Workers forked from a server that imported `PRELOAD` (spawned where there is none)."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(list(PRELOAD))
    return context


def run_local(tasks: Sequence[Task], workers: int, keep: Callable[[Outcome], None]) -> None:
    """Run tasks in `workers` child processes here, keeping each outcome as it arrives."""
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
    if worker.task is None:
        raise RuntimeError("a worker without a task died")
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
