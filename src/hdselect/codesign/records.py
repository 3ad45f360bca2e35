"""Co-design results as JSON documents.

What `fastest`, `--compare-ratios` and `max-payload` write, and what a study keeps
per case.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from hdselect.codesign.fastest_cycle import FastestResult, RatioComparison
from hdselect.codesign.maxpayload import MaxPayloadResult
from hdselect.motion.motionfile import Motion
from hdselect.sizing.records import (
    candidate_json,
    finite_or_none,
    payload_json,
    size_json,
)


def fastest_json(result: FastestResult) -> dict[str, Any]:
    """A co-design result as JSON: the cycle, what bounds it, and every joint's check."""
    motion = result.motion
    dwell = float(np.sum(motion.dwells))
    joints = []
    for joint in result.check.joints:
        (candidate,) = joint.candidates
        lim = result.limits[joint.name]
        joints.append({
            "name": joint.name,
            "unit": candidate.unit.id,
            "velocity_limit": lim.velocity,
            "velocity_limit_source": lim.velocity_source,
            "acceleration_limit": lim.acceleration,
            "torque_limit_nm": lim.torque,
            "motor": result.motors[joint.name].id if joint.name in result.motors else None,
            "motor_torque_limit_nm": (lim.motor_torque if joint.name in result.motors
                                      else None),
            "derating": result.derating.get(joint.name),
            "carried_mass_kg": joint.carried_mass,
            "binding_share": {limit: share for name, limit, share in result.binding_shares()
                              if name == joint.name},
            "candidate": candidate_json(candidate),
        })
    return {
        "robot": str(result.robot.path),
        "motion": str(motion.path),
        "cycle_time_s": result.cycle_time,
        "moving_time_s": result.cycle_time - dwell,
        "dwell_time_s": dwell,
        "optimum_s": result.optimum,
        "slowdown": result.slowdown,
        "lengthened_by": None if result.reason is None else {
            "joint": result.reason[0], "rule": result.reason[1]},
        "grid_per_waypoint": result.grid_per_waypoint,
        "samples": len(result.trajectory.t),
        "feasible": result.feasible,
        "assumptions": size_json(result.check)["assumptions"],
        "root_link": result.robot.root_link,
        "payload": payload_json(result.robot),
        "warnings": list(result.warnings),
        "joints": joints,
        "binding": [{"start_s": b.start, "end_s": b.end, "joint": b.joint, "limit": b.limit,
                     "utilization": b.utilization, "waypoints": list(b.waypoints)}
                    for b in result.binding],
    }


def ratios_json(comparison: RatioComparison) -> dict[str, Any]:
    """Every unit on every joint compared, as JSON; cycle times in s, null where none.

    For a mix (``mix``, its ``tasks`` at the base units), each cycle time is the
    share-weighted mean of its tasks' cycles (`FastestResult.mean_cycle_time`).
    """
    mix = {} if comparison.mix is None else {
        "mix": str(comparison.mix.path),
        "tasks": [{"name": item.task.label, "share": item.task.share,
                   "cycle_time_s": item.cycle_time} for item in comparison.base.tasks]}
    return {
        "robot": str(comparison.robot.path),
        "motion": str(comparison.motion.path),
        **mix,
        "units": {name: unit.id for name, unit in comparison.units.items()},
        "cycle_time_s": comparison.base.mean_cycle_time,
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


def max_payload_json(result: MaxPayloadResult, motion: Motion) -> dict[str, Any]:
    """The largest payload as JSON.

    ``max_payload_kg`` is null when no mass fits and ``unlimited`` true when no rule
    depends on the mass.
    """
    payload = result.payload
    selection = None
    if result.selection is not None:
        selection = size_json(replace(result.selection, motion=motion))
    return {
        "robot": str(result.selection.robot.path) if result.selection else None,
        "motion": str(motion.path),
        "max_payload_kg": finite_or_none(result.mass),
        "unlimited": result.mass is not None and not math.isfinite(result.mass),
        "payload": {"frame": result.frame, "frame_given": payload.frame is not None,
                    "com_m": list(payload.com),
                    "inertia_kg_m2_per_kg": [list(row) for row in payload.inertia]},
        "ranges_kg": [[lo, finite_or_none(hi)] for lo, hi in result.ranges],
        "binding": None if result.joint is None else {
            "joint": result.joint, "unit": result.unit.id if result.unit else None,
            "rule": result.rule},
        "selection": selection,
    }


def mix_payload_json(result: MaxPayloadResult) -> dict[str, Any]:
    """The largest payloads of a mix as JSON.

    ``factor`` multiplies each task's payload named in ``scaled`` (mass and inertia);
    ``payloads_kg`` gives their masses there. ``factor`` is null when no factor fits and
    ``unlimited`` true when no rule depends on it.
    """
    finite = result.factor is not None and math.isfinite(result.factor)
    selection = result.selection
    return {
        "robot": None if selection is None else str(selection.robot.path),
        "mix": None if selection is None or selection.mix is None else str(selection.mix.path),
        "factor": finite_or_none(result.factor),
        "unlimited": result.factor is not None and not finite,
        "scaled": list(result.scaled),
        "payloads_kg": result.masses() if finite else None,
        "given_kg": {name: payload.mass for name, payload in result.payloads.items()},
        "ranges": [[lo, finite_or_none(hi)] for lo, hi in result.ranges],
        "binding": None if result.joint is None else {
            "joint": result.joint, "unit": result.unit.id if result.unit else None,
            "rule": result.rule},
        "selection": None if selection is None else size_json(selection),
    }


def mix_fastest_json(result: FastestResult) -> dict[str, Any]:
    """The shortest cycle of each task of a mix as JSON, with the duty's check (``check``).

    ``motors`` names the motor of each joint that has one.
    """
    sized = result.robot.sized_joints
    return {
        "robot": str(result.check.robot.path),
        "mix": str(result.mix.path if result.mix is not None else result.motion.path),
        "units": {name: result.units[name].id for name in sized},
        "motors": {name: result.motors[name].id for name in sized if name in result.motors},
        "tasks": [{"name": item.task.label, "share": item.task.share,
                   "planned_cycle_s": item.planned, "optimum_s": item.optimum,
                   "cycle_time_s": item.cycle_time,
                   "cycles_per_hour": item.task.share * 3600.0 / item.cycle_time}
                  for item in result.tasks],
        "idle_share": result.idle,
        "slowdown": result.slowdown,
        "lengthened_by": None if result.reason is None else {
            "joint": result.reason[0], "rule": result.reason[1]},
        "feasible": result.feasible,
        "check": size_json(result.check),
    }
