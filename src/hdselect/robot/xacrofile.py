"""Expand a ``.xacro`` robot file into URDF with the ``xacro`` package (ROS's own, from PyPI).

Properties, macros, ``xacro:include`` (relative to the including file), ``xacro:if``
and ``xacro:arg`` with the arguments given (``name:=value`` on the command line)
mean what they mean to ROS's xacro, because xacro itself expands them. xacro keeps
its state in module globals, so expansions are serialised here. ROS-only
substitutions such as ``$(find package)`` need a ROS installation; without one
xacro's own error is the message. Warnings xacro prints become notes.
"""

from __future__ import annotations

import contextlib
import io
import threading
from collections.abc import Mapping
from pathlib import Path

from hdselect.base.errors import InputError

_LOCK = threading.Lock()


def xacro_arguments(value: object, field: str = "xacro_args") -> dict[str, str]:
    """The xacro arguments as names and text values, from a mapping or ``name:=value`` strings.

    Args:
        value: None, a mapping of name to a string or number, or a sequence of
            ``name:=value`` strings (as ``--xacro-arg`` gives them).
        field: The parameter or option, for messages.

    Returns:
        The arguments by name.

    Raises:
        InputError: A name is empty, a value is not text or a number, or a string lacks ``:=``.
    """
    if value is None:
        return {}
    if isinstance(value, Mapping):
        pairs = list(value.items())
    elif isinstance(value, list | tuple):
        pairs = []
        for item in value:
            if not isinstance(item, str) or ":=" not in item:
                raise InputError(f"expected name:=value, got {item!r}", field=field)
            name, _, text = item.partition(":=")
            pairs.append((name.strip(), text))
    else:
        raise InputError(f"expected a mapping of name to value, got {type(value).__name__}",
                         field=field)
    arguments = {}
    for name, text in pairs:
        if not isinstance(name, str) or not name:
            raise InputError(f"expected an argument name, got {name!r}", field=field)
        if isinstance(text, bool) or not isinstance(text, str | int | float):
            raise InputError(f"expected text or a number for {name}, got {text!r}",
                             field=f"{field}.{name}")
        arguments[name] = str(text)
    return arguments


def expand_xacro(path: Path, arguments: Mapping[str, str]) -> tuple[str, list[str]]:
    """The URDF a xacro file expands to, and what xacro warned about.

    Args:
        path: The ``.xacro`` file.
        arguments: Values of its ``xacro:arg`` arguments, by name.

    Returns:
        The expanded document as XML text, and xacro's warnings, one line each.

    Raises:
        InputError: xacro cannot expand it (its reason, one line), or the package is missing.
    """
    try:
        import xacro
    except ImportError as err:  # a dependency; only a broken installation lacks it
        raise InputError("expanding .xacro needs the xacro package (pip install xacro)",
                         path=path) from err
    printed = io.StringIO()
    with _LOCK, contextlib.redirect_stderr(printed), contextlib.redirect_stdout(printed):
        try:
            document = xacro.process_file(str(path), mappings=dict(arguments))
        except Exception as err:  # xacro evaluates the file's Python expressions: any error
            reason = " ".join(str(err).split()) or type(err).__name__
            if "package://" in reason or "$(find" in reason or "rospkg" in reason:
                reason += " (ROS package paths need a ROS installation; give paths relative " \
                          "to the including file)"
            raise InputError(f"xacro cannot expand it: {reason}", path=path) from err
    warnings = [" ".join(line.split()) for line in printed.getvalue().splitlines()
                if line.strip() and not line.startswith(("when processing file:", "in file:",
                                                         "included from:"))]
    return document.toxml(), [f"xacro: {line}" for line in warnings]
