"""Design studies: many sizing cases from one study file, run in parallel and kept.

`study` reads a study file, runs every case not yet done (worker processes here, or
a Dask cluster) and returns one row per case and joint. `load_study`, `run_study`
and `hdselect.study.store` are the steps on their own. The package is callable:
``hdselect.study(path)`` is `study`, and ``hdselect.study.load_study`` still works.
"""

from __future__ import annotations

import inspect
import sys
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hdselect.base.errors import InputError
from hdselect.base.scheduler import DEFAULT_TIMEOUT
from hdselect.study.case import Case
from hdselect.study.compute import COMPUTATIONS, Computation, Outcome
from hdselect.study.run import StudyRun, run_study
from hdselect.study.spec import Study, load_study
from hdselect.study.store import table

__all__ = ["COMPUTATIONS", "Case", "Computation", "Outcome", "Study", "StudyRun", "load_study",
           "run_study", "study"]


def study(path: str | Path, out: str | Path | None = None, *, workers: int | None = None,
          scheduler: str | None = None, timeout: float = DEFAULT_TIMEOUT,
          grouping: bool = True, retry_failed: bool = False, frame: bool = False,
          progress: Callable[[int, int, dict[str, Any]], None] | None = None) -> Any:
    """Run a study file and return its rows: one per case and joint.

    Args:
        path: The study file (TOML).
        out: The CSV file to keep results in (a JSON Lines journal beside it); a second
            call skips the cases already there. None keeps nothing.
        workers: Worker processes (default: the cores here; 0: in this process).
        scheduler: ``"local"`` for a Dask LocalCluster, ``"tcp://HOST:PORT"`` for a Dask
            scheduler; None for local worker processes.
        timeout: The time limit of connecting to the scheduler [s], at most a day.
        grouping: Evaluate cases of one robot and path from a shared basis.
        retry_failed: Run again the cases recorded as failed.
        frame: Return a pandas DataFrame instead of a list of dicts (needs pandas).
        progress: Called with (done, to do, record) after each case.

    Returns:
        The rows (the CSV's columns, typed values), in study order.

    Raises:
        InputError: The study file or an argument is bad, or pandas is missing for `frame`.
    """
    if frame:
        try:
            import pandas
        except ImportError as err:
            raise InputError("frame=True needs pandas: pip install pandas",
                             field="frame") from err
    loaded = load_study(path)
    run = run_study(loaded, out, workers=workers, scheduler=scheduler, timeout=timeout,
                    grouping=grouping, retry_failed=retry_failed, progress=progress)
    rows = table(loaded, run.records)
    return pandas.DataFrame(rows) if frame else rows


class _CallableModule(types.ModuleType):
    """This package, callable as the function `study` it exports, with its signature."""

    __call__ = staticmethod(study)
    __signature__ = inspect.signature(study)


sys.modules[__name__].__class__ = _CallableModule
