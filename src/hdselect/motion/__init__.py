"""What the robot must do: motion files and logs, and the trajectory planned from them.

`load_motion` reads a motion file (`motionfile`, logs through `logfile`), `load_mix` a
mix file of several motions sized as one duty (`mixfile`), `solve_motion` solves a
motion's tool poses for a robot's mounting (`solve`), `plan` turns it into a
`Trajectory` sampled on a fixed time grid (`planning`; `plan_motion` also returns the
solved motion and its straight lines' deviations), and `starter` writes a first motion
file for a robot.
"""

from hdselect.motion.loading import load_case
from hdselect.motion.mixfile import Mix, load_mix
from hdselect.motion.motionfile import Motion, load_motion
from hdselect.motion.planning import Trajectory, plan, plan_motion
from hdselect.motion.planning.solve import solve_motion
from hdselect.motion.starter import starter_motion

__all__ = ["Mix", "Motion", "Trajectory", "load_case", "load_mix", "load_motion", "plan",
           "plan_motion", "solve_motion", "starter_motion"]
