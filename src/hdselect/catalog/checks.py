"""How a check's life is reported.

A life beyond `LIFE_CAP` is reported as the cap. `Check`, the check tables and the margin's
`holds` and `derated` live in `hdselect.catalog.rules` (derived from its registry of
rules).
"""

from __future__ import annotations

import warnings

from hdselect.catalog.rules import (
    DEFAULT_MARGIN,
    Check,
    Rule,
)

LIFE_CAP = 1e6
"""The longest life reported as a number [h], 114 years of running: beyond it the cube
and 10/3-power laws extrapolate to figures no design can use (a torque near zero gives
1e37 h). A longer life is reported as the cap and flagged: ``> 1e6 h`` in every table and
the parts list, the cap with ``*_capped: true`` in JSON. The checks judge the life
computed, so a requirement is met or not whatever the cap."""


def reported_life(hours: float | None) -> float | None:
    """A life as reported [h]: at most `LIFE_CAP`; None (unlimited) stays None."""
    return None if hours is None else min(hours, LIFE_CAP)


def life_capped(hours: float | None) -> bool:
    """Whether a life [h] is reported as the cap (`LIFE_CAP`) rather than as itself."""
    return hours is not None and hours >= LIFE_CAP


def limit_check(value: float | None, limit: float, *, margin: float = DEFAULT_MARGIN,
                **detail: object) -> Check:
    """Deprecated: a value against its limit, as a rule judges it (`Rule.judge`)."""
    warnings.warn("hdselect.catalog.checks.limit_check is deprecated; use "
                  "hdselect.catalog.rules.Rule.judge", DeprecationWarning, stacklevel=2)
    return _MARGINED.judge(value, limit, margin, **detail)


_MARGINED = Rule()
"""Any rule the design margin applies to, for `limit_check`."""
