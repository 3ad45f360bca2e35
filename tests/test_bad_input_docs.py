"""docs/bad-input.md's examples, run as a user would, so they cannot drift."""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import pytest

from docs_examples import Example, examples, run
from hdselect.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "bad-input.md").read_text(encoding="utf-8")


def console_examples() -> list[tuple[str, str, tuple[Example, ...]]]:
    """Each ``$ hdselect ...`` line of a console block, with what it prints (out, then err),
    and the page's files and scripts before it (they write the files it reads)."""
    found, steps = [], []
    for example in examples(ROOT / "docs" / "bad-input.md"):
        if example.kind == "console":
            found.append((example.source, example.shown or "", tuple(steps)))
        else:
            steps.append(example)
    return found


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """The repository's robots, motors and motions, and an empty ``out/``."""
    for name in ("robots", "motors"):
        (tmp_path / name).symlink_to(ROOT / name)
    shutil.copytree(ROOT / "trajectories", tmp_path / "trajectories")
    (tmp_path / "out").mkdir()
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "80")
    return tmp_path


@pytest.mark.parametrize(("command", "shown", "before"), console_examples(),
                         ids=lambda x: x[:50] if isinstance(x, str) else "")
def test_console_example_prints_what_the_page_shows(workdir, capsys, command, shown, before):
    for step in before:
        run(step, workdir)
    capsys.readouterr()
    args = shlex.split(command)
    assert args[0] == "hdselect"
    status = main(args[1:])
    out, err = capsys.readouterr()
    printed = "\n".join(line.rstrip() for line in (out + err).rstrip().split("\n"))
    assert printed == shown.rstrip()
    assert status == (2 if shown.startswith("hdselect: error:") else 0)
    if status == 2:
        assert out == "" and len(err.strip().splitlines()) == 1


def test_every_file_the_page_runs_is_shipped_or_made_on_the_page():
    """Issue 27: the page ran a motion the project does not ship."""
    for command, _, before in console_examples():
        made = {step.shown for step in before if step.kind == "file"} | {
            path for step in before if step.kind == "python"
            for path in re.findall(r'Path\("([^"]+)"\)\.write_text', step.source)}
        for arg in shlex.split(command)[1:]:
            if arg.endswith((".toml", ".urdf", ".xacro", ".xml")) and arg not in made:
                assert (ROOT / arg).exists(), (arg, command)


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
