"""What a catalog file says beyond a unit's ratings: itself, its sources and stiffness.

A file may name itself (``name``, ``title``), tell the reader to check its numbers
(``check``) and say which were taken from a public transcription (``transcription``);
it may list the ``[documents]`` its numbers were read from and, in ``[provenance]``
(and a unit's ``[unit.provenance]``), the document, page and table of every numeric
key its units use. A file that claims any source must source every such key, and a
built-in file must claim them. Every value is checked here; the units are read by
`hdselect.catalog.catalogfile`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.tomlfile import as_number, check_keys, table_of
from hdselect.catalog.units import (
    RAD_PER_ARCMIN,
    WHOLE_UNIT,
    CatalogInfo,
    Flag,
    Source,
    Stiffness,
)

HEADER_KEYS = ("name", "title", "check", "transcription", "documents", "provenance")
"""The file-level keys read here (beside ``series``, ``source``, ``rules`` and ``unit``)."""


DOCUMENT_KEYS = ("title", "publisher", "edition", "copy")
"""The keys of one ``[documents.<key>]`` table, each a required non-empty string."""


SOURCE_KEYS = ("document", "page", "table")
"""The keys of one provenance entry, each a required non-empty string."""


# [unit.stiffness] key -> (Stiffness field, range, SI per unit of the key)
STIFFNESS_KEYS = {
    "t1_nm": ("t1", bounds.TORQUE, 1.0),
    "t2_nm": ("t2", bounds.TORQUE, 1.0),
    "k1_nm_per_rad": ("k1", bounds.TORSIONAL_STIFFNESS, 1.0),
    "k2_nm_per_rad": ("k2", bounds.TORSIONAL_STIFFNESS, 1.0),
    "k3_nm_per_rad": ("k3", bounds.TORSIONAL_STIFFNESS, 1.0),
    "hysteresis_loss_arcmin": ("hysteresis_loss", bounds.TWIST, RAD_PER_ARCMIN),
    "lost_motion_arcmin": ("lost_motion", bounds.TWIST, RAD_PER_ARCMIN),
}


# unit keys that are no number a source gives (the id's parts, notes and tables of their own)
_NOT_SOURCED = ("id", "size", "ratio", "defects", "provenance", "stiffness", "bearing")


def optional_text(document: Mapping[str, Any], key: str, path: Path, field: str) -> str:
    """An optional non-empty string of a table; ``""`` where the key is absent.

    Raises:
        InputError: It is given but not a non-empty string.
    """
    return sentence(document[key], path, field) if key in document else ""


def sentence(value: Any, path: Path, field: str) -> str:
    """`value`, a non-empty string, stripped.

    Raises:
        InputError: It is not one.
    """
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"expected a non-empty string, got {value!r}", path=path, field=field)
    return value.strip()


def catalog_info(document: Mapping[str, Any], path: Path) -> CatalogInfo:
    """The file's ``name``, ``title``, ``check`` and ``transcription``.

    Raises:
        InputError: One is not a non-empty string, or the name is not lower case
            without spaces.
    """
    name = optional_text(document, "name", path, "name")
    if name and (name != name.lower() or any(c.isspace() for c in name)):
        raise InputError(f"expected a lower-case name without spaces, got {name!r}", path=path,
                         field="name")
    return CatalogInfo(name, *(optional_text(document, key, path, key)
                               for key in ("title", "check", "transcription")))


def read_documents(document: Mapping[str, Any], path: Path) -> dict[str, tuple[str, ...]]:
    """The file's ``[documents]``: key -> (title, publisher, edition, copy).

    Raises:
        InputError: A document lacks one of `DOCUMENT_KEYS` or has another key.
    """
    found: dict[str, tuple[str, ...]] = {}
    for key, table in table_of(document.get("documents", {}), path, "documents").items():
        where = f"documents.{key}"
        check_keys(table_of(table, path, where), DOCUMENT_KEYS, path, where)
        for name in DOCUMENT_KEYS:
            if name not in table:
                raise InputError("required key is missing", path=path, field=f"{where}.{name}")
        found[key] = tuple(optional_text(table, name, path, f"{where}.{name}")
                           for name in DOCUMENT_KEYS)
    return found


def read_sources(table: Any, known: Mapping[str, tuple[str, ...]], allowed: Iterable[str],
            path: Path, where: str) -> dict[str, Source]:
    """A ``[provenance]`` table: catalog key -> `Source`.

    Args:
        table: The table as read.
        known: The file's documents (`read_documents`).
        allowed: The keys that may be sourced.
        path: The file, for messages.
        where: The table's dotted location, for messages.

    Raises:
        InputError: An unknown key, an entry lacking `SOURCE_KEYS`, or a document the
            file does not list.
    """
    found = {}
    entries = table_of(table, path, where)
    check_keys(entries, allowed, path, where)
    for key, entry in entries.items():
        field = f'{where}."{key}"'
        check_keys(table_of(entry, path, field), SOURCE_KEYS, path, field)
        for name in SOURCE_KEYS:
            if name not in entry:
                raise InputError("required key is missing", path=path, field=f"{field}.{name}")
        document, page, table_name = (optional_text(entry, name, path, f"{field}.{name}")
                                      for name in SOURCE_KEYS)
        if document not in known:
            listed = ", ".join(known) or "none"
            raise InputError(f"document '{document}' is not in [documents] (listed: {listed})",
                             path=path, field=f"{field}.document")
        title, publisher, edition, copy = known[document]
        found[key] = Source(title, publisher, edition, copy, page, table_name)
    return found


def sourced_keys(entry: Mapping[str, Any]) -> list[str]:
    """The numeric keys a ``[[unit]]`` uses, dotted for its sub-tables: what needs a source."""
    keys = [key for key in entry if key not in _NOT_SOURCED]
    for table in ("stiffness", "bearing"):
        if isinstance(entry.get(table), dict):
            keys += [f"{table}.{key}" for key in entry[table]]
    return keys


def rule_keys(rules: Mapping[str, Any]) -> list[str]:
    """The numeric keys of a ``[rules]`` table, as provenance names them (``rules.<key>``)."""
    return [f"rules.{key}" for key, value in rules.items()
            if isinstance(value, int | float) and not isinstance(value, bool)]


def read_stiffness(table: dict[str, Any], path: Path, where: str) -> Stiffness:
    """A unit's ``[unit.stiffness]``, in SI (the twists in radians).

    Raises:
        InputError: An unknown key, a number out of range, no figure at all, or T2 not
            above T1.
    """
    check_keys(table, list(STIFFNESS_KEYS), path, where)
    if not table:
        raise InputError("gives no figure: give at least one of " + ", ".join(STIFFNESS_KEYS),
                         path=path, field=where)
    values = {name: as_number(table[key], path, f"{where}.{key}", bound=bound, scale=scale,
                              unit="arcmin" if scale != 1.0 else None) * scale
              for key, (name, bound, scale) in STIFFNESS_KEYS.items() if key in table}
    if "t1" in values and "t2" in values and values["t2"] <= values["t1"]:
        raise InputError(f"T2 {values['t2']:g} N m must be above T1 {values['t1']:g} N m",
                         path=path, field=f"{where}.t2_nm")
    return Stiffness(**values)


def unit_notes(entry: Mapping[str, Any], info: CatalogInfo, path: Path,
               where: str) -> list[Flag]:
    """The notes on a whole unit: its file's transcription and its own ``defects``.

    Raises:
        InputError: ``defects`` is not a list of non-empty strings.
    """
    flags = ([Flag(WHOLE_UNIT, "transcription", info.transcription)]
             if info.transcription else [])
    defects = entry.get("defects", [])
    if not isinstance(defects, list):
        raise InputError(f"expected a list of sentences, got {defects!r}", path=path,
                         field=f"{where}.defects")
    flags += [Flag(WHOLE_UNIT, "defect", sentence(defect, path, f"{where}.defects[{i}]"))
              for i, defect in enumerate(defects)]
    return flags
