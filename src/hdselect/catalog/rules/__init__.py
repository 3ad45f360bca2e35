"""The catalog's rules as objects: one joint's cycle against one gearhead (and motor).

Each rule is a `Rule` in a file of its own (`peak`, `mean`, `speed`, `average_speed`,
`momentary`, `static`, `life`, the joint's precision targets `torsion` and
`natural_frequency`; the output bearing's five in `bearing`, the motor's three in `motor`;
the pair's `inertia_ratio`; `peak` and `static` share `torque`), on the base
of `base`: its names, what it judges, its forward check, the margin applied once
(`Rule.judge`) and the solvers' forms (their inputs in `forms`, the payload intervals'
arithmetic in `masses`). `peak`, `static`, `momentary` and `speed` are each a
`UnitLimit`: the cycle's largest magnitude against one of the unit's fields. `registry` orders them
(`RULES`, `rule`) and derives the check tables from them; `check` applies them
(`check_unit`, `check_motor`). What the rules read of a cycle is in `load`, a unit's
verdicts in `candidate`.
"""

from hdselect.catalog.rules.base import (
    DEFAULT_MARGIN,
    Check,
    Part,
    Rule,
    RuleInput,
    Scope,
    UnitLimit,
    derated,
    holds,
    within,
)
from hdselect.catalog.rules.bearing import bearing_checks
from hdselect.catalog.rules.candidate import Candidate
from hdselect.catalog.rules.check import apply_rules, check_motor, check_unit
from hdselect.catalog.rules.forms import (
    TARGETS,
    Interval,
    MeanOfMass,
    PathCase,
    PayloadCase,
    Rows,
    ScaleTerms,
    UnitBatch,
    targets_of,
)
from hdselect.catalog.rules.inertia_ratio import inertia_ratio
from hdselect.catalog.rules.load import (
    ALLOWABLE_TORQUE_EXPONENT,
    MOMENTARY_EVENTS_FACTOR,
    REST_FRACTION,
    RPM_PER_RAD_S,
    CycleLoad,
    Momentary,
    MotorDemand,
    allowable_mean_torque,
    allowed_momentary_events,
    at_rest,
    cycle_load,
    l50_life_hours,
)
from hdselect.catalog.rules.registry import (
    BEARING_CHECKS,
    CHECK_LABELS,
    CHECK_NAMES,
    CHECKS,
    LIFE_CHECKS,
    MOTOR_CHECKS,
    PAIR_CHECKS,
    PER_SAMPLE_CHECKS,
    RULES,
    register,
    registered,
    rule,
    rules_of,
    unregister,
)

__all__ = [
    "ALLOWABLE_TORQUE_EXPONENT", "BEARING_CHECKS", "CHECKS", "CHECK_LABELS", "CHECK_NAMES",
    "DEFAULT_MARGIN", "LIFE_CHECKS", "MOMENTARY_EVENTS_FACTOR", "MOTOR_CHECKS",
    "PAIR_CHECKS", "PER_SAMPLE_CHECKS", "REST_FRACTION", "RPM_PER_RAD_S", "RULES",
    "Candidate", "Check", "CycleLoad", "Interval", "MeanOfMass", "Momentary",
    "MotorDemand", "Part", "PathCase", "PayloadCase", "Rows", "Rule", "RuleInput",
    "ScaleTerms", "Scope", "TARGETS", "UnitBatch", "UnitLimit", "allowable_mean_torque",
    "allowed_momentary_events", "apply_rules", "at_rest", "bearing_checks", "check_motor",
    "check_unit", "cycle_load",
    "derated", "holds", "inertia_ratio", "l50_life_hours", "register", "registered", "rule",
    "rules_of", "targets_of", "unregister", "within",
]
