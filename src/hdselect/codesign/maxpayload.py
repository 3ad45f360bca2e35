"""The largest payload a motion (or a mix's tasks) can carry with a unit on every joint, exactly.

For a fixed trajectory the joint torques are affine in the payload mass m (its
inertia about its centre of mass scales with m: the same body, denser):
tau(m) = tau_0 + m tau_1, and so is the emergency stop's. Two pairs of batched passes
(without payload, and with 1 kg) therefore give every rule of every unit as a
function of m; a mix's payloads scale by one factor x alike, every task's samples
pooled at its share (`duty_bounds`):

- peak, static, emergency stop, crash: |tau_0 + m tau_1| <= limit (minus K |qd| for the
  crash) at every sample: an interval of m per sample, intersected;
- mean torque and life: T_av(m) = (sum w |tau_0 + m tau_1|^3 / sum w)^(1/3), w = |qd| dt
  over the moving samples, is convex in m, so T_av(m) <= T_allow (the allowance, and
  the torque that gives the required life, do not depend on m) is an interval, found
  from the sorted roots of the samples' torques (`hdselect.codesign.cubicmean`);
- input speed and average input speed do not depend on m.

With payload events, the part the events move is what scales (`scaled_part`): its term
is zero at the samples that do not carry it, so the torque stays affine in its mass.

The units chosen (and so the gearhead masses the joints nearer the base carry) depend
on m: the largest mass with the masses of the units `size` selects there is found, the
selection redone at it, and the two repeated until the masses settle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.rules import Candidate
from hdselect.catalog.rules.forms import Interval
from hdselect.catalog.rules.masses import meet
from hdselect.catalog.units import Unit
from hdselect.codesign.choice import duty_of, refuse_arm_targets
from hdselect.codesign.payloadbounds import UnitBound, duty_bounds
from hdselect.codesign.payloadsizing import (
    PayloadSizing,
    payload_tasks,
    scaled_tasks,
)
from hdselect.codesign.scaledpart import scaled_part
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import fixed_units
from hdselect.sizing.options import Options
from hdselect.sizing.problem import Problem
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.tasks import Task

_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class MaxPayloadResult:
    """The largest payload with a feasible unit on every joint.

    The answer is a factor x on the payload of every task that scales: one motion's is its
    geometry at 1 kg (x its mass [kg]), a mix's each task's as given (`masses`: at x).

    Attributes:
        mass: The largest x (one motion's payload mass [kg], a mix's factor [-]);
            math.inf when no rule depends on it; None when no x, not even 0, has a unit
            on every joint.
        payload: The (first scaled task's) payload at x = 1: one motion's geometry per
            kilogram: frame, centre of mass [m] and inertia about it [kg m^2 per kg].
        ranges: Every interval of x with a unit on every joint.
        joint: The joint that runs out of units at `mass`, or None.
        unit: The last of its units to pass there, or None.
        rule: The rule that unit fails just above `mass`, or None.
        selection: The sizing at `mass` (just inside it), or None.
        trajectory: The trajectory the payload rides (the first task's).
        bounds: Per joint, each unit's interval of x.
        frame: The link the payload is attached to (the robot's default payload frame,
            the tip of the longest chain of joints not excluded, when `payload` names none).
        scaled: The tasks whose payload scales, by name.
        payloads: Each scaled task's payload at x = 1, by name.
        tasks: The duty's tasks at x = 1; idle: the fraction of the time none runs [-].
        mix: The mix, or None for one motion.
        unloaded: Where no x fits: the sizing at x = 0 (no scaled payload), which names
            the joints no unit fits even then (`hdselect.sizing.diagnosis.with_diagnoses`
            says why); else None.
    """

    mass: float | None
    payload: Payload
    ranges: tuple[Interval, ...]
    joint: str | None
    unit: Unit | None
    rule: str | None
    selection: SizingResult | None
    trajectory: Trajectory
    bounds: Mapping[str, tuple[UnitBound, ...]]
    frame: str = ""
    scaled: tuple[str, ...] = ()
    payloads: Mapping[str, Payload] = field(default_factory=dict)
    tasks: tuple[Task, ...] = ()
    idle: float = 0.0
    mix: Mix | None = None
    unloaded: SizingResult | None = None

    @property
    def factor(self) -> float | None:
        """The largest factor on the scaled payloads [-] (`mass`)."""
        return self.mass

    def masses(self, factor: float | None = None) -> dict[str, float]:
        """Each scaled task's payload mass at a factor (default: the largest) [kg]."""
        x = self.mass if factor is None else factor
        if x is None:
            return {}
        return {name: payload.mass * x for name, payload in self.payloads.items()}


def max_payload(robot: Robot | Problem, motion: Motion | Mix | None = None,
                options: Options | None = None, *,
                catalog: Sequence[Unit] | None = None, frame: str | None = None,
                com: Sequence[float] | None = None,
                trajectory: Trajectory | None = None,
                units: Mapping[str, Unit | str] | None = None,
                motors: Motors | None = None,
                tasks: Sequence[str] | None = None) -> MaxPayloadResult:
    """The largest payload for which every joint still has a feasible unit.

    For one motion, the largest payload mass; for a mix, the largest common factor on
    the payloads of its tasks (mass and inertia alike), the others keeping theirs.

    Args:
        robot: The robot as the motion runs it (its payload, if any, sets the geometry);
            or the resolved `Problem` (`hdselect.resolve`), alone: its motion or mix,
            catalog, options and motors.
        motion: The motion, or a mix.
        options: The assumptions (default: `options_for(motion)`, or the mix's).
        catalog: The units (default: the built-in catalog, and the mix file's).
        frame: Frame one motion's payload is attached to (default: the payload's, else
            `Robot.default_payload_frame`, the tip of the longest chain of joints).
        com: Its centre of mass in that frame [m] (default: the payload's, else 0).
        trajectory: The trajectory one motion's payload rides (default: the motion as
            planned; a study gives it run s times slower), not depending on the payload.
        units: A fixed unit (or unit id) for every sized joint; None chooses them at each
            mass, as `hdselect.size` does.
        motors: Candidate motors per sized joint (one per joint with fixed units); None
            takes the files' ``[motor]``. Their rules bound the mass too
            (`hdselect.codesign.payloadsizing`).
        tasks: The tasks of a mix whose payload scales, by name (default: every task that
            carries one).

    Returns:
        The mass (or factor), where it binds, and the sizing there.

    Raises:
        InputError: A trajectory depends on the payload (TOPPRA with torque limits), the
            frame does not exist, a name is not a task, or no task named carries a
            payload.
        PlanningError: A motion cannot be planned.
    """
    duty, options, catalog, candidates = duty_of(
        robot, motion, options, catalog, motors, what="", units=units, frame=frame, com=com,
        trajectory=trajectory, tasks=tasks)
    expect_type(trajectory, (Trajectory, type(None)), "trajectory", "a Trajectory or None")
    refuse_arm_targets(options, "the largest payload")
    for item in duty.motions:
        if item.planner == "toppra" and item.torque_limit is not None:
            raise InputError("the TOPPRA torque limits make the trajectory depend on the "
                             "payload; max-payload needs a trajectory that does not: remove "
                             "them", path=item.path, field="limits.torque")
    planned = payload_tasks(duty, options, frame, com, trajectory)
    scaled = scaled_tasks(planned, tasks, duty)
    fixed = fixed_units(units, catalog, duty.robot)
    sizing = PayloadSizing(planned, scaled, duty.idle, catalog, options, fixed, candidates,
                           pooled=duty.mix is not None)
    # a rated output bearing's rules are not affine in m (a moment and forces combined):
    # like a motor's, the sizing judges them, and the mass is bisected on its verdict
    bearings = options.bearing_loads and any(unit.bearing is not None for unit in catalog)
    masses: dict[str, float] = {}
    for _ in range(_ROUNDS):
        bounds = duty_bounds(planned, duty.idle, scaled, masses, catalog, options)
        if fixed:
            bounds = {name: tuple(b for b in per_unit if b.unit is fixed[name])
                      for name, per_unit in bounds.items()}
        ranges = _feasible(bounds)
        mass = ranges[-1][1] if ranges else None
        selection = failing = None
        if mass is not None and math.isfinite(mass):
            inside = max(mass * (1.0 - 1e-9), ranges[-1][0])
            if fixed or candidates or bearings:  # their rules are the sizing's: bisect on it
                mass, selection, failing = sizing.largest(ranges[-1][0], inside)
            else:  # a round's sizing gives the masses: slow-downs only for the answer
                selection = sizing.at(inside, slowdowns=False)
        if selection is None or not options.mass_coupling:
            break
        chosen = {joint.name: _carried(joint.selected or joint.strongest, options)
                  for joint in selection.joints}
        if chosen == masses:
            break
        masses = chosen
    if selection is not None and failing is None and not selection.feasible:
        selection = sizing.at(inside)  # a joint no unit fits: its slow-downs, as size gives
    joint = unit = rule = None
    if failing is not None:  # a motor's rule or a fixed unit binds
        stuck = next(j for j in failing.joints if j.selected is None)
        closest = stuck.strongest
        joint, unit, rule = stuck.name, closest.unit, closest.binding
        ranges = [span for span in ranges if mass is not None and span[0] <= mass]
        if ranges and mass is not None:
            ranges[-1] = (ranges[-1][0], mass)
    elif mass is not None and math.isfinite(mass):
        joint, best = _binding(bounds, mass)
        unit, rule = best.unit, best.limiting(mass)
    if selection is not None and duty.mix is not None:
        selection = replace(selection, mix=duty.mix)
    payloads = {task.label: part for task in planned
                if task.label in scaled and (part := scaled_part(task)) is not None}
    first = next(task for task in planned if task.label in scaled)
    unloaded = sizing.at(0.0) if mass is None else None  # the joints no unit fits, and why
    return MaxPayloadResult(mass, payloads[first.label], tuple(ranges), joint, unit, rule,
                            selection, planned[0].trajectory, bounds,
                            payloads[first.label].frame or first.robot.payload_frame, scaled,
                            payloads, planned, duty.idle, duty.mix, unloaded)


def _carried(chosen: Candidate, options: Options) -> float:
    """Mass a joint's unit (or pair) adds to the joints nearer the base [kg]."""
    motor = chosen.motor_unit
    return chosen.unit.mass + (motor.mass if motor is not None else options.motor_mass)


def _feasible(bounds: Mapping[str, tuple[UnitBound, ...]]) -> list[Interval]:
    """The masses >= 0 at which every joint has some unit: union per joint, then meet."""
    spans: list[Interval] = [(0.0, math.inf)]
    for per_unit in bounds.values():
        union = _union([b.masses for b in per_unit if b.masses is not None])
        spans = [s for a in spans for b in union for s in [meet(a, b)] if s is not None]
    return sorted(spans)


def _union(spans: list[Interval]) -> list[Interval]:
    out: list[Interval] = []
    for lo, hi in sorted(spans):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out


def _binding(bounds: Mapping[str, tuple[UnitBound, ...]], mass: float) -> tuple[str, UnitBound]:
    """The joint whose units all stop passing at `mass` [kg], and the last of them."""
    last: dict[str, UnitBound] = {}
    for joint, per_unit in bounds.items():
        passing = [b for b in per_unit if b.masses is not None and b.masses[0] <= mass]
        if passing:
            last[joint] = max(passing, key=_upper)
    joint = min(last, key=lambda name: _upper(last[name]))
    return joint, last[joint]


def _upper(bound: UnitBound) -> float:
    return bound.masses[1] if bound.masses is not None else -math.inf
