"""Size every joint: torques along the cycle, reflected through each unit, checked, chosen.

`size`, `size_trajectory` and `size_tasks` (`core`) are the product's main job (a
mix file's tasks through `duty`); `options` holds the
run's assumptions, `reflect` puts a joint's demand through a unit's ratio, `timescale`
finds the slow-down a unit needs, `loads` lists every joint against its robot-file
limits, and `summary` keeps a compact record of a result.
"""

from hdselect.sizing.core import check_units, size, size_tasks, size_trajectory
from hdselect.sizing.options import Options
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import Summary, summarize

__all__ = ["JointSizing", "Options", "SizingResult", "Summary", "check_units", "size",
           "size_tasks", "size_trajectory", "summarize"]
