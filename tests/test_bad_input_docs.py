"""docs/bad-input.md's examples, run as a user would, so they cannot drift."""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import pytest

from hdselect.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "bad-input.md").read_text(encoding="utf-8")


def console_examples() -> list[tuple[str, str]]:
    """Each ``$ hdselect ...`` line of a console block, with what it prints (out, then err)."""
    examples = []
    for block in re.findall(r"```console\n(.*?)```", PAGE, flags=re.S):
        command, *shown = block.rstrip("\n").split("\n")
        examples.append((command.removeprefix("$ "), "\n".join(shown)))
    return examples


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """The repository's robots, motors and motions, and the page's coarse variant."""
    for name in ("robots", "motors"):
        (tmp_path / name).symlink_to(ROOT / name)
    shutil.copytree(ROOT / "trajectories", tmp_path / "trajectories")
    text = (ROOT / "trajectories" / "benchtop6_pick_place.toml").read_text()
    (tmp_path / "trajectories" / "benchtop6_pick_place_coarse.toml").write_text(
        re.sub(r"(?m)^dt = .*$", "dt = 0.008", text))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "80")
    return tmp_path


@pytest.mark.parametrize(("command", "shown"), console_examples(), ids=lambda x: x[:50])
def test_console_example_prints_what_the_page_shows(workdir, capsys, command, shown):
    args = shlex.split(command)
    assert args[0] == "hdselect"
    status = main(args[1:])
    out, err = capsys.readouterr()
    printed = "\n".join(line.rstrip() for line in (out + err).rstrip().split("\n"))
    assert printed == shown.rstrip()
    assert status == (2 if shown.startswith("hdselect: error:") else 0)
    if status == 2:
        assert out == "" and len(err.strip().splitlines()) == 1


def test_the_warning_shown_is_the_one_a_toppra_log_gets(tmp_path):
    """The text block under "Logs of positions only" is what a positions-only TOPPRA log says."""
    import numpy as np

    import hdselect
    from hdselect.motion.planning import plan

    (shown,) = re.findall(r"```text\n(.*?)```", PAGE, flags=re.S)
    text = (ROOT / "trajectories" / "pan_tilt_scan.toml").read_text().replace(
        '"../robots/', f'"{ROOT}/robots/')
    robot, motion = hdselect.load_case(_written(tmp_path / "scan.toml", text))
    trajectory = plan(robot, motion)
    np.savetxt(tmp_path / "LOG.csv", np.column_stack([trajectory.t, trajectory.q]),
               delimiter=",", header="t,q_pan,q_tilt", comments="", fmt="%.17g")
    logged = _written(tmp_path / "log.toml", f'robot = "{ROOT}/robots/pan_tilt.urdf"\n'
                      'planner = "samples"\nangle_unit = "rad"\n[samples]\nfile = "LOG.csv"\n')
    warnings = hdselect.size(None, logged).warnings
    assert " ".join(shown.split()) in warnings


def _written(path: Path, text: str) -> Path:
    path.write_text(text)
    return path
