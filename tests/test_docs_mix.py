"""docs/mix.md's examples, run as a user would, so they cannot drift (as test_readme does).

Console blocks run through the command line at 80 columns and must print what the page
shows (a block ending in ``...`` shows the first lines only); each Python block must
print the text block that follows it; the TOML blocks are the shipped files; the
study runs and its CSV names the task that binds.
"""

from __future__ import annotations

import csv
import re
import shlex
from pathlib import Path

import pytest

from hdselect.cli.main import main
from test_readme import workdir

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "mix.md").read_text(encoding="utf-8")


def console_examples() -> list[tuple[str, str]]:
    """Each ``$ hdselect ...`` block: the command and the output shown under it."""
    examples = []
    for block in re.findall(r"```console\n(.*?)```", PAGE, flags=re.S):
        lines = block.rstrip("\n").split("\n")
        examples.append((lines[0].removeprefix("$ "), "\n".join(lines[1:])))
    return examples


@pytest.mark.parametrize(("command", "shown"), console_examples(), ids=lambda x: x[:60])
def test_console_example_prints_what_the_page_shows(command, shown, tmp_path, monkeypatch,
                                                    capsys):
    monkeypatch.chdir(workdir(tmp_path))
    monkeypatch.setenv("COLUMNS", "80")
    args = shlex.split(command)
    assert args[0] == "hdselect"
    assert main(args[1:]) == 0
    printed = [line.rstrip() for line in capsys.readouterr().out.rstrip().split("\n")]
    expected = shown.rstrip().split("\n")
    if expected[-1] == "...":
        expected = expected[:-1]
        printed = printed[:len(expected)]
    assert "\n".join(printed) == "\n".join(expected)


def test_python_examples_print_what_the_page_shows(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(workdir(tmp_path))
    pairs = re.findall(r"```python\n(.*?)```\n\n```text\n(.*?)```", PAGE, flags=re.S)
    assert len(pairs) == 2
    for code, shown in pairs:
        exec(compile(code, "docs/mix.md", "exec"), {})
        assert capsys.readouterr().out.rstrip() == shown.rstrip()


def test_the_files_shown_are_the_shipped_files():
    blocks = re.findall(r"```toml\n(.*?)```", PAGE, flags=re.S)
    shipped = [ROOT / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml",
               ROOT / "trajectories" / "studies" / "benchtop6_pick_inspect_shares.toml"]
    assert [block.rstrip() for block in blocks] == [p.read_text().rstrip() for p in shipped]


def test_the_study_shown_runs_and_names_the_binding_task(tmp_path, monkeypatch):
    (command,) = re.findall(r"```sh\n(.*?)\n```", PAGE, flags=re.S)
    monkeypatch.chdir(workdir(tmp_path))
    args = shlex.split(command)
    assert main([*args[1:], "--workers", "0"]) == 0
    with open(tmp_path / "shares.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == 12 * 6 and {row["status"] for row in rows} == {"ok"}
    assert {row["binding_task"] for row in rows} <= {"pick", "inspect", "pooled"}
    assert {row["payloads"] for row in rows} == {"pick=0.4", "pick=0.8", "pick=1.2"}
