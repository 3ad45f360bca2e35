"""``hdselect study``: every case of a design study, kept as it completes."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from hdselect.cli.output import EXIT_CASES_FAILED, EXIT_OK, rendered, say_written


def run_study(args: argparse.Namespace) -> int:
    """``hdselect study``: every case of a study, in parallel, kept as it completes.

    The CSV and its journal are appended to as cases complete (what makes a study
    resumable); the study file is read and both paths are checked before any case
    runs, and the plot is written with the other outputs' transaction at the end.
    """
    import time

    from hdselect.base.outputs import Outputs
    from hdselect.cli.inputs import timeout_of
    from hdselect.report.study_tables import study_tables, study_value_table
    from hdselect.report.tables import Paragraphs
    from hdselect.study.run import run_study as run
    from hdselect.study.spec import load_study
    from hdselect.study.store import Store, journal_path, pivots, table, value_pivot

    timeout = timeout_of(args)
    study = load_study(args.study)
    store = Store(args.out, study)  # checks both paths before any case runs
    with Outputs([args.study, *store.paths]) as outputs:
        plot = outputs.file(args.plot, "--plot") if args.plot is not None else None
        started = time.perf_counter()
        args.kept.note = (f"the cases done are kept in {args.out} and its journal "
                          f"{store.journal_path.name}; run the same command to resume")
        with _progress(study.title) as progress:
            done = run(study, store, workers=args.workers, scheduler=args.scheduler,
                       timeout=timeout, grouping=not args.no_grouping,
                       retry_failed=args.retry_failed, progress=progress)
        methods = ", ".join(f"{count} {name}" for name, count in sorted(done.methods.items()))
        items: list[Any] = [Paragraphs((
            f"{study.title}: {len(study.cases)} cases: {done.ran} run now"
            + (f" ({methods})" if methods else "")
            + f", {done.skipped} already done, {done.failed} failed",))]
        rows = table(study, done.records)
        if "size" in study.compute:
            tables, constant = pivots(study, done.records)
            items += [Paragraphs((item,)) if isinstance(item, str) else item
                      for item in study_tables(tables, constant)]
        for name, what, value in _STUDY_VALUES:
            pivot = (value_pivot(study, done.records, name, value) if name in study.compute
                     else None)
            if pivot is not None:
                items.append(study_value_table(pivot, what))
        csv_shown = store.csv_path if Path(args.out).is_symlink() else Path(args.out)
        journal_shown = (store.journal_path if Path(args.out).is_symlink()
                         else journal_path(args.out))
        items.append(Paragraphs((f"rows: {csv_shown}; records: {journal_shown}",)))
        if plot is not None and "size" in study.compute:
            from hdselect.report.study_figures import write_study_png

            joints = list(dict.fromkeys(row["joint"] for row in rows if row.get("joint")))
            first = study.varied[0] if study.varied else "case"
            second = study.varied[1] if len(study.varied) > 1 else None
            options: dict[str, Any] = next((r["result"]["options"] for r in done.records.values()
                            if r.get("ok") and r.get("result")), {})
            write_study_png(plot, study.title, [r for r in rows if r["compute"] == "size"],
                            first, second, joints, required_life=options.get("life_hours"),
                            life_basis=options.get("life_basis") or "L50",
                            others=study.varied[2:])
        text = "" if args.plot == "-" else rendered(*items)
        outputs.commit()
    sys.stdout.write(text)
    say_written([(args.plot, "the unit selected and its life per joint")], args)
    if done.ran:
        print(f"hdselect: {done.ran} cases in {time.perf_counter() - started:.1f} s on "
              f"{done.executor}", file=sys.stderr)
    return EXIT_CASES_FAILED if done.failed else EXIT_OK


def _payload_cell(result: dict) -> str:
    if result["unlimited"]:
        return "no limit"
    mass = result["max_payload_kg"]
    return "none" if mass is None else f"{mass:.3g}"


def _cycle_cell(result: dict) -> str:
    cycle = result["cycle_time_s"]
    return "none" if cycle is None else f"{cycle:.3f}"


_STUDY_VALUES = (("fastest", "fastest cycle s", _cycle_cell),
                 ("max-payload", "largest payload kg", _payload_cell))
"""The number a study prints per case of a computation other than ``size``."""


class _progress:
    """A progress bar with ETA on a terminal (standard error); nothing when piped."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.bar: Any = None

    def __enter__(self):
        if not sys.stderr.isatty():
            return None
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        bar = self.bar = Progress(
            TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
            console=Console(stderr=True), transient=True)
        self.bar.start()
        task = self.bar.add_task(self.title, total=None)

        def update(done: int, total: int, record: dict) -> None:
            bar.update(task, completed=done, total=total)
        return update

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()
