"""What a user reads: terminal tables, JSON and CSV, figures and the HTML report.

The modules format results; none computes a number a result does not already hold.
`terminal` and `tables` print, `export` writes JSON and CSV, `figures` and `html`
draw and write the report, `provenance` records where a result came from.

`write_report` and `report_page` load on first use, so importing this package
imports no matplotlib. Where a result came from is
``hdselect.report.provenance.provenance(result, command)``.
"""

import importlib
from typing import TYPE_CHECKING, Any

__all__ = ["report_page", "write_report"]

if TYPE_CHECKING:
    from hdselect.report.report_files import report_page, write_report


def __getattr__(name: str) -> Any:
    """Import `write_report` and `report_page` from their module when first used."""
    if name not in __all__:
        raise AttributeError(f"module 'hdselect.report' has no attribute {name!r}")
    value = getattr(importlib.import_module("hdselect.report.report_files"), name)
    globals()[name] = value
    return value
