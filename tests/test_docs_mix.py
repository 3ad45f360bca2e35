"""docs/mix.md beyond what test_docs runs on every page (its commands and scripts print
what it shows): the TOML blocks are the shipped files, and the study it shows runs and
its CSV names the task that binds.
"""

from __future__ import annotations

import csv
import re
import shlex
from pathlib import Path

import pytest

from docs_examples import scratch
from hdselect.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "mix.md").read_text(encoding="utf-8")


def test_the_files_shown_are_the_shipped_files():
    """Every TOML block but those the page writes itself (``<!-- file: out/... -->``)."""
    blocks = re.findall(r"(?<!-->\n)```toml\n(.*?)```", PAGE, flags=re.S)
    shipped = [ROOT / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml",
               ROOT / "trajectories" / "studies" / "benchtop6_pick_inspect_shares.toml"]
    assert [block.rstrip() for block in blocks] == [p.read_text().rstrip() for p in shipped]


@pytest.mark.slow
def test_the_study_shown_runs_and_names_the_binding_task(tmp_path, monkeypatch):
    (command,) = re.findall(r"```sh\n(.*?)\n```", PAGE, flags=re.S)
    monkeypatch.chdir(scratch(tmp_path))
    args = shlex.split(command)
    assert main([*args[1:], "--workers", "0"]) == 0
    with open(tmp_path / "out" / "shares.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == 12 * 6 and {row["status"] for row in rows} == {"ok"}
    assert {row["binding_task"] for row in rows} <= {"pick", "inspect", "pooled"}
    assert {row["payloads"] for row in rows} == {"pick=0.4", "pick=0.8", "pick=1.2"}
