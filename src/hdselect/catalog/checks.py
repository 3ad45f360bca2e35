"""One rule applied to one gearhead: its demand, its limit and how close it is."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Check:
    """One rule applied to one gearhead.

    Attributes:
        value: The demand ([N m], [N], input speed [rpm]), or for a life the life
            expected [h] and for a static safety the safety reached [-]; None if the
            rule does not apply to this cycle or this unit.
        limit: What the gearhead allows (for a life or a safety: what is required);
            infinite where the unit has no such limit.
        ok: The rule holds.
        utilization: Demand over allowance [-] (a life or a safety: required over
            reached); 0 if the rule does not apply, above 1 when it fails.
        detail: Extra figures for reports, e.g. ``{"kind": "crash"}``.
    """

    value: float | None
    limit: float
    ok: bool
    utilization: float
    detail: dict[str, object] = field(default_factory=dict)


def limit_check(value: float | None, limit: float, **detail: object) -> Check:
    """One check: a value against its limit [same unit], utilization = value / limit."""
    utilization = 0.0 if value is None else value / limit
    return Check(value, limit, utilization <= 1.0, utilization, dict(detail))
