"""hdselect: size Harmonic Drive PSA-G gearheads for robot joints from the robot's dynamics."""

import logging

from hdselect.errors import HdselectError, InputError, PlanningError
from hdselect.robot import Payload, Robot, load_robot

__version__ = "0.1.0"

__all__ = [
    "HdselectError",
    "InputError",
    "Payload",
    "PlanningError",
    "Robot",
    "__version__",
    "load_robot",
]

logging.getLogger(__name__).addHandler(logging.NullHandler())
