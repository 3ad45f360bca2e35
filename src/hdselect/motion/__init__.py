"""What the robot must do: motion files and logs, and the trajectory planned from them.

`load_motion` reads a motion file (`motionfile`, logs through `logfile`), `load_mix` a
mix file of several motions sized as one duty (`mixfile`), `plan` turns a motion into a
`Trajectory` sampled on a fixed time grid (`planning`), and `starter` writes a first
motion file for a robot.
"""

from hdselect.motion.case import load_case
from hdselect.motion.mixfile import Mix, load_mix
from hdselect.motion.motionfile import Motion, load_motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.motion.starter import starter_motion

__all__ = ["Mix", "Motion", "Trajectory", "load_case", "load_mix", "load_motion", "plan",
           "starter_motion"]
