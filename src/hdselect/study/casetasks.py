"""A study case as the tasks it sizes: a motion file is one task, a mix file several.

Every case resolves to a `CaseDuty`: the robot, its tasks (each a motion with the
mounting it runs with, the payload the case carries in it and its share of the
time), the options and the mix file (None for a motion file). A motion file is
exactly a mix of one task with share 1, so the grouped evaluation
(`hdselect.study.pooled`) has one path for both.

A mix case gives the shares of its tasks and per-task payload masses as parameters
(``shares``, ``payloads``), on top of the mix file's. Files are read once per worker
task (`Inputs`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from hdselect.base.errors import InputError
from hdselect.catalog.builtin import of_series
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor, load_motors
from hdselect.catalog.units import Unit
from hdselect.codesign.scaledpart import moved_part
from hdselect.motion.loading import robot_for_mix, robot_for_motion
from hdselect.motion.mixfile import Mix, is_mix_file, load_mix, mix_robot_file
from hdselect.motion.motionfile import Motion, load_motion
from hdselect.motion.option_specs import from_edge
from hdselect.motion.robot_named import load_named, robot_source
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.options import Options
from hdselect.sizing.problem import file_motors, source_options
from hdselect.sizing.result import Motors
from hdselect.sizing.tasks import check_shares
from hdselect.study.case import Case


@dataclass(frozen=True)
class CaseTask:
    """One task of a case: what its group's basis is built from, and the case's weights.

    Attributes:
        motion: The task's motion file, read.
        mounting: Mounting the task runs with: the case's, else the mix file's for the
            task; None: the motion file's.
        payload: The payload the case carries in this task (shape and mass), or None.
        share: Fraction of the operating time [-]; None for a mix in cycles per hour,
            whose shares follow from its planned cycles (a grouped case refuses it).
        name: The task's name in its mix file ("" for a motion file).
        part: `payload` is the part the motion's payload events move (`case_part`), the
            ``[payload]`` carried as the file gives it; else it is the ``[payload]``.
    """

    motion: Motion
    mounting: Mounting | None
    payload: Payload | None
    share: float | None
    name: str = ""
    part: bool = False


@dataclass(frozen=True)
class CaseDuty:
    """A case resolved: its robot and its tasks, in file order.

    Attributes:
        robot: The robot as loaded, no payload (a mix's sized joints applied).
        tasks: The tasks; one, with share 1, for a motion file.
        options: The case's options over its files', one thread.
        mix: The mix file, or None for a motion file.
    """

    robot: Robot
    tasks: tuple[CaseTask, ...]
    options: Options
    mix: Mix | None = None

    def mounted(self, k: int) -> Robot:
        """Task k's robot as it runs the task, without the payload the case scales.

        Mounting and joints applied; where the case scales the part the events move, with
        the file's ``[payload]``.

        Raises:
            InputError: As `hdselect.motion.loading.robot_for_motion`.
        """
        task = self.tasks[k]
        joints = None if self.mix is None else self.robot.sized_joints
        return robot_for_motion(self.robot, task.motion if task.part
                                else replace(task.motion, payload=None),
                                mounting=task.mounting, joints=joints,
                                exclude=None if joints is None else ())


def case_part(case: Case, motion: Motion) -> bool:
    """A motion file's case scales the part its payload events move, not its ``[payload]``.

    Where its events move one part; where they move several, only a case that gives no
    ``payload`` (each part then carried as the file gives it).

    Raises:
        InputError: The case gives a ``payload`` and the events move several parts.
    """
    moved = {event.part for event in motion.events}
    if len(moved) > 1 and case.payload is not None:
        moved_part(motion)  # refuses: one part scales
    return len(moved) == 1


def is_mix_case(case: Case) -> bool:
    """The case's motion is a mix file (a file that cannot be read is not: it fails later)."""
    try:
        return is_mix_file(case.motion)
    except InputError:
        return False


class Inputs:
    """Robots, motions and catalogs read once per worker task, keyed by file."""

    def __init__(self) -> None:
        """Nothing read yet."""
        self.robots: dict[tuple[Path, tuple[tuple[str, str], ...]], Robot] = {}
        self.mix_robots: dict[Path, Robot] = {}  # a mix file's robot, by its file
        self.mixes: dict[tuple[Path, Path], tuple[Robot, Mix]] = {}  # by mix and robot file
        self.motions: dict[tuple[Path, tuple[Path, tuple[tuple[str, str], ...]]], Motion] = {}
        self.units: dict[tuple[tuple[Path, ...], int | None, tuple[str, ...]],
                         tuple[Unit, ...]] = {}
        self.motor_files: dict[Path, tuple[Motor, ...]] = {}
        self.robot_files: dict[Path, tuple[Path, dict[str, str]]] = {}

    def case(self, case: Case) -> tuple[Robot, Motion, Payload | None]:
        """The bare robot, the motion and the case's payload (a motion file's case)."""
        arguments: dict[str, str] = {}
        if case.robot is not None:
            robot_file = case.robot
        else:  # the motion file read once for the robot it names
            if case.motion not in self.robot_files:
                self.robot_files[case.motion] = robot_source(case.motion)
            robot_file, arguments = self.robot_files[case.motion]
        key = (robot_file, tuple(sorted(arguments.items())))
        if key not in self.robots:
            self.robots[key] = load_named(robot_file, arguments, case.motion)
        robot = self.robots[key]
        if (case.motion, key) not in self.motions:
            self.motions[case.motion, key] = load_motion(case.motion, robot)
        motion = self.motions[case.motion, key]
        return robot, motion, case.payload_for(moved_part(motion) if case_part(case, motion)
                                               else motion.payload)

    def duty(self, case: Case) -> CaseDuty:
        """The case resolved to its tasks: one for a motion file, a mix file's otherwise.

        Raises:
            InputError: A file is bad, or the case's parameters do not fit it.
        """
        if is_mix_case(case):
            return mix_duty(case, *self.mix(case))
        robot, motion, payload = self.case(case)
        return CaseDuty(robot, (CaseTask(motion, case.mounting, payload, 1.0, "",
                                         case_part(case, motion)),),
                        case_options(case, motion))

    def mix(self, case: Case) -> tuple[Robot, Mix]:
        """A mix case's robot (sized joints applied, no payload) and mix, read once.

        Raises:
            InputError: A file is bad, or the case gives a single ``payload`` for a mix.
        """
        if case.payload is not None:
            raise InputError("a mix's tasks carry their own payloads: vary `payloads` (task "
                             "name -> mass [kg]) instead of `payload`", field="payload")
        file = case.robot if case.robot is not None else mix_robot_file(case.motion)
        if (case.motion, file) not in self.mixes:
            if file not in self.mix_robots:
                self.mix_robots[file] = load_robot(file)
            mix = load_mix(case.motion, self.mix_robots[file])
            self.mixes[case.motion, file] = robot_for_mix(self.mix_robots[file], mix), mix
        return self.mixes[case.motion, file]

    def catalog(self, case: Case) -> tuple[Unit, ...]:
        """The case's candidate units (its catalogs; only its series and ratio if it gives them)."""
        key = (case.catalog, case.ratio, case.series)
        if key not in self.units:
            units = of_series(load_catalog(case.catalog), case.series)
            if case.ratio is not None:
                chosen = tuple(u for u in units if u.ratio == case.ratio)
                if not chosen:
                    ratios = sorted({u.ratio for u in units})
                    raise InputError(f"no unit has ratio {case.ratio}; the catalog's ratios "
                                     f"are: {', '.join(map(str, ratios))}", field="ratio")
                units = chosen
            self.units[key] = units
        return self.units[key]

    def duty_motors(self, case: Case, duty: CaseDuty, mounted: Robot) -> Motors:
        """A case's candidate motors per sized joint of `mounted` (its first task's robot)."""
        return self.motors(case, mounted, duty.mix if duty.mix is not None
                           else duty.tasks[0].motion)

    def motors(self, case: Case, robot: Robot,
               source: Motion | Mix) -> dict[str, tuple[Motor, ...]]:
        """The case's candidate motors per sized joint of `robot` (empty without motors).

        Its ``motor_catalog`` for every sized joint, else the motion or mix file's
        ``[motor]`` (`hdselect.sizing.problem.file_motors`).
        """
        if case.motor_catalog is None:
            return file_motors(robot, source)
        if case.motor_catalog not in self.motor_files:
            self.motor_files[case.motor_catalog] = load_motors(case.motor_catalog)
        return {name: self.motor_files[case.motor_catalog] for name in robot.sized_joints}


def case_options(case: Case, source: Motion | Mix) -> Options:
    """The case's options over its motion or mix file's (`source_options`), one thread.

    The study gives them in the units of the files (arcmin, mm: `from_edge`).
    """
    return source_options(source, **from_edge(case.options), threads=1)


def mix_duty(case: Case, robot: Robot, mix: Mix) -> CaseDuty:
    """A mix case's tasks: the case's shares and payload masses over the mix file's.

    A mix in cycles per hour has its shares only once its tasks are planned: without
    the case's ``shares``, each task's is None.

    Args:
        case: The case.
        robot: The mix's robot (sized joints applied, no payload).
        mix: The case's mix file, read.

    Raises:
        InputError: The shares or payloads do not fit the mix.
    """
    payloads = case_payloads(case, mix)
    given = case_shares(case, mix)
    if given is not None:
        check_shares(given, field="shares")
    shares: Sequence[float | None] = given if given is not None else [
        None if task.share is None else float(task.share) for task in mix.tasks]
    tasks = tuple(CaseTask(item.motion, case.mounting if case.mounting is not None
                           else item.mounting, payloads.get(k, _shape(mix, k)), shares[k],
                           item.name)
                  for k, item in enumerate(mix.tasks))
    return CaseDuty(robot, tasks, case_options(case, mix), mix)


def case_payloads(case: Case, mix: Mix) -> dict[int, Payload]:
    """The case's payload per task index, from its ``payloads`` masses.

    Each mass goes in its task's payload shape, as a study's ``payload`` does (centre of
    mass, inertia about it and frame kept): the mix file's, else the motion file's, else
    a point mass at the robot's default payload frame.

    Raises:
        InputError: A task name is not the mix's.
    """
    names = [task.name for task in mix.tasks]
    check_task_keys(None, case.payloads, names, mix.path.name)
    out: dict[int, Payload] = {}
    for name, mass in case.payloads or ():
        k = names.index(name)
        shape = _shape(mix, k)
        out[k] = Payload(mass) if shape is None else replace(shape, mass=mass)
    return out


def _shape(mix: Mix, k: int) -> Payload | None:
    """Task k's payload as the files give it: the mix file's, else the motion file's."""
    item = mix.tasks[k]
    return item.payload if item.payload is not None else item.motion.payload


def case_shares(case: Case, mix: Mix) -> list[float] | None:
    """The case's shares in task order, or None for the mix file's.

    Raises:
        InputError: Their count is not the mix's number of tasks.
    """
    if case.shares is None:
        return None
    check_task_keys(case.shares, None, [t.name for t in mix.tasks], mix.path.name)
    return list(case.shares)


def check_task_keys(shares: Sequence[float] | None,
                    payloads: Iterable[tuple[str, float]] | Mapping[str, float] | None,
                    names: Sequence[str], file: str) -> None:
    """Refuse a case's ``shares`` and ``payloads`` that do not fit a mix's tasks.

    Args:
        shares: One share per task, or None.
        payloads: Payload masses by task name [kg], or None.
        names: The mix's task names, in order.
        file: The mix file's name, for the message.

    Raises:
        InputError: Not one share per task (field ``shares``), or a payload names no task
            (field ``payloads``).
    """
    if shares is not None and len(shares) != len(names):
        raise InputError(f"{len(shares)} share{'s' if len(shares) != 1 else ''} for the "
                         f"{len(names)} tasks of {file} ({', '.join(names)})", field="shares")
    for name in (payloads.keys() if isinstance(payloads, Mapping) else
                 (name for name, _ in payloads or ())):
        if name not in names:
            raise InputError(f"no task {name!r} in {file}; its tasks are: {', '.join(names)}",
                             field="payloads")
