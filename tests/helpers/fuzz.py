"""The generators and the promise check of the fuzz tests (tests/test_fuzz*.py):
random and extreme TOML values, a scratch folder, and `check_run`, which holds one
command line to bad-input.md (status, one line, no output, finite JSON, no warning).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from hypothesis import event
from hypothesis import strategies as st

from hdselect.cli.main import main
from helpers import REPO

MAX_SAMPLES = "20000"
"""Every generated run is bounded to this many samples, so no case takes long."""


EXTREMES = [math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 1e-300, -1e-300, 5e-324, 1e308,
            -1e308, 1e300, 1e-7, 1e9, 10**20, -(10**20), 10**400]
"""Numbers that broke something once, or could."""


extreme = st.sampled_from(EXTREMES)


wrong_type = st.one_of(st.text(max_size=6), st.booleans(), st.just([]), st.just([1, "x"]),
                       st.just({}), st.just({"a": 1}))


anything = st.one_of(extreme, st.floats(), st.integers(-(10**6), 10**6), wrong_type)


corruptions = st.sampled_from([0, 0, 0, 0, 1, 1, 1, 2, 3])
"""How many values of an otherwise sane input are made extreme or of the wrong type."""


def toml_value(value: object) -> str:
    """A value as TOML text (nan and inf included, as TOML writes them)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(v)}"
                               for k, v in value.items()) + "}"
    raise TypeError(value)


def toml_text(entries: list[tuple[str, object]]) -> str:
    """TOML from (key, value) pairs in order; ``[table]`` / ``[[array]]`` keys open tables.

    Pairs may repeat a key (a duplicated key is itself a case to test).
    """
    lines = []
    for key, value in entries:
        if key.startswith("["):
            lines.append(key)
        else:
            lines.append(f"{key} = {toml_value(value)}")
    return "\n".join(lines) + "\n"


@st.composite
def shuffled_entries(draw, entries: list[tuple[str, object]]) -> list[tuple[str, object]]:
    """Corrupt a few values, and drop, duplicate or add a key now and then.

    Tables (``[name]`` keys) keep their keys under them.
    """
    entries = list(entries)
    keyed = [i for i, (key, _) in enumerate(entries) if not key.startswith("[")]
    for _ in range(draw(corruptions) if keyed else 0):
        i = keyed[draw(st.integers(0, len(keyed) - 1))]
        entries[i] = (entries[i][0], draw(anything))
    if keyed and draw(st.integers(0, 3)) == 0:
        i = draw(st.sampled_from(keyed))
        key, value = entries[i]
        change = draw(st.sampled_from(["missing", "duplicated", "unknown"]))
        if change == "missing":
            del entries[i]
        elif change == "duplicated":
            entries.insert(i + 1, (key, draw(st.one_of(st.just(value), anything))))
        else:
            entries.insert(i + 1, (key + draw(st.sampled_from(["x", "_", "s"])), value))
    return entries


@contextlib.contextmanager
def workdir() -> Iterator[Path]:
    """A fresh directory with the shipped robots and motions, as the working directory."""
    old = Path.cwd()
    with tempfile.TemporaryDirectory() as name:
        work = Path(name)
        (work / "robots").symlink_to(REPO / "robots")
        (work / "motors").symlink_to(REPO / "motors")
        shutil.copytree(REPO / "trajectories", work / "tr")
        (work / "existing_dir").mkdir()
        os.chdir(work)
        try:
            yield work
        finally:
            os.chdir(old)


def snapshot(work: Path) -> dict[str, tuple[int, float]]:
    """Every file and directory under `work` (not following links): a file with its size
    and time (a directory's time changes when a temporary comes and goes: not an output)."""
    files = {}
    for root, dirs, names in os.walk(work):
        for name in dirs:
            files[str(Path(root, name).relative_to(work))] = (0, 0)
        for name in names:
            path = Path(root, name)
            info = path.lstat()
            files[str(path.relative_to(work))] = (info.st_size, info.st_mtime_ns)
    return files


@contextlib.contextmanager
def c_level_stderr() -> Iterator[io.StringIO]:
    """What C and C++ code writes straight to file descriptor 2 while the block runs."""
    captured = io.StringIO()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 2)
        try:
            yield captured
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            captured.write(sink.read().decode("utf-8", errors="replace"))
            captured.seek(0)


def finite_json(text: str) -> object:
    """Parse strict JSON and check every number is finite."""
    def refuse(constant: str) -> None:
        raise AssertionError(f"not strict JSON: {constant}")

    document = json.loads(text, parse_constant=refuse)

    def walk(node: object) -> None:
        if isinstance(node, float):
            assert math.isfinite(node), node
        elif isinstance(node, dict):
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(document)
    return document


def check_run(work: Path, argv: list[str], *, stdout_json: bool = False,
              json_files: tuple[str, ...] = (), csv_files: tuple[str, ...] = (),
              jsonl_files: tuple[str, ...] = (), statuses: tuple[int, ...] = (0, 1, 2)) -> int:
    """Run the command line and check the promise; returns the exit status.

    `stdout_json`: on success standard output is a JSON document; `json_files`, `csv_files`,
    `jsonl_files` (JSON Lines): files the command may have written (``-``: standard output);
    `statuses`: the exit statuses allowed.
    """
    before = snapshot(work)
    out, err = io.StringIO(), io.StringIO()
    with c_level_stderr() as c_err, contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as exit:  # argparse refuses an argument from inside main()
            status = int(exit.code or 0)
    error_text = err.getvalue() + c_err.read()
    out_text, err_lines = out.getvalue(), error_text.strip().splitlines()
    event(f"exit {status}")
    assert status in statuses, (argv, status, error_text)
    assert "Traceback" not in error_text, error_text
    if status == 2:
        assert len(err_lines) == 1, (argv, error_text)
        event("refused: " + ": ".join(err_lines[0].split(": ")[2:4])[:40])
        assert out_text == "", (argv, out_text[:200])
        assert snapshot(work) == before, argv
    else:
        if stdout_json:
            finite_json(out_text)
        for name in json_files:
            if Path(name).is_file():
                finite_json(Path(name).read_text())
        for name in csv_files:
            text = out_text if name == "-" else Path(name).read_text() if Path(name).is_file() \
                else None
            if text is not None:
                data = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, ndmin=2)
                assert data.size and np.all(np.isfinite(data)), name
        for name in jsonl_files:
            for line in Path(name).read_text().splitlines():
                finite_json(line)
    return status


option_value = st.one_of(st.sampled_from(
    ["nan", "inf", "-inf", "0", "-0", "-1", "1e-300", "1e308", "1e400", "abc", "", "0.5", "1",
     "2", "100", "20000", "0.05", "0.9"]), extreme.map(repr))


output_path = st.sampled_from(["-", "out.json", os.devnull, "/proc/x/out.json", "none/out.json",
                               "existing_dir", "tr/planar2_pick_place.toml", "out.csv"])
