"""One rule's verdict: a demand against its limit, judged with the design margin.

Every check of every rule (the gearhead's, its output bearing's, the motor's, the pair's)
is a `Check`, and `holds` is the one place a utilization is judged: a design margin m
means every rule must hold at (1 - m) of its limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field

MOTOR_CHECKS = ("motor_peak", "motor_rms", "motor_speed")
"""The checks of the motor behind a gearhead, when one is given (`check_motor`)."""


BEARING_CHECKS = ("bearing_moment", "bearing_radial", "bearing_axial", "bearing_life",
                  "bearing_static")
"""The checks of a rated output bearing (`hdselect.catalog.bearing_rules`), each present
where the catalog gives its rating and the bearing's loads are known (the life also needs a
required life)."""


PAIR_CHECKS = ("inertia_ratio",)
"""The checks of a gearhead and motor pair as a whole: the load-to-rotor inertia ratio
against the largest allowed, present only when a largest ratio is given. The design margin
does not apply to it: the largest ratio is itself a design choice, not a rating."""


CHECKS = ("peak", "mean", "speed", "average_speed", "momentary", "static", "life",
          *BEARING_CHECKS, *MOTOR_CHECKS, *PAIR_CHECKS)
"""Every check by name, in the order of results and reports: the gearhead's, its output
bearing's, its motor's, the pair's. ``life`` is present only when a life is required, the
output bearing's only where the catalog rates it (and its loads are known), the motor
checks only when a motor is given, ``inertia_ratio`` only when a largest inertia ratio is
given too; the others always, with value None where they do not apply."""


LIFE_CAP = 1e6
"""The longest life reported as a number [h], 114 years of running: beyond it the cube
and 10/3-power laws extrapolate to figures no design can use (a torque near zero gives
1e37 h). A longer life is reported as the cap and flagged: ``> 1e6 h`` in every table and
the parts list, the cap with ``*_capped: true`` in JSON. The checks judge the life
computed, so a requirement is met or not whatever the cap."""
LIFE_CHECKS = ("life", "bearing_life")
"""The checks whose value is a life [h], reported within `LIFE_CAP`."""


def reported_life(hours: float | None) -> float | None:
    """A life as reported [h]: at most `LIFE_CAP`; None (unlimited) stays None."""
    return None if hours is None else min(hours, LIFE_CAP)


def life_capped(hours: float | None) -> bool:
    """Whether a life [h] is reported as the cap (`LIFE_CAP`) rather than as itself."""
    return hours is not None and hours >= LIFE_CAP


PER_SAMPLE_CHECKS = ("peak", "speed", "momentary", "static", "motor_peak", "motor_speed",
                     "inertia_ratio", "bearing_moment", "bearing_radial", "bearing_axial")
"""The checks of single samples (or single poses): over several tasks, the worst task's.
The inertia ratio is one of them: its load inertia is the largest M_jj over every task's
poses; the bearing's largest moment and forces are too. The others pool every task's
samples: mean torque, average speed, life, motor RMS, the bearing's life and its static
safety (whose load adds the largest radial force, moment and axial force over the duty,
which may come from different tasks)."""


CHECK_LABELS = {"peak": "peak", "mean": "mean", "speed": "speed", "average_speed": "avg speed",
                "momentary": "mom.", "static": "static", "life": "life",
                "bearing_moment": "b.moment", "bearing_radial": "b.radial",
                "bearing_axial": "b.axial", "bearing_life": "b.life",
                "bearing_static": "b.static",
                "motor_peak": "m.peak", "motor_rms": "m.rms", "motor_speed": "m.speed",
                "inertia_ratio": "inertia"}
"""Short names of the checks, for table headers (``b.``: the output bearing's, ``m.``: the
motor's)."""


CHECK_NAMES = {"peak": "repeated peak torque", "mean": "mean torque", "speed": "input speed",
               "average_speed": "average input speed", "momentary": "momentary torque",
               "static": "static torque", "life": "life",
               "bearing_moment": "bearing tilting moment", "bearing_radial": "bearing radial load",
               "bearing_axial": "bearing axial load", "bearing_life": "bearing life",
               "bearing_static": "bearing static safety", "motor_peak": "motor peak torque",
               "motor_rms": "motor RMS torque", "motor_speed": "motor speed",
               "inertia_ratio": "load-to-rotor inertia ratio"}
"""The checks in words, for figure titles and summaries read by people."""


DEFAULT_MARGIN = 0.0
"""Design margin by default [-]: every rule holds at up to 100 % of its limit."""


def holds(utilization: float, margin: float = DEFAULT_MARGIN) -> bool:
    """Whether a rule holds with a design margin: utilization <= 1 - margin.

    The one place a check decides pass or fail: every rule of `check_unit`, the motor's
    rules and every front end built on them (size, compare, fastest, duty, studies,
    max-payload) judge through it. Utilization stays demand / limit.

    Args:
        utilization: Demand over limit [-] (a life or a safety: required over reached).
        margin: Share of every limit kept in reserve [-], in [0, 1).

    Returns:
        True when the rule holds with the margin.
    """
    return utilization <= 1.0 - margin


def derated(limit: float, margin: float = DEFAULT_MARGIN) -> float:
    """The usable part of a limit with a design margin, (1 - margin) x limit [same unit].

    What the closed-form solvers (time scales, path bounds, payload intervals) use as the
    limit, so that they agree with `holds`.
    """
    return limit * (1.0 - margin)



@dataclass(frozen=True)
class Check:
    """One rule applied to one gearhead.

    Attributes:
        value: The demand ([N m], [N], input speed [rpm]), or for a life the life
            expected [h] and for a static safety the safety reached [-]; None if the
            rule does not apply to this cycle or this unit.
        limit: What the gearhead allows (for a life or a safety: what is required);
            infinite where the unit has no such limit.
        ok: The rule holds with the design margin (`holds`).
        utilization: Demand over allowance [-] (a life or a safety: required over
            reached); 0 if the rule does not apply, above 1 when it fails.
        detail: Extra figures for reports, e.g. ``{"kind": "crash"}``.
    """

    value: float | None
    limit: float
    ok: bool
    utilization: float
    detail: dict[str, object] = field(default_factory=dict)



def limit_check(value: float | None, limit: float, *, margin: float = DEFAULT_MARGIN,
                **detail: object) -> Check:
    """One check: a value against its limit [same unit], utilization = value / limit.

    It holds when the utilization is at most 1 - `margin` (`holds`).
    """
    utilization = 0.0 if value is None else value / limit
    return Check(value, limit, holds(utilization, margin), utilization, dict(detail))
