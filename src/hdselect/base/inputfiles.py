"""Input files checked and read with a size bound; a named pipe is copied aside on its first read.

Every input is a regular file or a stream (a FIFO, a process substitution
``/dev/fd/N``, a character device), no larger than its kind's limit:
`MAX_INPUT_BYTES` for robot, motion, mix, envelope, catalog, motor and study files,
`MAX_LOG_BYTES` for logs. A directory, a socket, a file that cannot be opened or
one over the limit is refused in one line, naming the file, before any reader sees it.

A command reads some inputs more than once (the motion file to find its robot, then
to read it; a log's header, then its numbers) and hands robot files to readers that
open them by name. A regular file can be opened again; a stream cannot: its content
is gone after the first read, and a second open blocks. `readable` therefore copies
a stream, on its first use, into a private temporary file of the same name, and
gives that file to every later reader in this process; the copy is bounded by the
limit (``/dev/zero`` is refused, not copied forever) and removed when the copy is
refused or interrupted, and at exit.
"""

from __future__ import annotations

import atexit
import os
import shutil
import stat
import tempfile
from pathlib import Path

from hdselect.base.errors import InputError

MAX_INPUT_BYTES = 64 * 2**20
"""The largest robot, motion, mix, envelope, catalog, motor or study file read [bytes]."""
MAX_LOG_BYTES = 16 * 2**30
"""The largest log read [bytes]: 8 hours at 1 kHz of q, qd and qdd of 12 joints fit."""
_CHUNK = 2**20
"""Bytes copied from a stream at a time."""

_COPIES: dict[str, Path] = {}
"""Absolute path of each stream read so far -> its copy."""


def is_stream(path: Path) -> bool:
    """`path` (symlinks followed) is a FIFO or a character device: readable once."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):  # ValueError: a NUL character in the name
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISCHR(mode)


def is_input_file(path: Path) -> bool:
    """`path` can be read as a file: a regular file, or a stream read once (`readable`)."""
    try:
        return str(path) in _COPIES or path.is_file() or is_stream(path)
    except (OSError, ValueError):  # a name too long, or holding a NUL character
        return False


def readable(path: Path, limit: int = MAX_INPUT_BYTES) -> Path:
    """A path that can be opened as often as needed with `path`'s content, checked.

    Args:
        path: An input file.
        limit: The largest content accepted [bytes]; a character device is held to
            `MAX_INPUT_BYTES` whatever the kind (no log is a device).

    Returns:
        `path` itself when it is a regular file; else the copy of the stream's content,
        read from it on the first call and kept for the rest of the process.

    Raises:
        InputError: The file is missing, a directory or another special file, cannot be
            opened, or is larger than `limit`.
    """
    key = os.path.abspath(path)
    if key in _COPIES:
        return _COPIES[key]
    try:
        status = os.stat(path)
    except FileNotFoundError as err:
        raise InputError("file not found", path=path) from err
    except OSError as err:
        raise InputError(f"cannot read it ({err.strerror})", path=path) from err
    except ValueError as err:
        raise InputError("is no file name: it holds a NUL character", path=path) from err
    mode = status.st_mode
    if stat.S_ISDIR(mode):
        raise InputError("is a directory, not a file", path=path)
    if stat.S_ISREG(mode):
        if status.st_size > limit:
            raise _too_large(path, limit)
        try:
            os.close(os.open(path, os.O_RDONLY))
        except OSError as err:
            raise InputError(f"cannot read it ({err.strerror})", path=path) from err
        return path
    if not (stat.S_ISFIFO(mode) or stat.S_ISCHR(mode)):
        raise InputError("is not a file (a socket or a block device); give a file or a named "
                         "pipe", path=path)
    copy = _copied(path, min(limit, MAX_INPUT_BYTES) if stat.S_ISCHR(mode) else limit)
    _COPIES[key] = copy
    return copy


def read_input(path: Path, limit: int = MAX_INPUT_BYTES) -> bytes:
    """The content of an input file, checked by `readable` and read within `limit`.

    Raises:
        InputError: As `readable`; or reading fails.
    """
    source = readable(path, limit)
    try:
        with open(source, "rb") as stream:
            data = stream.read(limit + 1)
    except OSError as err:
        raise InputError(f"cannot read it ({err.strerror})", path=path) from err
    if len(data) > limit:  # grew since it was checked
        raise _too_large(path, limit)
    return data


def _copied(path: Path, limit: int) -> Path:
    """A stream's content copied into a new private folder, which a refusal removes."""
    folder = Path(tempfile.mkdtemp(prefix="hdselect-input-"))
    copy = folder / (path.name or "input")
    try:
        with open(path, "rb") as source, copy.open("wb") as sink:
            copied = 0
            while chunk := source.read(min(_CHUNK, limit + 1 - copied)):
                sink.write(chunk)
                copied += len(chunk)
                if copied > limit:
                    raise _too_large(path, limit)
    except OSError as err:
        shutil.rmtree(folder, ignore_errors=True)
        raise InputError(f"cannot read it ({err.strerror})", path=path) from err
    except BaseException:  # refused, interrupted or terminated: leave nothing behind
        shutil.rmtree(folder, ignore_errors=True)
        raise
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    return copy


def _too_large(path: Path, limit: int) -> InputError:
    return InputError(f"larger than {limit / 2**20:g} MiB, the most hdselect reads from such "
                      "a file; is it the right file?", path=path)
