"""A study refused for its outputs or its spec: exit 2, one line, and not one byte written.

Every output and every key is checked before the first case runs. The tests run as root,
whom a read-only file does not stop: what root cannot write is simulated with
``/dev/full``, a directory in place of a file, or the operating system's refusal
monkeypatched where the study would meet it (opening its journal to append).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from hdselect.cli.main import main
from helpers import REPO

MIX = "trajectories/mixes/benchtop6_pick_inspect.toml"
SINGLE = "trajectories/planar2_pick_place.toml"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A scratch folder with the shipped robots and motions, and a two-case study."""
    for name in ("robots", "trajectories"):
        shutil.copytree(REPO / name, tmp_path / name)
    (tmp_path / "s.toml").write_text(f'[grid]\nmotion = ["{SINGLE}"]\npayload = [0.2, 0.4]\n')
    return tmp_path


def _refused(capsys, folder: Path, *argv: str, words: tuple[str, ...]) -> None:
    """The command exits 2 with one line holding `words`, and leaves no file in `folder`."""
    before = set(os.listdir(folder))
    assert main(list(argv)) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    for word in words:
        assert word in lines[0], (word, lines[0])
    assert set(os.listdir(folder)) == before


def _study(folder: Path, text: str) -> str:
    path = folder / "case.toml"
    path.write_text(text)
    return str(path)


def test_a_plot_to_a_full_device_is_refused_before_any_case(capsys, folder):
    _refused(capsys, folder, "study", str(folder / "s.toml"), "--out", str(folder / "s.csv"),
             "--workers", "0", "--plot", "/dev/full",
             words=("--plot", "/dev/full", "No space left on device"))


def test_a_plot_under_a_regular_file_is_refused_before_any_case(capsys, folder):
    _refused(capsys, folder, "study", str(folder / "s.toml"), "--out", str(folder / "s.csv"),
             "--workers", "0", "--plot", str(folder / "s.toml" / "p.png"),
             words=("--plot",))


def test_a_journal_that_is_a_directory_is_refused(capsys, folder):
    (folder / "s.jsonl").mkdir()
    _refused(capsys, folder, "study", str(folder / "s.toml"), "--out", str(folder / "s.csv"),
             "--workers", "0", words=("s.jsonl", "--out", "is a directory"))


def test_a_journal_that_cannot_be_appended_to_leaves_no_csv(capsys, folder, monkeypatch):
    """A read-only journal (for root: opening it to append refused, as for anyone else)."""
    journal = folder / "s.jsonl"
    journal.write_text("")
    opened = Path.open

    def refuse(self, mode="r", *args, **kwargs):
        if Path(os.path.realpath(self)) == journal.resolve() and "a" in mode:
            raise PermissionError(13, "Permission denied", str(self))
        return opened(self, mode, *args, **kwargs)

    monkeypatch.setattr(Path, "open", refuse)
    _refused(capsys, folder, "study", str(folder / "s.toml"), "--out", str(folder / "s.csv"),
             "--workers", "0", words=("s.jsonl", "Permission denied", "appends"))
    assert journal.read_text() == ""


def test_a_folder_that_cannot_be_written_is_refused(capsys, folder, monkeypatch):
    """A read-only folder (for root: the access check answering as for anyone else)."""
    real = os.access
    monkeypatch.setattr(os, "access", lambda path, mode, **kw: False
                        if Path(path) == folder and mode & os.W_OK else real(path, mode, **kw))
    _refused(capsys, folder, "study", str(folder / "s.toml"), "--out", str(folder / "s.csv"),
             "--workers", "0", words=("s.csv", "--out", "appends"))


@pytest.mark.parametrize(("text", "words"), [
    (f'[base]\nmotion = "{MIX}"\n[grid]\nshares = [[1.0]]\n',
     ("grid.shares", "1 share for the 2 tasks of benchtop6_pick_inspect.toml (pick, inspect)")),
    (f'[base]\nmotion = "{MIX}"\n[[case]]\nshares = [0.5, 0.3, 0.2]\n',
     ("case[0].shares", "3 shares for the 2 tasks")),
    (f'[base]\nmotion = "{MIX}"\n[[case]]\npayloads = {{pick = 0.3, plac = 0.1}}\n',
     ("case[0].payloads", "no task 'plac'", "its tasks are: pick, inspect")),
    (f'[base]\nmotion = "{MIX}"\npayload = 0.3\n', ("base.payload", "vary `payloads`")),
    (f'[base]\nmotion = "{SINGLE}"\n[grid]\nshares = [[1.0], [1.0]]\n',
     ("grid.shares", "single motion")),
    (f'[base]\nmotion = "{SINGLE}"\npayloads = {{pick = 0.3}}\n',
     ("base.payloads", "single motion")),
    (f'[grid]\nmotion = ["{SINGLE}", "{MIX}"]\nshares = [[0.5, 0.5]]\n',
     ("grid.shares", "planar2_pick_place.toml is a single motion")),
])
def test_keys_the_motion_file_cannot_take_are_refused_before_any_case(capsys, folder, text,
                                                                      words):
    _refused(capsys, folder, "study", _study(folder, text), "--out", str(folder / "r.csv"),
             "--workers", "0", words=words)


def test_shares_that_fit_the_mix_are_taken(folder):
    from hdselect.study import load_study

    study = load_study(_study(folder, f'[base]\nmotion = "{MIX}"\n[grid]\n'
                                      "shares = [[0.5, 0.5], [0.7, 0.3]]\n"
                                      "payloads = [{pick = 0.2}, {inspect = 0.1}]\n"))
    assert [case.shares for case in study.cases] == [(0.5, 0.5), (0.5, 0.5), (0.7, 0.3),
                                                     (0.7, 0.3)]


@pytest.mark.parametrize(("text", "words"), [
    ('[base]\nmotion = "a\\u0000.toml"\n[grid]\npayload = [0.2]\n',
     ("base.motion", "expected a file name")),
    ('[grid]\nmotion = ["x.toml"]\ncatalog = ["c\\u0000.toml"]\n',
     ("grid.catalog", "expected a catalog file")),
])
def test_a_file_name_holding_a_nul_is_refused_before_any_case(capsys, folder, text, words):
    # found by the hostile battery: ValueError 'embedded null byte' (exit 70) as the study's
    # outputs were checked against its inputs
    _refused(capsys, folder, "study", _study(folder, text), "--out", str(folder / "r.csv"),
             "--workers", "0", words=words)


def test_a_motion_naming_a_robot_with_a_nul_fails_its_case_alone(capsys, folder):
    motion = folder / "trajectories" / "nul.toml"
    motion.write_text((folder / SINGLE).read_text().replace(
        'robot = "../robots/planar2.urdf"', 'robot = "a\\u0000b.urdf"'))
    study = _study(folder, f'[grid]\nmotion = ["{motion}"]\npayload = [0.2]\n')
    assert main(["study", study, "--out", str(folder / "r.csv"), "--workers", "0"]) == 3
    assert "robot file not found" in (folder / "r.jsonl").read_text()
