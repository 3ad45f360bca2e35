"""Output files as one transaction: checked before the work, written aside, committed together.

A command's outputs (a CSV, a PNG, a JSON file, a report directory, standard
output) are each reserved before any work starts: the path is checked (not an
input, not a directory, not given twice, writable) and a temporary is made
beside it. The work writes into the temporaries; `Outputs.commit` then moves them
all into place, and puts back what it replaced if any move fails, so a command
leaves all its outputs or none. Leaving the ``with`` block without committing
(an error, Ctrl-C, SIGTERM) removes every temporary.

Targets: ``-`` is standard output (written at commit, at most one output per
command); a symlink is followed and its target replaced; a character device or
a FIFO (``/dev/null``, a named pipe) is written directly, never replaced; other
special files are refused.
"""

from __future__ import annotations

import os
import secrets
import shutil
import stat
import sys
import tempfile
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any

from hdselect.base.errors import InputError


@dataclass
class _Staged:
    """One reserved output: where it is written now and where it goes at commit."""

    option: str
    target: Path | None  # None: standard output
    staging: Path
    kind: str  # "file", "direct" (device or FIFO), "stdout", "directory"
    created: list[Path] = field(default_factory=list)
    exclusive: bool = False  # a new file only: never replaces one


def writable_target(target: str | Path, option: str | None = None) -> tuple[Path, str]:
    """Where writing `target` really goes, and how.

    Returns:
        The real path (symlinks followed) and ``"file"`` (write aside, then rename
        over it) or ``"direct"`` (a character device or a FIFO: write into it).

    Raises:
        InputError: It is a directory or another special file, or its directory is missing.
    """
    path = Path(target)
    real = Path(os.path.realpath(path))
    try:
        mode = os.stat(path).st_mode  # through symlinks, /dev/stdout on a pipe too
    except FileNotFoundError:
        mode = None
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror})", path=path, field=option) from err
    if mode is not None:
        if stat.S_ISDIR(mode):
            raise InputError("is a directory; give a file name", path=path, field=option)
        if stat.S_ISCHR(mode):
            _write_nothing(path, option)
        if stat.S_ISCHR(mode) or stat.S_ISFIFO(mode):
            # a pipe's /proc link (pipe:[N]) is no path: open it by the name given
            return (real if real.exists() else path.absolute()), "direct"
        if not stat.S_ISREG(mode):
            raise InputError("is a special file (a block device or a socket); not written",
                             path=path, field=option)
    elif not real.parent.is_dir():
        raise InputError(f"the directory {real.parent} does not exist; create it first",
                         path=path, field=option)
    return real, "file"


def _write_nothing(path: Path, option: str | None) -> None:
    """Write zero bytes into a character device, before any work.

    A device that refuses every write (``/dev/full``) refuses this too; a terminal or
    ``/dev/null`` takes it.

    Raises:
        InputError: The device cannot be opened or written.
    """
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK | os.O_NOCTTY)
        try:
            os.write(fd, b"")
        finally:
            os.close(fd)
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror})", path=path, field=option) from err


def write_file(target: str | Path, write: Callable[[Any], None], *,
                 binary: bool = False) -> None:
    """Write one file atomically (temporary file, then rename); ``-`` is standard output.

    A symlink is followed and its target replaced, keeping its mode; a character
    device or a FIFO (``/dev/null``, a named pipe) is written directly, never
    replaced. For several outputs that must appear together, see `Outputs`.

    Args:
        target: The file, or ``-``.
        write: Writes the content to the open stream it is given.
        binary: Open the file in binary mode (text, UTF-8, otherwise).

    Raises:
        InputError: The file cannot be written.
    """
    if str(target) == "-":
        write(getattr(sys.stdout, "buffer", sys.stdout) if binary else sys.stdout)
        return
    real, kind = writable_target(target)
    if kind == "direct":
        try:
            with (open(real, "wb") if binary else
                  open(real, "w", encoding="utf-8", newline="")) as stream:
                write(stream)
        except OSError as err:
            raise InputError(f"cannot write here ({err.strerror})", path=target) from err
        return
    try:
        fd, tmp = tempfile.mkstemp(dir=real.parent, prefix=f".{real.name}.")
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror})", path=target) from err
    try:
        with (os.fdopen(fd, "wb") if binary else
              os.fdopen(fd, "w", encoding="utf-8", newline="")) as stream:
            write(stream)
        if real.exists():
            shutil.copymode(real, tmp)
        else:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; a report is not
        os.replace(tmp, real)
    except OSError as err:
        Path(tmp).unlink(missing_ok=True)
        raise InputError(f"cannot write here ({err.strerror})", path=target) from err
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class Outputs:
    """A command's output files, reserved up front and committed all at once.

    Args:
        inputs: Files the command reads; none of them may be an output.
    """

    def __init__(self, inputs: Iterable[str | Path] = ()) -> None:
        self._inputs = [Path(os.path.realpath(p)) for p in inputs]
        self._staged: list[_Staged] = []
        self._committed = False

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.discard()

    def file(self, target: str | Path, option: str, *, exclusive: bool = False) -> Path:
        """Reserve an output file (``-``: standard output); returns the path to write to.

        Args:
            target: The file, or ``-``.
            option: The command-line option that names it, for messages.
            exclusive: Never replace an existing file: refuse it now, and at commit fail
                (changing nothing) if one appeared meanwhile. Devices and FIFOs are still
                written into.

        Raises:
            InputError: The target cannot be written, is an input, is reserved already,
                or exists when `exclusive`.
        """
        check_output_path(target, option, directory=False)
        if str(target) == "-":
            if any(s.kind == "stdout" for s in self._staged):
                raise InputError("only one output can go to standard output ('-')",
                                 field=option)
            return self._reserve(option, None, "stdout", Path(tempfile.gettempdir()))
        real, kind = writable_target(target, option)
        self._check_new(Path(target), real, option)
        if exclusive and kind == "file" and os.path.lexists(real):
            raise InputError("exists; choose another path or remove it first", path=target,
                             field=option)
        directory = Path(tempfile.gettempdir()) if kind == "direct" else real.parent
        staging = self._reserve(option, real, kind, directory)
        self._staged[-1].exclusive = exclusive
        return staging

    def directory(self, target: str | Path, option: str) -> Path:
        """Reserve an output directory (created at commit if missing); returns a staging one.

        Files written into the staging directory are moved into the target at commit,
        replacing files of the same name; other files there are left alone.

        Raises:
            InputError: The target is empty, a file, an input, or cannot be written.
        """
        check_output_path(target, option, directory=True)
        path = Path(target)
        real = Path(os.path.realpath(path))
        if real.exists() and not real.is_dir():
            raise InputError("exists and is not a directory", path=path, field=option)
        self._check_new(path, real, option)
        anchor = real.parent
        while not anchor.exists():
            anchor = anchor.parent
        if not anchor.is_dir():
            raise InputError(f"{anchor} is not a directory", path=path, field=option)
        try:
            staging = Path(tempfile.mkdtemp(dir=anchor, prefix=f".{real.name}."))
        except OSError as err:
            raise InputError(f"cannot write here ({err.strerror})", path=path,
                             field=option) from err
        self._staged.append(_Staged(option, real, staging, "directory"))
        return staging

    def commit(self) -> None:
        """Move every output into place; on a failure, put back everything replaced.

        Raises:
            InputError: An output could not be moved into place (nothing is left changed).
        """
        self._check_directories()
        done: list[tuple[Path, Path | None]] = []  # (target, backup of what it replaced)
        created: list[Path] = []
        current: _Staged | None = None  # the output being placed, for the message
        try:
            for staged in self._staged:
                current = staged
                if staged.kind == "file" and staged.exclusive:
                    if staged.target is None:
                        raise RuntimeError(f"staged {staged.kind} output has no target")
                    _place_new(staged.staging, staged.target)
                    done.append((staged.target, None))
                elif staged.kind == "file":
                    if staged.target is None:
                        raise RuntimeError(f"staged {staged.kind} output has no target")
                    done.append((staged.target, _swap(staged.staging, staged.target)))
                elif staged.kind == "directory":
                    if staged.target is None:
                        raise RuntimeError(f"staged {staged.kind} output has no target")
                    created += _make_directory(staged.target)
                    for item in sorted(staged.staging.iterdir()):
                        destination = staged.target / item.name
                        done.append((destination, _swap(item, destination)))
            for staged in self._staged:
                current = staged
                if staged.kind == "direct":
                    if staged.target is None:
                        raise RuntimeError(f"staged {staged.kind} output has no target")
                    with staged.staging.open("rb") as source, staged.target.open("wb") as sink:
                        shutil.copyfileobj(source, sink)
        except FileExistsError as err:
            _roll_back(done, created)
            raise InputError("appeared while hdselect ran, and is not replaced; nothing was "
                             "changed", path=err.filename) from err
        except OSError as err:
            _roll_back(done, created)
            raise InputError(f"cannot write here ({err.strerror or err}); nothing was changed",
                             path=None if current is None else current.target,
                             field=None if current is None else current.option) from err
        except BaseException:
            _roll_back(done, created)
            raise
        for _, backup in done:
            if backup is not None:
                backup.unlink(missing_ok=True)
        try:  # last, as it cannot be taken back; a reader that went away is not our error
            for staged in self._staged:
                if staged.kind == "stdout":
                    _to_stdout(staged.staging)
        finally:
            self._committed = True
            self.discard()

    def discard(self) -> None:
        """Remove every temporary (after a commit, only what is left of them)."""
        for staged in self._staged:
            if staged.staging.is_dir():
                shutil.rmtree(staged.staging, ignore_errors=True)
            else:
                staged.staging.unlink(missing_ok=True)
        self._staged.clear()

    def _check_directories(self) -> None:
        """Refuse, before anything moves, a directory output that would replace an input.

        Raises:
            InputError: A file written into an output directory has the name of an input
                file there (e.g. a motion file named ``index.html`` inside ``--report DIR``).
        """
        for staged in self._staged:
            if staged.kind != "directory":
                continue
            if staged.target is None:
                raise RuntimeError(f"staged {staged.kind} output has no target")
            for item in sorted(staged.staging.iterdir()):
                destination = Path(os.path.realpath(staged.target / item.name))
                if destination in self._inputs:
                    raise InputError(f"would write {item.name} over the input file "
                                     f"{destination}; choose another directory", path=staged.target,
                                     field=staged.option)

    def _check_new(self, path: Path, real: Path, option: str) -> None:
        if real in self._inputs:
            raise InputError("is an input file; choose another output path", path=path,
                             field=option)
        for staged in self._staged:
            if staged.target == real:
                raise InputError(f"is already the output of {staged.option}", path=path,
                                 field=option)

    def _reserve(self, option: str, target: Path | None, kind: str, directory: Path) -> Path:
        name = target.name if target is not None else "stdout"
        try:
            fd, name = tempfile.mkstemp(dir=directory, prefix=f".{name}.")
        except OSError as err:
            raise InputError(f"cannot write here ({err.strerror})", path=target,
                             field=option) from err
        os.close(fd)
        staging = Path(name)
        self._staged.append(_Staged(option, target, staging, kind))
        return staging


def check_output_path(target: str | Path, option: str, *, directory: bool = False) -> None:
    """Refuse an empty path, and a file path ending in '/' (it names a directory).

    Raises:
        InputError: Naming the option.
    """
    text = str(target) if isinstance(target, Path) else target
    if not isinstance(text, str) or not text.strip():
        raise InputError(f"an empty path; give a {'directory' if directory else 'file'} name "
                         "(or '-' for standard output)", field=option)
    if not directory and text.endswith(("/", os.sep)):
        raise InputError("ends in '/', which names a directory; give a file name", path=text,
                         field=option)


def _to_stdout(staged: Path) -> None:
    """Copy a staged output to standard output: as bytes, or as text to a text-only one."""
    sys.stdout.flush()
    binary = getattr(sys.stdout, "buffer", None)
    with staged.open("rb") as source:
        if binary is not None:
            shutil.copyfileobj(source, binary)
            binary.flush()
        else:
            for block in iter(lambda: source.read(1 << 20), b""):
                sys.stdout.write(block.decode("utf-8", errors="replace"))


def _swap(new: Path, target: Path) -> Path | None:
    """Rename `new` over `target`, keeping a hard link (or copy) of what it replaces."""
    backup = None
    if target.exists():
        backup = target.with_name(f".{target.name}.replaced-{secrets.token_hex(6)}")
        try:
            os.link(target, backup)
        except OSError:
            shutil.copy2(target, backup)
        shutil.copymode(target, new)
    else:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(new, 0o666 & ~umask)  # a temporary is private; an output is not
    os.replace(new, target)
    return backup


def _place_new(new: Path, target: Path) -> None:
    """Give `new` the name `target`, which must not exist (a hard link: atomic, no replace).

    Raises:
        FileExistsError: `target` exists.
    """
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(new, 0o666 & ~umask)  # a temporary is private; an output is not
    try:
        os.link(new, target)
    except FileExistsError as err:
        raise FileExistsError(err.errno, err.strerror, str(target)) from err
    except OSError:  # no hard links here: create it exclusively and copy
        with new.open("rb") as source, target.open("xb") as sink:
            shutil.copyfileobj(source, sink)
    new.unlink()


def _make_directory(target: Path) -> list[Path]:
    """Create `target` and any missing parents; the directories created, deepest first."""
    missing = []
    path = target
    while not path.exists():
        missing.append(path)
        path = path.parent
    for directory in reversed(missing):
        directory.mkdir()
    return missing


def _roll_back(done: list[tuple[Path, Path | None]], created: list[Path]) -> None:
    """Put back what `commit` replaced and remove what it added."""
    for target, backup in reversed(done):
        try:
            if backup is not None:
                os.replace(backup, target)
            else:
                target.unlink(missing_ok=True)
        except OSError:
            pass
    for directory in created:
        try:
            directory.rmdir()
        except OSError:
            pass
