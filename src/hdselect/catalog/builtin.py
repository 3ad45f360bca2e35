"""The built-in catalogs, by name: one per file of ``hdselect/catalog/data``.

A catalog is named where a file is accepted (``load_catalog(["csg-2uh"])``,
``--catalog csg-2uh``, a mix file's or a study's ``catalog``): a value is a built-in
name when it is one, otherwise a file. A name that is also a file beside the one that
gives it is refused as ambiguous; the file is then written as a path (``./csg-2uh``).
The catalogs are found in the data directory, so a new file needs no code.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from hdselect.base.bounds import files_argument
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import read_toml
from hdselect.catalog.units import Unit

DATA = Path(__file__).parent / "data"
"""The directory of the built-in catalog files."""


DEFAULT = "psa-g"
"""The built-in catalog always loaded (the seed's PSA-G page)."""


@dataclass(frozen=True)
class BuiltinCatalog:
    """One built-in catalog file.

    Attributes:
        name: Its name, e.g. ``"csg-2uh"`` (the file's stem with ``-`` for ``_``).
        series: The series it holds, e.g. ``"CSG-2UH"``.
        title: Its title; empty where the file gives none.
        file: The file.
    """

    name: str
    series: str
    title: str
    file: Path


@functools.cache
def builtin_catalogs() -> tuple[BuiltinCatalog, ...]:
    """Every built-in catalog, by name, the default (`DEFAULT`) first.

    Raises:
        InputError: A file cannot be read, or its ``name`` is not its file name.
    """
    found = []
    for file in sorted(DATA.glob("*.toml")):
        document = read_toml(file)
        name = file.stem.replace("_", "-")
        if document.get("name", name) != name:
            raise InputError(f"expected the name of the file, {name!r}, got "
                             f"{document.get('name')!r}", path=file, field="name")
        found.append(BuiltinCatalog(name, str(document.get("series", "")),
                                    str(document.get("title", "")), file))
    return tuple(sorted(found, key=lambda c: (c.name != DEFAULT, c.name)))


def builtin_names() -> str:
    """The built-in catalogs' names, for messages, e.g. ``psa-g, csg-2uh``."""
    return ", ".join(catalog.name for catalog in builtin_catalogs())


def default_file() -> Path:
    """The default built-in catalog's file."""
    return next(c.file for c in builtin_catalogs() if c.name == DEFAULT)


def catalog_file(value: str | Path, *, base: Path | None = None, path: Path | None = None,
                 field: str | None = None, missing_ok: bool = False) -> Path:
    """The file a catalog value names: a built-in catalog's, else the file itself.

    Args:
        value: A built-in name or a file (a `Path` is always a file).
        base: The directory a relative file is in (None: the current directory).
        path: The file that gives `value` (a mix file, a study), for messages.
        field: Its key there, for messages.
        missing_ok: Return a file that does not exist (its reader refuses it later).

    Raises:
        InputError: It is both a built-in name and a file in `base`, or neither (unless
            `missing_ok`).
    """
    local = Path(value) if base is None else base / value
    named = {c.name: c.file for c in builtin_catalogs()}
    if isinstance(value, str) and value in named:
        if local.exists():
            raise InputError(f"'{value}' is both a built-in catalog and the file {local}; "
                             f"write the file as a path, ./{value}, or the name of another "
                             "file", path=path, field=field)
        return named[value]
    if not local.exists() and not missing_ok:
        if path is None:
            raise InputError(f"file not found; built-in catalogs: {builtin_names()}",
                             path=local)
        raise InputError(f"catalog file not found: {str(value)!r}; built-in catalogs: "
                         f"{builtin_names()}", path=path, field=field)
    return local


def catalog_files(values: object, *, field: str = "catalog") -> list[Path]:
    """The catalog files a list of values names (`catalog_file`), each once, without the default.

    The default catalog is always loaded, so naming it adds nothing.

    Raises:
        InputError: `values` is not a list of names and files, or as `catalog_file`.
    """
    files_argument(values, field)  # the type: a list of strings and paths
    seen = {default_file().resolve()}
    files = []
    for value in cast(Iterable[str | Path], values):
        file = catalog_file(value, field=field)
        if file.resolve() not in seen:
            seen.add(file.resolve())
            files.append(file)
    return files


def of_series(units: Sequence[Unit], series: Sequence[str], *,
              field: str = "series") -> tuple[Unit, ...]:
    """The units of the given series, each named as its series or its catalog's name.

    A value matches a unit's series (``"CSG-2UH"``) or its catalog's name (``"csg-2uh"``),
    either case. None or empty: every unit.

    Raises:
        InputError: `series` is not a list of names, or a value matches no unit loaded
            (the message lists the loaded series).
    """
    if isinstance(series, str | bytes) or not isinstance(series, Sequence) \
            or not all(isinstance(value, str) for value in series):
        raise InputError(f"expected a list of series names, got {series!r}", field=field)
    if not series:
        return tuple(units)
    names = {value.lower() for value in series}

    def named(unit: Unit) -> set[str]:
        return {unit.series.lower(), unit.catalog.name.lower()} - {""}

    for value in series:
        if not any(value.lower() in named(unit) for unit in units):
            loaded = dict.fromkeys(f"{u.series} ({u.catalog.name})" if u.catalog.name
                                   else u.series for u in units)
            raise InputError(f"no unit loaded is of series {value!r}; loaded: "
                             f"{', '.join(loaded)} (add a catalog with --catalog; built in: "
                             f"{builtin_names()})", field=field)
    return tuple(unit for unit in units if named(unit) & names)
