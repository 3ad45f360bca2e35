"""Co-design: the shortest cycle a choice of gearheads allows, and every ratio compared on it.

`fastest` runs the motion's path as fast as the units allow, in three steps:

1. TOPPRA under every limit that holds sample by sample (`hdselect.fastpath`): the
   motion's and the URDF's speeds, the units' maximum input speeds over their
   ratios, the motion's accelerations, the units' repeated-peak torques (through
   the dynamics, payload and carried gearheads included), the emergency stop and
   the crash. Any trajectory that passes the rules meets these, so this cycle, the
   `optimum`, is the shortest possible to the grid's resolution.
2. The rules over the whole cycle (mean torque, life, average input speed) are then
   checked on it. Where one fails, the smallest uniform slow-down s of the moves
   (dwells keep their length) at which every rule of every joint passes is found
   with the exact time scaling of `hdselect.timescale`: the rules on single samples
   exactly, the whole-cycle rules with `hdselect.rules.check_unit` itself on 1 %
   steps, bisected to 1e-6. Derating instead the repeated-peak limits of the joints
   that failed (lambda = 0.9, 0.8, ... of the limit, re-solved by TOPPRA, each again
   with its smallest slow-down) keeps the moves at full speed while the torque
   drops; the derating with the shortest cycle is refined by golden section to
   within 0.01. A pure bang-bang move gives the same answer both ways (both run it
   at the mean-torque allowance); a move that cruises is faster derated.
3. The trajectory is sampled on the motion's time grid and checked by
   `hdselect.sizing.check_units`, the sizing's own path. Where the samples land on a
   peak the scaled model missed, the slow-down grows by the excess until every rule
   passes (with a margin of `WRITTEN_MARGIN` for the digits written to a file).

`compare_ratios` does this for every catalog unit on each joint, the others fixed,
sharing one path and its dynamics (a unit's mass changes the torque coefficients
linearly, so no unit needs new dynamics passes on the path).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from hdselect.catalog import Unit, load_catalog
from hdselect.dynamics import cycle_torques
from hdselect.errors import InputError, PlanningError
from hdselect.fastpath import (
    JointLimits,
    PathInfeasible,
    PathModel,
    cycle,
    kinematic_scales,
    solve,
)
from hdselect.motion import Motion
from hdselect.options import Options, options_for
from hdselect.planning import Trajectory, plan
from hdselect.planning.toppra import Profile
from hdselect.reflect import reflect
from hdselect.robot import Robot
from hdselect.rules import RPM_PER_RAD_S, Candidate, check_unit, cycle_load
from hdselect.sizing import SizingResult, at_rest, check_units, size_trajectory
from hdselect.timescale import S_MAX, ScalableCycle, exact_scales

WHOLE_CYCLE_RULES = ("mean", "life", "average_speed")
"""Rules on the whole cycle: a slow-down or a derating fixes them, TOPPRA cannot."""
DERATINGS = (0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3)
"""Fractions of the repeated-peak limit tried, until the cycle stops getting shorter."""
DERATING_RESOLUTION = 0.01
"""Width to which the best derating is refined [-]."""
SCALE_STEP = 1.01
"""Step of the search for the smallest slow-down, before bisection [-]."""
SCALE_RTOL = 1e-6
"""Relative accuracy of the slow-down [-]."""
WRITTEN_MARGIN = 1e-7
"""Utilization a rule that scales with speed must stay below 1 by, so that the
trajectory written with 10 significant digits passes too [-]."""
OPTIMAL_WITHIN = 1e-3
"""A cycle at most this fraction longer than the optimum counts as the optimum: the
slow-down that corrects TOPPRA's overshoot between gridpoints is of this order [-]."""
_VERIFY_ROUNDS = 12


@dataclass(frozen=True)
class Binding:
    """A stretch of the cycle during which one limit of one joint is the closest to its bound.

    Attributes:
        start: Start of the stretch [s].
        end: End of the stretch [s].
        joint: The joint.
        limit: The limit: ``"velocity (motion file)"``, ``"velocity (URDF)"``, ``"max input
            speed"``, ``"acceleration"``, ``"torque"``, ``"emergency stop"`` or ``"crash"``.
        utilization: The largest demand / limit over the stretch [-] (torque: against
            the undearated repeated-peak limit).
        waypoints: The waypoints between which the stretch starts.
    """

    start: float
    end: float
    joint: str
    limit: str
    utilization: float
    waypoints: tuple[int, int]


@dataclass(frozen=True, eq=False)
class FastestResult:
    """The shortest cycle of a motion's path that a choice of units allows.

    Attributes:
        robot: The robot (payload and mounting applied, no gearhead masses).
        motion: The motion whose path was run.
        units: The unit of every sized joint.
        options: The assumptions.
        trajectory: The trajectory, sampled every ``motion.dt``.
        check: Every rule of every joint's unit on that trajectory (`check_units`).
        limits: What bounded each joint along the path, by joint name.
        optimum: The time-optimal cycle under the limits on single samples, before any
            slow-down or derating [s].
        slowdown: The uniform slow-down of the moves beyond TOPPRA's own overshoot
            correction [-]; 1 when none was needed.
        derating: Fraction of its repeated-peak limit each derated joint was held to [-].
        reason: What made the cycle longer than `optimum` (by more than `OPTIMAL_WITHIN`):
            ``(joint, rule)``, or None.
        binding: Which limit is closest to its bound along the moves, stretch by stretch.
        grid_per_waypoint: TOPPRA gridpoints per waypoint.
    """

    robot: Robot
    motion: Motion
    units: Mapping[str, Unit]
    options: Options
    trajectory: Trajectory
    check: SizingResult
    limits: Mapping[str, JointLimits]
    optimum: float
    slowdown: float
    derating: Mapping[str, float]
    reason: tuple[str, str] | None
    binding: tuple[Binding, ...]
    grid_per_waypoint: int

    @property
    def cycle_time(self) -> float:
        """The cycle time, dwells included [s]."""
        return self.trajectory.duration

    @property
    def feasible(self) -> bool:
        """Every rule of every joint passes on the trajectory."""
        return self.check.feasible

    def binding_shares(self) -> list[tuple[str, str, float]]:
        """(joint, limit, share of the moving time) [-], longest first."""
        total: dict[tuple[str, str], float] = {}
        for b in self.binding:
            total[(b.joint, b.limit)] = total.get((b.joint, b.limit), 0.0) + b.end - b.start
        moving = sum(total.values()) or 1.0
        return sorted(((j, lim, t / moving) for (j, lim), t in total.items()),
                      key=lambda item: -item[2])


@dataclass(frozen=True)
class RatioRow:
    """One unit on one joint, the other joints' units fixed.

    Attributes:
        unit: The unit.
        cycle_time: The shortest cycle [s]; None when the units cannot run the path.
        optimum: The time-optimal cycle under the limits on single samples [s], or None.
        gravity: The units cannot run the path at any speed because a load that does not
            depend on the speed (gravity, held at rest or moving) is beyond a limit.
        note: Why there is no cycle, or what lengthened it beyond `optimum`, in a few words.
        binding: The limit that binds longest, ``(joint, limit)``, or None.
        lengthened_by: The ``(joint, rule)`` that lengthened the cycle, or None.
        derating: The fraction of its repeated-peak limit the derated joint kept [-].
        slowdown: The uniform slow-down of the moves [-].
    """

    unit: Unit
    cycle_time: float | None
    optimum: float | None
    gravity: bool
    note: str | None
    binding: tuple[str, str] | None
    lengthened_by: tuple[str, str] | None = None
    derating: float | None = None
    slowdown: float = 1.0


@dataclass(frozen=True)
class JointRatios:
    """Every catalog unit on one joint.

    Attributes:
        joint: The joint.
        selected: The unit `hdselect.size` picks for the motion as planned, or None.
        rows: One per unit, in catalog order.
    """

    joint: str
    selected: str | None
    rows: tuple[RatioRow, ...]


@dataclass(frozen=True, eq=False)
class RatioComparison:
    """The shortest cycle with each unit on each joint compared.

    Attributes:
        robot: The robot (payload and mounting applied).
        motion: The motion whose path was run.
        units: The units the other joints keep.
        options: The assumptions.
        joints: One comparison per joint compared.
        base: The fastest cycle with `units` everywhere.
    """

    robot: Robot
    motion: Motion
    units: Mapping[str, Unit]
    options: Options
    joints: tuple[JointRatios, ...]
    base: FastestResult = field(repr=False)


def fastest(robot: Robot, motion: Motion, units: Mapping[str, Unit | str] | None = None,
            options: Options | None = None, *,
            catalog: Sequence[Unit] | None = None) -> FastestResult:
    """The shortest cycle of the motion's path that the units allow, every rule passing.

    Args:
        robot: The robot as the motion runs it (`hdselect.load_case`).
        motion: A motion with waypoints (a Ruckig or TOPPRA motion, not a log).
        units: Unit (or unit id) per sized joint; joints not given get the unit
            `hdselect.size_trajectory` selects for the motion as planned.
        options: The assumptions (default: `options_for(motion)`).
        catalog: Units to resolve ids and defaults from (default: the built-in catalog).

    Returns:
        The fastest trajectory, its check and what bounds it.

    Raises:
        InputError: The motion is a log, or a joint or unit id is unknown.
        PlanningError: The path cannot be run with these units at any speed (the
            message names the joint, the limit and where), or TOPPRA fails.
    """
    options = options if options is not None else options_for(motion)
    catalog = tuple(catalog) if catalog is not None else load_catalog()
    chosen, _ = resolve_units(robot, motion, units, catalog, options, selection=False)
    model = PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
    return _fastest(model, chosen, options)


def compare_ratios(robot: Robot, motion: Motion, units: Mapping[str, Unit | str] | None = None,
                   options: Options | None = None, *, catalog: Sequence[Unit] | None = None,
                   joints: Sequence[str] | None = None) -> RatioComparison:
    """The shortest cycle with each catalog unit on each joint, the other joints' units fixed.

    Args:
        robot: The robot as the motion runs it.
        motion: A motion with waypoints.
        units: Units the other joints keep (defaults as in `fastest`).
        options: The assumptions (default: `options_for(motion)`).
        catalog: The units compared (default: the built-in catalog).
        joints: The joints compared (default: every sized joint).

    Returns:
        One row per unit and joint.

    Raises:
        InputError: The motion is a log, or a joint or unit id is unknown.
        PlanningError: The units given cannot run the path at all.
    """
    options = options if options is not None else options_for(motion)
    catalog = tuple(catalog) if catalog is not None else load_catalog()
    chosen, selected = resolve_units(robot, motion, units, catalog, options)
    names = list(robot.sized_joints)
    for name in joints or ():
        if name not in names:
            raise InputError(f"unknown joint '{name}'; sized joints are: {', '.join(names)}",
                             field="joint")
    model = PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
    base = _fastest(model, chosen, options)
    out = []
    for name in joints or names:
        rows = []
        for unit in catalog:
            if unit is chosen[name]:
                rows.append(_row(unit, base))
                continue
            try:
                rows.append(_row(unit, _fastest(model, {**chosen, name: unit}, options)))
            except PathInfeasible as err:
                rows.append(RatioRow(unit, None, None, err.gravity, _short(err), None))
        out.append(JointRatios(name, selected.get(name), tuple(rows)))
    return RatioComparison(robot, motion, chosen, options, tuple(out), base)


def resolve_units(robot: Robot, motion: Motion, given: Mapping[str, Unit | str] | None,
                  catalog: Sequence[Unit], options: Options, *,
                  selection: bool = True) -> tuple[dict[str, Unit], dict[str, str]]:
    """The unit of every sized joint: those given, the sizing's selection for the others.

    Args:
        robot: The robot as the motion runs it.
        motion: The motion (planned with its own planner for the selection).
        given: Unit or unit id per joint.
        catalog: The units ids refer to, and the sizing chooses from.
        options: The assumptions of the sizing.
        selection: Size the motion even when every joint has a unit given.

    Returns:
        The unit per sized joint, and the unit id the sizing selects per joint (where
        one fits; else the one that fits with the smallest slow-down; empty when the
        motion was not sized).

    Raises:
        InputError: The motion is a log, a name is not a sized joint, or an id is unknown.
        PlanningError: No unit can run a joint not given, at any speed.
    """
    if motion.planner == "samples":
        raise InputError("a logged trajectory ('samples') has no path to run faster; give "
                         "a motion with waypoints", path=motion.path, field="planner")
    by_id = {unit.id: unit for unit in catalog}
    chosen: dict[str, Unit] = {}
    for name, unit in (given or {}).items():
        if name not in robot.sized_joints:
            raise InputError(f"unknown joint '{name}'; sized joints are: "
                             f"{', '.join(robot.sized_joints)}", field="units")
        if isinstance(unit, str):
            if unit not in by_id:
                raise InputError(f"unknown unit '{unit}' for joint '{name}'; units are: "
                                 f"{', '.join(by_id)}", field="units")
            unit = by_id[unit]
        chosen[name] = unit
    if not selection and all(name in chosen for name in robot.sized_joints):
        return chosen, {}
    sizing = size_trajectory(robot, plan(robot, motion), catalog, options)
    selected: dict[str, str] = {}
    for joint in sizing.joints:
        pick = joint.selected.unit.id if joint.selected is not None else (
            joint.slowdown.unit if joint.slowdown is not None else None)
        if pick is not None:
            selected[joint.name] = pick
        if joint.name not in chosen:
            if pick is None:
                raise PlanningError(f"{motion.path}: no unit can run joint '{joint.name}' on "
                                    "this motion at any speed; give one with --units")
            chosen[joint.name] = by_id[pick]
    return chosen, selected


@dataclass(frozen=True, eq=False)
class _Trial:
    """TOPPRA's profiles for one derating, and the smallest slow-down that passes."""

    derating: Mapping[str, float]
    profiles: list[Profile | None]
    kinematic: list[float]
    moving: float
    dwell: float
    scale: float
    reason: tuple[str, str] | None
    whole_cycle_failing: tuple[str, ...] = ()

    @property
    def cycle_time(self) -> float:
        return self.moving * self.scale + self.dwell


def _fastest(model: PathModel, units: Mapping[str, Unit], options: Options) -> FastestResult:
    """Steps 1 to 3 of the module's method for one choice of units."""
    robot = model.robot
    masses = ({name: unit.mass + options.motor_mass for name, unit in units.items()}
              if options.mass_coupling else {})
    carrying = robot.with_gearheads(masses)
    first = _trial(model, carrying, units, masses, {}, options)
    best = first
    if first.whole_cycle_failing:
        best = _derated(model, carrying, units, masses, first, options)
    limits = joint_limits(robot, model.motion, units, options, best.derating)
    trajectory, held, check, scale = _verified(model, units, best, options)
    slowdown = scale
    optimum = first.moving + first.dwell
    reason = None
    if trajectory.duration > optimum * (1.0 + OPTIMAL_WITHIN):
        reason = first.reason if best is not first else best.reason
    return FastestResult(
        robot=robot, motion=model.motion, units=dict(units), options=options,
        trajectory=trajectory, check=check,
        limits=dict(zip(robot.joint_names, limits, strict=True)),
        optimum=optimum, slowdown=slowdown, derating=dict(best.derating),
        reason=reason, binding=_bindings(model, best, scale, check, held, limits, units),
        grid_per_waypoint=model.grid_per_waypoint)


def joint_limits(robot: Robot, motion: Motion, units: Mapping[str, Unit], options: Options,
                 derating: Mapping[str, float] | None = None) -> list[JointLimits]:
    """What bounds each joint of the robot along the path, in the robot's joint order.

    Args:
        robot: The robot (its URDF velocity limits).
        motion: The motion (its velocity, acceleration and torque limits).
        units: The unit of every sized joint.
        options: Stop time and motor rotor inertia.
        derating: Fraction of the repeated-peak limit per joint (default none) [-].
    """
    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    assert velocity is not None and acceleration is not None  # waypoint planners require them
    out = []
    for j, name in enumerate(robot.joint_names):
        speeds = [(float(velocity[j]), "motion")]
        urdf = float(robot.velocity_limit[j])
        if math.isfinite(urdf) and urdf > 0.0:
            speeds.append((urdf, "robot"))
        torque = math.inf if motion.torque_limit is None else float(motion.torque_limit[j])
        static, momentary, gain = torque, math.inf, 0.0
        unit = units.get(name)
        if unit is not None:
            speeds.append((unit.max_input_speed / unit.ratio / RPM_PER_RAD_S, "unit"))
            torque = min(torque, unit.repeated_torque * (derating or {}).get(name, 1.0))
            static = min(static, unit.static_torque)
            momentary = unit.momentary_torque
            gain = (unit.input_inertia + options.rotor_inertia) * unit.ratio**2 / options.stop_time
        limit, source = min(speeds)
        out.append(JointLimits(limit, source, float(acceleration[j]), torque, static,
                               momentary, gain))
    return out


def _trial(model: PathModel, carrying: Robot, units: Mapping[str, Unit],
           masses: Mapping[str, float], derating: Mapping[str, float],
           options: Options) -> _Trial:
    """Solve TOPPRA at one derating and find the smallest slow-down at which all passes."""
    motion = model.motion
    limits = joint_limits(model.robot, motion, units, options, derating)
    profiles = solve(model, limits, masses, stop_time=options.stop_time)
    kinematic = kinematic_scales(profiles, limits)
    trajectory, held = cycle(motion, profiles, kinematic)
    moving = sum(p.duration * r for p, r in zip(profiles, kinematic, strict=True)
                 if p is not None)
    cycles, held = _scalable(carrying, trajectory, held, units, options)
    scale, reason = _smallest_scale(cycles, held, units, options, motion)
    failing = {name for name, cycle_ in cycles.items()
               if any(not c.ok for rule, c in _check_scaled(cycle_, held, units[name], 1.0,
                                                             options).checks.items()
                      if rule in WHOLE_CYCLE_RULES)}
    return _Trial(dict(derating), profiles, kinematic, moving,
                  trajectory.duration - moving, scale, reason, tuple(sorted(failing)))


def _scalable(carrying: Robot, trajectory: Trajectory, held: np.ndarray,
              units: Mapping[str, Unit],
              options: Options) -> tuple[dict[str, ScalableCycle], np.ndarray]:
    """Each sized joint's cycle split by how its torque scales with time (four passes).

    A dwell holds one pose at rest: it is kept as one sample that lasts the whole
    dwell, which every rule weighs alike (the motor's RMS torque, which assumes equal
    samples, is not a rule).

    Returns:
        The cycles by joint, and which of their samples are dwells.
    """
    keep = np.flatnonzero(~held | np.r_[True, ~held[:-1]])
    lasts = np.diff(np.r_[keep, len(held)]) * trajectory.dt
    q, qd, qdd = trajectory.q[keep], trajectory.qd[keep], trajectory.qdd[keep]
    dt = np.where(held[keep], lasts, trajectory.dt)
    torques = cycle_torques(carrying, q, qd, qdd, options.stop_time, split=True,
                            threads=options.threads)
    assert torques.gravity is not None and torques.coasting is not None
    out = {}
    for name in units:
        j = carrying.joint_index(name)
        out[name] = ScalableCycle.split(
            trajectory.t[keep], dt, trajectory.duration, qd[:, j], qdd[:, j],
            at_rest(qd[:, j], qdd[:, j]), torque=torques.tau[:, j],
            stop_torque=torques.stop[:, j], gravity=torques.gravity[:, j],
            coast=torques.coasting[:, j], stop_time=options.stop_time)
    return out, held[keep]


def _check_scaled(cycle_: ScalableCycle, held: np.ndarray, unit: Unit, s: float,
                  options: Options) -> Candidate:
    """Every rule of `check_unit` on a joint's cycle with its moves run s times slower [-].

    As `hdselect.timescale.check_at`, except that dwells keep their length.
    """
    at = cycle_.at(s)
    dt = np.where(held, cycle_.dt, at.dt)
    load = cycle_load(at.torque, at.qd, dt, at.at_rest)
    (reflection,) = reflect([unit], at.t, at.torque, at.qd, at.qdd, at.stop_torque,
                            stop_time=cycle_.stop_time, efficiency=options.efficiency,
                            rotor_inertia=options.rotor_inertia)
    return check_unit(load, unit, momentary=reflection.momentary, motor=reflection.motor,
                      life_hours=options.life_hours, life_basis=options.life_basis)


def _failing(cycles: Mapping[str, ScalableCycle], held: np.ndarray,
             units: Mapping[str, Unit], options: Options, s: float) -> tuple[str, str] | None:
    """The (joint, rule) that fails worst at scale s [-], or None when all pass."""
    worst: tuple[float, str, str] | None = None
    for name, cycle_ in cycles.items():
        candidate = _check_scaled(cycle_, held, units[name], s, options)
        if not candidate.feasible:
            rule = candidate.binding
            utilization = candidate.checks[rule].utilization
            if worst is None or utilization > worst[0]:
                worst = (utilization, name, rule)
    return None if worst is None else (worst[1], worst[2])


def _smallest_scale(cycles: Mapping[str, ScalableCycle], held: np.ndarray,
                    units: Mapping[str, Unit], options: Options,
                    motion: Motion) -> tuple[float, tuple[str, str] | None]:
    """The smallest s >= 1 [-] at which every joint passes every rule, and what set it.

    The rules on single samples give exact intervals of s (`exact_scales`); inside
    them the whole-cycle rules are checked on steps of `SCALE_STEP` (20 % beyond
    s = 2) and the first pass is bisected to `SCALE_RTOL`.

    Returns:
        s, and the (joint, rule) failing just below it (None when s = 1).

    Raises:
        PathInfeasible: No s from 1 to `S_MAX` passes.
    """
    feasible: list[tuple[float, float]] = [(1.0, S_MAX)]
    for name, cycle_ in cycles.items():
        feasible = _intersect(feasible, list(exact_scales(
            cycle_, units[name], rotor_inertia=options.rotor_inertia)))
        if not feasible:
            failing = _failing({name: cycle_}, held, units, options, S_MAX)
            raise _hopeless(motion, name, failing[1] if failing else "peak", units[name])

    def fails(s: float) -> tuple[str, str] | None:
        return _failing(cycles, held, units, options, s)

    for lo, hi in feasible:
        below: float | None = None
        s = lo
        while True:
            if fails(s) is None:
                if below is None:
                    return s, (fails(s / (1.0 + 1e-3)) if s > 1.0 else None)
                low, high = below, s
                while high > low * (1.0 + SCALE_RTOL):
                    middle = math.sqrt(low * high)
                    low, high = (middle, high) if fails(middle) else (low, middle)
                return high, fails(low)
            below = s
            if s >= hi:
                break
            s = min(hi, s * (SCALE_STEP if s < 2.0 else 1.2))
    name, rule = fails(S_MAX) or (next(iter(cycles)), "mean")
    raise _hopeless(motion, name, rule, units[name])


def _hopeless(motion: Motion, joint: str, rule: str, unit: Unit) -> PathInfeasible:
    return PathInfeasible(f"{motion.path}: joint '{joint}' fails its {rule} rule with "
                          f"{unit.id} at every speed (from as fast as the limits allow to "
                          f"{S_MAX:g} times slower)", joint=joint, limit=rule,
                          gravity=rule in ("static", "peak", "momentary"))


def _intersect(a: list[tuple[float, float]],
               b: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Intersection of two sorted lists of disjoint closed intervals."""
    out = []
    for lo1, hi1 in a:
        for lo2, hi2 in b:
            lo, hi = max(lo1, lo2), min(hi1, hi2)
            if lo <= hi:
                out.append((lo, hi))
    return sorted(out)


def _derated(model: PathModel, carrying: Robot, units: Mapping[str, Unit],
             masses: Mapping[str, float], first: _Trial, options: Options) -> _Trial:
    """The derating of the failing joints' torque limits that gives the shortest cycle."""
    joints = first.whole_cycle_failing

    def attempt(fraction: float) -> _Trial | None:
        try:
            return _trial(model, carrying, units, masses, dict.fromkeys(joints, fraction),
                          options)
        except PathInfeasible:
            return None

    tried: dict[float, _Trial | None] = {1.0: first}
    best, previous = first, first.cycle_time
    for fraction in DERATINGS:
        found = tried[fraction] = attempt(fraction)
        if found is None or found.cycle_time > previous:
            break
        previous = found.cycle_time
        if found.cycle_time < best.cycle_time:
            best = found
    centre = max(best.derating.values(), default=1.0)
    lo, hi = max(centre - 0.1, 0.05), min(centre + 0.1, 1.0)
    golden = (math.sqrt(5.0) - 1.0) / 2.0

    def cycle_at(fraction: float) -> float:
        if fraction not in tried:
            tried[fraction] = attempt(fraction)
        found = tried[fraction]
        return math.inf if found is None else found.cycle_time

    x1, x2 = hi - golden * (hi - lo), lo + golden * (hi - lo)
    while hi - lo > DERATING_RESOLUTION:
        if cycle_at(x1) <= cycle_at(x2):
            hi, x2 = x2, x1
            x1 = hi - golden * (hi - lo)
        else:
            lo, x1 = x1, x2
            x2 = lo + golden * (hi - lo)
    for found in tried.values():
        if found is not None and found.cycle_time < best.cycle_time:
            best = found
    return best


def _verified(model: PathModel, units: Mapping[str, Unit], trial: _Trial,
              options: Options) -> tuple[Trajectory, np.ndarray, SizingResult, float]:
    """The trajectory on the motion's grid and its check, slowed until every rule passes.

    Returns:
        The trajectory, its dwell samples, its check and the slow-down [-].
    """
    scale = trial.scale
    passing = None
    for _ in range(_VERIFY_ROUNDS):
        trajectory, held = cycle(model.motion, trial.profiles,
                                 [r * scale for r in trial.kinematic])
        check = check_units(model.robot, trajectory, units, options)
        candidates = [c for joint in check.joints for c in joint.candidates]
        excess = max((c.checks[rule].utilization for c in candidates for rule in c.checks
                      if rule != "static"), default=0.0)
        if check.feasible:
            passing = passing or (trajectory, held, check, scale)
            if excess <= 1.0 - WRITTEN_MARGIN:
                return trajectory, held, check, scale
        if any(not c.checks["static"].ok for c in candidates):
            break  # a held load: no speed helps
        scale *= max(math.sqrt(excess), 1.0 + 10.0 * WRITTEN_MARGIN)
    if passing is not None:  # at its limit to within the margin, whatever the speed
        return passing
    failing = [(joint.name, c.binding) for joint in check.joints for c in joint.candidates
               if not c.feasible]
    name, rule = failing[0] if failing else (next(iter(units)), "peak")
    raise _hopeless(model.motion, name, rule, units[name])


def _bindings(model: PathModel, trial: _Trial, scale: float, check: SizingResult,
              held: np.ndarray, limits: Sequence[JointLimits],
              units: Mapping[str, Unit]) -> tuple[Binding, ...]:
    """The limit closest to its bound at each moving sample, grouped into stretches."""
    trajectory = check.trajectory
    robot = model.robot
    names = list(robot.joint_names)
    labels = {"motion": "velocity (motion file)", "robot": "velocity (URDF)",
              "unit": "max input speed"}
    rows: list[tuple[str, str, np.ndarray]] = []
    for j, lim in enumerate(limits):
        name = names[j]
        rows.append((name, labels[lim.velocity_source], np.abs(trajectory.qd[:, j]) / lim.velocity))
        rows.append((name, "acceleration", np.abs(trajectory.qdd[:, j]) / lim.acceleration))
    for joint in check.joints:
        j = names.index(joint.name)
        lim, unit = limits[j], units[joint.name]
        rows.append((joint.name, "torque", np.abs(joint.torque) / unit.repeated_torque))
        rows.append((joint.name, "emergency stop", np.abs(joint.stop_torque) / lim.momentary))
        rows.append((joint.name, "crash", (np.abs(joint.torque) + lim.crash_gain
                                           * np.abs(trajectory.qd[:, j])) / lim.momentary))
    table = np.stack([r[2] for r in rows])
    moving = ~held
    best = np.argmax(table, axis=0)
    best[~moving] = -1
    times = trajectory.t
    dt = trajectory.dt
    stretches: list[list] = []
    for k in np.flatnonzero(moving):
        row = int(best[k])
        if stretches and stretches[-1][2] == row and stretches[-1][1] >= times[k] - 1.5 * dt:
            stretches[-1][1] = times[k] + dt
            stretches[-1][3] = max(stretches[-1][3], float(table[row, k]))
        else:
            stretches.append([float(times[k]), float(times[k] + dt), row, float(table[row, k])])
    total = sum(b - a for a, b, _, _ in stretches) or 1.0
    merged: list[list] = []
    for stretch in stretches:  # a stretch under 1 % of the moving time joins its neighbour
        joins = merged and merged[-1][1] >= stretch[0] - 1.5 * dt
        if joins and merged[-1][2] == stretch[2]:
            merged[-1][1], merged[-1][3] = stretch[1], max(merged[-1][3], stretch[3])
        elif joins and stretch[1] - stretch[0] < 0.01 * total:
            merged[-1][1] = stretch[1]
        elif joins and merged[-1][1] - merged[-1][0] < 0.01 * total:
            merged[-1][1:] = stretch[1:]
        else:
            merged.append(list(stretch))
    return tuple(Binding(float(a), float(b), rows[row][0], rows[row][1], float(peak),
                         _waypoints_at(model, trial, scale, (a + b) / 2.0))
                 for a, b, row, peak in merged)


def _waypoints_at(model: PathModel, trial: _Trial, scale: float,
                  time: float) -> tuple[int, int]:
    """The waypoints between which the path is at a time of the cycle [s]."""
    motion = model.motion
    clock = motion.dwells[0]
    for profile, r in zip(trial.profiles, trial.kinematic, strict=True):
        if profile is None:
            continue
        duration = profile.duration * r * scale
        if time < clock + duration:
            s = profile.path_state(np.array([max(time - clock, 0.0) / (r * scale)]))[0][0]
            return profile.piece.segment(float(s))
        clock += duration + motion.dwells[profile.piece.last]
    return len(motion.waypoints) - 2, len(motion.waypoints) - 1


def _row(unit: Unit, result: FastestResult) -> RatioRow:
    shares = result.binding_shares()
    derating = min(result.derating.values()) if result.derating else None
    note = None
    if result.reason is not None:
        how = [f"derated {derating:.0%}"] if derating is not None else []
        if result.slowdown > 1.0 + 1e-9:
            how.append(f"x{result.slowdown:.4f}")
        note = f"{result.reason[0]} {result.reason[1]}: {', '.join(how)}"
    return RatioRow(unit, result.cycle_time, result.optimum, False, note,
                    (shares[0][0], shares[0][1]) if shares else None, result.reason, derating,
                    result.slowdown)


def _short(err: PathInfeasible) -> str:
    """A few words for a table: who cannot do what."""
    if err.joint is None:
        return f"{err.limit} limits"
    if err.gravity:
        limit = "momentary" if err.limit == "emergency stop" else err.limit
        return f"gravity on {err.joint} > its {limit} limit"
    return f"{err.joint} {err.limit} fails at any speed"
