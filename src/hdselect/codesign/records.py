"""Co-design results as JSON documents.

What `fastest`, `--compare-ratios` and `max-payload` write, and what a study keeps
per case.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

from hdselect.codesign.bindings import Binding
from hdselect.codesign.choice import NoUnit
from hdselect.codesign.fastest_result import FastestResult, RatioComparison, TaskFastest
from hdselect.codesign.maxpayload import MaxPayloadResult
from hdselect.codesign.pathbounds import PathInfeasible
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.sizing.diagnosis import diagnosis_of, with_diagnoses
from hdselect.sizing.records import (
    candidate_json,
    finite_or_none,
    payload_json,
    size_json,
)
from hdselect.sizing.result import SizingResult


def fastest_json(result: FastestResult) -> dict[str, Any]:
    """A co-design result as JSON: the cycle, what bounds it, and every joint's check.

    A motion is a duty of one task. A mix adds ``mix``, ``units``, ``motors``, ``tasks``
    (each task's cycle, limits and binding), ``idle_share`` and ``check`` (the duty's in
    the ``size`` shape); its ``cycle_time_s``, ``moving_time_s``, ``dwell_time_s`` and
    ``optimum_s`` are its tasks' weighted by their shares, ``samples`` theirs summed,
    ``binding`` every task's stretches (each naming its ``task``), and a figure of one
    task's path (``motion``, ``payload``, a joint's limits) is null unless it has one task.
    """
    alone = result.tasks[0] if len(result.tasks) == 1 else None
    several = alone is None
    joints = []
    for joint in result.check.joints:
        (candidate,) = joint.candidates
        joints.append({
            "name": joint.name,
            "unit": candidate.unit.id,
            **_limits_json(alone, joint.name, result),
            "derating": result.derating.get(joint.name),
            "carried_mass_kg": joint.carried_mass,
            "binding_share": {limit: share for name, limit, share in result.binding_shares()
                              if name == joint.name},
            "candidate": candidate_json(candidate),
        })
    dwell = result.weighted([item.dwell_time for item in result.tasks])
    check = size_json(result.check)
    document = {
        "robot": str(result.robot.path),
        "motion": None if alone is None else str(alone.motion.path),
        "cycle_time_s": result.cycle_time,
        "moving_time_s": result.cycle_time - dwell,
        "dwell_time_s": dwell,
        "optimum_s": result.optimum,
        "slowdown": result.slowdown,
        "lengthened_by": None if result.reason is None else {
            "joint": result.reason[0], "rule": result.reason[1]},
        "grid_per_waypoint": result.grid_per_waypoint,
        "samples": sum(len(item.task.trajectory.t) for item in result.tasks),
        "feasible": result.feasible,
        "assumptions": check["assumptions"],
        "root_link": result.robot.root_link,
        "payload": None if alone is None else payload_json(alone.task.robot),
        "warnings": list(result.warnings),
        "notes": list(result.notes),
        "joints": joints,
        "binding": [_stretch_json(b, several) for b in result.binding],
    }
    if result.mix is None:
        return document
    sized = result.robot.sized_joints
    return {**document, "mix": str(result.mix.path),
            "units": {name: result.units[name].id for name in sized},
            "motors": {name: result.motors[name].id for name in sized if name in result.motors},
            "tasks": [_task_json(item, result) for item in result.tasks],
            "idle_share": result.idle, "check": check}


def no_fit_json(err: NoUnit | PathInfeasible, robot: str, source: Motion | Mix | None,
                command: Sequence[str] | None = None) -> dict[str, Any]:
    """``fastest`` where a joint has no unit that runs the path at any speed, as JSON.

    A result, not an error: ``feasible`` false, ``cycle_time_s`` null, ``joints`` empty,
    and ``no_unit``: per joint without one, its ``joint`` and the ``reason`` in words; where
    the selection found none, its ``diagnosis`` (`hdselect.sizing.diagnosis.Diagnosis`, as
    ``size --json`` writes it); where a unit given cannot run it, the ``limit`` at fault and
    whether ``gravity`` alone exceeds it.

    Args:
        err: Why (`NoUnit` from the selection, or `PathInfeasible` for the units given).
        robot: The robot file.
        source: The motion (``motion``), or the mix (``mix``, ``motion`` null).
        command: The run's command line, for the next steps' commands (`NoUnit.diagnoses`).
    """
    rows: list[dict[str, Any]]
    if isinstance(err, NoUnit):
        rows = [{"joint": name, "reason": " ".join(found.lines()), "diagnosis": found.to_dict()}
                for name, found in err.diagnoses(command).items()]
    else:
        rows = [{"joint": err.joint, "reason": str(err), "limit": err.limit,
                 "gravity": err.gravity}]
    document = {"robot": robot, "motion": str(source.path) if isinstance(source, Motion)
                else None, "cycle_time_s": None, "feasible": False, "joints": [],
                "no_unit": rows}
    return document if not isinstance(source, Mix) else {**document, "mix": str(source.path)}


def no_unit_json(sizing: SizingResult) -> list[dict[str, Any]]:
    """The joints of a sizing without a unit, as JSON.

    Each: ``joint``, the ``reason`` (its diagnosis's sentences) and the ``diagnosis``
    (`hdselect.sizing.diagnosis.Diagnosis.to_dict`).
    """
    sizing = with_diagnoses(sizing)
    return [{"joint": joint.name, "reason": " ".join(found.lines()),
             "diagnosis": found.to_dict()} for joint in sizing.joints
            if (found := diagnosis_of(sizing, joint.name)) is not None]


def _limits_json(item: TaskFastest | None, name: str, result: FastestResult) -> dict[str, Any]:
    """What bounded one joint along one task's path; nulls for a duty of several tasks."""
    lim = None if item is None else item.limits[name]
    motor = name in result.motors
    return {"velocity_limit": None if lim is None else lim.velocity,
            "velocity_limit_source": None if lim is None else lim.velocity_source,
            "acceleration_limit": None if lim is None else lim.acceleration,
            "torque_limit_nm": None if lim is None else lim.torque,
            "torque_limit_rule": None if lim is None or not lim.torque_by else lim.torque_by,
            "motor": result.motors[name].id if motor else None,
            "motor_torque_limit_nm": lim.motor_torque if motor and lim is not None else None}


def _stretch_json(b: Binding, named: bool) -> dict[str, Any]:
    """One stretch of what binds; `named`: it says its task (a duty of several)."""
    return {**({"task": b.task} if named else {}), "start_s": b.start, "end_s": b.end,
            "joint": b.joint, "limit": b.limit, "utilization": b.utilization,
            "waypoints": list(b.waypoints)}


def _task_json(item: TaskFastest, result: FastestResult) -> dict[str, Any]:
    """One task of a duty at its fastest: its cycle, its limits and what binds it."""
    task = item.task
    return {"name": task.label, "share": task.share, "motion": str(item.motion.path),
            "planned_cycle_s": item.planned, "optimum_s": item.optimum,
            "cycle_time_s": item.cycle_time,
            "cycles_per_hour": task.share * 3600.0 / item.cycle_time,
            "moving_time_s": item.cycle_time - item.dwell_time,
            "dwell_time_s": item.dwell_time, "samples": len(task.trajectory.t),
            "payload": payload_json(task.robot),
            "joints": [{"name": name, **_limits_json(item, name, result),
                        "binding_share": {limit: share for joint, limit, share
                                          in item.binding_shares() if joint == name}}
                       for name in result.robot.sized_joints],
            "binding": [_stretch_json(b, False) for b in item.binding]}


def ratios_json(comparison: RatioComparison) -> dict[str, Any]:
    """Every unit on every joint compared, as JSON; cycle times in s, null where none.

    For a mix (``mix``, its ``tasks`` at the base units as `fastest_json` gives them;
    ``motion`` null unless it has one task), each cycle time is the share-weighted mean
    of its tasks' cycles (`FastestResult.cycle_time`).
    """
    base = comparison.base
    mix = {} if comparison.mix is None else {
        "mix": str(comparison.mix.path),
        "tasks": [_task_json(item, base) for item in base.tasks]}
    return {
        "robot": str(comparison.robot.path),
        "motion": str(base.tasks[0].motion.path) if len(base.tasks) == 1 else None,
        **mix,
        "units": {name: unit.id for name, unit in comparison.units.items()},
        "cycle_time_s": base.cycle_time,
        "notes": list(base.notes),
        "joints": [{
            "name": joint.joint,
            "selected": joint.selected,
            "units": [{"unit": row.unit.id, "cycle_time_s": row.cycle_time,
                       "optimum_s": row.optimum, "feasible": row.cycle_time is not None,
                       "gravity": row.gravity, "note": row.note,
                       "binding": None if row.binding is None else {
                           "joint": row.binding[0], "limit": row.binding[1]},
                       "lengthened_by": None if row.lengthened_by is None else {
                           "joint": row.lengthened_by[0], "rule": row.lengthened_by[1]},
                       "derating": row.derating, "slowdown": row.slowdown}
                      for row in joint.rows],
        } for joint in comparison.joints],
    }


def max_payload_json(result: MaxPayloadResult, motion: Motion | None = None) -> dict[str, Any]:
    """The largest payload as JSON.

    ``max_payload_kg`` is null when no mass fits (``no_unit`` then lists the joints no
    unit fits even without the payload, as `no_unit_json`) and ``unlimited`` true when no
    rule depends on the mass. A motion is a duty of one task. A mix's answer is a factor on
    the payloads of its tasks in ``scaled``: it adds ``mix``, ``factor``, ``scaled``,
    ``payloads_kg`` (their masses there), ``given_kg`` and ``ranges`` (of the factor);
    ``max_payload_kg``, ``payload`` and ``ranges_kg`` are of the one task that scales
    (null when several do), ``motion`` of its one task (null when it has several).

    Args:
        result: The largest payload.
        motion: The motion named (default: the one task's, where the duty has one).
    """
    x = result.mass
    finite = x is not None and math.isfinite(x)
    selection = result.selection
    mix = result.mix
    if motion is None and len(result.tasks) == 1:
        motion = result.tasks[0].motion
    if mix is None:
        per_kg: float | None = 1.0  # one motion's payload is its shape at 1 kg
    else:
        per_kg = (next(iter(result.payloads.values())).mass if len(result.payloads) == 1
                  else None)
    payload = result.payload
    document = {
        "robot": None if selection is None else str(selection.robot.path),
        "motion": None if motion is None else str(motion.path),
        "max_payload_kg": None if per_kg is None else finite_or_none(
            None if x is None else x * per_kg),
        "unlimited": x is not None and not finite,
        "payload": None if per_kg is None else {
            "part": payload.name or None,
            "frame": result.frame, "frame_given": payload.frame is not None,
            "com_m": list(payload.com),
            "inertia_kg_m2_per_kg": [[value / per_kg for value in row]
                                     for row in payload.inertia]},
        "ranges_kg": None if per_kg is None else [
            [lo * per_kg, finite_or_none(hi * per_kg)] for lo, hi in result.ranges],
        "binding": None if result.joint is None else {
            "joint": result.joint, "unit": result.unit.id if result.unit else None,
            "rule": result.rule},
        "selection": None if selection is None else size_json(
            selection if mix is not None or motion is None
            else replace(selection, motion=motion)),
        "no_unit": [] if result.unloaded is None else no_unit_json(result.unloaded),
    }
    if mix is None:
        return document
    return {**document, "mix": str(mix.path), "factor": finite_or_none(x),
            "scaled": list(result.scaled), "payloads_kg": result.masses() if finite else None,
            "given_kg": {name: item.mass for name, item in result.payloads.items()},
            "ranges": [[lo, finite_or_none(hi)] for lo, hi in result.ranges]}


_RENAMED = {"mix_fastest_json": ("fastest_json", fastest_json),
            "mix_payload_json": ("max_payload_json", max_payload_json)}


def __getattr__(name: str) -> Any:
    """The mix's old writers, with a DeprecationWarning naming the one writer."""
    if name in _RENAMED:
        new, value = _RENAMED[name]
        warnings.warn(f"hdselect.codesign.records.{name} is deprecated: use "
                      f"hdselect.codesign.records.{new} (it writes a mix and a motion)",
                      DeprecationWarning, stacklevel=2)
        return value
    raise AttributeError(f"module 'hdselect.codesign.records' has no attribute {name!r}")
