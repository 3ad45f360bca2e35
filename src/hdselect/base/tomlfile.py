"""Reading user TOML files with messages that name the file and the field."""

from __future__ import annotations

import difflib
import math
import tomllib
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from hdselect.base.bounds import Bound
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import read_input


def read_toml(path: str | Path, *, kind: str = "a TOML file", hint: str = "") -> dict[str, Any]:
    """Parse a TOML file.

    Args:
        path: The file to read.
        kind: What the file should be, for the message when it is XML (a robot file
            given in its place), e.g. ``"a motion file"``.
        hint: Said after that message: how to get the right file.

    Returns:
        The parsed document.

    Raises:
        InputError: The file is missing, unreadable, too large (`read_input`) or not valid
            TOML.
    """
    path = Path(path)
    try:
        text = read_input(path).decode("utf-8")
    except UnicodeDecodeError as err:
        raise InputError(f"cannot read file ({err})", path=path) from err
    try:
        return tomllib.loads(text)
    except RecursionError as err:
        raise InputError("not valid TOML here: nested too deeply", path=path) from err
    except tomllib.TOMLDecodeError as err:
        if text.lstrip("\ufeff \t\r\n").startswith("<"):
            raise InputError(f"this is a robot file (XML), not {kind}{hint}", path=path) from err
        raise InputError(f"not valid TOML: {err}", path=path) from err


_KINDS = (
    ("a mix file", ("task",)),
    ("a motion file", ("waypoint", "samples", "planner", "dt", "tool", "xacro_args")),
    ("a study file", ("case", "grid", "compute")),
    ("a duty profile", ("phase", "momentary", "static")),
    ("a catalog file", ("series", "unit")),
    ("an envelope file", ("robot", "limits", "duty")),
)
"""Each kind of hdselect TOML file and top-level keys that mark it, in the order asked."""


def toml_kind(data: bytes) -> str | None:
    """What hdselect file a document is, when it is TOML: ``"a motion file"``, ...

    A file read where another kind is wanted (a motion file given as the robot) is
    told by what it is rather than by the parser's complaint.

    Args:
        data: The file's content.

    Returns:
        The kind with its article (``"a TOML file"`` when no kind's keys are there), or
        None when the content is not TOML or empty.
    """
    try:
        doc = tomllib.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError):
        return None
    if not doc:
        return None  # empty: nothing tells what it is
    if isinstance(doc.get("motor"), list):
        return "a motor file"
    return next((kind for kind, keys in _KINDS if any(key in doc for key in keys)),
                "a TOML file")


def check_keys(table: Mapping[str, Any], allowed: Iterable[str], path: Path, where: str) -> None:
    """Reject keys of `table` that are not in `allowed`, suggesting the nearest valid one.

    Raises:
        InputError: A key is unknown.
    """
    allowed = list(allowed)
    for key in table:
        if key not in allowed:
            near = difflib.get_close_matches(key, allowed, n=1)
            hint = f"; did you mean '{near[0]}'?" if near else f"; valid keys: {', '.join(allowed)}"
            raise InputError(f"unknown key '{key}'{hint}", path=path, field=join(where, key))


def number(
    table: Mapping[str, Any],
    key: str,
    path: Path,
    where: str,
    *,
    default: float | None = None,
    minimum: float | None = None,
    positive: bool = False,
    bound: Bound | None = None,
) -> float:
    """Read one finite number from a TOML table.

    Args:
        table: The table holding the key.
        key: The key to read.
        path: The file, for messages.
        where: The dotted location of `table` in the file, for messages.
        default: Value when the key is absent; None makes the key required.
        minimum: Smallest allowed value (inclusive), if any.
        positive: Require a value strictly greater than zero.
        bound: The physical range of the quantity (`hdselect.base.bounds`), if any.

    Returns:
        The value as a float.

    Raises:
        InputError: The key is missing, not a number, not finite or out of range.
    """
    field = join(where, key)
    if key not in table:
        if default is None:
            raise InputError("required key is missing", path=path, field=field)
        return default
    return as_number(table[key], path, field, minimum=minimum, positive=positive, bound=bound)


def as_number(
    value: Any, path: Path, field: str, *, minimum: float | None = None, positive: bool = False,
    bound: Bound | None = None, scale: float = 1.0, unit: str | None = None,
) -> float:
    """Check that `value` is a finite number in range and return it as a float.

    Args:
        value: The value as read.
        path: The file, for messages.
        field: The dotted field, for messages.
        minimum: Smallest allowed value (inclusive), if any.
        positive: Require a value strictly greater than zero.
        bound: The physical range of the quantity, checked in SI (`hdselect.base.bounds`).
        scale: SI per unit of `value`, for `bound`.
        unit: The label of the unit of `value`, for `bound`'s message.

    Raises:
        InputError: It is not.
    """
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"expected a number, got {value!r}", path=path, field=field)
    value = finite_float(value, path, field)
    if bound is not None:
        bound.check(value, path=path, field=field, scale=scale, unit=unit)
    if positive and value <= 0.0:
        raise InputError(f"must be positive, got {value:g}", path=path, field=field)
    if minimum is not None and value < minimum:
        raise InputError(f"must be at least {minimum:g}, got {value:g}", path=path, field=field)
    return value


def finite_float(value: int | float, path: Path | None, field: str | None) -> float:
    """A number as a finite float (a huge integer does not fit one).

    Raises:
        InputError: It is not finite or does not fit a float.
    """
    try:
        number = float(value)
    except OverflowError as err:
        raise InputError("must be finite, got an integer too large for a float", path=path,
                         field=field) from err
    if not math.isfinite(number):
        raise InputError(f"must be finite, got {number}", path=path, field=field)
    return number


def table_of(value: Any, path: Path, field: str) -> dict[str, Any]:
    """Check that `value` is a TOML table.

    Raises:
        InputError: It is not.
    """
    if not isinstance(value, dict):
        raise InputError(f"expected a table, got {value!r}", path=path, field=field)
    return value


def join(where: str, key: str) -> str:
    """Dotted field name of `key` inside the table at `where`."""
    return f"{where}.{key}" if where else key
