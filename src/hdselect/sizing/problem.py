"""One sizing problem, resolved once from files or Python objects: what the core solves.

`resolve` reads (or takes) the robot and its motion or mix, applies the payload, the
mounting and the sized joints, takes the options and the motors (given, else the
files'), loads the catalog and plans every task with its own payload and mounting.
A motion is a problem of one task with share 1, a mix one task per ``[[task]]``; the
command line, `hdselect.size` and the envelope all start from a `Problem`, and
`hdselect.sizing.core.size_problem` solves it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.catalog.builtin import catalog_files
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.motion import planning
from hdselect.motion.loading import load_case, solved_on
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.robot.model import Robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import OptionValues, checked_motors, options_argument
from hdselect.sizing.mixtasks import mix_motors, mix_options, mix_tasks, sized_motors
from hdselect.sizing.options import Options, options_for
from hdselect.sizing.result import Motors
from hdselect.sizing.tasks import Task, task_of

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["Problem", "catalog_argument", "catalog_units", "file_motors", "plan_tasks",
           "problem_of", "resolve", "source_files", "source_options"]

Catalog = Sequence[str | Path] | Sequence[Unit]
"""Catalog files (the built-in PSA-G page always loaded) or the units already loaded."""


@dataclass(frozen=True, eq=False)
class Problem:
    """A sizing problem, resolved: everything the one selection needs, validated once.

    Attributes:
        robot: The robot as sized: for a motion, as it runs it (payload and mounting
            applied); for a mix, with the duty's sized joints (each task applies its
            own payload and mounting). No gearhead masses: the sizing adds those.
        source: The motion (its tool poses solved for the robot's mounting) or the mix
            the tasks come from; None for tasks made in Python (the envelope's default
            duty).
        units: The catalog's units to choose from.
        options: The assumptions (its ``prefer`` None: the core's default).
        motors: Candidate motors per sized joint (checked); empty without motor data.
        tasks: Every task, in order (`hdselect.sizing.tasks.Task`: its robot with payload
            and mounting, planned trajectory, share, solved motion and name); empty until
            planned (`plan_tasks`). A motion is one task with share 1.
        idle: The fraction of the time no task runs [-] (a mix in cycles per hour).
        files: The files read (robot, motion or mix and its motions, logs, motor and
            catalog files), for provenance.
        mounting: The mounting given over the files' (a parameter or a flag: a mix's on
            every task, which a tool pose it cannot place blames), else None.
    """

    robot: Robot
    source: Motion | Mix | None
    units: tuple[Unit, ...]
    options: Options
    motors: Mapping[str, tuple[Motor, ...]]
    tasks: tuple[Task, ...] = ()
    idle: float = 0.0
    files: tuple[Path, ...] = ()
    mounting: Mounting | None = None

    @property
    def motion(self) -> Motion | None:
        """The motion, where the task comes from one motion (not a mix, nor made in Python)."""
        return self.source if isinstance(self.source, Motion) else None

    @property
    def mix(self) -> Mix | None:
        """The mix file's contents, where the tasks come from one (reports list them)."""
        return self.source if isinstance(self.source, Mix) else None

    @property
    def planned(self) -> bool:
        """Whether the tasks are planned."""
        return bool(self.tasks)


def resolve(
    robot: Robot | str | Path | None,
    motion: Motion | Mix | str | Path,
    *,
    catalog: Catalog | None = (),
    payload: Payload | None = None,
    mounting: Mounting | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
    motors: Motors | None = None,
    options: Options | None = None,
    plan: bool = True,
    **values: Unpack[OptionValues],
) -> Problem:
    """Resolve a robot and its motion (or mix), as files or objects, into one `Problem`.

    Args:
        robot: Robot file or loaded robot; None takes the one the motion (or mix) names.
        motion: Motion file or `Motion`; or a mix file or `Mix` (every task planned with
            its own payload and mounting, one duty).
        catalog: Extra catalog files (the built-in PSA-G catalog always loaded, and a mix
            file's ``[sizing] catalog``; None: none), or the units already loaded (used as
            they are).
        payload: Payload, overriding the motion file's (refused for a mix: its tasks give
            theirs).
        mounting: Mounting, overriding the motion file's (a mix's: every task's).
        joints: Joints to size (default: the file's ``[sizing] joints``, else every
            revolute joint that is not a mimic follower).
        exclude: Joints not to size; they still move and load the others.
        motors: Candidate motors per joint name, replacing the files' ``[motor]``.
        options: The assumptions as a whole (the files' are not read); None: `values`,
            else the files', else the defaults.
        plan: Plan the tasks; False leaves `Problem.tasks` empty for `plan_tasks` (or a
            front end that plans its own way).
        **values: Fields of `Options`, each over the files' value (None: not given).

    Returns:
        The problem.

    Raises:
        InputError: A file or argument is invalid, or two arguments contradict.
        PlanningError: A motion cannot be planned.
    """
    options_argument(options, values)
    expect_type(plan, (bool,), "plan", "True or False")
    given = catalog_argument(catalog)
    mounted, source = load_case(motion, robot, payload=payload, mounting=mounting,
                                joints=joints, exclude=exclude)
    if options is None:
        options = source_options(source, **values)
    return problem_of(mounted, source, catalog=given, motors=motors, options=options,
                      plan=plan, mounting=mounting)


def problem_of(robot: Robot, source: Motion | Mix, *, catalog: Catalog | None = (),
               motors: Motors | None = None, options: Options | None = None,
               plan: bool = True, mounting: Mounting | None = None) -> Problem:
    """The problem of a robot already set up for its motion or mix (`hdselect.load_case`).

    `resolve` after its files are read; a front end that reads them its own way (the
    command line, naming its flags in messages) starts here.

    Args:
        robot: The robot as the motion runs it (a mix: with the duty's sized joints).
        source: The motion (tool poses solved) or the mix.
        catalog: As `resolve`'s.
        motors: Candidate motors per joint name; None takes the files'.
        options: The assumptions; None takes the files', else the defaults.
        plan: Plan the tasks (see `resolve`).
        mounting: Mounting over the files': a motion's (the robot mounted with it and
            its tool poses solved again), a mix's on every task; None: as they are.

    Raises:
        InputError: The catalog, the motors, the options or the mounting are invalid.
        PlanningError: A motion cannot be planned.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_case)")
    expect_type(source, (Motion, Mix), "motion", "a Motion or a Mix (hdselect.load_case)")
    expect_type(options, (Options, type(None)), "options", "an Options or None")
    given = catalog_argument(catalog)
    options = options if options is not None else source_options(source)
    if mounting is not None:  # a bad mounting refused once, not task by task
        mounted = robot.with_mounting(mounting)
        if isinstance(source, Motion):
            robot, source = mounted, solved_on(mounted, source, mounting)
        else:
            source = source.with_mounting(mounting)
    mix = source if isinstance(source, Mix) else None
    files = [] if isinstance(given, tuple) else [*(mix.catalog if mix else ()), *given]
    units = given if isinstance(given, tuple) else load_catalog(files)
    chosen = checked_motors(robot, motors if motors is not None
                            else file_motors(robot, source), options)
    motor_files = sorted({m.source for ms in chosen.values() for m in ms if m.source})
    problem = Problem(robot, source, units, options, chosen, files=tuple(dict.fromkeys(
        [*source_files(robot, source), *files, *motor_files])), mounting=mounting)
    return plan_tasks(problem) if plan else problem


def catalog_units(catalog: Catalog | None) -> tuple[Unit, ...]:
    """The units to choose from: those given loaded, else the built-in catalog and the files.

    Raises:
        InputError: The argument is neither files nor units, or a file is invalid.
    """
    given = catalog_argument(catalog)
    return given if isinstance(given, tuple) else load_catalog(given)


def plan_tasks(problem: Problem) -> Problem:
    """The problem with every task planned (each with its own payload and mounting).

    A mix's tasks run on `Problem.mounting` where it is given, else each on its own.

    Raises:
        InputError: A task's tool pose cannot be solved for its mounting, or a mix's
            cycles per hour overfill the hour.
        PlanningError: A motion cannot be planned.
    """
    robot, limit = problem.robot, problem.options.max_samples
    if problem.mix is not None:
        tasks, idle = mix_tasks(robot, problem.mix, mounting=problem.mounting,
                                joints=robot.sized_joints, exclude=(), max_samples=limit)
        return replace(problem, tasks=tasks, idle=idle)
    if not isinstance(problem.source, Motion):
        raise InputError("the problem has no motion to plan: give its tasks", field="tasks")
    planned = planning.plan_motion(robot, problem.source, max_samples=limit)
    return replace(problem, tasks=(task_of(robot, planned.trajectory, planned.motion),),
                   idle=0.0)


def source_options(source: Motion | Mix | None, **values: Any) -> Options:
    """Options from keyword values (None: not given), else the files', else the defaults.

    A motion file's ``[safety]``, ``[requirements]`` and bearing offsets; a mix file's
    duty-wide values, else those its motions agree on (`hdselect.sizing.mixtasks.mix_options`).

    Raises:
        InputError: An unknown name, a value out of range, or two motion files disagree.
    """
    return mix_options(source, **values) if isinstance(source, Mix) else options_for(
        source, **values)


def file_motors(robot: Robot, source: Motion | Mix) -> dict[str, tuple[Motor, ...]]:
    """The files' candidate motors for the robot's sized joints (empty if none).

    A motion file's ``[motor]`` tables; a mix file's, else those its motions agree on.

    Raises:
        InputError: A ``[motor.JOINT]`` block names a joint that is not sized, or two
            motion files of a mix disagree.
    """
    if isinstance(source, Mix):
        return mix_motors(robot, source)
    return sized_motors(robot, source.motors, source.motor_joints, source.path)


def source_files(robot: Robot, source: Motion | Mix) -> list[Path]:
    """The files a robot and a motion (or mix) were read from (logs and motor files included)."""
    if isinstance(source, Mix):
        files = [source.path, *source.catalog]
        for item in dict.fromkeys(source.motions):
            files += [f for f in source_files(robot, item) if f not in files]
        mine = {m.source for ms in (source.given.get("motors") or {}).values() for m in ms
                if m.source}
        return files + sorted(f for f in mine if f not in files)
    files = [source.path, robot.path]
    motors = {m.source for ms in (source.motors or {}).values() for m in ms if m.source}
    return files + ([source.samples.path] if source.samples is not None else []) + sorted(motors)


def catalog_argument(catalog: object) -> tuple[Unit, ...] | list[Path]:
    """The catalog argument checked: the loaded units as a tuple, or the files as a list.

    Raises:
        InputError: It is neither, or mixes units and files.
    """
    if catalog is None:
        return []
    if (isinstance(catalog, Sequence) and not isinstance(catalog, str | bytes)
            and any(isinstance(item, Unit) for item in catalog)):
        if not all(isinstance(item, Unit) for item in catalog):
            raise InputError("expected catalog files or the units of a loaded catalog "
                             "(hdselect.load_catalog), not both", field="catalog")
        return tuple(catalog)
    return catalog_files(catalog)
