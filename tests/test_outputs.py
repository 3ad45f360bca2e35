"""Outputs as one transaction: reserved before the work, all committed or none."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from hdselect.base.errors import InputError
from hdselect.base.outputs import Outputs, writable_target
from hdselect.report.export import write_json


def names(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


@pytest.mark.parametrize(("make", "target", "says"), [
    (lambda d: (d / "dir").mkdir(), "dir", "is a directory"),
    (lambda d: None, "missing/out.json", "does not exist; create it first"),
    (lambda d: (d / "in.toml").write_text("x"), "in.toml", "is an input file"),
])
def test_an_output_that_cannot_be_is_refused_when_reserved(tmp_path, make, target, says):
    make(tmp_path)
    with Outputs([tmp_path / "in.toml"]) as outputs, pytest.raises(InputError) as info:
        outputs.file(tmp_path / target, "--json")
    assert info.value.field == "--json" and says in info.value.reason


def test_the_same_output_twice_and_two_stdouts_are_refused(tmp_path):
    with Outputs() as outputs:
        outputs.file(tmp_path / "a.csv", "--out")
        with pytest.raises(InputError, match="already the output of --out"):
            outputs.file(tmp_path / "." / "a.csv", "--plot")
        outputs.file("-", "--json")
        with pytest.raises(InputError, match="only one output"):
            outputs.file("-", "--report")


def test_nothing_is_written_until_commit_and_nothing_is_left_without_it(tmp_path):
    (tmp_path / "old.json").write_text("old")
    with Outputs() as outputs:
        first = outputs.file(tmp_path / "old.json", "--json")
        second = outputs.file(tmp_path / "new.csv", "--out")
        write_json(first, {"a": 1})
        second.write_text("t\n")
        assert (tmp_path / "old.json").read_text() == "old"
        assert not (tmp_path / "new.csv").exists()
    assert names(tmp_path) == ["old.json"]  # left without commit: temporaries gone
    with Outputs() as outputs:
        first = outputs.file(tmp_path / "old.json", "--json")
        write_json(first, {"a": 1})
        outputs.commit()
    assert names(tmp_path) == ["old.json"] and '"a": 1' in (tmp_path / "old.json").read_text()


def test_a_replaced_file_keeps_its_permissions_and_a_new_one_follows_the_umask(tmp_path):
    target = tmp_path / "out.json"
    target.write_text("old")
    target.chmod(0o640)
    with Outputs() as outputs:
        outputs.file(target, "--json").write_text("new")
        outputs.file(tmp_path / "fresh.json", "--out").write_text("new")
        outputs.commit()
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE((tmp_path / "fresh.json").stat().st_mode) == 0o666 & ~umask


def test_a_report_directory_is_created_at_commit_with_its_parents(tmp_path):
    target = tmp_path / "a" / "b" / "report"
    with Outputs() as outputs:
        staging = outputs.directory(target, "--report")
        (staging / "index.html").write_text("page")
        assert not (tmp_path / "a").exists()
        outputs.commit()
    assert (target / "index.html").read_text() == "page"
    assert names(tmp_path) == ["a"] and names(target) == ["index.html"]


def test_a_dangling_symlink_is_followed_to_where_it_points(tmp_path):
    (tmp_path / "link.json").symlink_to(tmp_path / "made.json")
    real, kind = writable_target(tmp_path / "link.json")
    assert real == tmp_path / "made.json" and kind == "file"
    write_json(tmp_path / "link.json", {"b": 2})
    assert (tmp_path / "link.json").is_symlink() and (tmp_path / "made.json").exists()


def test_special_files(tmp_path):
    assert writable_target(os.devnull) == (Path(os.devnull), "direct")
    os.mkfifo(tmp_path / "fifo")
    assert writable_target(tmp_path / "fifo")[1] == "direct"
    write_json(os.devnull, {"c": 3})
    assert Path(os.devnull).is_char_device()
