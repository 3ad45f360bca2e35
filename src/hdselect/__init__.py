"""hdselect: size Harmonic Drive PSA-G gearheads for robot joints from the robot's dynamics.

The public names load on first use, so ``import hdselect`` (and the command line's
start-up, which Ctrl-C may interrupt) does not import Pinocchio, Ruckig or numpy.
"""

import importlib
import logging
import sys
import types
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

_HOME = {
    "FastestResult": "codesign",
    "HdselectError": "errors",
    "InputError": "errors",
    "MaxPayloadResult": "maxpayload",
    "Motion": "motion",
    "Motor": "motors",
    "Options": "options",
    "Payload": "robot",
    "PlanningError": "errors",
    "RatioComparison": "codesign",
    "Robot": "robot",
    "SizingResult": "sizing",
    "Summary": "summary",
    "Trajectory": "planning",
    "Unit": "catalog",
    "check_units": "sizing",
    "compare_ratios": "codesign",
    "describe_joints": "joints",
    "fastest": "codesign",
    "load_catalog": "catalog",
    "load_case": "motion",
    "load_duty": "duty",
    "load_motion": "motion",
    "load_motors": "motors",
    "load_robot": "robot",
    "max_payload": "maxpayload",
    "plan": "planning",
    "size": "sizing",
    "size_duty": "duty",
    "size_trajectory": "sizing",
    "starter_motion": "starter",
    "study": "study",
    "summarize": "summary",
}
"""The module each public name lives in."""

__all__ = [
    "FastestResult",
    "HdselectError",
    "InputError",
    "MaxPayloadResult",
    "Motion",
    "Motor",
    "Options",
    "Payload",
    "PlanningError",
    "RatioComparison",
    "Robot",
    "SizingResult",
    "Summary",
    "Trajectory",
    "Unit",
    "__version__",
    "check_units",
    "compare_ratios",
    "describe_joints",
    "fastest",
    "load_catalog",
    "load_case",
    "load_duty",
    "load_motion",
    "load_motors",
    "load_robot",
    "max_payload",
    "plan",
    "size",
    "size_duty",
    "size_trajectory",
    "starter_motion",
    "study",
    "summarize",
]

if TYPE_CHECKING:
    from hdselect.catalog import Unit, load_catalog
    from hdselect.codesign import FastestResult, RatioComparison, compare_ratios, fastest
    from hdselect.duty import load_duty, size_duty
    from hdselect.errors import HdselectError, InputError, PlanningError
    from hdselect.joints import describe_joints
    from hdselect.maxpayload import MaxPayloadResult, max_payload
    from hdselect.motion import Motion, load_case, load_motion
    from hdselect.motors import Motor, load_motors
    from hdselect.options import Options
    from hdselect.planning import Trajectory, plan
    from hdselect.robot import Payload, Robot, load_robot
    from hdselect.sizing import SizingResult, check_units, size, size_trajectory
    from hdselect.starter import starter_motion
    from hdselect.study import study
    from hdselect.summary import Summary, summarize


def __getattr__(name: str) -> Any:
    """Import a public name's module when the name is first used."""
    if name not in _HOME:
        raise AttributeError(f"module 'hdselect' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"hdselect.{_HOME[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """The package, whose ``study`` stays the function when the subpackage is imported.

    Importing ``hdselect.study.spec`` (say) binds the subpackage to ``hdselect.study``;
    the public name is the function `hdselect.study.study`, as an eager import would leave it.
    """

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "study" and isinstance(value, types.ModuleType):
            value = value.study
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


logging.getLogger(__name__).addHandler(logging.NullHandler())
