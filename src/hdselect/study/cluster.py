"""A Dask distributed cluster: a LocalCluster here, or a running scheduler elsewhere."""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from hdselect.base.errors import InputError
from hdselect.study.compute import Outcome
from hdselect.study.tasks import Task, evaluate_all, shipped

DASK_HINT = "pip install 'hdselect[dask]'"
"""How to install the optional Dask executor."""


def _local_cluster(workers: int) -> Any:
    """A Dask LocalCluster on this machine: worker processes of one thread, on 127.0.0.1 only."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR)


def run_dask(tasks: Sequence[Task], scheduler: str, workers: int,
              keep: Callable[[Outcome], None]) -> str:
    """Run tasks on a Dask cluster (``local`` or ``tcp://HOST:PORT``); return its description."""
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
            futures = {client.submit(evaluate_all, shipped(task), pure=False): task
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
                            again = client.submit(evaluate_all, shipped(single), pure=False)
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
