"""What a co-design case runs: its tasks, and the unit and motor of every sized joint.

A motion is a duty of one task (share 1); a mix file's tasks are planned with their own
payloads and mountings (`hdselect.sizing.mixtasks.mix_tasks`). The units not given, and the
motor of a joint with several candidates, are what the sizing selects for the duty as
planned (`hdselect.sizing.core.size_tasks`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import cast

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError, PlanningError
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import Candidate
from hdselect.catalog.select import DEFAULT_PREFER_WITH_MOTORS, select
from hdselect.catalog.units import Unit
from hdselect.codesign.pathbounds import PathInfeasible
from hdselect.codesign.payloadbounds import duty_bounds
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.option_specs import OPTION
from hdselect.motion.planning import Trajectory, plan
from hdselect.motion.planning.solve import solve_motion
from hdselect.robot.model import Robot
from hdselect.sizing.arguments import checked_motors, fixed_units
from hdselect.sizing.core import size_tasks
from hdselect.sizing.diagnosis import Diagnosis, diagnosis_of, with_diagnoses
from hdselect.sizing.options import WHOLE_ARM_TARGETS, Options
from hdselect.sizing.problem import Problem, file_motors, plan_tasks, problem_of
from hdselect.sizing.result import Motors, SizingResult
from hdselect.sizing.tasks import Task, task_of


class NoUnit(PlanningError):
    """No candidate unit can run a joint at any speed: a result of the physics, not bad input.

    The command line prints it as a result and exits 1 (no fit), as ``size`` does for a
    joint without a unit, with each such joint's diagnosis
    (`hdselect.sizing.diagnosis.Diagnosis`, the one ``size`` prints: `lines`). The
    message names the joints; the diagnoses are computed when first asked for.

    Attributes:
        where: The motion or mix file.
        over: The duty in words (``"this motion"``, ``"this mix"``).
        sizing: The selection that found no unit (every candidate checked).
        joints: The joints without a unit (none given for them), in the robot's order.
    """

    def __init__(self, where: str, over: str, sizing: SizingResult, names: Sequence[str]):
        self.where, self.over, self.sizing = where, over, sizing
        self.joints = tuple(joint.name for joint in sizing.joints if joint.name in names)
        self._diagnosed: dict[tuple[str, ...] | None, SizingResult] = {}
        super().__init__("\n".join(self._head(name) for name in self.joints))

    def diagnoses(self, command: Sequence[str] | None = None) -> dict[str, Diagnosis]:
        """Each joint without a unit: its diagnosis, the next steps verified.

        Args:
            command: The run's command line, program name first: each step's command is
                it with one option set; None gives ``hdselect size FILE ...``.
        """
        key = None if command is None else tuple(command)
        if key not in self._diagnosed:
            self._diagnosed[key] = with_diagnoses(self.sizing, payload_bounds=duty_bounds,
                                                  command=command)
        sizing = self._diagnosed[key]
        return {name: found for name in self.joints
                if (found := diagnosis_of(sizing, name)) is not None}

    def lines(self, command: Sequence[str] | None = None) -> list[str]:
        """What the command line prints: each joint named, then its diagnosis's sentences."""
        found = self.diagnoses(command)
        return [line for name in self.joints
                for line in [self._head(name), *(found[name].lines() if name in found else [])]]

    def _head(self, name: str) -> str:
        return f"{self.where}: no unit of the catalog can run joint '{name}' on {self.over} at " \
               "any speed."


def no_fit(err: BaseException) -> bool:
    """The error is a result, not bad input: no unit (of those given) runs a joint at any speed.

    `NoUnit`, or a `PathInfeasible` whose fault is the units' (or motors') limits rather
    than the motion's own velocity and acceleration limits.
    """
    return isinstance(err, NoUnit) or (isinstance(err, PathInfeasible)
                                       and err.limit != "velocity and acceleration")


@dataclass(frozen=True, eq=False)
class Duty:
    """A robot's tasks as co-design runs them: one motion, or a mix file's tasks.

    Attributes:
        where: The motion or mix file, as errors name it.
        robot: The robot with the duty's sized joints (a motion's: as it runs it).
        robots: Each counted task's robot (payload and mounting applied).
        motions: Each counted task's motion, tool poses solved.
        shares: Each counted task's share of the time [-].
        idle: The fraction of the time no task runs [-].
        mix: The mix, or None for one motion.
        planned: The counted tasks as planned (a mix's); empty for a motion, which is
            planned only where the sizing needs it (`tasks`).
        trajectory: One motion's trajectory as planned, where the problem had it.
        task: One motion's task as the problem planned it (its payload events on its own
            times: a study's run s times slower keeps them), where it had it.
    """

    where: str
    robot: Robot
    robots: tuple[Robot, ...]
    motions: tuple[Motion, ...]
    shares: tuple[float, ...]
    idle: float = 0.0
    mix: Mix | None = None
    planned: tuple[Task, ...] = ()
    trajectory: Trajectory | None = None
    task: Task | None = None

    @property
    def over(self) -> str:
        """What the duty is, in a refusal's words."""
        return "this mix" if self.mix is not None else "this motion"

    def tasks(self, options: Options, trajectory: Trajectory | None = None) -> tuple[Task, ...]:
        """The counted tasks as planned; a motion's `trajectory` replaces its plan."""
        if self.planned and trajectory is None:
            return self.planned
        if len(self.motions) != 1 or self.mix is not None:
            raise InputError("a trajectory replaces one motion's plan, not a mix's",
                             field="trajectory")
        if trajectory is None and self.task is not None:
            return (self.task,)
        robot, motion = self.robots[0], self.motions[0]
        given = trajectory if trajectory is not None else self.trajectory
        run = given if given is not None else plan(robot, motion, max_samples=options.max_samples)
        return (task_of(robot, run, motion),)


_KINDS: dict[str, tuple[tuple[type, ...], str]] = {
    "units": ((Mapping,), "a mapping of joint names to units or unit ids"),
    "options": ((Options,), "an Options"),
    "catalog": ((Sequence,), "catalog files or the units of a loaded catalog"),
    "motors": ((Mapping,), "a mapping of joint names to motors"),
    "joints": ((Sequence,), "a list of joint names"),
    "frame": ((str,), "a link name"),
    "com": ((Sequence,), "three numbers [m]"),
    "trajectory": ((Trajectory,), "a Trajectory"),
    "tasks": ((Sequence,), "a list of task names"),
}
"""What each optional argument of the co-design calls may be (None: not given)."""


def duty_of(robot: Robot | Problem, motion: Motion | Mix | None, options: Options | None,
            catalog: Sequence[Unit] | None, motors: Motors | None, *,
            what: str = "path to run faster", **others: object
            ) -> tuple[Duty, Options, tuple[Unit, ...], Mapping[str, tuple[Motor, ...]]]:
    """The duty of a problem (or of a motion or a mix), its options, catalog and motors.

    Args:
        robot: The resolved problem (`hdselect.resolve`), or the robot
            (`hdselect.load_case` of the motion or mix file).
        motion: A motion (one task), or a mix; None with a problem.
        options: The assumptions (default: the motion's or the mix's); None with a problem.
        catalog: The units (default: the built-in catalog, and the mix file's); None with
            a problem.
        motors: Candidate motors per sized joint; None takes the files' ``[motor]`` (with
            a problem: its own).
        what: What a logged trajectory has none of, for its refusal; empty: logs are taken.
        **others: The call's other optional arguments, by name: without a motion, an
            argument of no type it takes is named before the motion missing.

    Raises:
        InputError: A task is a log (where refused), or an argument is invalid.
        PlanningError: A mix's motion cannot be planned.
    """
    if isinstance(robot, Problem):
        given: dict[str, object] = {"motion": motion, "options": options, "catalog": catalog,
                                    "motors": motors}
        for name, value in given.items():
            if value is not None:
                raise InputError("a Problem holds it: give the problem alone, or a robot and "
                                 "its motion with it", field=name)
        problem = robot
    else:
        expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case) or a Problem")
        given = {**others, "options": options, "catalog": catalog, "motors": motors}
        for name, value in given.items() if motion is None else ():
            kinds, words = _KINDS[name]
            expect_type(value, (*kinds, type(None)), name, words)
        expect_type(motion, (Motion, Mix), "motion", "a Motion or Mix (hdselect.load_case)")
        source = (solve_motion(robot, motion) if isinstance(motion, Motion)
                  else cast(Mix, motion))  # a motion's tool poses solved for its mounting
        problem = problem_of(robot, source, catalog=catalog if catalog is not None else (),
                             motors=motors, options=options, plan=False)
    mix = problem.mix
    if mix is None:  # one motion: planned where the sizing needs it
        motion = cast(Motion, problem.source)
        if what:
            refuse_logs((motion,), what)
        duty = Duty(str(motion.path), problem.robot, (problem.robot,), (motion,), (1.0,),
                    trajectory=problem.tasks[0].trajectory if problem.planned else None,
                    task=problem.tasks[0] if problem.planned else None)
    else:
        if what:
            refuse_logs(tuple(task.motion for task in mix.tasks), what, several=True)
        planned = problem if problem.planned else plan_tasks(problem)
        counted = tuple(task for task in planned.tasks if task.share > 0.0)
        duty = Duty(str(mix.path), problem.robot, tuple(task.robot for task in counted),
                    tuple(task.motion for task in counted  # type: ignore[misc]
                          if task.motion is not None), tuple(task.share for task in counted),
                    planned.idle, mix, counted)
    return duty, problem.options, problem.units, problem.motors


def refuse_arm_targets(options: Options, what: str) -> None:
    """Refuse a whole-arm precision target where a solver does not judge it.

    Args:
        options: The assumptions resolved.
        what: What the solver finds, in words (``"the shortest cycle"``).

    Raises:
        InputError: A whole-arm target is set; the field names its flag and file key.
    """
    for name in WHOLE_ARM_TARGETS:
        if getattr(options, name) is not None:
            option = OPTION[name]
            table, key = str(option.key).split(".")
            raise InputError(f"{what} is bounded by the per-joint rules and targets only: a "
                             "whole-arm target (the tool's sag, the arm's lowest mode) is "
                             "judged by `hdselect size`, which raises units for it; leave it "
                             "out here and give the units size chooses (--units)",
                             field=f"{option.flag} ([{table}] {key})")


def choose(robot: Robot, duty: Duty, given: Mapping[str, Unit | str] | None,
           catalog: Sequence[Unit], options: Options, candidates: Mapping[str, tuple[Motor, ...]],
           *, selection: bool = True, trajectory: Trajectory | None = None
           ) -> tuple[dict[str, Unit], dict[str, str], dict[str, Motor]]:
    """The unit (and motor) of every sized joint: those given, the sizing's for the others.

    Args:
        robot: The robot with the duty's sized joints.
        duty: The tasks.
        given: Unit or unit id per joint.
        catalog: The units ids refer to, and the sizing chooses from.
        options: The assumptions of the sizing.
        candidates: Candidate motors per joint (checked).
        selection: Size the duty even when every joint has a unit and one motor given.
        trajectory: The trajectory a motion's selection sizes (default: the motion as
            planned; a study gives it run s times slower).

    Returns:
        The unit per sized joint; the unit id the sizing selects per joint (where one
        fits; else the one that fits with the smallest slow-down; empty when the duty
        was not sized); the motor per joint that has motors: the only one given, else
        the one the sizing pairs with the joint's unit (the pair it selects, else the one
        closest to passing).

    Raises:
        InputError: A name is not a sized joint, or an id is unknown.
        NoUnit: No unit can run a joint not given, at any speed.
    """
    chosen = fixed_units(given, catalog, robot)
    by_id = {unit.id: unit for unit in catalog}
    single = all(len(found) == 1 for found in candidates.values())
    if not selection and single and all(name in chosen for name in robot.sized_joints):
        return chosen, {}, {name: found[0] for name, found in candidates.items()}
    sizing = size_tasks(duty.tasks(options, trajectory), catalog, options, motors=candidates,
                        idle=duty.idle)
    picks = {joint.name: joint.selected.unit.id if joint.selected is not None else (
        joint.slowdown.unit.split(" + ")[0]  # a slow-down names a pair "UNIT + MOTOR"
        if joint.slowdown is not None and joint.slowdown.unit is not None else None)
        for joint in sizing.joints}
    stuck = [name for name, pick in picks.items() if pick is None and name not in chosen]
    if stuck:
        named = replace(sizing, mix=duty.mix,  # the next steps' commands name its file
                        motion=duty.motions[0] if duty.mix is None else None)
        raise NoUnit(duty.where, duty.over, named, stuck)
    selected = {name: pick for name, pick in picks.items() if pick is not None}
    paired: dict[str, Motor] = {}
    for joint in sizing.joints:
        if joint.name not in chosen:
            chosen[joint.name] = by_id[selected[joint.name]]
        if joint.name in candidates:
            paired[joint.name] = _paired_motor(joint.candidates, chosen[joint.name],
                                               candidates[joint.name], sizing.options)
    return chosen, selected, paired


def resolve_case(robot: Robot, motion: Motion, given: Mapping[str, Unit | str] | None,
                 catalog: Sequence[Unit], options: Options, *,
                 selection: bool = True, trajectory: Trajectory | None = None,
                 motors: Motors | None = None
                 ) -> tuple[dict[str, Unit], dict[str, str], dict[str, Motor]]:
    """The unit (and motor) of every sized joint of one motion: `choose` for its duty.

    Args:
        robot: The robot as the motion runs it.
        motion: The motion (planned with its own planner for the selection).
        given: Unit or unit id per joint.
        catalog: The units ids refer to, and the sizing chooses from.
        options: The assumptions of the sizing.
        selection: Size the motion even when every joint has a unit and one motor given.
        trajectory: The trajectory the selection sizes (default: the motion as planned).
        motors: Candidate motors per joint; None takes the motion file's ``[motor]``.

    Returns:
        As `choose`.

    Raises:
        InputError: A name is not a sized joint, or an id is unknown.
        PlanningError: No unit can run a joint not given, at any speed.
    """
    candidates = checked_motors(robot, file_motors(robot, motion) if motors is None
                                else motors, options)
    duty = Duty(str(motion.path), robot, (robot,), (motion,), (1.0,))
    return choose(robot, duty, given, catalog, options, candidates, selection=selection,
                  trajectory=trajectory)


def resolve_units(robot: Robot, motion: Motion, given: Mapping[str, Unit | str] | None,
                  catalog: Sequence[Unit], options: Options, *,
                  selection: bool = True, trajectory: Trajectory | None = None
                  ) -> tuple[dict[str, Unit], dict[str, str]]:
    """The unit of every sized joint: those given, the sizing's selection for the others.

    As `resolve_case`, with the motion file's motors; without the motors chosen.

    Raises:
        InputError: As `resolve_case`; the motion is a log (it has no path to run faster).
    """
    refuse_logs((motion,))
    chosen, selected, _ = resolve_case(robot, motion, given, catalog, options,
                                       selection=selection, trajectory=trajectory)
    return chosen, selected


def refuse_logs(motions: Sequence[Motion], what: str = "path to run faster", *,
                several: bool = False) -> None:
    """A logged trajectory has no path to run faster (or `what`): refused, naming its planner.

    `several`: the motions are a mix's tasks.
    """
    for motion in motions:
        if motion.planner == "samples":
            raise InputError(f"a logged trajectory ('samples') has no {what}; give "
                             f"{'motions' if several else 'a motion'} with waypoints",
                             path=motion.path, field="planner")


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
        raise PlanningError(f"no motor pairs with {unit.id}")
    return best.motor_unit
