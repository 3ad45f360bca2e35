"""A Dask distributed cluster: a LocalCluster here, or a running scheduler elsewhere."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from hdselect.base.errors import InputError
from hdselect.base.scheduler import DASK_HINT, DEFAULT_TIMEOUT, open_client, where
from hdselect.study.compute import Outcome
from hdselect.study.jobs import Task, evaluate_all, shipped


def run_dask(tasks: Sequence[Task], scheduler: str, workers: int,
             keep: Callable[[Outcome], None], timeout: float = DEFAULT_TIMEOUT) -> str:
    """Run tasks on a Dask cluster (``local`` or ``tcp://HOST:PORT``); return its description.

    Args:
        tasks: The tasks.
        scheduler: ``local`` or a scheduler's address, checked
            (`hdselect.base.scheduler.scheduler_address`).
        workers: The LocalCluster's workers.
        keep: Called with each case's outcome as it arrives.
        timeout: The time limit of connecting to the scheduler [s], checked.

    Raises:
        InputError: No Dask, or no Dask scheduler answering there in time.
    """
    try:
        import dask
        from distributed import as_completed
    except ImportError as err:
        raise InputError(f"needs Dask's distributed scheduler: {DASK_HINT}",
                         field="--scheduler") from err
    with dask.config.set({"distributed.scheduler.allowed-failures": 1,
                          "distributed.worker.daemon": False}):
        client, cluster = open_client(scheduler, workers, timeout, "--scheduler")
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
    return where(scheduler, workers)
