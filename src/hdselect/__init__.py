"""hdselect: size Harmonic Drive PSA-G gearheads for robot joints from the robot's dynamics.

The public names load on first use, so ``import hdselect`` (and the command line's
start-up, which Ctrl-C may interrupt) does not import Pinocchio, Ruckig or numpy.
"""

import importlib
import logging
from typing import TYPE_CHECKING, Any

__version__ = "0.7.0"

_HOME = {
    "BasePose": "robot",
    "Carried": "motion.events",
    "DutyCycle": "catalog.duty",
    "DutyResult": "catalog",
    "EnvelopeResult": "envelope",
    "FastestResult": "codesign",
    "HdselectError": "base",
    "InputError": "base",
    "JointInfo": "robot",
    "MaxPayloadResult": "codesign",
    "Mix": "motion",
    "Motion": "motion",
    "Motor": "catalog",
    "Options": "sizing",
    "Payload": "robot",
    "Planned": "motion.planning",
    "PlanningError": "base",
    "Problem": "sizing",
    "RatioComparison": "codesign",
    "Robot": "robot",
    "SearchSettings": "envelope",
    "SizingResult": "sizing",
    "Summary": "sizing",
    "Task": "sizing",
    "Trajectory": "motion",
    "Unit": "catalog",
    "check_units": "sizing",
    "compare_ratios": "codesign",
    "describe_joints": "robot",
    "envelope": "envelope",
    "fastest": "codesign",
    "load_catalog": "catalog",
    "load_case": "motion",
    "load_duty": "catalog",
    "load_mix": "motion",
    "load_motion": "motion",
    "load_motors": "catalog",
    "load_robot": "robot",
    "max_payload": "codesign",
    "plan": "motion",
    "plan_motion": "motion",
    "resolve": "sizing",
    "size": "sizing",
    "size_duty": "catalog",
    "size_problem": "sizing",
    "size_tasks": "sizing",
    "size_trajectory": "sizing",
    "solve_motion": "motion",
    "starter_motion": "motion",
    "study": "study",
    "summarize": "sizing",
}
"""The package (or module) each public name lives in."""

__all__ = [
    "BasePose",
    "Carried",
    "DutyCycle",
    "DutyResult",
    "EnvelopeResult",
    "FastestResult",
    "HdselectError",
    "InputError",
    "JointInfo",
    "MaxPayloadResult",
    "Mix",
    "Motion",
    "Motor",
    "Options",
    "Payload",
    "Planned",
    "PlanningError",
    "Problem",
    "RatioComparison",
    "Robot",
    "SearchSettings",
    "SizingResult",
    "Summary",
    "Task",
    "Trajectory",
    "Unit",
    "__version__",
    "check_units",
    "compare_ratios",
    "describe_joints",
    "envelope",
    "fastest",
    "load_catalog",
    "load_case",
    "load_duty",
    "load_mix",
    "load_motion",
    "load_motors",
    "load_robot",
    "max_payload",
    "plan",
    "plan_motion",
    "resolve",
    "size",
    "size_duty",
    "size_problem",
    "size_tasks",
    "size_trajectory",
    "solve_motion",
    "starter_motion",
    "study",
    "summarize",
]

if TYPE_CHECKING:
    from hdselect.base import HdselectError, InputError, PlanningError
    from hdselect.catalog import (
        DutyResult,
        Motor,
        Unit,
        load_catalog,
        load_duty,
        load_motors,
        size_duty,
    )
    from hdselect.catalog.duty import DutyCycle
    from hdselect.codesign import (
        FastestResult,
        MaxPayloadResult,
        RatioComparison,
        compare_ratios,
        fastest,
        max_payload,
    )
    from hdselect.envelope import EnvelopeResult, SearchSettings, envelope
    from hdselect.motion import (
        Mix,
        Motion,
        Trajectory,
        load_case,
        load_mix,
        load_motion,
        plan,
        plan_motion,
        solve_motion,
        starter_motion,
    )
    from hdselect.motion.events import Carried
    from hdselect.motion.planning import Planned
    from hdselect.robot import BasePose, JointInfo, Payload, Robot, describe_joints, load_robot
    from hdselect.sizing import (
        Options,
        Problem,
        SizingResult,
        Summary,
        Task,
        check_units,
        resolve,
        size,
        size_problem,
        size_tasks,
        size_trajectory,
        summarize,
    )
    from hdselect.study import study


def __getattr__(name: str) -> Any:
    """Import a public name's module when the name is first used."""
    if name not in _HOME:
        raise AttributeError(f"module 'hdselect' has no attribute {name!r}")
    package = importlib.import_module(f"hdselect.{_HOME[name]}")
    value = package if name in ("envelope", "study") else getattr(package, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


logging.getLogger(__name__).addHandler(logging.NullHandler())
