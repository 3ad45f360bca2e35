"""The sizing at one payload mass, with motors or fixed units, and the largest mass it passes.

`hdselect.codesign.maxpayload` finds the largest payload exactly from the gearheads' rules
(torque is affine in the payload mass). A motor's rules (peak torque through the ratio
and the efficiency, RMS torque, speed) and a fixed unit per joint are then taken from the
sizing itself: `PayloadSizing.at` sizes (or checks) the tasks with the payloads scaled
(`at_factor`: one motion's 1 kg payload scaled to a mass, a mix's payloads by a factor),
and
`PayloadSizing.largest` bisects the mass between one that passes and one that does not,
so the answer is exactly what `hdselect.size` says at that payload. The gearheads' exact
mass bounds it from above: a motor only adds rules (its rotor inertia, larger than none,
only tightens the crash rule).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from hdselect.base.bounds import LENGTH, expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.codesign.choice import Duty
from hdselect.codesign.scaledpart import scaled_part, with_part
from hdselect.codesign.trials import check_tasks
from hdselect.motion.planning import Trajectory
from hdselect.robot.payload import Payload
from hdselect.sizing.core import check_units, size_tasks
from hdselect.sizing.options import Options
from hdselect.sizing.result import SizingResult
from hdselect.sizing.tasks import Task

MASS_RTOL = 1e-6
"""Relative width to which the largest mass is bisected where motors or fixed units bind [-]."""


@dataclass(frozen=True)
class PayloadSizing:
    """How the robot's tasks are sized at a factor x on the payloads that scale.

    Attributes:
        tasks: The duty's counted tasks, the payloads that scale at x = 1 (one motion's:
            1 kg, so that x is its mass [kg]).
        scaled: The tasks whose payload scales, by label.
        idle: The fraction of the time no task runs [-].
        catalog: The units to choose from.
        options: The assumptions.
        units: The fixed unit of every sized joint, or empty to choose them.
        motors: Candidate motors per joint (one per joint with fixed units).
        pooled: Check fixed units over the tasks pooled (`check_tasks`: a mix); False
            checks the one task's trajectory (`hdselect.sizing.core.check_units`).
    """

    tasks: tuple[Task, ...]
    scaled: tuple[str, ...]
    idle: float
    catalog: tuple[Unit, ...]
    options: Options
    units: Mapping[str, Unit]
    motors: Mapping[str, tuple[Motor, ...]]
    pooled: bool = False

    def __post_init__(self) -> None:
        if self.units:
            missing = [name for name in self.tasks[0].robot.sized_joints
                       if name not in self.units]
            if missing:
                raise InputError(f"no unit given for {', '.join(missing)}: give a unit for "
                                 "every sized joint, or none to choose them", field="units")
            several = [name for name, found in self.motors.items() if len(found) > 1]
            if several:
                raise InputError(f"with fixed units, give one motor per joint ({several[0]} "
                                 f"has {len(self.motors[several[0]])} to choose from)",
                                 field="motors")

    def at(self, mass: float, *, slowdowns: bool = True) -> SizingResult:
        """The sizing (or the check of the fixed units) at a factor `mass` on the payloads.

        Args:
            mass: The factor x [-] (one motion's payload mass [kg]).
            slowdowns: Find, for a joint no unit fits, the time scales at which each
                would (`hdselect.sizing.slowdown`); False asks for the verdict only.
        """
        tasks = at_factor(self.tasks, self.scaled, mass)
        if self.units:
            motors = {name: found[0] for name, found in self.motors.items()}
            if self.pooled:
                return check_tasks(tasks, self.units, self.options, self.idle, motors)
            return check_units(tasks[0].robot, tasks[0].trajectory, self.units, self.options,
                               motors=motors, carried=tasks[0].carried)
        return size_tasks(tasks, self.catalog, self.options, motors=self.motors,
                          slowdowns=slowdowns, idle=self.idle)
    def largest(self, low: float, high: float) -> tuple[float | None, SizingResult | None,
                                                         SizingResult | None]:
        """The largest factor in [low, high] [-] at which every joint passes, by bisection.

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


def at_factor(tasks: Sequence[Task], scaled: Sequence[str], factor: float) -> tuple[Task, ...]:
    """The tasks with the scaled parts (`scaled_part`) of `scaled` ones times `factor` [-].

    Mass and inertia alike; a factor of 0 or less takes the part off.
    """
    out = []
    for task in tasks:
        payload = scaled_part(task) if task.label in scaled else None
        if payload is not None:
            task = with_part(task, None if factor <= 0.0 else replace(
                payload, mass=payload.mass * factor,
                inertia=tuple(tuple(v * factor for v in row) for row in payload.inertia)))
        out.append(task)
    return tuple(out)


def scaled(payload: Payload, mass: float) -> Payload:
    """The payload of `payload`'s geometry with `mass` [kg] (inertia scaled alike)."""
    return replace(payload, mass=mass,
                   inertia=tuple(tuple(v * mass / payload.mass for v in row)
                                 for row in payload.inertia))


def per_kilogram(payload: Payload | None, *, frame: str | None = None,
                 com: Sequence[float] | None = None) -> Payload:
    """A 1 kg payload of the given geometry; its inertia is the payload's per kg.

    With `frame` or `com` given, a point mass there (the payload's inertia was about
    its own centre, in its own frame).
    """
    expect_type(frame, (str, type(None)), "frame", "a link name or None")
    if com is not None:
        if isinstance(com, str) or not isinstance(com, Sequence) or len(com) != 3:
            raise InputError(f"expected three numbers [m], got {com!r}", field="com")
        com = [LENGTH.check(c, field=f"com[{i}]") for i, c in enumerate(com)]
    if payload is not None and frame is None and com is None:
        return replace(payload, mass=1.0, inertia=tuple(tuple(v / payload.mass for v in row)
                                                        for row in payload.inertia))
    at = tuple(com) if com is not None else (payload.com if payload is not None and frame is None
                                              else (0.0, 0.0, 0.0))
    where = frame if frame is not None else (payload.frame if payload is not None else None)
    return Payload(1.0, (float(at[0]), float(at[1]), float(at[2])), frame=where,
                   name="" if payload is None else payload.name)


def payload_tasks(duty: Duty, options: Options, frame: str | None,
                  com: Sequence[float] | None, trajectory: Trajectory | None
                  ) -> tuple[Task, ...]:
    """The duty's tasks planned, the payloads that scale at x = 1.

    One motion's payload is its geometry at 1 kg (`per_kilogram` of `frame` and `com`),
    so that x is its mass [kg]; a mix's tasks keep their payloads as the files give them.

    Raises:
        InputError: The frame does not exist, or a mix is given a frame, a centre of mass
            or a trajectory (each task has its own).
    """
    if duty.mix is None:
        (task,) = duty.tasks(options, trajectory)
        task = replace(task, motion=duty.motions[0], name=duty.motions[0].path.name)
        payload = per_kilogram(scaled_part(task), frame=frame, com=com)
        task.robot.with_payload(None).with_payload(payload)  # the frame must exist
        return (with_part(task, payload),)
    if frame is not None or com is not None or trajectory is not None:
        raise InputError("each task of a mix gives its own payload and trajectory",
                         field="frame" if frame is not None else
                         "com" if com is not None else "trajectory")
    return duty.tasks(options)


def scaled_tasks(planned: Sequence[Task], names: Sequence[str] | None,
                 duty: Duty) -> tuple[str, ...]:
    """The tasks whose payload scales: those named, else every one that carries a payload.

    Raises:
        InputError: A name is not a task, or no task named carries a payload.
    """
    labels = [task.label for task in planned]
    for name in names or ():
        if name not in labels:
            raise InputError(f"no task {name!r} in {duty.where.rsplit('/', 1)[-1]}; its tasks "
                             f"are: {', '.join(labels)}", field="task")
    chosen = tuple(task.label for task in planned if (names is None or task.label in names)
                   and scaled_part(task) is not None)
    if not chosen:
        raise InputError("no task " + ("named " if names else "of the mix ")
                         + "carries a payload to scale", path=duty.where, field="task")
    return chosen
