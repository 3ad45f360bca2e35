"""The largest payload a motion can carry with some unit on every joint, found exactly.

For a fixed trajectory the joint torques are affine in the payload mass m (its
inertia about its centre of mass scales with m: the same body, denser):
tau(m) = tau_0 + m tau_1, and so is the emergency stop's. Two pairs of batched passes
(without payload, and with 1 kg) therefore give every rule of every unit as a
function of m:

- peak, static, emergency stop, crash: |tau_0 + m tau_1| <= limit (minus K |qd| for the
  crash) at every sample: an interval of m per sample, intersected;
- mean torque and life: T_av(m) = (sum w |tau_0 + m tau_1|^3 / sum w)^(1/3), w = |qd| dt
  over the moving samples, is convex in m, so T_av(m) <= T_allow (the allowance, and
  the torque that gives the required life, do not depend on m) is an interval, found
  from the sorted roots of the samples' torques (`hdselect.codesign.cubicmean`);
- input speed and average input speed do not depend on m.

The units chosen (and so the gearhead masses the joints nearer the base carry)
depend on m: the largest mass with the masses of the units `size` selects there is
found, the selection redone at it, and the two repeated until the masses settle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from hdselect.base.bounds import LENGTH, expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import Candidate, at_rest
from hdselect.catalog.rules.forms import Interval
from hdselect.catalog.rules.masses import meet
from hdselect.catalog.units import Unit
from hdselect.codesign.payloadbounds import UnitBound, joint_mean, unit_bound
from hdselect.codesign.payloadsizing import PayloadSizing
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, plan
from hdselect.robot.dynamics import cycle_torques
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.robot.wrenches import axis_wrenches
from hdselect.sizing.arguments import checked_motors, fixed_units, units_argument
from hdselect.sizing.core import motion_motors
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.result import Motors, SizingResult

_ROUNDS = 12
_ROUNDOFF = 1e-12
"""Per-kg torque below this fraction of a joint's torques is rounding, not load [-]."""


@dataclass(frozen=True, eq=False)
class MaxPayloadResult:
    """The largest payload with a feasible unit on every joint.

    Attributes:
        mass: The largest payload mass [kg]; math.inf when no rule depends on it; None
            when no mass, not even 0, has a unit on every joint.
        payload: The payload's geometry per kilogram: frame, centre of mass [m] and
            inertia about it [kg m^2 per kg].
        ranges: Every interval of masses with a unit on every joint [kg].
        joint: The joint that runs out of units at `mass`, or None.
        unit: The last of its units to pass there, or None.
        rule: The rule that unit fails just above `mass`, or None.
        selection: The sizing at `mass` (just inside it), or None.
        trajectory: The trajectory the payload rides.
        bounds: Per joint, each unit's interval of masses.
        frame: The link the payload is attached to (the robot's default payload frame,
            the tip of the longest chain of joints not excluded, when `payload` names none).
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


def max_payload(robot: Robot, motion: Motion, options: Options | None = None, *,
                catalog: Sequence[Unit] | None = None, frame: str | None = None,
                com: Sequence[float] | None = None,
                trajectory: Trajectory | None = None,
                units: Mapping[str, Unit | str] | None = None,
                motors: Motors | None = None) -> MaxPayloadResult:
    """The largest payload mass for which every joint still has a feasible unit.

    Args:
        robot: The robot as the motion runs it (its payload, if any, sets the geometry).
        motion: The motion.
        options: The assumptions (default: `options_for(motion)`).
        catalog: The units (default: the built-in catalog).
        frame: Frame the payload is attached to (default: the payload's, else the tip of
            the longest chain of joints not excluded, `Robot.default_payload_frame`).
        com: Its centre of mass in that frame [m] (default: the payload's, else the
            frame's origin).
        trajectory: The trajectory the payload rides (default: the motion as planned;
            a study gives it run s times slower). It must not depend on the payload.
        units: A fixed unit (or unit id) for every sized joint; None chooses them at each
            mass, as `hdselect.size` does.
        motors: Candidate motors per sized joint (one per joint with fixed units); None
            takes the motion file's ``[motor]``. Their rules bound the mass too
            (`hdselect.codesign.payloadsizing`).

    Returns:
        The mass, where it binds, and the sizing there.

    Raises:
        InputError: The motion's trajectory depends on the payload (TOPPRA with torque
            limits), or the frame does not exist.
        PlanningError: The motion cannot be planned.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(motion, (Motion,), "motion", "a Motion (hdselect.load_case)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    expect_type(trajectory, (Trajectory, type(None)), "trajectory", "a Trajectory or None")
    if motion.planner == "toppra" and motion.torque_limit is not None:
        raise InputError("the TOPPRA torque limits make the trajectory depend on the payload;"
                         " max-payload needs a trajectory that does not: remove them",
                         path=motion.path, field="limits.torque")
    options = options if options is not None else options_for(motion)
    catalog = units_argument(catalog) if catalog is not None else load_catalog()
    payload = per_kilogram(robot.payload, frame=frame, com=com)
    bare = robot.with_payload(None)
    bare.with_payload(payload)  # the frame must exist
    fixed = fixed_units(units, catalog, robot)
    candidates = checked_motors(robot, motion_motors(robot, motion) if motors is None
                                else motors, options)
    if trajectory is None:
        trajectory = plan(robot, motion, max_samples=options.max_samples)
    sizing = PayloadSizing(bare, payload, trajectory, catalog, options, fixed, candidates)
    # a rated output bearing's rules are not affine in m (a moment and forces combined):
    # like a motor's, the sizing judges them, and the mass is bisected on its verdict
    bearings = options.bearing_loads and any(unit.bearing is not None for unit in catalog)
    masses: dict[str, float] = {}
    result = None
    for _ in range(_ROUNDS):
        bounds = joint_bounds(bare.with_gearheads(masses), payload, trajectory, catalog, options)
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
        result = (mass, ranges, bounds, selection, failing)
        if selection is None or not options.mass_coupling:
            break
        chosen = {joint.name: _carried(joint.selected or joint.strongest, options)
                  for joint in selection.joints}
        if chosen == masses:
            break
        masses = chosen
    if result is None:
        raise RuntimeError("the payload search ran no round")
    mass, ranges, bounds, selection, failing = result
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
    return MaxPayloadResult(mass, payload, tuple(ranges), joint, unit, rule, selection,
                            trajectory, bounds, bare.with_payload(payload).payload_frame)


def _carried(chosen: Candidate, options: Options) -> float:
    """Mass a joint's unit (or pair) adds to the joints nearer the base [kg]."""
    motor = chosen.motor_unit
    return chosen.unit.mass + (motor.mass if motor is not None else options.motor_mass)


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
        return Payload(1.0, payload.com, tuple(tuple(v / payload.mass for v in row)
                                               for row in payload.inertia), payload.frame)
    at = tuple(com) if com is not None else (payload.com if payload is not None and frame is None
                                              else (0.0, 0.0, 0.0))
    where = frame if frame is not None else (payload.frame if payload is not None else None)
    return Payload(1.0, (float(at[0]), float(at[1]), float(at[2])), frame=where)


def joint_bounds(carrying: Robot, payload: Payload, trajectory: Trajectory,
                 units: Sequence[Unit], options: Options) -> dict[str, tuple[UnitBound, ...]]:
    """Each unit's interval of payload masses on each sized joint, for fixed gearhead masses.

    Args:
        carrying: The robot without payload, carrying the gearhead masses.
        payload: The 1 kg payload.
        trajectory: The trajectory.
        units: The catalog.
        options: The assumptions.
    """
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    empty = cycle_torques(carrying, q, qd, qdd, options.stop_time, threads=options.threads)
    loaded = cycle_torques(carrying.with_payload(payload), q, qd, qdd, options.stop_time,
                           threads=options.threads)
    names = list(carrying.sized_joints)
    wrenches = None  # a rated output bearing is judged on the joint's wrench, affine in m too
    if options.bearing_loads and any(unit.bearing is not None for unit in units):
        wrenches = [axis_wrenches(robot, q, qd, qdd, names, threads=options.threads)
                    for robot in (carrying, carrying.with_payload(payload))]
    out = {}
    for k, name in enumerate(names):
        j = carrying.joint_index(name)
        tau0, stop0 = empty.tau[:, j], empty.stop[:, j]
        tau1 = _per_kg(loaded.tau[:, j], tau0)
        stop1 = _per_kg(loaded.stop[:, j], stop0)
        cubic = joint_mean(trajectory.dt, at_rest(qd[:, j], qdd[:, j]), qd[:, j], tau0, tau1)
        wrench = (None if wrenches is None else
                  (wrenches[0][k], wrenches[1][k] - wrenches[0][k],
                   options.bearing_offset.get(name, 0.0)))
        out[name] = tuple(unit_bound(unit, trajectory.dt, at_rest(qd[:, j], qdd[:, j]), qd[:, j],
                                     tau0, tau1, stop0, stop1, options, cubic=cubic,
                                     t=trajectory.t, qdd=qdd[:, j], wrench=wrench)
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
