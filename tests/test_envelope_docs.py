"""docs/envelope.md beyond what tests/test_docs.py runs: its listings and its exit statuses.

`test_docs` runs every example of the page and compares what it prints; here, a toml
listing whose first line names a shipped file must be that file, and each console
example must exit 0, or 2 where it shows an error.
"""

from __future__ import annotations

import re
import shlex

import pytest

from docs_examples import ROOT, examples, scratch
from hdselect.cli.main import main

PAGE = ROOT / "docs" / "envelope.md"


def test_the_listings_are_the_shipped_files():
    listings = re.findall(r"```toml\n(.*?)```", PAGE.read_text(encoding="utf-8"), flags=re.S)
    assert listings
    for block in listings:
        first, _, body = block.partition("\n")
        assert first.startswith("# "), first
        assert (ROOT / first[2:].strip()).read_text(encoding="utf-8") == body


@pytest.mark.parametrize("example", [e for e in examples(PAGE) if e.kind == "console"
                                     and "hdselect: error:" in (e.shown or "")],
                         ids=lambda e: e.source[:60])
def test_an_example_that_shows_an_error_exits_2(example, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(scratch(tmp_path))
    assert main(shlex.split(example.source)[1:]) == 2
    assert capsys.readouterr().err.strip() == example.shown
