"""Input files read once: a named pipe or ``<(...)`` is copied aside on its first read.

A command reads some inputs more than once (the motion file to find its robot, then
to read it; a log's header, then its numbers) and hands robot files to readers that
open them by name. A regular file can be opened again; a FIFO, a process
substitution (``/dev/fd/N``) or a character device cannot: its content is gone
after the first read, and a second open blocks. `readable` therefore copies such a
stream, on its first use, into a private temporary file of the same name, and gives
that file to every later reader in this process.
"""

from __future__ import annotations

import atexit
import os
import shutil
import stat
import tempfile
from pathlib import Path

from hdselect.base.errors import InputError

_COPIES: dict[str, Path] = {}
"""Absolute path of each stream read so far -> its copy."""
_FOLDER: list[Path] = []
"""The private folder holding the copies, made on first need."""


def is_stream(path: Path) -> bool:
    """`path` (symlinks followed) is a FIFO or a character device: readable once."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISCHR(mode)


def is_input_file(path: Path) -> bool:
    """`path` can be read as a file: a regular file, or a stream read once (`readable`)."""
    return str(path) in _COPIES or path.is_file() or is_stream(path)


def readable(path: Path) -> Path:
    """A path that can be opened as often as needed with `path`'s content.

    Args:
        path: An input file.

    Returns:
        `path` itself when it is not a stream; else the copy of its content, read from it
        on the first call and kept for the rest of the process.

    Raises:
        InputError: The stream cannot be read.
    """
    key = os.path.abspath(path)
    if key in _COPIES:
        return _COPIES[key]
    if not is_stream(path):
        return path
    if not _FOLDER:
        _FOLDER.append(Path(tempfile.mkdtemp(prefix="hdselect-inputs-")))
        atexit.register(shutil.rmtree, _FOLDER[0], ignore_errors=True)
    folder = Path(tempfile.mkdtemp(dir=_FOLDER[0]))
    copy = folder / (path.name or "input")
    try:
        with open(path, "rb") as source, copy.open("wb") as sink:
            shutil.copyfileobj(source, sink)
    except OSError as err:
        raise InputError(f"cannot read it ({err.strerror})", path=path) from err
    _COPIES[key] = copy
    return copy
