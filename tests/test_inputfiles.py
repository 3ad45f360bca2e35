"""Every input file is checked and read within a size bound (hdselect.base.inputfiles).

A directory, a file that cannot be opened, a device that never ends (``/dev/zero``)
and a file larger than its kind's limit are each refused in one line naming the
file, exit status 2, and a refused stream leaves no temporary folder behind.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from hdselect.base import inputfiles
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_INPUT_BYTES, MAX_LOG_BYTES, readable
from helpers import REPO, run_redirected

ROBOT = REPO / "robots" / "planar2.urdf"
MOTION = REPO / "trajectories" / "planar2_pick_place.toml"


def one_line(argv: list[object], says: str) -> None:
    status, out, err = run_redirected(argv)
    assert status == 2 and out == "" and err.count("\n") == 1, err
    assert says in err, err


def sparse(path: Path, size: int) -> Path:
    """A file of `size` bytes that takes no room on disk."""
    with path.open("wb") as stream:
        stream.truncate(size)
    return path


@pytest.mark.slow
@pytest.mark.parametrize("argv", [
    ["joints", "/dev/zero"], ["size", "/dev/urandom"], ["size", "/dev/zero", MOTION],
    ["envelope", "/dev/zero", "--acceleration", "100"]])
def test_an_endless_device_is_refused_and_leaves_no_temporary_folder(tmp_path, argv):
    """Before: the copy of /dev/zero never ended, and a killed run left its folder."""
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    done = subprocess.run([sys.executable, "-m", "hdselect.cli", *map(str, argv)],
                          capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "TMPDIR": str(scratch)})
    assert done.returncode == 2 and done.stdout == "", done.stderr
    device = next(a for a in argv if str(a).startswith("/dev/"))
    assert done.stderr == (f"hdselect: error: {device}: larger than 64 MiB, the most hdselect "
                           "reads from such a file; is it the right file?\n")
    assert list(scratch.iterdir()) == []


@pytest.mark.slow
def test_a_stream_copied_then_refused_leaves_no_temporary_folder(tmp_path):
    """A named pipe is copied whole; the command's refusal of its content removes the copy."""
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    fifo = tmp_path / "motion.toml"
    os.mkfifo(fifo)
    text = MOTION.read_text().replace("../robots/", f"{REPO}/robots/") + "\nnosuch = 1\n"

    def serve() -> None:
        with open(fifo, "w") as stream:
            stream.write(text)

    writer = threading.Thread(target=serve, daemon=True)
    writer.start()
    done = subprocess.run([sys.executable, "-m", "hdselect.cli", "size", str(fifo)],
                          capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "TMPDIR": str(scratch)})
    writer.join(timeout=5)
    assert done.returncode == 2 and "nosuch: unknown key 'nosuch'" in done.stderr, done.stderr
    assert list(scratch.iterdir()) == []


def test_a_refused_stream_copy_removes_its_folder(tmp_path, monkeypatch):
    monkeypatch.setattr(inputfiles.tempfile, "tempdir", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    fifo = tmp_path / "motion.toml"
    os.mkfifo(fifo)

    def serve() -> None:
        with open(fifo, "w") as stream:
            stream.write("x" * 100)

    writer = threading.Thread(target=serve, daemon=True)
    writer.start()
    with pytest.raises(InputError, match="larger than"):
        readable(fifo, limit=50)
    writer.join(timeout=5)
    assert list((tmp_path / "tmp").iterdir()) == []


@pytest.mark.parametrize("command", ["robot", "motion", "joints", "envelope"])
def test_a_directory_is_refused_as_a_directory(tmp_path, command):
    folder = tmp_path / "robot.urdf"
    folder.mkdir()
    argv = {"robot": ["size", folder, MOTION], "motion": ["size", ROBOT, folder],
            "joints": ["joints", folder], "envelope": ["envelope", folder, "--acceleration",
                                                       "100"]}[command]
    one_line(argv, f"{folder}: is a directory, not a file")


def deny(monkeypatch, denied: Path) -> None:
    """Opening `denied` fails as for a file without read permission (root reads any file)."""
    real = os.open

    def opened(path, flags, *args, **kwargs):
        if Path(path) == denied:
            raise PermissionError(13, "Permission denied", str(path))
        return real(path, flags, *args, **kwargs)

    monkeypatch.setattr(inputfiles.os, "open", opened)


@pytest.mark.parametrize("which", ["robot", "motion"])
def test_an_unreadable_file_is_one_line(tmp_path, monkeypatch, which):
    """Before: PermissionError escaped as exit 70."""
    robot = tmp_path / "planar2.urdf"
    robot.write_bytes(ROBOT.read_bytes())
    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION.read_text().replace("../robots/planar2.urdf", "planar2.urdf"))
    denied = robot if which == "robot" else motion
    deny(monkeypatch, denied)
    one_line(["size", robot, motion], f"{denied}: cannot read it (Permission denied)")
    if which == "robot":
        one_line(["joints", robot], f"{denied}: cannot read it (Permission denied)")


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file without read permission")
def test_a_file_without_read_permission_is_one_line(tmp_path):
    robot = tmp_path / "planar2.urdf"
    robot.write_bytes(ROBOT.read_bytes())
    robot.chmod(0)
    one_line(["joints", robot], f"{robot}: cannot read it (Permission denied)")


def test_a_file_over_the_limit_is_refused_before_it_is_read(tmp_path):
    big = sparse(tmp_path / "big.urdf", MAX_INPUT_BYTES + 1)
    one_line(["joints", big], f"{big}: larger than 64 MiB")
    one_line(["size", ROBOT, sparse(tmp_path / "big.toml", MAX_INPUT_BYTES + 1)], "64 MiB")


def test_a_log_may_be_larger_than_other_files_within_its_own_limit(tmp_path):
    logged = (REPO / "trajectories" / "pan_tilt_logged.toml").read_text()
    log = next(line.split('"')[1] for line in logged.splitlines() if line.startswith("file"))
    motion = tmp_path / "logged.toml"
    motion.write_text(logged.replace(log, "log.csv").replace('"../robots/',
                                                             f'"{REPO}/robots/'))
    sparse(tmp_path / "log.csv", MAX_LOG_BYTES + 1)
    one_line(["size", motion], "larger than 16384 MiB")
    assert readable(sparse(tmp_path / "mid.csv", MAX_INPUT_BYTES + 1), MAX_LOG_BYTES)


@pytest.mark.parametrize(("name", "says"), [
    ("a\x00b.urdf", "robot file not found"),  # ValueError 'embedded null byte', exit 70, before
    ("a" * 5000 + ".urdf", "robot file not found"),  # OSError 'File name too long', exit 70
])
def test_a_robot_name_no_file_can_have_is_not_found(tmp_path, name, says):
    motion = tmp_path / "m.toml"
    written = name.replace("\x00", "\\u0000")  # TOML's escape of the NUL
    motion.write_text(MOTION.read_text().replace('robot = "../robots/planar2.urdf"',
                                                 f'robot = "{written}"'))
    one_line(["size", motion], f"{motion}: robot: {says}")
    assert not inputfiles.is_input_file(Path(name))
    with pytest.raises(InputError, match="NUL character" if "\x00" in name else "cannot read"):
        readable(Path(name))


def test_toml_nested_too_deeply_is_one_line(tmp_path):
    motion = tmp_path / "m.toml"
    motion.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")  # RecursionError, exit 70, before
    one_line(["size", motion], f"{motion}: not valid TOML here: nested too deeply")
