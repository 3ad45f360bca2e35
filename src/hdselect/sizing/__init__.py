"""Size every joint: torques along the cycle, reflected through each unit, checked, chosen.

`size` and `size_trajectory` (`core`) are the product's main job; `options` holds the
run's assumptions, `reflect` puts a joint's demand through a unit's ratio, `timescale`
finds the slow-down a unit needs, `loads` lists every joint against its robot-file
limits, and `summary` keeps a compact record of a result.
"""

from hdselect.sizing.core import check_units, size, size_trajectory
from hdselect.sizing.options import Options
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import Summary, summarize

__all__ = ["JointSizing", "Options", "SizingResult", "Summary", "check_units", "size",
           "size_trajectory", "summarize"]
