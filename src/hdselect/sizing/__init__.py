"""Size every joint: torques along the cycle, reflected through each unit, checked, chosen.

`resolve` (`problem`) turns files or objects into one `Problem`; `size`,
`size_problem`, `size_trajectory` and `size_tasks` (`core`) are the product's main job
(a mix file's tasks through `duty`); `options` holds the
run's assumptions, `reflect` puts a joint's demand through a unit's ratio, `timescale`
finds the slow-down a unit needs, `loads` lists every joint against its robot-file
limits, and `summary` keeps a compact record of a result.
"""

from hdselect.sizing.core import check_units, size, size_problem, size_tasks, size_trajectory
from hdselect.sizing.options import Options
from hdselect.sizing.problem import Problem, plan_tasks, resolve
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import Summary, summarize
from hdselect.sizing.tasks import Task

__all__ = ["JointSizing", "Options", "Problem", "SizingResult", "Summary", "Task", "check_units",
           "plan_tasks", "resolve", "size", "size_problem", "size_tasks", "size_trajectory",
           "summarize"]
