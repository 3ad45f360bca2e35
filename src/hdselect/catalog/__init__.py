"""Gearheads and motors as data, the series' rules, and the choice among candidates.

`load_catalog` reads units and their series' `[rules]` (`units`), `rules` holds every rule
as an object (one file each) and checks one joint's cycle against one unit by them,
`select` chooses among the checked candidates,
`motors` reads motor files, and `duty` is the catalog page's own phase-by-phase method.
"""

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.duty import DutyResult, load_duty, size_duty
from hdselect.catalog.motors import Motor, load_motors
from hdselect.catalog.units import SeriesRules, Unit

__all__ = ["DutyResult", "Motor", "SeriesRules", "Unit", "load_catalog", "load_duty",
           "load_motors", "size_duty"]
