"""Pinocchio's URDF reader, its answer made usable: the model, or its reason in one line.

Pinocchio decides what a valid URDF is. urdfdom prints its reasons on the C++
standard error (file descriptor 2), which is captured here and folded into one
line, with the line of the joint or link it names. Mimic joints are built as
such when asked: a follower has no degree of freedom and moves with its leader.
"""

from __future__ import annotations

import logging
import os
import re
import sys
import tempfile
import xml.parsers.expat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.base.inputfiles import read_input

logger = logging.getLogger(__name__)


def build_urdf(path: Path, text: str | None, *, mimic: bool,
               said: list[str] | None = None) -> pin.Model:
    """Pinocchio's model of a URDF file, or of its expanded text.

    Args:
        path: The robot file (read by Pinocchio when `text` is None; named in messages).
        text: The URDF document to read instead of the file (an expanded xacro).
        mimic: Build mimic joints as followers of their leaders.
        said: Where to put what urdfdom printed (errors it recovered from), one line each.

    Returns:
        The model, with the file's armature, damping and friction as Pinocchio reads them.

    Raises:
        InputError: Pinocchio rejects it; the parser's reason in the message.
    """
    with _stderr_captured() as printed:
        try:
            if text is None:
                model = pin.buildModelFromUrdf(str(path), mimic=mimic)
            else:
                model = pin.buildModelFromXML(text, mimic=mimic)
            error = None
        except (RuntimeError, ValueError) as err:
            error = err
    if error is None and not printed:
        return model
    source = read_input(path) if text is None else text.encode()
    if error is not None:
        reason = _parser_reason(str(error), printed, source)
        raise InputError(f"not a valid URDF robot: {reason}", path=path) from error
    for line in _messages(printed, source):
        logger.info("%s: parser: %s", path, line)
        if said is not None:
            said.append(line)
    return model


@contextmanager
def _stderr_captured() -> Iterator[list[str]]:
    """Collect what C++ code writes on standard error (file descriptor 2) meanwhile.

    Where descriptor 2 cannot be redirected (closed, say) the lines go where they
    always went.
    """
    lines: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield lines
        return
    with tempfile.TemporaryFile() as capture:
        os.dup2(capture.fileno(), 2)
        try:
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            capture.seek(0)
            lines.extend(capture.read().decode("utf-8", "replace").splitlines())


def _parser_reason(error: str, printed: list[str], source: bytes) -> str:
    """One line from a parser's exception text and what it printed on standard error.

    Pinocchio's own text is generic ("does not contain a valid URDF model") or starts
    with C++ source locations; the reason is what urdfdom printed.

    Args:
        error: The exception's text.
        printed: Lines the parser wrote on standard error.
        source: The document (its line numbers are looked up for named joints and links).

    Returns:
        The reason, one line.
    """
    reasons = _messages(printed, source)
    if not reasons or "valid URDF model" not in error:
        lines = [line.strip() for line in error.strip().splitlines() if line.strip()]
        generic = [line for line in lines if not line.startswith(("From file:", "in function:",
                                                                  "at line:"))]
        reasons.append(" ".join(generic or lines[:1] or ["rejected by the parser"]))
    unique = list(dict.fromkeys(r.rstrip(".") for r in reasons if r))
    return "; ".join(unique)


_TINYXML = re.compile(r"Error=XML_ERROR_(\w+) ErrorID=\d+ \(0x[0-9a-f]+\) Line number=(\d+)"
                      r"(?::\s*(.*))?")
_NAMED = re.compile(r"(Joint|joint|Link|link) \[([^\]]+)\]")


def _messages(printed: list[str], source: bytes) -> list[str]:
    """The parser's ``Error:`` and ``Warning:`` lines, without their C++ source locations."""
    messages = []
    for line in printed:
        text = line.strip()
        if not text or re.match(r"at line \d+ in \S+\.(cpp|hpp|h)$", text):
            continue
        text = re.sub(r"^(Error|Warning|Info|Debug):\s*", "", text)
        xml_error = _TINYXML.search(text)
        if xml_error:
            kind, line_no, detail = xml_error.groups()
            text = (f"malformed XML at line {line_no} ({kind.lower().replace('_', ' ')}"
                    f"{': ' + detail.strip() if detail else ''})")
        else:
            named = _NAMED.search(text)
            line_no = _element_line(source, named.group(1).lower(), named.group(2)) \
                if named else None
            if line_no is not None:
                text = f"{text} (line {line_no})"
        messages.append(text)
    return messages


def _element_line(source: bytes, tag: str, name: str) -> int | None:
    """The line of the first ``<tag name="name">`` of a document, if a lenient scan finds it."""
    found: list[int] = []
    parser = xml.parsers.expat.ParserCreate()

    def start(element: str, attributes: dict[str, str]) -> None:
        if not found and element == tag and attributes.get("name") == name:
            found.append(parser.CurrentLineNumber)

    parser.StartElementHandler = start
    try:
        parser.Parse(source, True)
    except xml.parsers.expat.ExpatError:
        pass
    return found[0] if found else None
