"""A catalog quantity given in SI, in the catalog's imperial units, or both.

A page that prints both columns is transcribed with both; where they disagree
beyond the rounding of the printed digits the lower value is used, and flagged.
"""

from __future__ import annotations

from typing import Any

from hdselect.base import bounds
from hdselect.catalog.units import (
    KG_M2_PER_KG_CM2,
    KG_M2_PER_LB_IN2,
    KG_PER_LB,
    NM_PER_LB_IN,
    Flag,
)

# quantity -> ((SI key, factor to SI), (imperial key, factor to SI))
QUANTITIES = {
    "rated_torque": (("rated_torque_nm", 1.0), ("rated_torque_lb_in", NM_PER_LB_IN)),
    "repeated_torque": (("repeated_torque_nm", 1.0), ("repeated_torque_lb_in", NM_PER_LB_IN)),
    "momentary_torque": (("momentary_torque_nm", 1.0),
                         ("momentary_torque_lb_in", NM_PER_LB_IN)),
    "static_torque": (("static_torque_nm", 1.0), ("static_torque_lb_in", NM_PER_LB_IN)),
    "average_torque": (("average_torque_nm", 1.0), ("average_torque_lb_in", NM_PER_LB_IN)),
    "input_inertia": (("input_inertia_kg_cm2", KG_M2_PER_KG_CM2),
                      ("input_inertia_lb_in2", KG_M2_PER_LB_IN2)),
    "mass": (("mass_kg", 1.0), ("mass_lb", KG_PER_LB)),
}


# quantity -> its physical range in SI
RANGES = {"rated_torque": bounds.TORQUE, "repeated_torque": bounds.TORQUE,
          "momentary_torque": bounds.TORQUE, "static_torque": bounds.TORQUE,
          "average_torque": bounds.TORQUE, "input_inertia": bounds.GEAR_INERTIA,
          "mass": bounds.GEAR_MASS}


def agree(quantity: str, given: list[tuple[str, Any, float]], flags: list[Flag]) -> float:
    """One SI value from one or two published columns; the lower where they disagree.

    Two columns agree when their rounding intervals (half a unit of the last
    printed digit of each) overlap after conversion.
    """
    si = [(key, raw, float(raw) * factor, half_digit(raw) * factor) for key, raw, factor in given]
    if len(si) == 1:
        return si[0][2]
    (key_a, raw_a, a, tol_a), (key_b, raw_b, b, tol_b) = si
    if abs(a - b) <= tol_a + tol_b:
        return a
    low = min(a, b)
    si_label = {"input_inertia": "kg m^2", "mass": "kg"}.get(quantity, "N m")
    label = (quantity.replace("_", " ").replace("torque", "limit")
             .replace("rated limit", "rated torque").replace("average limit",
                                                             "average-torque limit"))
    disagree = (f"{label}: the source's {raw_a:g} {unit_label(key_a)} and {raw_b:g} "
                f"{unit_label(key_b)} disagree; the lower, ")
    flags.append(Flag(quantity, "corrected", f"{disagree}{low:.3g} {si_label}, is used",
                      f"{disagree}{imperial(quantity, low)}, is used"))
    return low


def imperial(quantity: str, value: float) -> str:
    """An SI value of a catalog quantity in the page's imperial units, e.g. ``70 lb-in``."""
    if quantity == "input_inertia":
        return f"{value / KG_M2_PER_LB_IN2:.3g} lb-in^2"
    if quantity == "mass":
        return f"{value / KG_PER_LB:.3g} lb"
    return f"{value / NM_PER_LB_IN:.3g} lb-in"


def unit_label(key: str) -> str:
    """The unit a catalog key is written in, e.g. ``lb-in`` for ``static_torque_lb_in``."""
    for suffix, label in (("_lb_in2", "lb-in^2"), ("_lb_in", "lb-in"), ("_nm", "N m"),
                          ("_kg_cm2", "kg cm^2"), ("_kg", "kg"), ("_lb", "lb")):
        if key.endswith(suffix):
            return label
    return ""


def half_digit(raw: int | float) -> float:
    """Half a unit of the last digit of a TOML number as written (0.5 for an integer)."""
    text = repr(raw)
    if isinstance(raw, int) or "e" in text or "." not in text:
        return 0.5
    return 0.5 * 10.0 ** -len(text.split(".")[1])
