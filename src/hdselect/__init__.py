"""hdselect: size Harmonic Drive PSA-G gearheads for robot joints from the robot's dynamics."""

import logging

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

__version__ = "0.1.0"

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

logging.getLogger(__name__).addHandler(logging.NullHandler())
