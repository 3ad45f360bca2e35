"""Co-design: the shortest cycle a choice of gearheads allows, and every ratio compared on it.

`fastest` runs the motion's path as fast as the units allow, in three steps:

1. TOPPRA under every limit that holds sample by sample (`hdselect.codesign.fastpath`,
   `hdselect.codesign.pathbounds`): the motion's and the robot file's speeds, the units' maximum
   input speeds over their ratios, the motion's accelerations, the units'
   repeated-peak torques (through the dynamics, payload and carried gearheads
   included), the emergency stop and the crash. Any trajectory that passes the rules
   meets these, so this cycle, the `optimum`, is the shortest possible to the grid's
   resolution.
2. The rules over the whole cycle (mean torque, life, average input speed) are
   checked on it; where one fails, the cycle is lengthened by the smallest exact
   slow-down, or by derating the failing joints' torque limits, whichever is shorter
   (`hdselect.codesign.cyclerules`). A pure bang-bang move gives the same answer both ways
   (both run it at the mean-torque allowance); a move that cruises is faster derated.
3. The trajectory is sampled on the motion's time grid and checked by
   `hdselect.sizing.core.check_units`, the sizing's own path, and slowed by any excess.

`compare_ratios` does this for every catalog unit on each joint, the others fixed,
sharing one path and its dynamics (a unit's mass changes the torque coefficients
linearly, so no unit needs new dynamics passes on the path).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError, PlanningError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import Candidate
from hdselect.catalog.select import DEFAULT_PREFER_WITH_MOTORS, select
from hdselect.catalog.units import Unit
from hdselect.codesign.bindings import Binding, bindings
from hdselect.codesign.cyclerules import derated, run_trial, verified
from hdselect.codesign.fastpath import PathModel
from hdselect.codesign.pathbounds import JointLimits, PathInfeasible, joint_limits
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, check_within_limits, plan
from hdselect.motion.solve import solve_motion
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import checked_motors, fixed_units, not_sized, units_argument
from hdselect.sizing.core import motion_motors, size_trajectory
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.result import Motors, SizingResult

OPTIMAL_WITHIN = 1e-3
"""A cycle at most this fraction longer than the optimum counts as the optimum: the
slow-down that corrects TOPPRA's overshoot between gridpoints is of this order [-]."""
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
        motors: The motor behind the unit of each joint that has one (its peak torque,
            speed and rotor inertia bound the path; its rules are checked).
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
    motors: Mapping[str, Motor] = field(default_factory=dict)

    @property
    def cycle_time(self) -> float:
        """The cycle time, dwells included [s]."""
        return self.trajectory.duration

    @property
    def feasible(self) -> bool:
        """Every rule of every joint passes on the trajectory."""
        return self.check.feasible

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the robot and motion files raised, and robot-file limits the cycle exceeds.

        As `hdselect.sizing.core.SizingResult.warnings`: each line starts with ``robot file:``,
        ``motion file:`` or ``cycle:``.
        """
        return replace(self.check, motion=self.motion).warnings

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
            catalog: Sequence[Unit] | None = None,
            motors: Motors | None = None) -> FastestResult:
    """The shortest cycle of the motion's path that the units allow, every rule passing.

    Args:
        robot: The robot as the motion runs it (`hdselect.load_case`).
        motion: A motion with waypoints (a Ruckig or TOPPRA motion, not a log).
        units: Unit (or unit id) per sized joint; joints not given get the unit
            `hdselect.size_trajectory` selects for the motion as planned.
        options: The assumptions (default: `options_for(motion)`).
        catalog: Units to resolve ids and defaults from (default: the built-in catalog).
        motors: Candidate motors per sized joint (a `Motor` is a fixed one); None takes
            the motion file's ``[motor]``. A joint with several gets the motor the sizing
            pairs with its unit. The motor's peak torque (through the ratio, with the
            reflected inertia (J_in + J_m) N qdd) and maximum speed bound the path, and
            its rules are checked on the result.

    Returns:
        The fastest trajectory, its check and what bounds it.

    Raises:
        InputError: The motion is a log, or a joint, unit id or motor is unknown or
            invalid.
        PlanningError: The path cannot be run with these units at any speed (the
            message names the joint, the limit and where), or TOPPRA fails.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(motion, (Motion,), "motion", "a Motion (hdselect.load_case)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    _refuse_log(motion)
    motion = solve_motion(robot, motion)
    options = options if options is not None else options_for(motion)
    catalog = units_argument(catalog) if catalog is not None else load_catalog()
    chosen, _, paired = resolve_case(robot, motion, units, catalog, options, selection=False,
                                     motors=motors)
    model = PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
    return _fastest(model, chosen, options, paired)


def compare_ratios(robot: Robot, motion: Motion, units: Mapping[str, Unit | str] | None = None,
                   options: Options | None = None, *, catalog: Sequence[Unit] | None = None,
                   joints: Sequence[str] | None = None,
                   motors: Motors | None = None) -> RatioComparison:
    """The shortest cycle with each catalog unit on each joint, the other joints' units fixed.

    Args:
        robot: The robot as the motion runs it.
        motion: A motion with waypoints.
        units: Units the other joints keep (defaults as in `fastest`).
        options: The assumptions (default: `options_for(motion)`).
        catalog: The units compared (default: the built-in catalog).
        joints: The joints compared (default: every sized joint).
        motors: Candidate motors per sized joint, as `fastest` takes them; each joint
            keeps its motor whatever unit it is compared with.

    Returns:
        One row per unit and joint.

    Raises:
        InputError: The motion is a log, or a joint or unit id is unknown.
        PlanningError: The units given cannot run the path at all.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(motion, (Motion,), "motion", "a Motion (hdselect.load_case)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    _refuse_log(motion)
    motion = solve_motion(robot, motion)
    options = options if options is not None else options_for(motion)
    catalog = units_argument(catalog) if catalog is not None else load_catalog()
    chosen, selected, paired = resolve_case(robot, motion, units, catalog, options,
                                            motors=motors)
    names = list(robot.sized_joints)
    if joints is not None and (isinstance(joints, str) or not isinstance(joints, Sequence)
                               or not all(isinstance(name, str) for name in joints)):
        raise InputError(f"expected a list of joint names, got {joints!r}", field="joints")
    for name in joints or ():
        if name not in names:
            raise not_sized(robot, name, "joint")
    model = PathModel.build(robot, motion, robot.sized_joints, threads=options.threads)
    base = _fastest(model, chosen, options, paired)
    out = []
    for name in joints or names:
        rows = []
        for unit in catalog:
            if unit is chosen[name]:
                rows.append(_row(unit, base))
                continue
            try:
                rows.append(_row(unit, _fastest(model, {**chosen, name: unit}, options,
                                                paired)))
            except PathInfeasible as err:
                rows.append(RatioRow(unit, None, None, err.gravity, _short(err), None))
        out.append(JointRatios(name, selected.get(name), tuple(rows)))
    return RatioComparison(robot, motion, chosen, options, tuple(out), base)


def resolve_units(robot: Robot, motion: Motion, given: Mapping[str, Unit | str] | None,
                  catalog: Sequence[Unit], options: Options, *,
                  selection: bool = True, trajectory: Trajectory | None = None
                  ) -> tuple[dict[str, Unit], dict[str, str]]:
    """The unit of every sized joint: those given, the sizing's selection for the others.

    As `resolve_case`, with the motion file's motors; without the motors chosen.

    Raises:
        InputError: As `resolve_case`; the motion is a log (it has no path to run faster).
    """
    _refuse_log(motion)
    chosen, selected, _ = resolve_case(robot, motion, given, catalog, options,
                                       selection=selection, trajectory=trajectory)
    return chosen, selected


def resolve_case(robot: Robot, motion: Motion, given: Mapping[str, Unit | str] | None,
                 catalog: Sequence[Unit], options: Options, *,
                 selection: bool = True, trajectory: Trajectory | None = None,
                 motors: Motors | None = None
                 ) -> tuple[dict[str, Unit], dict[str, str], dict[str, Motor]]:
    """The unit (and motor) of every sized joint: those given, the sizing's for the others.

    Args:
        robot: The robot as the motion runs it.
        motion: The motion (planned with its own planner for the selection).
        given: Unit or unit id per joint.
        catalog: The units ids refer to, and the sizing chooses from.
        options: The assumptions of the sizing.
        selection: Size the motion even when every joint has a unit and one motor given.
        trajectory: The trajectory the selection sizes (default: the motion as planned;
            a study gives it run s times slower).
        motors: Candidate motors per joint; None takes the motion file's ``[motor]``.

    Returns:
        The unit per sized joint; the unit id the sizing selects per joint (where one
        fits; else the one that fits with the smallest slow-down; empty when the motion
        was not sized); the motor per joint that has motors: the only one given, else
        the one the sizing pairs with the joint's unit (the pair it selects, else the one
        closest to passing).

    Raises:
        InputError: A name is not a sized joint, or an id is unknown.
        PlanningError: No unit can run a joint not given, at any speed.
    """
    chosen = fixed_units(given, catalog, robot)
    by_id = {unit.id: unit for unit in catalog}
    candidates = checked_motors(robot, motion_motors(robot, motion) if motors is None
                                else motors, options)
    single = all(len(found) == 1 for found in candidates.values())
    if not selection and single and all(name in chosen for name in robot.sized_joints):
        return chosen, {}, {name: found[0] for name, found in candidates.items()}
    sized = (trajectory if trajectory is not None
             else plan(robot, motion, max_samples=options.max_samples))
    sizing = size_trajectory(robot, sized, catalog, options, motors=candidates)
    selected: dict[str, str] = {}
    paired: dict[str, Motor] = {}
    for joint in sizing.joints:
        pick = joint.selected.unit.id if joint.selected is not None else (
            joint.slowdown.unit.split(" + ")[0]
            if joint.slowdown is not None and joint.slowdown.unit is not None else None)
        if pick is not None:  # a slow-down names a pair "UNIT + MOTOR"
            selected[joint.name] = pick
        if joint.name not in chosen:
            if pick is None:
                raise PlanningError(f"{motion.path}: {no_unit_at_any_speed(joint.name)}")
            chosen[joint.name] = by_id[pick]
        if joint.name in candidates:
            paired[joint.name] = _paired_motor(joint.candidates, chosen[joint.name],
                                               candidates[joint.name], sizing.options)
    return chosen, selected, paired


def no_unit_at_any_speed(joint: str, over: str = "this motion") -> str:
    """The refusal for a joint no catalog unit can run, slowed or not, with what helps."""
    return (f"no unit of the catalog can run joint '{joint}' on {over} at any speed "
            f"(hdselect size says how close each comes); leave it out with --exclude {joint}, "
            "or give a catalog with a stronger unit (--catalog)")


def _refuse_log(motion: Motion) -> None:
    """A logged trajectory has no path to run faster: refused, naming its planner."""
    if motion.planner == "samples":
        raise InputError("a logged trajectory ('samples') has no path to run faster; give "
                         "a motion with waypoints", path=motion.path, field="planner")


def _paired_motor(pairs: Sequence[Candidate], unit: Unit, motors: Sequence[Motor],
                  options: Options) -> Motor:
    """The motor for `unit`: the only one, the pair the selection order picks, or the closest."""
    if len(motors) == 1:
        return motors[0]
    mine = [pair for pair in pairs if pair.unit.id == unit.id and pair.motor_unit is not None]
    best = select(mine, options.prefer or DEFAULT_PREFER_WITH_MOTORS)
    if best is None:
        best = min(mine, key=lambda pair: max(c.utilization for c in pair.checks.values()))
    if best.motor_unit is None:
        raise RuntimeError(f"{unit.id}: the best pair has no motor")
    return best.motor_unit


def _fastest(model: PathModel, units: Mapping[str, Unit], options: Options,
             motors: Mapping[str, Motor] | None = None) -> FastestResult:
    """Steps 1 to 3 of the module's method for one choice of units (and motors)."""
    robot = model.robot
    motors = dict(motors or {})
    masses = ({name: unit.mass + (motors[name].mass if name in motors else options.motor_mass)
               for name, unit in units.items()} if options.mass_coupling else {})
    carrying = robot.with_gearheads(masses)
    first = run_trial(model, carrying, units, masses, {}, options, motors)
    best = first
    if first.whole_cycle_failing:
        best = derated(model, carrying, units, masses, first, options, motors)
    limits = joint_limits(robot, model.motion, units, options, best.derating, motors=motors)
    trajectory, held, check, scale = verified(model, units, best, options, motors)
    check_within_limits(robot, model.motion, trajectory, what="fastest")  # as plan does
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
        reason=reason, binding=bindings(model, best, scale, check, held,
                                        joint_limits(robot, model.motion, units, options,
                                                     motors=motors)),
        grid_per_waypoint=model.grid_per_waypoint, motors=motors)


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
