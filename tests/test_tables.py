"""FittedTable: one table, tables below, or blocks; never a cut cell."""

from __future__ import annotations

import io

from rich.console import Console

from hdselect.report.tables import Column, FittedTable, console_for

COLUMNS = (Column("name", "left"), Column("answer", "left"), Column("a", group="one"),
           Column("b", group="one"), Column("c", group="two"))
ROWS = (("a_rather_long_joint_name", "PSA-14-100 fails peak +200%", "123.456", "7", "x" * 12),
        ("short", "PSA-08-80", "1", "22", "y"))


def render(table: FittedTable, width: int) -> list[str]:
    stream = io.StringIO()
    console = console_for(stream)
    console.width = width
    console.print(table)
    return stream.getvalue().splitlines()


def test_wide_enough_one_table():
    table = FittedTable("", COLUMNS, ROWS)
    assert table.layout(Console(width=200), 200) == [[0, 1, 2, 3, 4]]
    lines = render(table, 200)
    assert lines[0].split() == ["name", "answer", "a", "b", "c"]


def test_groups_move_below_whole_and_in_order():
    table = FittedTable("", COLUMNS, ROWS)
    console = Console(width=200)
    full = table._width(console, [0, 1, 2, 3, 4], 200)
    assert table.layout(console, full - 1) == [[0, 1, 2, 3], [0, 4]]
    narrow = max(table._width(console, [0, 1], 200), table._width(console, [0, 2, 3, 4], 200))
    assert table._width(console, [0, 1, 2, 3], 200) > narrow
    assert table.layout(console, narrow) == [[0, 1], [0, 2, 3, 4]]
    lines = render(table, narrow)
    assert [line.split()[0] for line in lines if line.strip() and "─" not in line] == [
        "name", "a_rather_long_joint_name", "short", "name", "a_rather_long_joint_name", "short"]


def test_too_narrow_for_the_essentials_lists_each_row():
    table = FittedTable("title", COLUMNS, ROWS, notes=("a note",))
    assert table.layout(Console(width=34), 34) is None
    lines = render(table, 34)
    assert "a_rather_long_joint_name" in lines
    assert "  c: xxxxxxxxxxxx" in lines
    assert lines[lines.index("  answer:") + 1] == "    PSA-14-100 fails peak +200%"  # whole
    assert lines[-1] == "a note"


def test_piped_output_has_no_trailing_spaces_and_no_colour():
    table = FittedTable("", COLUMNS, (("[red]bad[/red]", "x", "1", "2", "3"),))
    text = "\n".join(render(table, 100))
    assert "\x1b[" not in text
    assert all(line == line.rstrip() for line in text.splitlines())
