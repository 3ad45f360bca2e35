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
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

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
        catalog: The catalog (``--catalog`` argument) of a ``catalog`` step; else None.
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
                   catalogs: Mapping[str, Sequence[Unit]]) -> dict[str, list[NextStep]]:
    """Per joint, the shipped series whose smallest holding unit is smallest, verified.

    Each catalog's units are first checked against the joint's cycle as sized (the same
    rules, the same carried masses); the best catalog is then verified by sizing the
    whole duty with it added, as ``--catalog`` does, and offered only where that sizing
    gives the joint a unit (the unit it gives is the one named).
    """
    have = {unit.id for unit in result.units}
    offered = {name: tuple(units) for name, units in catalogs.items()
               if any(unit.id not in have for unit in units)}
    if not offered:
        return {}
    samples = pooled(tasks, result.idle)
    options = result.options
    best: dict[str, list[tuple[tuple[float, float], str]]] = {}
    for joint in missing:
        cycle = JointCycle(samples, result.robot.joint_index(joint.name), joint.torque,
                           joint.stop_torque, joint.wrench,
                           options.bearing_offset.get(joint.name, 0.0))
        for name, units in offered.items():
            fresh = tuple(u for u in units if u.id not in have)
            found = size_joint(joint.name, cycle, fresh, options,
                               motors=result.motors.get(joint.name, ()), detail=False)
            if found.selected is not None:
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
            if chosen is not None:
                out[joint.name] = [NextStep(
                    "catalog", f"the {name} catalog holds it with {chosen.label}",
                    _command(result, f"--catalog {name}"), chosen.label, catalog=name)]
                break
    return out


def payload_steps(result: SizingResult, missing: Sequence[JointSizing], tasks: Sequence[Task],
                   masses: Mapping[str, float],
                   payload_bounds: PayloadBounds | None) -> dict[str, list[NextStep]]:
    """Per joint, the largest payload at which some candidate holds it, verified by sizing."""
    scaled = [task.label for task in tasks if task.robot.payload is not None]
    if payload_bounds is None or not scaled or any(
            task.motion is not None and task.motion.planner == "toppra"
            and task.motion.torque_limit is not None for task in tasks):
        return {}  # no payload, or a trajectory that depends on it
    bounds = payload_bounds(tasks, result.idle, scaled, masses, result.units, result.options)
    single = len(tasks) == 1
    out: dict[str, list[NextStep]] = {}
    for joint in missing:
        ends = [min(b.masses[1], 1.0) for b in bounds[joint.name]
                if b.masses is not None and b.masses[0] <= min(b.masses[1], 1.0)]
        if not ends:
            continue
        factor = max(ends)
        if single:
            mass = tasks[0].robot.payload.mass  # type: ignore[union-attr]
            kg = math.floor(factor * mass / PAYLOAD_STEP) * PAYLOAD_STEP
            factor = kg / mass
        else:
            factor = math.floor(factor / PAYLOAD_STEP) * PAYLOAD_STEP
        if factor <= 0.0:
            continue
        lighter = tuple(_scaled(task, factor) if task.label in scaled else task
                        for task in tasks)
        check = size_tasks(lighter, result.units, result.options,
                           motors=result.motors or None, idle=result.idle, slowdowns=False)
        chosen = next(j for j in check.joints if j.name == joint.name).selected
        if chosen is None:
            continue
        if single:
            text = f"a payload of {kg:.2f} kg (not more) lets {chosen.label} hold it"
            command = _command(result, f"--payload {kg:.2f}")
            out[joint.name] = [NextStep("payload", text, command, chosen.label, kg)]
        else:
            carried = ", ".join(f"{task.label} {task.robot.payload.mass:.3g} kg"
                                for task in lighter if task.label in scaled
                                and task.robot.payload is not None)
            out[joint.name] = [NextStep(
                "payload", f"the payloads scaled by {factor:.2f} ({carried}) let "
                f"{chosen.label} hold it", None, chosen.label, factor)]
    return out


def _scaled(task: Task, factor: float) -> Task:
    """The task with its payload `factor` times as heavy (mass and inertia alike)."""
    payload = task.robot.payload
    assert payload is not None
    lighter = replace(payload, mass=payload.mass * factor,
                      inertia=tuple(tuple(x * factor for x in row) for row in payload.inertia))
    return replace(task, robot=task.robot.with_payload(lighter))


def exclude_step(result: SizingResult, joint: str) -> NextStep:
    """Leave the joint out of the sizing: it still moves and loads the others."""
    left_out = [load.name for load in result.loads
                if not load.sized and load.kind == "revolute" and load.leader is None]
    names = ",".join([*left_out, joint])
    return NextStep("exclude", "size the other joints without it",
                    _command(result, f"--exclude {names}"))


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


def _command(result: SizingResult, option: str) -> str | None:
    """``hdselect size FILE OPTION`` for the result's motion (or mix) file; None without one."""
    source = result.mix.path if result.mix is not None else (
        result.motion.path if result.motion is not None else None)
    if source is None:
        return None
    return f"hdselect size {_shown(source)} {option}"


def _shown(path: Path) -> str:
    """A path as a user would type it here: relative below the working folder."""
    try:
        shown = os.path.relpath(path)
    except ValueError:
        return str(path)
    return str(path) if shown.startswith("..") else shown
