"""The next steps for a joint no candidate holds, each checked before it is offered.

`hdselect.sizing.diagnosis` puts them in a joint's diagnosis, in the order `NEXT_STEPS`:

- a shipped series: each catalog's units checked against the joint's cycle as sized,
  the best verified by sizing the whole duty with it added, as ``--catalog`` does;
- less payload: the payload solver's largest mass at which some candidate holds the
  joint, rounded down and verified by sizing at it;
- the joint left out (``--exclude``): it still moves and loads the others;
- a slow-down, where the exact time-scale solver (`hdselect.sizing.timescale`) found one.
"""

from __future__ import annotations

import math
import os
import shlex
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from hdselect.catalog.rules import Candidate, rule
from hdselect.catalog.units import Unit
from hdselect.sizing.core import size_tasks
from hdselect.sizing.joint import JointCycle, size_joint
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.tasks import Task, pooled

PayloadBounds = Callable[..., Mapping[str, Sequence[Any]]]
"""The payload solver: `hdselect.codesign.maxpayload.duty_bounds` (tasks, idle, scaled
task names, carried masses, units, options) -> per joint, each unit's `UnitBound` (its
``masses``: the interval of factors x on the scaled payloads at which it passes)."""

PAYLOAD_STEP = 0.01
"""The payload offered is rounded down to this [kg] (a factor of a mix's to 0.01 [-])."""


@dataclass(frozen=True)
class NextStep:
    """Something that gives the joint a unit, checked before it is offered.

    Attributes:
        kind: ``"catalog"`` (a shipped series), ``"payload"`` (less payload),
            ``"exclude"`` (the joint left out) or ``"slowdown"`` (the cycle run slower).
        text: The step in words.
        command: The command line that takes it, where one does; else None.
        unit: The unit that then holds the joint; None for ``exclude``.
        value: The payload [kg] (a mix's factor [-]) or the time scale [-]; else None.
        catalog: The catalog (``--catalog`` argument) of a ``catalog`` step, several
            joined by ``,`` for the step that adds them together; else None.
    """

    kind: str
    text: str
    command: str | None = None
    unit: str | None = None
    value: float | None = None
    catalog: str | None = None


NEXT_STEPS = ("catalog", "payload", "exclude", "slowdown")
"""The kinds of next step, in the order they are offered."""


def catalog_steps(result: SizingResult, missing: Sequence[JointSizing], tasks: Sequence[Task],
                   catalogs: Mapping[str, Sequence[Unit]],
                   command: Sequence[str] | None = None) -> dict[str, list[NextStep]]:
    """Per joint, the shipped series whose smallest holding unit is smallest, verified.

    Each catalog's units are first checked against the joint's cycle as sized (the same
    rules, the same carried masses); the best catalog is then verified by sizing the
    whole duty with it added, as ``--catalog`` does, and offered only where that sizing
    gives the joint a unit (the unit it gives is the one named) whose source rates the
    stiffness of every precision target the joint failed (a unit that rates no K1 does
    not hold a torsion target).
    """
    have = {unit.id for unit in result.units}
    offered = {name: fresh for name, units in catalogs.items()
               if (fresh := tuple(unit for unit in units if unit.id not in have))}
    if not offered:
        return {}
    samples = pooled(tasks, result.idle)
    options = result.options
    best: dict[str, list[tuple[tuple[float, float], str]]] = {}
    for joint in missing:
        if len(joint.torque) != len(samples):
            continue  # sized on more than its tasks' samples (an envelope's worst states)
        cycle = JointCycle(samples, result.robot.joint_index(joint.name), joint.torque,
                           joint.stop_torque, joint.wrench,
                           options.bearing_offset.get(joint.name, 0.0))
        for name, units in offered.items():
            found = size_joint(joint.name, cycle, units, options,
                               motors=result.motors.get(joint.name, ()), detail=False,
                               load_inertia=joint.load_inertia)
            if found.selected is not None and _rated_hold(found.selected, joint):
                unit = found.selected.unit
                best.setdefault(joint.name, []).append(((unit.size, unit.mass), name))
    out: dict[str, list[NextStep]] = {}
    sized: dict[str, SizingResult] = {}
    for joint in missing:
        for _, name in sorted(best.get(joint.name, [])):
            if name not in sized:
                sized[name] = size_tasks(tasks, (*result.units, *offered[name]), options,
                                         motors=result.motors or None, idle=result.idle,
                                         slowdowns=False)
            chosen = next(j for j in sized[name].joints if j.name == joint.name).selected
            if chosen is not None and _rated_hold(chosen, joint):
                out[joint.name] = [NextStep(
                    "catalog", f"the {name} catalog holds it with {chosen.label}",
                    _command(result, command, ("--catalog", name),
                             *([("--series", name)] if given(command, "--series") else [])),
                    chosen.label, catalog=name)]
                break
    names = sorted({step.catalog for steps in out.values() for step in steps if step.catalog})
    if len(names) > 1:  # joints held by different catalogs: one command for all of them
        together = size_tasks(tasks, (*result.units, *(u for n in names for u in offered[n])),
                              options, motors=result.motors or None, idle=result.idle,
                              slowdowns=False)
        failed = {joint.name: joint for joint in missing}
        held = {j.name for j in together.joints
                if j.selected is not None and (j.name not in failed
                                               or _rated_hold(j.selected, failed[j.name]))}
        if {joint.name for joint in missing} <= held:
            step = NextStep("catalog", f"with {' and '.join(names)} together, every joint "
                            "gets a unit", _command(result, command,
                                                    *(("--catalog", n) for n in names)),
                            catalog=",".join(names))
            for steps in out.values():
                steps.append(step)
    return out


def payload_steps(result: SizingResult, missing: Sequence[JointSizing], tasks: Sequence[Task],
                   masses: Mapping[str, float],
                   payload_bounds: PayloadBounds | None,
                   command: Sequence[str] | None = None) -> dict[str, list[NextStep]]:
    """Per joint, the largest payload at which some candidate holds it, verified by sizing."""
    scaled = [task.label for task in tasks if task.robot.payload is not None]
    evented = any(task.carried is not None for task in tasks)  # a part moves, not --payload's
    if payload_bounds is None or not scaled or evented or any(
            task.motion is not None and task.motion.planner == "toppra"
            and task.motion.torque_limit is not None for task in tasks):
        return {}  # no payload, payload events, or a trajectory that depends on it
    bounds = payload_bounds(tasks, result.idle, scaled, masses, result.units, result.options)
    single = len(tasks) == 1
    count = len(pooled(tasks, result.idle))
    out: dict[str, list[NextStep]] = {}
    for joint in missing:
        if len(joint.torque) != count:
            continue  # sized on more than its tasks' samples: they alone do not check it
        ends = [min(b.masses[1], 1.0) for b in bounds[joint.name]
                if b.masses is not None and b.masses[0] <= min(b.masses[1], 1.0)]
        if not ends:
            continue
        factor = max(ends)
        if single:  # as --payload KG: the mass changed, its inertia and place kept
            kg = _rounded_down(factor * _mass(tasks[0]))
            lighter = tuple(_lighter(task, kg, 1.0) for task in tasks)
        else:  # every scaled task's payload x times: mass and inertia alike
            factor = _rounded_down(factor)
            lighter = tuple(_lighter(task, _mass(task) * factor, factor)
                            if task.label in scaled else task for task in tasks)
        if (kg if single else factor) <= 0.0:
            continue
        check = size_tasks(lighter, result.units, result.options,
                           motors=result.motors or None, idle=result.idle, slowdowns=False)
        chosen = next(j for j in check.joints if j.name == joint.name).selected
        if chosen is None:
            continue
        if single:
            text = f"a payload of {kg:.2f} kg (not more) lets {chosen.label} hold it"
            out[joint.name] = [NextStep("payload", text,
                                        _command(result, command, ("--payload", f"{kg:.2f}")),
                                        chosen.label, kg)]
        else:
            carried = ", ".join(f"{task.label} {task.robot.payload.mass:.3g} kg"
                                for task in lighter if task.label in scaled
                                and task.robot.payload is not None)
            out[joint.name] = [NextStep(
                "payload", f"the payloads scaled by {factor:.2f} ({carried}) let "
                f"{chosen.label} hold it", None, chosen.label, factor)]
    return out


def _rated_hold(chosen: Candidate | None, joint: JointSizing) -> bool:
    """A candidate holds the joint, and rates the stiffness of each target the joint failed.

    A unit that rates no K1 holds a precision target unchecked: that is no next step.
    """
    failed = [name for name, check in joint.strongest.checks.items() if not check.ok
              and chosen is not None and "stiffness" in rule(name).fields(chosen.unit)]
    return chosen is not None and not any(
        "not_rated" in chosen.checks[name].detail for name in failed if name in chosen.checks)


def _rounded_down(x: float) -> float:
    """`x` rounded down to `PAYLOAD_STEP`, as it is printed (two decimals)."""
    return math.floor(round(x / PAYLOAD_STEP, 6)) * PAYLOAD_STEP


def _mass(task: Task) -> float:
    """The task's payload mass [kg] (0 without one)."""
    return 0.0 if task.robot.payload is None else task.robot.payload.mass


def _lighter(task: Task, mass: float, inertia: float) -> Task:
    """The task with a payload of `mass` [kg], its inertia times `inertia` [-]."""
    payload = task.robot.payload
    if payload is None:
        return task
    lighter = replace(payload, mass=float(f"{mass:.12g}"),
                      inertia=tuple(tuple(x * inertia for x in row) for row in payload.inertia))
    return replace(task, robot=task.robot.with_payload(lighter))


def exclude_step(result: SizingResult, joints: Sequence[str],
                 command: Sequence[str] | None = None) -> NextStep | None:
    """Leave out every joint no unit holds: they still move and load the others.

    One step for all of them, so that its command runs (leaving out one of two would
    still find the other without a unit). ``--exclude`` replaces the file's list: the
    joints left out already are kept in it. None where no other joint would be sized.
    """
    if set(result.robot.sized_joints) <= set(joints):
        return None
    before = given(command, "--exclude")
    left_out = (before.split(",") if before else
                [load.name for load in result.loads
                 if not load.sized and load.kind == "revolute" and load.leader is None])
    text = ("size the other joints without it" if len(joints) == 1 else
            f"size the other joints without the {len(joints)} that no unit holds")
    return NextStep("exclude", text,
                    _command(result, command, ("--exclude", ",".join([*left_out, *joints]))))


def slowdown_step(result: SizingResult, joint: JointSizing) -> NextStep | None:
    """The uniform slow-down the time-scale solver found, where it found one.

    For a duty of several tasks, every task runs s times slower at the same shares.
    """
    slowdown = joint.slowdown
    if slowdown is None or slowdown.factor is None or slowdown.unit is None:
        return None
    factor = slowdown.factor
    speed = f"{factor:.3f}x slower" if factor >= 1.0 else f"{1.0 / factor:.3f}x faster"
    if len(result.counted) > 1:
        cycles = ", ".join(f"{task.label} {factor * task.trajectory.duration:.3f} s"
                           for task in result.counted)
        text = f"run every task {speed} (cycles {cycles})"
    else:
        text = f"run the motion {speed} (cycle {factor * result.cycle_time:.3f} s)"
    return NextStep("slowdown", f"{text} and {slowdown.unit} holds it", None, slowdown.unit,
                    factor)


OUTPUT_OPTIONS = ("--json", "--report", "--bom")
"""Options that write files: left out of a next step's command (it is run to be read)."""


def _command(result: SizingResult, command: Sequence[str] | None,
             *options: tuple[str, str]) -> str | None:
    """The run's command line with `options` set, or ``hdselect size FILE`` with them.

    The user's own options are kept (so the step is checked on the same assumptions it
    is run with), each option of `options` replaced where given (``--catalog`` and
    ``--series``, which repeat, added to), the output options left out.

    Args:
        result: The sizing, for its motion or mix file where no command is known.
        command: The command line of the run, program name first; None from Python.
        *options: The options to set, each (option, value), e.g. ``("--payload", "2.5")``.

    Returns:
        The command, quoted for a POSIX shell; None without a command or a file.
    """
    added = [word for pair in options for word in pair]
    if command is None:
        source = result.mix.path if result.mix is not None else (
            result.motion.path if result.motion is not None else None)
        if source is None:
            return None
        return shlex.join(["hdselect", "size", _shown(source), *added])
    replaced = {option for option, _ in options} - set(REPEATED)
    kept: list[str] = []
    words = list(command)
    k = 0
    while k < len(words):
        word = words[k]
        name = word.split("=", 1)[0]
        if name in OUTPUT_OPTIONS or name in replaced:
            k += 1 if "=" in word else 2
            continue
        kept.append(word)
        k += 1
    return shlex.join([*kept, *added])


REPEATED = ("--catalog", "--series")
"""Options given once per value: a step adds its value to the run's."""


def given(command: Sequence[str] | None, option: str) -> str | None:
    """The value of `option` in a command line (its last), or None."""
    found = None
    words = list(command or ())
    for k, word in enumerate(words):
        if word == option and k + 1 < len(words):
            found = words[k + 1]
        elif word.startswith(option + "="):
            found = word.split("=", 1)[1]
    return found


def _shown(path: Path) -> str:
    """A path as a user would type it here: relative below the working folder."""
    try:
        shown = os.path.relpath(path)
    except ValueError:
        return str(path)
    return str(path) if shown.startswith("..") else shown
