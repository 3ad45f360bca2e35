"""docs/envelope.md's examples, run as a user would, so they cannot drift.

A console block is one command and what it prints at 80 columns (standard error after
standard output); a line ``...`` stands for any number of lines. It must exit 0, or 2
where it shows an error. A python block followed by a text block must print that text.
A toml block naming a file in its first comment line must be that file.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from hdselect.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "envelope.md").read_text(encoding="utf-8")


def workdir(tmp_path: Path) -> Path:
    """A directory where the page's relative paths resolve and outputs land."""
    for name in ("robots", "trajectories", "motors", "specs"):
        (tmp_path / name).symlink_to(ROOT / name)
    return tmp_path


def matches(shown: list[str], printed: list[str]) -> bool:
    """The printed lines, with ``...`` in `shown` standing for any run of lines."""
    if not shown:
        return not printed
    if shown[0] == "...":
        return any(matches(shown[1:], printed[k:]) for k in range(len(printed) + 1))
    return bool(printed) and shown[0] == printed[0] and matches(shown[1:], printed[1:])


def console_examples() -> list[tuple[str, str]]:
    examples = []
    for block in re.findall(r"```console\n(.*?)```", DOC, flags=re.S):
        lines = block.rstrip("\n").split("\n")
        examples.append((lines[0].removeprefix("$ "), "\n".join(lines[1:])))
    return examples


@pytest.mark.parametrize(("command", "shown"), console_examples(), ids=lambda x: x[:50])
def test_console_example_prints_what_the_page_shows(command, shown, tmp_path, monkeypatch,
                                                    capsys):
    monkeypatch.chdir(workdir(tmp_path))
    monkeypatch.setenv("COLUMNS", "80")
    args = shlex.split(command)
    assert args[0] == "hdselect"
    status = main(args[1:])
    captured = capsys.readouterr()
    printed = [line.rstrip() for line in (captured.out + captured.err).rstrip().split("\n")]
    assert status == (2 if "hdselect: error:" in shown else 0)
    assert matches(shown.rstrip().split("\n"), printed), "\n".join(printed)


def test_python_examples_print_what_the_page_shows(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(workdir(tmp_path))
    pairs = re.findall(r"```python\n(.*?)```\n+```text\n(.*?)```", DOC, flags=re.S)
    assert pairs
    namespace: dict[str, object] = {}
    for code, shown in pairs:
        exec(compile(code, "docs/envelope.md", "exec"), namespace)
        printed = capsys.readouterr().out.rstrip().split("\n")
        assert matches(shown.rstrip().split("\n"), printed), "\n".join(printed)


def test_file_listings_are_the_shipped_files():
    for block in re.findall(r"```toml\n(.*?)```", DOC, flags=re.S):
        first = block.split("\n", 1)[0]
        assert first.startswith("# "), first
        assert (ROOT / first[2:].strip()).read_text(encoding="utf-8") == block.split("\n", 1)[1]
