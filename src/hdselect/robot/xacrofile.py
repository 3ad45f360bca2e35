"""Expand a ``.xacro`` robot file into URDF with the ``xacro`` package (ROS's own, from PyPI).

Properties, macros, ``xacro:include`` (relative to the including file), ``xacro:if``
and ``xacro:arg`` with the arguments given (``name:=value`` on the command line)
mean what they mean to ROS's xacro, because xacro itself expands them. xacro keeps
its state in module globals, so expansions are serialised here. ROS-only
substitutions such as ``$(find package)`` need a ROS installation; without one
xacro's own error is the message. Warnings xacro prints become notes.

An argument the file neither declares (``<xacro:arg name=...>``) nor reads
(``$(arg name)``) is refused, naming the file's arguments: xacro itself would drop
it silently, and a misspelt ``gripper_mas`` would size the default gripper. The
refusal's field is ``xacro_args.NAME``, which the callers turn into where the
argument came from (``--xacro-arg``, a motion file's ``xacro_args``).
"""

from __future__ import annotations

import contextlib
import io
import math
import re
import threading
from collections.abc import Mapping
from pathlib import Path

from hdselect.base.errors import InputError

_LOCK = threading.Lock()


class _Asked(dict[str, str]):
    """xacro's argument table, remembering every name xacro looked up.

    xacro tests ``name in table`` for each ``<xacro:arg>`` it meets and reads
    ``table[name]`` for each ``$(arg name)``: the names asked for are the file's
    arguments.
    """

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.asked: set[str] = set()

    def __contains__(self, name: object) -> bool:
        if isinstance(name, str):
            self.asked.add(name)
        return super().__contains__(name)

    def __getitem__(self, name: str) -> str:
        self.asked.add(name)
        return super().__getitem__(name)


def xacro_arguments(value: object, field: str = "xacro_args") -> dict[str, str]:
    """The xacro arguments as names and text values, from a mapping or ``name:=value`` strings.

    Args:
        value: None, a mapping of name to a string or number, or a sequence of
            ``name:=value`` strings (as ``--xacro-arg`` gives them).
        field: The parameter or option, for messages.

    Returns:
        The arguments by name.

    Raises:
        InputError: A name or a value is empty, a value is not text or a number, a string
            lacks ``:=``, or a name is given twice.
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
    arguments: dict[str, str] = {}
    for name, text in pairs:
        if not isinstance(name, str) or not name:
            raise InputError(f"expected an argument name, got {name!r}", field=field)
        if name in arguments:  # only a list can repeat a name; the last would win unseen
            raise InputError(f"{name} given twice ({arguments[name]} and {text}); give it once",
                             field=field)
        if isinstance(text, bool) or not isinstance(text, str | int | float):
            raise InputError(f"expected text or a number for {name}, got {text!r}",
                             field=f"{field}.{name}")
        if not str(text).strip():
            raise InputError(f"no value given for {name}", field=field if field.startswith("-")
                             else f"{field}.{name}")
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
        InputError: xacro cannot expand it (its reason, one line), an argument is not one of
            the file's (field ``xacro_args.NAME``), or the package is missing.
    """
    try:
        import xacro
    except ImportError as err:  # a dependency; only a broken installation lacks it
        raise InputError("expanding .xacro needs the xacro package (pip install xacro)",
                         path=path) from err
    printed = io.StringIO()
    table = _Asked(arguments)
    with _LOCK, contextlib.redirect_stderr(printed), contextlib.redirect_stdout(printed):
        try:
            document = xacro.process_file(str(path), mappings=table)
        except Exception as err:  # xacro evaluates the file's Python expressions: any error
            reason = " ".join(str(err).split()) or type(err).__name__
            if "package://" in reason or "$(find" in reason or "rospkg" in reason:
                reason += " (ROS package paths need a ROS installation; give paths relative " \
                          "to the including file)"
            if arguments:
                reason += f" (arguments given: {_listed(arguments)})"
            raise InputError(f"xacro cannot expand it: {reason}", path=path) from err
    unknown = [name for name in arguments if name not in table.asked]
    if unknown:
        known = sorted(table.asked)
        raise InputError(f"{path.name} has no xacro argument '{unknown[0]}'; " + (
            f"its arguments are: {', '.join(known)}" if known else "it declares none"),
            path=path, field=f"xacro_args.{unknown[0]}")
    warnings = [" ".join(line.split()) for line in printed.getvalue().splitlines()
                if line.strip() and not line.startswith(("when processing file:", "in file:",
                                                         "included from:"))]
    return document.toxml(), [f"xacro: {line}" for line in warnings]


def blamed_argument(err: InputError, path: Path, arguments: Mapping[str, str]) -> InputError:
    """A refusal of the expanded file, told as the xacro argument's fault where it is.

    The argument whose value the refusal quotes (as given, or as xacro turned it into a
    number: ``1e400`` becomes ``inf``) is named, in the field ``xacro_args.NAME`` that the
    callers turn into where it came from; when no single argument is quoted, the message
    lists the arguments given.

    Args:
        err: The refusal of the expanded document (its field names the link or joint).
        path: The ``.xacro`` file.
        arguments: The arguments it was expanded with, by name.

    Returns:
        The error to raise instead of `err`.
    """
    quoted = [name for name, value in arguments.items()
              if any(re.search(rf"(?<![\w.+-]){re.escape(form)}(?![\w.])", err.reason)
                     for form in _forms(value))]
    if len(quoted) != 1:
        return InputError(f"{err.reason} (in the file expanded with the xacro arguments "
                          f"{_listed(arguments)})", path=err.path, field=err.field)
    name = quoted[0]
    where = f"{err.field} of the expanded {path.name}" if err.field else f"the expanded {path.name}"
    return InputError(f"{name}:={arguments[name]} makes {where} fail: {err.reason}", path=path,
                      field=f"xacro_args.{name}")


def _forms(value: str) -> set[str]:
    """How a value may appear in a message: as given, and as the number xacro makes of it."""
    forms = {value.strip()}
    try:
        number = float(value)
    except ValueError:
        return forms
    forms |= {f"{number:g}", repr(number)}
    if math.isfinite(number) and number == int(number):
        forms.add(str(int(number)))
    return forms


def _listed(arguments: Mapping[str, str]) -> str:
    return ", ".join(f"{name}:={value}" for name, value in arguments.items())
