"""The search's quasi-random states spread over worker processes, or a Dask cluster.

The bulk of an envelope's work is evaluating every demand at many quasi-random
states (`hdselect.envelope.demands.all_demands`); the states are independent, so
they split into chunks computed wherever workers run, each on one thread. The
refinement that follows is a chain of small batches and stays here. On one machine
the batched dynamics already use every core, so workers pay off on a larger machine
or a cluster, not on a laptop.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import replace
from types import TracebackType
from typing import Any

import numpy as np

from hdselect.base.errors import InputError
from hdselect.base.scheduler import (
    DEFAULT_TIMEOUT,
    open_client,
    scheduler_address,
    timeout_seconds,
    where,
)
from hdselect.envelope.box import LimitBox
from hdselect.envelope.demands import all_demands
from hdselect.robot.model import Robot

CHUNKS_PER_WORKER = 2
"""Chunks each worker gets per batch of states: enough to even out their speeds."""


def _chunk_demands(robot: Robot, box: LimitBox, x: np.ndarray, joints: Sequence[int],
                   stop_time: float) -> np.ndarray:
    """`all_demands` of one chunk, on one thread (what a worker runs)."""
    return all_demands(robot, box, x, joints, stop_time, threads=1)


def default_workers() -> int:
    """The cores this process may use."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def shippable(robot: Robot) -> Robot:
    """The same robot with its read-only mappings as plain dicts, so that it pickles."""
    return replace(robot, gearhead_masses=dict(robot.gearhead_masses), mimic=dict(robot.mimic))


class Spread:
    """Evaluates the search's states in chunks on workers: a context manager and an `Evaluate`.

    Args:
        workers: Worker processes (with ``scheduler="local"``: Dask workers), at least 1.
        scheduler: None for worker processes here; ``"local"`` for a Dask LocalCluster on
            this machine; ``"tcp://HOST:PORT"`` for a running Dask scheduler.
        timeout: The time limit of connecting to the scheduler [s].

    Raises:
        InputError: The worker count is not a whole number from 1, the scheduler is not
            ``local`` or an address, the time limit not in (0, 1 day], Dask is not
            installed, or no Dask scheduler answers in time (raised on entering).
    """

    def __init__(self, workers: int, scheduler: str | None = None,
                 timeout: float = DEFAULT_TIMEOUT) -> None:
        if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= 4096:
            raise InputError(f"must be a whole number from 1 to 4096, got {workers!r}",
                             field="workers")
        self.scheduler = None if scheduler is None else scheduler_address(scheduler,
                                                                          "scheduler")
        self.timeout = timeout_seconds(timeout, "timeout")
        self.workers = workers
        self._pool: Executor | None = None
        self._client: Any = None
        self._cluster: Any = None

    @property
    def where(self) -> str:
        """Where the states are computed, in words."""
        if self.scheduler is None:
            return f"{self.workers} worker process{'es' if self.workers > 1 else ''}"
        return where(self.scheduler, self.workers)

    def __enter__(self) -> Spread:
        if self.scheduler is None:
            self._pool = ProcessPoolExecutor(self.workers,
                                             mp_context=multiprocessing.get_context("spawn"))
            return self
        self._client, self._cluster = open_client(self.scheduler, self.workers, self.timeout,
                                                  "scheduler")
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self._close()

    def __call__(self, robot: Robot, box: LimitBox, x: np.ndarray, joints: Sequence[int],
                 stop_time: float) -> np.ndarray:
        """All demands of `joints` at the points `x`, computed in chunks on the workers."""
        chunks = np.array_split(x, max(1, min(len(x), CHUNKS_PER_WORKER * self.workers)))
        robot, joints = shippable(robot), list(joints)
        if self._client is not None:
            # keys of their own (hash=False): the same robot and box scattered again by the
            # next round would share the last round's keys, which that round's release can
            # drop while the new tasks still need them ("lost dependencies")
            shared = self._client.scatter([robot, box], broadcast=True, hash=False)
            futures = [self._client.submit(_chunk_demands, shared[0], shared[1], chunk, joints,
                                           stop_time, pure=False) for chunk in chunks]
            parts = self._client.gather(futures)
        else:
            if self._pool is None:
                raise RuntimeError("use Spread as a context manager")
            parts = list(self._pool.map(_chunk_demands, [robot] * len(chunks),
                                        [box] * len(chunks), chunks,
                                        [joints] * len(chunks), [stop_time] * len(chunks)))
        return np.concatenate(parts)

    def _close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        if self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None
