"""hdselect: size Harmonic Drive PSA-G gearheads for robot joints from the robot's dynamics."""

import logging

from hdselect.catalog import Unit, load_catalog
from hdselect.duty import load_duty, size_duty
from hdselect.errors import HdselectError, InputError, PlanningError
from hdselect.motion import Motion, load_motion
from hdselect.plan import Trajectory, plan
from hdselect.robot import Payload, Robot, load_robot
from hdselect.sizing import SizingResult, size

__version__ = "0.1.0"

__all__ = [
    "HdselectError",
    "InputError",
    "Motion",
    "Payload",
    "PlanningError",
    "Robot",
    "SizingResult",
    "Trajectory",
    "Unit",
    "__version__",
    "load_catalog",
    "load_duty",
    "load_motion",
    "load_robot",
    "plan",
    "size",
    "size_duty",
]

logging.getLogger(__name__).addHandler(logging.NullHandler())
