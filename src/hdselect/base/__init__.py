"""What every step stands on: errors, input bounds, TOML reading, outputs, the run's session.

Nothing here knows about robots or gearheads; every other package may import it.
"""

from hdselect.base.errors import HdselectError, InputError, PlanningError

__all__ = ["HdselectError", "InputError", "PlanningError"]
