"""The examples of README.md and docs/*.md, read from the pages and run as a user would.

A page's fenced blocks are taken in order, each page in a scratch folder of its own
where ``robots/``, ``trajectories/``, ``motors/`` and ``catalogs/`` are the repository's and
``out/`` exists (the pages write their files there):

- ``console``: each ``$ hdselect ...`` line is run at 80 columns, piped; the lines
  under it, up to the next ``$``, are what it prints (standard output, then standard
  error). A line ``...`` stands for any number of lines left out.
- ``python``: run as a script; a ``text`` block right after it is what it prints.
- ``toml`` (or any block) right after ``<!-- file: PATH -->``: written to PATH in the
  scratch folder first, so the commands after it read it.

``python tests/docs_examples.py PAGE...`` prints what each example prints now, to
paste where a page has changed.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
"""Every page whose examples are run."""

SHIPPED = ("robots", "trajectories", "motors", "catalogs")
"""The repository's folders a page's relative paths name."""

ELLIPSIS = "..."
"""A line of shown output standing for any number of lines."""

_FENCE = re.compile(r"^(<!-- file: (?P<file>\S+) -->\n)?```(?P<kind>\w*)\n(?P<body>.*?)^```\n"
                    r"(?:\n*```text\n(?P<text>.*?)^```\n)?", flags=re.S | re.M)


@dataclass(frozen=True)
class Example:
    """One step of a page: a command, a script or a file to write.

    Attributes:
        page: The page's name, for messages.
        kind: ``"console"`` (a command), ``"python"`` (a script) or ``"file"``.
        source: The command line, the script, or the file's text.
        shown: What the page shows it printing (None: not compared; for a file, its path).
    """

    page: str
    kind: str
    source: str
    shown: str | None


def examples(page: Path, text: str | None = None) -> list[Example]:
    """Every example of a page, in order.

    Args:
        page: The Markdown file.
        text: The part of it to read (default: all of it).
    """
    text = page.read_text(encoding="utf-8") if text is None else text
    found = []
    for match in _FENCE.finditer(text):
        kind, body = match["kind"], match["body"]
        if match["file"]:
            found.append(Example(page.name, "file", body, match["file"]))
        elif kind == "console":
            for command in re.split(r"^(?=\$ )", body, flags=re.M):
                if command.strip():
                    line, _, shown = command.partition("\n")
                    found.append(Example(page.name, "console", line.removeprefix("$ "),
                                         shown.rstrip("\n")))
        elif kind == "python":
            found.append(Example(page.name, "python", body,
                                 None if match["text"] is None else match["text"].rstrip("\n")))
    return found


def scratch(folder: Path) -> Path:
    """Make `folder` a place where a page's relative paths resolve."""
    for name in SHIPPED:
        (folder / name).symlink_to(ROOT / name)
    (folder / "out").mkdir()
    return folder


def run(example: Example, folder: Path) -> str | None:
    """Run one example in `folder` (the working directory); what it printed, stripped.

    Raises:
        ValueError: A console line does not run hdselect.
    """
    if example.kind == "file":
        path = folder / example.shown
        path.write_text(example.source, encoding="utf-8")
        return None
    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(folder), _columns(80), contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        if example.kind == "console":
            from hdselect.cli.main import main

            args = shlex.split(example.source)
            if args[0] != "hdselect":
                raise ValueError(f"{example.page}: a console example runs hdselect: "
                                 f"{example.source}")
            main(args[1:])
        else:
            exec(compile(example.source, example.page, "exec"), {"__name__": "__main__"})
    printed = out.getvalue() + err.getvalue()
    return "\n".join(line.rstrip() for line in printed.rstrip().split("\n"))


_TIMING = re.compile(r"^(hdselect: \d+ cases in )\d+(?:\.\d+)? s on .*$", flags=re.M)
"""A study's closing line: its time and executor (worker processes: one per core) vary."""


def normalised(text: str) -> str:
    """`text` with what varies from run to run and machine to machine made alike."""
    return _TIMING.sub(r"\1(time) s on (executor)", text)


def matches(printed: str, shown: str) -> bool:
    """Whether `printed` is `shown`, each ``...`` line standing for any lines.

    A study's time and executor are not compared (see `normalised`).
    """
    printed, shown = normalised(printed), normalised(shown)
    pieces = [piece.strip("\n") for piece in re.split(r"^\.\.\.$", shown, flags=re.M)]
    if len(pieces) == 1:
        return printed == shown
    lines = printed.split("\n")
    first, *middle, last = [piece.split("\n") if piece else [] for piece in pieces]
    if lines[:len(first)] != first or (last and lines[len(lines) - len(last):] != last):
        return False
    at, end = len(first), len(lines) - len(last)
    if end < at:
        return False
    for piece in middle:
        while at + len(piece) <= end and lines[at:at + len(piece)] != piece:
            at += 1
        if at + len(piece) > end:
            return False
        at += len(piece)
    return True


@contextlib.contextmanager
def _columns(width: int):
    before = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(width)
    try:
        yield
    finally:
        if before is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = before


if __name__ == "__main__":
    import tempfile

    for name in sys.argv[1:]:
        with tempfile.TemporaryDirectory() as folder:
            work = scratch(Path(folder))
            for example in examples(Path(name).resolve()):
                printed = run(example, work)
                if printed is not None:
                    mark = "" if example.shown is None or matches(printed, example.shown) \
                        else "   <-- differs"
                    print(f"=== {example.kind}: {example.source.splitlines()[0]}{mark}")
                    print(printed)


OWN_ROBOT = "## Your own robot"
"""The README section whose steps build on a file the reader edits: test_readme runs it."""
