"""The sizing at one payload mass, with motors or fixed units, and the largest mass it passes.

`hdselect.codesign.maxpayload` finds the largest payload exactly from the gearheads' rules
(torque is affine in the payload mass). A motor's rules (peak torque through the ratio
and the efficiency, RMS torque, speed) and a fixed unit per joint are then taken from the
sizing itself: `PayloadSizing.at` sizes (or checks) the trajectory with the payload, and
`PayloadSizing.largest` bisects the mass between one that passes and one that does not,
so the answer is exactly what `hdselect.size` says at that payload. The gearheads' exact
mass bounds it from above: a motor only adds rules (its rotor inertia, larger than none,
only tightens the crash rule).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.sizing.core import check_units, size_tasks
from hdselect.sizing.options import Options
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task

MASS_RTOL = 1e-6
"""Relative width to which the largest mass is bisected where motors or fixed units bind [-]."""


@dataclass(frozen=True)
class PayloadSizing:
    """How the robot is sized at a payload mass.

    Attributes:
        bare: The robot without payload (no gearhead masses).
        payload: The payload's geometry for 1 kg.
        trajectory: The trajectory the payload rides.
        catalog: The units to choose from.
        options: The assumptions.
        units: The fixed unit of every sized joint, or empty to choose them.
        motors: Candidate motors per joint (one per joint with fixed units).
    """

    bare: Robot
    payload: Payload
    trajectory: Trajectory
    catalog: tuple[Unit, ...]
    options: Options
    units: Mapping[str, Unit]
    motors: Mapping[str, tuple[Motor, ...]]

    def __post_init__(self) -> None:
        if self.units:
            missing = [name for name in self.bare.sized_joints if name not in self.units]
            if missing:
                raise InputError(f"no unit given for {', '.join(missing)}: give a unit for "
                                 "every sized joint, or none to choose them", field="units")
            several = [name for name, found in self.motors.items() if len(found) > 1]
            if several:
                raise InputError(f"with fixed units, give one motor per joint ({several[0]} "
                                 f"has {len(self.motors[several[0]])} to choose from)",
                                 field="motors")

    def at(self, mass: float, *, slowdowns: bool = True) -> SizingResult:
        """The sizing (or the check of the fixed units) with `mass` [kg] of payload.

        Args:
            mass: The payload's mass [kg].
            slowdowns: Find, for a joint no unit fits, the time scales at which each
                would (`hdselect.sizing.slowdown`); False asks for the verdict only.
        """
        robot = self.bare.with_payload(scaled(self.payload, mass)) if mass > 0 else self.bare
        if self.units:
            return check_units(robot, self.trajectory, self.units, self.options,
                               motors={name: found[0] for name, found in self.motors.items()})
        return size_tasks((Task(robot, self.trajectory),), self.catalog, self.options,
                          motors=self.motors, slowdowns=slowdowns)

    def largest(self, low: float, high: float) -> tuple[float | None, SizingResult | None,
                                                         SizingResult | None]:
        """The largest mass in [low, high] [kg] at which every joint passes, by bisection.

        Returns:
            The mass (None when not even `low` passes), the sizing there, and the sizing
            just above it that fails (None when `high` passes).
        """
        top = self.at(high, slowdowns=False)  # a sizing that fails only names its rule
        if top.feasible:
            return high, top, None
        bottom = self.at(low, slowdowns=False)
        if not bottom.feasible:
            return None, None, bottom
        failing = top
        while high - low > MASS_RTOL * max(high, 1e-9):
            middle = 0.5 * (low + high)
            found = self.at(middle, slowdowns=False)
            if found.feasible:
                low, bottom = middle, found
            else:
                high, failing = middle, found
        return low, bottom, failing


def scaled(payload: Payload, mass: float) -> Payload:
    """The payload of `payload`'s geometry with `mass` [kg] (inertia scaled alike)."""
    return replace(payload, mass=mass,
                   inertia=tuple(tuple(v * mass / payload.mass for v in row)
                                 for row in payload.inertia))
