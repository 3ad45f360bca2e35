"""Write results as JSON and CSV, atomically: a file is complete or absent."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.catalog import SeriesRules, Unit
from hdselect.codesign import FastestResult, RatioComparison
from hdselect.duty import DutyResult
from hdselect.joints import JointInfo
from hdselect.loads import JointLoad
from hdselect.maxpayload import MaxPayloadResult
from hdselect.motion import Motion
from hdselect.motors import Motor
from hdselect.outputs import write_file
from hdselect.planning import Trajectory
from hdselect.robot import Robot
from hdselect.rules import RPM_PER_RAD_S, Candidate, Check
from hdselect.sizing import SizingResult

MOTOR_MODEL_NOTE = ("peak: every sample's motor torque under the motor's torque-speed curve (its "
                    "flat peak torque without one); rms: the RMS torque of one cycle repeated "
                    "back to back against the rated torque, with no thermal model (no thermal "
                    "time constants), no drive current limit and no bus voltage beyond the "
                    "curve; speed: the largest input speed against the motor's maximum")
MEAN_SPEED_NOTE = ("mean speed averages the moving part of the cycle only (the catalog page's "
                   "t1..t3); dwells do not dilute it, which is the conservative reading")
WHOLE_CYCLE_NOTE = ("mean speed follows each unit's series rules: over the whole cycle, dwells "
                    "included, where its catalog's [rules] say mean_speed = \"whole-cycle\"; "
                    "over the moving part only where they say \"moving\"")

_CSV_ROWS = 1 << 14
"""Rows of a trajectory CSV formatted at a time."""
HOLD_NOTE = ("hold only: nothing moves in this cycle, so only holding the pose (static) and an "
             "emergency stop (momentary) are checked; mean torque, speed and life do not apply")
"""The note on a cycle in which nothing moves (``"hold_only": true`` in JSON)."""


def mean_speed_note(units: Iterable[Unit]) -> str:
    """How the mean speed of these units is taken, for reports."""
    if all(unit.rules.mean_speed == "moving" for unit in units):
        return MEAN_SPEED_NOTE
    return WHOLE_CYCLE_NOTE


def write_output(target: str | Path, write: Callable[[Any], None], *,
                 binary: bool = False) -> None:
    """Write a file atomically (temporary file, then rename); ``-`` is standard output.

    The same as `hdselect.outputs.write_file`: a symlink is followed and its target
    replaced; a character device or a FIFO (``/dev/null``, a named pipe) is written
    directly, never replaced. For several outputs that must appear together, see
    `hdselect.outputs.Outputs`.

    Args:
        target: The file, or ``-``.
        write: Writes the content to the open stream it is given.
        binary: Open the file in binary mode (text, UTF-8, otherwise).

    Raises:
        InputError: The file cannot be written.
    """
    write_file(target, write, binary=binary)


def write_json(target: str | Path, document: dict[str, Any]) -> None:
    """Write a JSON document to a file or ``-`` (standard output).

    Strict JSON: a number that is not finite is an error (ValueError), never ``NaN``.
    """
    text = json.dumps(document, indent=2, allow_nan=False) + "\n"

    def write(stream: Any) -> None:
        stream.write(text)

    write_output(target, write)


def check_json(check: Check) -> dict[str, Any]:
    """One check as JSON: value, limit, ok, utilization and any detail."""
    document: dict[str, Any] = {"value": _finite(check.value), "limit": _finite(check.limit),
                                "ok": check.ok, "utilization": _finite(check.utilization)}
    document.update({key: _finite(value) for key, value in check.detail.items()})
    return document


def candidate_json(candidate: Candidate) -> dict[str, Any]:
    """One candidate as JSON, the shape shared by ``duty`` and ``size`` (which adds ``motor``)."""
    unit = candidate.unit
    document: dict[str, Any] = {
        "unit": unit.id,
        "size": unit.size,
        "ratio": unit.ratio,
        "feasible": candidate.feasible,
        "life_hours": _finite(candidate.life_hours),
        "l10_hours": _finite(candidate.l10_hours),
        "flags": sorted({flag.code for flag in candidate.flags}),
        "notes": [flag.note for flag in candidate.flags],
        "binding": candidate.binding,
        "rules": rules_json(unit.rules),
        "checks": {name: check_json(check) for name, check in candidate.checks.items()},
    }
    motor = candidate.motor
    if motor is not None:
        document["motor"] = {"peak_torque_nm": motor.peak_torque,
                             "rms_torque_nm": motor.rms_torque,
                             "max_speed_rpm": motor.max_speed,
                             "efficiency": motor.efficiency,
                             "rms_speed_rpm": motor.rms_speed}
        if candidate.motor_unit is not None:
            document["motor"]["id"] = candidate.motor_unit.id
            document["gearhead_binding"] = candidate.gearhead_binding
            document["motor_binding"] = candidate.motor_binding
    return document


def motor_json(motor: Motor) -> dict[str, Any]:
    """One motor's data as JSON, in SI (speeds in rpm)."""
    return {"id": motor.id, "rated_torque_nm": motor.rated_torque,
            "peak_torque_nm": motor.peak_torque, "max_speed_rpm": motor.max_speed,
            "rated_speed_rpm": motor.rated_speed, "rotor_inertia_kg_m2": motor.rotor_inertia,
            "mass_kg": motor.mass, "torque_constant_nm_per_a": motor.torque_constant,
            "resistance_ohm": motor.resistance,
            "curve": None if motor.curve is None else [list(p) for p in motor.curve],
            "source": None if motor.source is None else str(motor.source)}


def rules_json(rules: SeriesRules) -> dict[str, Any]:
    """A series' rules as JSON; ``assumed`` when the unit's catalog file states none."""
    return {"rated_input_speed_rpm": rules.rated_input_speed,
            "rated_life_hours": rules.rated_life_hours, "life_basis": rules.life_basis,
            "mean_torque_limit": rules.mean_torque_limit, "mean_speed": rules.mean_speed,
            "max_momentary_events": rules.max_momentary_events,
            "assumed": rules.flag is not None}


def duty_json(result: DutyResult) -> dict[str, Any]:
    """A duty-cycle result as JSON; each candidate's life on both bases (L50 and L10)."""
    load = result.load
    return {
        "profile": str(result.cycle.path),
        "mean_torque_nm": _finite(load.mean_torque),
        "mean_output_speed_rpm": load.mean_speed * RPM_PER_RAD_S,
        "cycle_mean_output_speed_rpm": load.cycle_mean_speed * RPM_PER_RAD_S,
        "cycle_time_s": load.cycle_time,
        "peak_torque_nm": load.peak_torque,
        "required_life_hours": result.cycle.life_hours,
        "life_basis": result.cycle.life_basis,
        "mean_speed_rule": mean_speed_note(c.unit for c in result.candidates),
        "selected": result.selected.unit.id if result.selected else None,
        "hold_only": result.hold_only,
        "candidates": [candidate_json(c) for c in result.candidates],
    }


def catalog_json(units: Iterable[Unit]) -> dict[str, Any]:
    """The catalog as JSON, in SI, with flags."""
    return {"units": [{
        "unit": u.id, "series": u.series, "size": u.size, "ratio": u.ratio,
        "rated_torque_nm": u.rated_torque, "repeated_torque_nm": u.repeated_torque,
        "momentary_torque_nm": u.momentary_torque, "static_torque_nm": u.static_torque,
        "max_input_speed_rpm": u.max_input_speed, "input_inertia_kg_m2": u.input_inertia,
        "mass_kg": u.mass, "efficiency_table": u.efficiency is not None,
        "flags": [{"field": f.field, "kind": f.kind, "note": f.note} for f in u.flags],
        "source": str(u.source),
    } for u in units]}


def assumptions(result: SizingResult) -> dict[str, str]:
    """The assumptions of a sizing run, as text for reports."""
    options = result.options
    if result.motors:
        files = sorted({m.source.name if m.source is not None else "given in Python"
                        for ms in result.motors.values() for m in ms})
        bare = [j.name for j in result.joints if j.name not in result.motors]
        motor = {"motors": (f"chosen with each gearhead from {', '.join(files)} (rotor inertia "
                            "in the motor torque and the crash, mass carried)"
                            + (f"; none for {', '.join(bare)}: rotor inertia and mass not "
                               "included there" if bare else ""))}
    elif options.rotor_inertia == 0.0 and options.motor_mass == 0.0:
        motor = {"motor": "none given: motor rotor inertia and mass not included"}
    else:
        motor = {"motor rotor inertia": f"{options.rotor_inertia:g} kg m^2",
                 "motor mass": f"{options.motor_mass:g} kg"}
    return {
        "efficiency": f"{options.efficiency:.2f} (where a unit has no table)",
        "stop time": f"{options.stop_time:g} s (emergency stop and crash)",
        **motor,
        "mass coupling": (("on: each chosen gearhead's and motor's mass is carried by the joints "
                           "nearer the base" if result.motors else
                           "on: each chosen unit's mass is carried by the joints nearer the base")
                          if options.mass_coupling else "off"),
        "selection": str(options.prefer),
        "required life": ("none" if options.life_hours is None
                          else f"{options.life_hours:g} h ({options.life_basis})"),
        "mean speed": mean_speed_note(result.units).removeprefix("mean speed "),
        "joint losses": JOINT_LOSSES_NOTE,
    }


JOINT_LOSSES_NOTE = ("the robot file's armature, joint damping, friction and springs are the "
                     "motor's and the joint's own, not load on the gear output: left out")


def base_text(robot: Robot) -> str:
    """The fixed link and the payload in a line, for headers."""
    payload = robot.payload
    if payload is None:
        carried = f"none (a payload would go on '{robot.payload_frame}')"
    else:
        com = ", ".join(f"{c:g}" for c in payload.com)
        carried = f"{payload.mass:g} kg on '{robot.payload_frame}', centre of mass ({com}) m"
    return f"base: '{robot.root_link}' held fixed; payload: {carried}"


def payload_json(robot: Robot) -> dict[str, Any]:
    """The payload as JSON: mass 0 when none; the frame it is (or would be) attached to."""
    payload = robot.payload
    return {"mass_kg": 0.0 if payload is None else payload.mass,
            "frame": robot.payload_frame,
            "frame_given": payload is not None and payload.frame is not None,
            "com_m": [0.0, 0.0, 0.0] if payload is None else list(payload.com),
            "inertia_kg_m2": [[0.0] * 3] * 3 if payload is None
            else [list(row) for row in payload.inertia]}


def joints_json(robot: Robot, infos: Iterable[JointInfo]) -> dict[str, Any]:
    """A robot's joints as JSON (``hdselect joints --json``), in SI; null for no limit."""
    joints = []
    for info in infos:
        linear = info.kind == "prismatic"
        joints.append({
            "name": info.name, "index": info.index, "type": info.kind, "sized": info.sized,
            "lower": _finite(info.lower), "upper": _finite(info.upper),
            "unit": "m" if linear else "rad",
            "velocity_limit": _finite(info.velocity_limit),
            "effort_limit": _finite(info.effort_limit),
            "moved_mass_kg": info.moved_mass, "leader": info.leader,
            "multiplier": info.multiplier if info.leader else None,
            "offset": info.offset if info.leader else None})
    return {"robot": str(robot.path), "root_link": robot.root_link,
            "payload_frame": robot.default_payload_frame,
            "list_order": list(robot.joint_names),
            "file_order": None if robot.file_order is None else list(robot.file_order),
            "notes": list(robot.notes), "joints": joints}


def joint_load_json(load: JointLoad) -> dict[str, Any]:
    """One joint's load over the cycle as JSON, in SI (N m or N, rad or m)."""
    linear = load.linear
    force, per_s, position = ("n", "m_s", "m") if linear else ("nm", "rad_s", "rad")
    return {"name": load.name, "type": load.kind, "sized": load.sized, "note": load.note,
            "leader": load.leader,
            f"peak_{'force' if linear else 'torque'}_{force}": load.peak,
            f"effort_limit_{force}": _finite(load.effort_limit),
            f"max_speed_{per_s}": load.max_speed,
            f"velocity_limit_{per_s}": _finite(load.velocity_limit),
            f"travel_{position}": list(load.travel),
            "above_effort_limit": load.above_effort,
            "above_velocity_limit": load.above_velocity}


def size_json(result: SizingResult) -> dict[str, Any]:
    """A sizing result as JSON; each candidate has the ``duty`` shape plus ``motor``."""
    options = result.options
    joints = []
    for joint in result.joints:
        slowdown = joint.slowdown
        document: dict[str, Any] = {
            "name": joint.name,
            "selected": joint.selected.unit.id if joint.selected else None,
            "binding": joint.selected.binding if joint.selected else None,
            "carried_mass_kg": joint.carried_mass,
            "gravity_loaded": joint.gravity_loaded,
            "max_gravity_torque_nm": joint.max_gravity_torque,
            "peak_torque_nm": joint.load.peak_torque,
            "mean_torque_nm": joint.load.mean_torque,
            "mean_output_speed_rpm": joint.load.mean_speed * RPM_PER_RAD_S,
            "effort_limit_nm": _finite(float(
                result.robot.effort_limit[result.robot.joint_index(joint.name)]) or math.inf),
            "slowdown": None if slowdown is None else {
                "factor": slowdown.factor, "unit": slowdown.unit,
                "cycle_time_s": slowdown.cycle_time},
            "time_scales": None if joint.scales is None else {
                unit: [[lo, _finite(hi)] for lo, hi in intervals]
                for unit, intervals in joint.scales.fits.items()},
            "candidates": [candidate_json(c) for c in joint.candidates],
        }
        if joint.name in result.motors:
            chosen = joint.selected
            document.update({
                "selected_motor": (chosen.motor_unit.id if chosen is not None
                                   and chosen.motor_unit is not None else None),
                "gearhead_binding": chosen.gearhead_binding if chosen else None,
                "motor_binding": chosen.motor_binding if chosen else None,
                "load_inertia_kg_m2": joint.load_inertia,
                "inertia_ratio": None if chosen is None else joint.inertia_ratio(chosen)})
            for candidate, entry in zip(joint.candidates, document["candidates"], strict=True):
                entry["motor"]["inertia_ratio"] = joint.inertia_ratio(candidate)
        joints.append(document)
    return {
        "robot": str(result.robot.path),
        "motion": None if result.motion is None else str(result.motion.path),
        "cycle_time_s": result.cycle_time,
        "samples": len(result.trajectory.t),
        "feasible": result.feasible,
        "hold_only": result.hold_only,
        "assumptions": {
            "efficiency": options.efficiency, "stop_time_s": options.stop_time,
            "rotor_inertia_kg_m2": options.rotor_inertia, "motor_mass_kg": options.motor_mass,
            "mass_coupling": options.mass_coupling, "prefer": options.prefer,
            "life_hours": options.life_hours, "life_basis": options.life_basis,
            "mean_speed_rule": mean_speed_note(result.units),
            "joint_losses": JOINT_LOSSES_NOTE,
            "motors": ({name: [m.id for m in ms] for name, ms in result.motors.items()}
                       if result.motors else None),
            "motor_rules": MOTOR_MODEL_NOTE if result.motors else None},
        "motors": [motor_json(m) for m in _distinct(result.motors)],
        "joints": joints,
        "root_link": result.robot.root_link,
        "payload": payload_json(result.robot),
        "warnings": list(result.warnings),
        "joint_loads": [joint_load_json(load) for load in result.loads],
    }


def write_trajectory_csv(target: str | Path, trajectory: Trajectory, tau: Any,
                         joints: Iterable[str]) -> None:
    """One row per sample: t, then q_, qd_, qdd_, tau_ of every listed joint (SI).

    A prismatic joint's columns are in m, m/s, m/s^2 and N.
    """
    names = list(trajectory.joint_names)
    columns = [names.index(name) for name in joints]
    header = ["t"] + [f"{kind}_{names[j]}" for j in columns
                      for kind in ("q", "qd", "qdd", "tau")]

    def rows(part: slice) -> np.ndarray:
        return np.column_stack([trajectory.t[part]] + [
            array[part, j] for j in columns
            for array in (trajectory.q, trajectory.qd, trajectory.qdd, tau)])

    def write(stream: Any) -> None:
        stream.write(",".join(header) + "\n")
        for start in range(0, len(trajectory.t), _CSV_ROWS):  # bounded memory, any length
            np.savetxt(stream, rows(slice(start, start + _CSV_ROWS)), fmt="%.10g",
                       delimiter=",")

    write_output(target, write)


def _distinct(motors: Any) -> list[Motor]:
    """Every motor of a joint -> motors mapping once, in order of appearance."""
    seen: dict[tuple[str, str | None], Motor] = {}
    for candidates in motors.values():
        for motor in candidates:
            seen.setdefault((motor.id, str(motor.source)), motor)
    return list(seen.values())


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value




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
    """Every unit on every joint compared, as JSON; cycle times in s, null where none."""
    return {
        "robot": str(comparison.robot.path),
        "motion": str(comparison.motion.path),
        "units": {name: unit.id for name, unit in comparison.units.items()},
        "cycle_time_s": comparison.base.cycle_time,
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
        "max_payload_kg": _finite(result.mass),
        "unlimited": result.mass is not None and not math.isfinite(result.mass),
        "payload": {"frame": result.frame, "frame_given": payload.frame is not None,
                    "com_m": list(payload.com),
                    "inertia_kg_m2_per_kg": [list(row) for row in payload.inertia]},
        "ranges_kg": [[lo, _finite(hi)] for lo, hi in result.ranges],
        "binding": None if result.joint is None else {
            "joint": result.joint, "unit": result.unit.id if result.unit else None,
            "rule": result.rule},
        "selection": selection,
    }
