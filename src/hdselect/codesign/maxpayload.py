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

The units chosen (and so the gearhead masses the joints nearer the base carry) depend
on m: the largest mass with the masses of the units `size` selects there is found, the
selection redone at it, and the two repeated until the masses settle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.rules import RPM_PER_RAD_S, Candidate, allowable_mean_torque
from hdselect.catalog.units import L50_PER_L10, Unit
from hdselect.codesign.choice import duty_of
from hdselect.codesign.cubicmean import CubicMean
from hdselect.codesign.payloadsizing import (
    PayloadSizing,
    payload_tasks,
    scaled_tasks,
)
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import cycle_torques
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import fixed_units
from hdselect.sizing.options import Options
from hdselect.sizing.problem import Problem
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.tasks import Task, pooled

Interval = tuple[float, float]
"""A closed interval of payload masses (lo, hi) [kg]; hi may be math.inf."""
_ROUNDS = 12
_ROUNDOFF = 1e-12
"""Per-kg torque below this fraction of a joint's torques is rounding, not load [-]."""


@dataclass(frozen=True)
class UnitBound:
    """The payload masses at which one unit passes every rule on one joint.

    Attributes:
        unit: The unit.
        masses: The interval of masses [kg], or None when no mass >= 0 passes.
        ends: For each rule, the interval of masses it allows [kg] (None: none).
    """

    unit: Unit
    masses: Interval | None
    ends: Mapping[str, Interval | None]

    def limiting(self, mass: float) -> str:
        """The rule whose interval ends at (or closest above) `mass` [kg]."""
        hi = {rule: span[1] if span is not None else -math.inf
              for rule, span in self.ends.items()}
        return min(hi, key=lambda rule: abs(hi[rule] - mass))


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
    payloads = {task.label: task.robot.payload for task in planned
                if task.label in scaled and task.robot.payload is not None}
    first = next(task for task in planned if task.label in scaled)
    return MaxPayloadResult(mass, payloads[first.label], tuple(ranges), joint, unit, rule,
                            selection, planned[0].trajectory, bounds,
                            first.robot.payload_frame, scaled, payloads, planned, duty.idle,
                            duty.mix)


def _carried(chosen: Candidate, options: Options) -> float:
    """Mass a joint's unit (or pair) adds to the joints nearer the base [kg]."""
    motor = chosen.motor_unit
    return chosen.unit.mass + (motor.mass if motor is not None else options.motor_mass)


def duty_bounds(tasks: Sequence[Task], idle: float, scaled: Sequence[str],
                masses: Mapping[str, float], units: Sequence[Unit],
                options: Options) -> dict[str, tuple[UnitBound, ...]]:
    """Each unit's interval of x on each sized joint, gearhead masses fixed.

    The payloads of `scaled` tasks are x times theirs (mass and inertia), the others'
    fixed: every task's torque is affine in x on its fixed trajectory, so two batched
    passes per task give each rule as an interval of x, over the tasks' samples pooled at
    their shares (`hdselect.sizing.tasks.pooled`): the rules of single samples on every
    sample, the mean torque and life on the pooled cubic mean.

    Args:
        tasks: The duty's tasks, payloads at x = 1.
        idle: The fraction of the time no task runs [-].
        scaled: The tasks whose payload scales, by name.
        masses: The gearhead (and motor) mass per joint's unit [kg].
        units: The catalog.
        options: The assumptions.
    """
    counted = [task for task in tasks if task.share > 0.0]
    samples = pooled(counted, idle)
    parts = []
    for task in counted:
        traj = task.trajectory
        carrying = task.robot.with_payload(None).with_gearheads(masses)
        args = (traj.q, traj.qd, traj.qdd, options.stop_time)
        payload = task.robot.payload
        if task.label in scaled and payload is not None:
            none = cycle_torques(carrying, *args, threads=options.threads)
            full = cycle_torques(carrying.with_payload(payload), *args, threads=options.threads)
        else:
            none = full = cycle_torques(task.robot.with_gearheads(masses), *args,
                                        threads=options.threads)
        parts.append((none, full))
    robot = counted[0].robot
    out = {}
    for name in robot.sized_joints:
        j = robot.joint_index(name)
        tau0 = np.concatenate([none.tau[:, j] for none, _ in parts])
        stop0 = np.concatenate([none.stop[:, j] for none, _ in parts])
        tau1 = np.concatenate([_per_kg(full.tau[:, j], none.tau[:, j]) for none, full in parts])
        stop1 = np.concatenate([_per_kg(full.stop[:, j], none.stop[:, j])
                                for none, full in parts])
        rest, qd = samples.rest[:, j], samples.qd[:, j]
        cubic = joint_mean(samples.dt, rest, qd, tau0, tau1)
        out[name] = tuple(unit_bound(unit, samples.dt, rest, qd, tau0, tau1, stop0, stop1,
                                     options, samples.idle, cubic=cubic)
                          for unit in units)
    return out


def _per_kg(loaded: np.ndarray, empty: np.ndarray) -> np.ndarray:
    """The torque of 1 kg [N m]: loaded - empty, zero where it is within their roundoff.

    A payload on a joint's axis (its centre of mass on it, no inertia) loads it with
    nothing; the difference of two dynamics passes is then rounding, ~1e-16 of the
    torques, which would read as a limit of ~1e16 kg rather than none.
    """
    difference = loaded - empty
    scale = float(np.max(np.abs(loaded), initial=0.0) + np.max(np.abs(empty), initial=0.0))
    return np.where(np.abs(difference) <= _ROUNDOFF * scale, 0.0, difference)


def joint_mean(dt: float | np.ndarray, rest: np.ndarray, qd: np.ndarray, tau0: np.ndarray,
               tau1: np.ndarray) -> CubicMean:
    """A joint's cubic mean torque as a function of x, tau = tau0 + x tau1 [N m].

    The catalog's weights, |qd| dt over the moving samples, do not depend on the unit:
    one `CubicMean` (one sort of the samples' roots) serves every unit of the joint.

    Args:
        dt: What each sample stands for [s], a number or (n,).
        rest: Where the joint is held still, (n,).
        qd: The joint's speed [rad/s], (n,).
        tau0: Torque at x = 0 [N m], (n,).
        tau1: Its change per unit of x [N m], (n,).
    """
    step = np.broadcast_to(np.asarray(dt, dtype=float), np.shape(qd))
    return CubicMean(tau0, tau1, np.abs(qd) * step * ~rest)


def unit_bound(unit: Unit, dt: float | np.ndarray, rest: np.ndarray, qd: np.ndarray,
               tau0: np.ndarray, tau1: np.ndarray, stop0: np.ndarray, stop1: np.ndarray,
               options: Options, idle: float = 0.0, *,
               cubic: CubicMean | None = None) -> UnitBound:
    """Every rule of `check_unit` as an interval of x, with tau = tau0 + x tau1 [N m].

    Args:
        unit: The unit.
        dt: What each sample stands for [s] (pooled samples: `hdselect.sizing.tasks`).
        rest: Where the joint is held still, (n,).
        qd: The joint's speed [rad/s], (n,).
        tau0: Torque at x = 0 [N m], (n,).
        tau1: Its change per unit of x [N m], (n,).
        stop0: Emergency-stop torque at x = 0 [N m], (n,).
        stop1: Its change per unit of x [N m], (n,).
        options: The assumptions.
        idle: Time at rest no sample stands for [s] (a pause in a whole-cycle mean speed).
        cubic: The joint's mean torque (`joint_mean` of the same samples), shared by its
            units; None builds it.
    """
    moving = ~rest
    speed = np.abs(qd)
    gain = (unit.input_inertia + options.rotor_inertia) * unit.ratio**2 / options.stop_time
    usable = 1.0 - options.margin  # every limit less the design margin (`derated`)
    ends: dict[str, Interval | None] = {
        "peak": _within(tau0[moving], tau1[moving], unit.repeated_torque * usable),
        "static": _within(tau0[rest], tau1[rest], unit.static_torque * usable),
        "momentary": _meet(_within(stop0, stop1, unit.momentary_torque * usable),
                           _within(tau0, tau1, unit.momentary_torque * usable - gain * speed)),
    }
    step = np.broadcast_to(np.asarray(dt, dtype=float), speed.shape)
    weight = speed * step * moving
    moving_time = float(step[moving].sum())
    travel = float(weight.sum())
    mean_speed = travel / moving_time if moving_time > 0.0 else 0.0
    rules = unit.rules
    whole = float(step.sum()) + idle
    cycle_speed = travel / whole if whole > 0.0 else 0.0
    n_av = (mean_speed if rules.mean_speed == "moving" else cycle_speed) * RPM_PER_RAD_S \
        * unit.ratio
    everything: Interval = (-math.inf, math.inf)
    ends["speed"] = everything if speed.max(initial=0.0) * RPM_PER_RAD_S * unit.ratio \
        <= unit.max_input_speed * usable else None
    average = unit.max_average_input_speed
    ends["average_speed"] = everything if average is None or n_av <= average * usable else None
    if travel > 0.0:
        allowed, _ = allowable_mean_torque(unit, n_av)
        mean = joint_mean(dt, rest, qd, tau0, tau1) if cubic is None else cubic
        ends["mean"] = mean.at_most(allowed * usable)
        if options.life_hours is not None:  # required / expected <= usable
            required = (options.life_hours / usable
                        * (L50_PER_L10 if options.life_basis == "L10" else 1.0))
            most = (unit.rated_torque * (rules.rated_l50_hours * rules.rated_input_speed
                                         / (n_av * required)) ** (1.0 / 3.0)
                    if n_av > 0.0 else math.inf)
            ends["life"] = mean.at_most(most)
    masses: Interval | None = (0.0, math.inf)
    for span in ends.values():
        masses = _meet(masses, span)
    return UnitBound(unit, masses, ends)


def _within(c0: np.ndarray, c1: np.ndarray, limit: np.ndarray | float) -> Interval | None:
    """Where |c0 + m c1| <= limit at every sample: an interval of m, or None."""
    limit = np.broadcast_to(np.asarray(limit, dtype=float), np.shape(c0))
    if np.shape(c0)[0] == 0:
        return (-math.inf, math.inf)
    if np.any(limit < 0.0):
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (-limit - c0) / c1, (limit - c0) / c1
    flat = c1 == 0.0
    if np.any(flat & (np.abs(c0) > limit)):
        return None
    lo = np.where(flat, -np.inf, np.minimum(a, b))
    hi = np.where(flat, np.inf, np.maximum(a, b))
    low, high = float(lo.max()), float(hi.min())
    return (low, high) if low <= high else None


def _meet(a: Interval | None, b: Interval | None) -> Interval | None:
    if a is None or b is None:
        return None
    lo, hi = max(a[0], b[0]), min(a[1], b[1])
    return (lo, hi) if lo <= hi else None


def _feasible(bounds: Mapping[str, tuple[UnitBound, ...]]) -> list[Interval]:
    """The masses >= 0 at which every joint has some unit: union per joint, then meet."""
    spans: list[Interval] = [(0.0, math.inf)]
    for per_unit in bounds.values():
        union = _union([b.masses for b in per_unit if b.masses is not None])
        spans = [s for a in spans for b in union for s in [_meet(a, b)] if s is not None]
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
