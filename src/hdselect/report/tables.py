"""Terminal tables that never cut a value short, whatever the width.

A `FittedTable` is laid out when it is printed, for the width it is given: every
column in one table if they fit; else the essential columns (the key, say a joint
name, and the answer) stay in the first table and whole groups of the other
columns move, in order, into tables below it, each repeating the key; and on a
terminal too narrow even for that, each row becomes a block of ``header: value``
lines. A cell is never truncated: a long value wraps only in that last form.
"""

from __future__ import annotations

import io
import re
import textwrap
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import IO, cast

from rich import box
from rich.console import Console, ConsoleOptions, RenderResult
from rich.measure import Measurement
from rich.table import Table
from rich.text import Text


@dataclass(frozen=True)
class Column:
    r"""One column of a `FittedTable`.

    Attributes:
        header: Its heading; a ``\\n`` splits it over two lines.
        justify: ``"left"`` or ``"right"``.
        group: Columns with the same group move below the first table together; the
            empty group is essential and stays in the first table.
    """

    header: str
    justify: str = "right"
    group: str = ""


@dataclass(frozen=True)
class FittedTable:
    """A table with a title and notes, laid out for the width it is printed at.

    Attributes:
        title: Lines above the table (each wraps).
        columns: The columns; the first is the key, repeated in every table.
        rows: Each row's cells as rich markup, one per column.
        styles: A style per row (None for plain).
        notes: Paragraphs printed under the table (they wrap).
    """

    title: str
    columns: tuple[Column, ...]
    rows: tuple[tuple[str, ...], ...]
    styles: tuple[str | None, ...] = ()
    notes: tuple[str, ...] = ()

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        width = options.max_width
        if self.title:
            for line in self.title.split("\n"):
                yield from wrapped(line, width, indent="")
            yield Text("")
        parts = self.layout(console, width)
        if parts is None:
            yield from self._blocks(width)
        else:
            for i, part in enumerate(parts):
                if i:
                    yield Text("")
                yield self._table(part)
        if self.notes:
            yield Text("")
        for note in self.notes:
            yield from wrapped(note, width)

    def layout(self, console: Console, width: int) -> list[list[int]] | None:
        """The columns of each table for `width`, or None when even the first cannot fit.

        Args:
            console: The console that measures the cells.
            width: Columns available [characters].

        Returns:
            Column indices per table, key first; None for the one-block-per-row form.
        """
        essential = [0] + [i for i, c in enumerate(self.columns) if i and not c.group]
        groups: list[list[int]] = []
        for i, column in enumerate(self.columns):
            if i and column.group:
                if groups and self.columns[groups[-1][0]].group == column.group:
                    groups[-1].append(i)
                else:
                    groups.append([i])
        parts = [essential]
        if self._width(console, essential, width) > width:
            return None
        for group in groups:
            grown = sorted(parts[-1] + group)
            if self._width(console, grown, width) <= width:
                parts[-1] = grown
            elif self._width(console, [0, *group], width) <= width:
                parts.append([0, *group])
            else:
                return None
        return parts

    def _table(self, indices: Sequence[int]) -> Table:
        table = Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False,
                      collapse_padding=True)
        for i in indices:
            column = self.columns[i]
            table.add_column(column.header, justify=column.justify,  # type: ignore[arg-type]
                             no_wrap=True)
        for k, row in enumerate(self.rows):
            style = self.styles[k] if k < len(self.styles) else None
            table.add_row(*(Text.from_markup(row[i]) for i in indices), style=style)
        return table

    def _width(self, console: Console, indices: Sequence[int], width: int) -> int:
        """The width the table of these columns needs, uncut [characters]."""
        options = console.options.update_width(max(width, 1000))
        return Measurement.get(console, options, self._table(indices)).maximum

    def _blocks(self, width: int) -> Iterator[Text]:
        """Each row as its key, then one ``header: value`` line per other column.

        A value too long for its header's line goes on the next line, indented.
        """
        headers = [" ".join(c.header.split()).replace("/ ", "/") for c in self.columns]
        for k, row in enumerate(self.rows):
            style = self.styles[k] if k < len(self.styles) else ""
            if k:
                yield Text("")
            yield Text.from_markup(row[0], style=style or "")
            for header, cell in zip(headers[1:], row[1:], strict=True):
                value = Text.from_markup(cell, style=style or "")
                if len(header) + 4 + value.cell_len <= width:
                    yield Text(f"  {header}: ", style=style or "") + value
                else:
                    yield Text(f"  {header}:", style=style or "")
                    yield Text("    ", style=style or "") + value


_UNBROKEN = re.compile(r"(?<=\d) (?=N m|kg|rpm|h\b|s\b|lb|%|deg|rad|m/s|m\b|N\b)|(?<=\bN) (?=m\b)"
                       r"|(?<=kg) (?=cm)")
"""Spaces a line never breaks at: inside ``N m`` and ``kg cm``, after a number's digits."""


_COMMAND = re.compile(r"(?<=: )hdselect(?: \S*[^\s.;,])+$")
"""A command that ends a line (``...: hdselect size m.toml --exclude elbow``): one piece."""


def wrapped(text: str, width: int, *, indent: str = "  ") -> Iterator[Text]:
    """A paragraph as lines of at most `width`, continuation lines indented.

    Never breaks a word, nor a number from its unit (``2.6 N m`` stays on one line), nor
    a command that ends the paragraph (it moves to a line of its own, to be copied whole,
    even where that line is longer than `width`).
    """
    glued = _COMMAND.sub(lambda m: m[0].replace(" ", "\u00a0"), text)
    glued = _UNBROKEN.sub("\u00a0", glued)
    lines = textwrap.wrap(glued, width=max(width, 20), subsequent_indent=indent,
                          break_long_words=False, break_on_hyphens=False)
    for line in lines or [""]:
        yield Text(line.replace("\u00a0", " "))


@dataclass(frozen=True)
class Paragraphs:
    """Lines of text, each wrapped to the width it is printed at (see `wrapped`)."""

    lines: tuple[str, ...]

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        for line in self.lines:
            yield from wrapped(line, options.max_width)


class _Trimmed(io.TextIOBase):
    """A text stream that drops the spaces rich pads each line with."""

    def __init__(self, stream: IO[str]) -> None:
        self._stream = stream
        self._pending = ""

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return getattr(self._stream, "encoding", None) or "utf-8"

    def isatty(self) -> bool:
        return False

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:  # type: ignore[override]
        lines = (self._pending + text).split("\n")
        self._pending = lines.pop()
        for line in lines:
            self._stream.write(line.rstrip() + "\n")
        return len(text)

    def flush(self) -> None:
        if self._pending:
            self._stream.write(self._pending)
            self._pending = ""
        self._stream.flush()


def console_for(stream: IO[str]) -> Console:
    """A console for `stream`.

    A terminal is printed to at its width (or ``COLUMNS``), in colour. Anything
    else (a pipe, a file) gets ``COLUMNS`` or 80 columns, no colour, and no
    trailing spaces. A word longer than the width is never split.
    """
    # soft_wrap: our renderables wrap their own text; a word longer than the width (a
    # long path) is printed whole rather than folded.
    if stream.isatty():
        return Console(file=stream, highlight=False, soft_wrap=True)
    return Console(file=cast(IO[str], _Trimmed(stream)), highlight=False, soft_wrap=True)
