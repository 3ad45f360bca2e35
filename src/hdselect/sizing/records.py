"""A sizing result as a JSON document: the shape `hdselect size --json` writes.

Studies keep the same shape per case, so the document is built here, beside the
result, and written by `hdselect.report.export`. Every assumption is stated in it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

from hdselect.catalog.bearing_rules import NOT_RATED, BearingLoad
from hdselect.catalog.checks import life_capped, reported_life
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import LIFE_CHECKS, RPM_PER_RAD_S, Candidate, Check
from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS
from hdselect.catalog.units import MeanSpeed, SeriesRules, Unit
from hdselect.motion.mixfile import SECONDS_PER_HOUR
from hdselect.robot.model import Robot
from hdselect.robot.mounting import NAMED_BASES, mounting_name, shown_numbers
from hdselect.robot.payload import Payload
from hdselect.sizing.diagnosis import diagnosis_of, with_diagnoses
from hdselect.sizing.loads import JointLoad
from hdselect.sizing.precision_records import (
    precision_json,
    targets_json,
    targets_text,
)
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.summary import carrying_at, duty_events_text, event_records, peak_sample
from hdselect.sizing.tasks import cycle_of

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


HOLD_NOTE = ("hold only: nothing moves in this cycle, so only holding the pose (static) and an "
             "emergency stop (momentary) are checked; mean torque, speed and life do not apply")
"""The note on a cycle in which nothing moves (``"hold_only": true`` in JSON)."""


def mean_speed_note(units: Iterable[Unit]) -> str:
    """How the mean speed of these units is taken, for reports."""
    if all(unit.rules.mean_speed is MeanSpeed.MOVING for unit in units):
        return MEAN_SPEED_NOTE
    return WHOLE_CYCLE_NOTE


def check_json(check: Check, *, life: bool = False) -> dict[str, Any]:
    """One check as JSON: value, limit, ok, utilization and any detail.

    A life's check (`life`) reports its value within `hdselect.catalog.checks.LIFE_CAP`, with
    ``capped``.
    """
    value = reported_life(check.value) if life else check.value
    document: dict[str, Any] = {"value": finite_or_none(value),
                                "limit": finite_or_none(check.limit),
                                "ok": check.ok, "utilization": finite_or_none(check.utilization)}
    if life:
        document["capped"] = life_capped(check.value)
    document.update({key: finite_or_none(value) for key, value in check.detail.items()})
    return document


def candidate_json(candidate: Candidate) -> dict[str, Any]:
    """One candidate as JSON, the shape shared by ``duty`` and ``size`` (which adds ``motor``)."""
    unit = candidate.unit
    document: dict[str, Any] = {
        "unit": unit.id,
        "size": unit.size,
        "ratio": unit.ratio,
        "feasible": candidate.feasible,
        "life_hours": finite_or_none(reported_life(candidate.life_hours)),
        "l10_hours": finite_or_none(reported_life(candidate.l10_hours)),
        "life_capped": life_capped(candidate.life_hours),
        "l10_capped": life_capped(candidate.l10_hours),
        "flags": sorted({flag.code for flag in candidate.flags}),
        "notes": [flag.note for flag in candidate.flags],
        "binding": candidate.binding,
        "margin_required": candidate.required_margin,
        "rules": rules_json(unit.rules),
        "checks": {name: check_json(check, life=name in LIFE_CHECKS)
                   for name, check in candidate.checks.items()},
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
            "source": None if motor.source is None else str(motor.source),
            "max_inertia_ratio": motor.max_inertia_ratio}


def rules_json(rules: SeriesRules) -> dict[str, Any]:
    """A series' rules as JSON; ``assumed`` when the unit's catalog file states none."""
    return {"rated_input_speed_rpm": rules.rated_input_speed,
            "rated_life_hours": rules.rated_life_hours, "life_basis": rules.life_basis,
            "mean_torque_limit": rules.mean_torque_limit, "mean_speed": rules.mean_speed.value,
            "max_momentary_events": rules.max_momentary_events,
            "assumed": rules.flag is not None,
            "bearing_load_factor": rules.bearing_load_factor,
            "bearing_static_safety": rules.bearing_static_safety}


def bearing_load_json(load: BearingLoad) -> dict[str, Any]:
    """An output bearing's loads over the cycle as JSON, in SI (N, N m, m)."""
    return {"offset_m": load.offset, "spread_m": load.spread,
            "max_moment_nm": load.max_moment, "max_radial_n": load.max_radial,
            "max_axial_n": load.max_axial, "mean_moment_nm": load.mean_moment,
            "mean_radial_n": load.mean_radial, "mean_axial_n": load.mean_axial}


def bearing_rating_json(unit: Unit) -> dict[str, Any]:
    """What a unit's catalog rates its output bearing for, in SI; ``rated`` false if nothing."""
    rating = unit.bearing
    if rating is None:
        return {"rated": False, "note": NOT_RATED}
    return {"rated": True, "pitch_diameter_m": rating.pitch_diameter,
            "dynamic_rating_n": rating.dynamic_rating, "static_rating_n": rating.static_rating,
            "max_moment_nm": rating.max_moment, "max_radial_n": rating.max_radial,
            "max_axial_n": rating.max_axial, "offset_m": rating.offset}


def candidate_bearing_json(candidate: Candidate) -> dict[str, Any]:
    """What one unit's catalog rates its output bearing for, and its figures on this cycle."""
    document = bearing_rating_json(candidate.unit)
    figures = candidate.bearing
    if figures is not None:
        document.update({
            "loads": bearing_load_json(figures.load),
            "mean_output_speed_rpm": figures.mean_speed,
            "equivalent_load_n": figures.equivalent_load,
            "load_factors": None if figures.factors is None else list(figures.factors),
            "life_l10_hours": finite_or_none(reported_life(figures.life_hours)),
            "life_capped": life_capped(figures.life_hours),
            "static_load_n": figures.static_load,
            "static_safety": finite_or_none(figures.static_safety)})
    return document


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
                          + ("; where none fits, the strongest unit's" if any(
                              j.selected is None for j in result.joints) else "")
                          if options.mass_coupling else "off"),
        "selection": (options.prefer or (DEFAULT_PREFER_WITH_MOTORS if result.motors
                                         else DEFAULT_PREFER)) + (
            f" (target load-to-rotor inertia ratio {options.inertia_target:g})"
            if options.prefer == "inertia" else ""),
        # stated where it changes the judgement: the HTML summary and the JSON always state them
        **({"design margin": margin_text(options.margin)} if options.margin > 0.0 else {}),
        **({"largest inertia ratio": inertia_limit_text(result)}
           if result.motors and _inertia_limited(result) else {}),
        **({"precision targets": targets} if (targets := targets_text(options)) else {}),
        "required life": ("none" if options.life_hours is None
                          else f"{options.life_hours:g} h ({options.life_basis})"),
        "mean speed": mean_speed_note(result.units).removeprefix("mean speed "),
        "joint losses": JOINT_LOSSES_NOTE,
        **({"payload events": events} if (events := duty_events_text(result)) else {}),
    }


BEARING_RULE_NOTE = (
    "output bearing: the force and moment through each joint from the inverse dynamics "
    "(carried units and payload included): tilting moment M, radial force F_r and axial "
    "force F_a about the output flange (the joint origin unless [sizing] bearing_offset_m "
    "moves it; a unit's catalog offset_m from there, to the worse side per sample); largest "
    "over the cycle, and 10/3-power means over the moving part weighted by |n| t; where a "
    "catalog rates the bearing: M, F_r, F_a against its limits, the L10 life "
    "10^6 / (60 N_av) (C / (f_w P_c))^(10/3) with P_c = X (F_r,av + 2 M_av / d_p) + Y F_a,av "
    "and N_av the output mean speed as the series averages the gear's, and the static safety "
    "C0 / (F_r,max + 2 M_max / d_p + 0.44 F_a,max); emergency stops are not counted")


def margin_text(margin: float) -> str:
    """The design margin in words, e.g. ``20 %: every rule holds at up to 80 % of its limit``."""
    if margin == 0.0:
        return "none: every rule may reach 100 % of its limit"
    return (f"{margin * 100:g} %: every rule must hold at up to {(1 - margin) * 100:g} % of its "
            "limit (utilization is still demand / limit)")


def _inertia_limited(result: SizingResult) -> bool:
    """A largest load-to-rotor inertia ratio applies to some pair."""
    return result.options.max_inertia_ratio is not None or any(
        m.max_inertia_ratio is not None for ms in result.motors.values() for m in ms)


def inertia_limit_text(result: SizingResult) -> str:
    """The largest load-to-rotor inertia ratio a pair may have, in words."""
    if result.options.max_inertia_ratio is not None:
        return f"{result.options.max_inertia_ratio:g} (a pair above it is not feasible)"
    given = sorted({m.max_inertia_ratio for ms in result.motors.values() for m in ms
                    if m.max_inertia_ratio is not None})
    if not given:
        return "none: the ratio is reported, not checked"
    return (", ".join(f"{r:g}" for r in given) + " (from the motor file; a pair above it is "
            "not feasible)")


JOINT_LOSSES_NOTE = ("the robot file's armature, joint damping, friction and springs are the "
                     "motor's and the joint's own, not load on the gear output: left out")


def base_text(robot: Robot, moved: Sequence[Payload] = ()) -> str:
    """The fixed link, its mounting, payload and parts (all cycle; `moved` by events)."""
    mounting = ""
    if robot.base_pose != NAMED_BASES["floor"]:
        gravity = shown_numbers(robot.gravity)
        mounting = (f" on {mounting_name(robot.base_pose)} (gravity ({gravity}) m/s^2 in "
                    "its frame)")
    payload = robot.payload
    if payload is None:
        carried = f"none (a payload would go on '{robot.payload_frame}')"
    else:
        com = ", ".join(f"{c:g}" for c in payload.com)
        carried = f"{payload.mass:g} kg on '{robot.payload_frame}', centre of mass ({com}) m"
    for part, when in ([(part, "all cycle") for part in robot.parts]
                       + [(part, "between its events") for part in moved]):
        carried += (f"; part '{part.name}': {part.mass:g} kg on "
                    f"'{part.frame or robot.payload_frame}', {when}")
    return f"base: '{robot.root_link}' held fixed{mounting}; payload: {carried}"


def payload_json(robot: Robot) -> dict[str, Any]:
    """The payload as JSON: mass 0 when none; the frame it is (or would be) attached to."""
    payload = robot.payload
    return {"mass_kg": 0.0 if payload is None else payload.mass,
            "frame": robot.payload_frame,
            "frame_given": payload is not None and payload.frame is not None,
            "com_m": [0.0, 0.0, 0.0] if payload is None else list(payload.com),
            "inertia_kg_m2": [[0.0] * 3] * 3 if payload is None
            else [list(row) for row in payload.inertia]}


def joint_load_json(load: JointLoad) -> dict[str, Any]:
    """One joint's load over the cycle as JSON, in SI (N m or N, rad or m)."""
    linear = load.linear
    force, per_s, position = ("n", "m_s", "m") if linear else ("nm", "rad_s", "rad")
    return {"name": load.name, "type": load.kind, "sized": load.sized, "note": load.note,
            "leader": load.leader,
            f"peak_{'force' if linear else 'torque'}_{force}": load.peak,
            f"peak_{'force' if linear else 'torque'}_uncertainty_{force}": load.peak_uncertainty,
            f"effort_limit_{force}": finite_or_none(load.effort_limit),
            f"max_speed_{per_s}": load.max_speed,
            f"velocity_limit_{per_s}": finite_or_none(load.velocity_limit),
            f"travel_{position}": list(load.travel),
            "above_effort_limit": load.above_effort,
            "above_velocity_limit": load.above_velocity}


def tasks_json(result: SizingResult) -> list[dict[str, Any]]:
    """Every task of a duty as JSON: its motion, share, cycle, payload and mounting."""
    out = []
    for task in result.tasks:
        traj = task.trajectory
        out.append({"name": task.label,
                    "motion": None if task.motion is None else str(task.motion.path),
                    "share": task.share, "counted": task.share > 0.0,
                    "cycle_time_s": traj.duration, "samples": len(traj.t),
                    "cycles_per_hour": task.share * SECONDS_PER_HOUR / cycle_of(traj),
                    "payload": payload_json(task.robot),
                    "gravity_m_s2": [float(g) for g in task.robot.gravity],
                    "events": event_records(task)})
    return out


def _mix_joint_json(result: SizingResult, joint: JointSizing) -> dict[str, Any]:
    """A joint's rules by the task that sets each, and its unit against each task alone."""
    chosen = joint.selected or joint.strongest
    return {"set_by": {rule: result.set_by(joint, rule) if check.value is not None else None
                       for rule, check in chosen.checks.items()},
            "per_task": [{"task": task.label, **candidate_json(candidate)}
                         for task, candidate in zip(result.counted, joint.per_task,
                                                    strict=True)]}


def size_json(result: SizingResult) -> dict[str, Any]:
    """A sizing result as JSON; each candidate has the ``duty`` shape plus ``motor``.

    A duty of several tasks (a mix) adds ``mix``, ``tasks`` and ``idle_share`` at the
    top, and per joint ``set_by`` (rule -> the task setting it, or ``"pooled"``) and
    ``per_task`` (the joint's unit checked against each counted task alone); a slow-down
    (every task s times slower, at the same shares) gives ``task_cycle_times_s``. A joint
    no unit fits has its ``diagnosis`` (`hdselect.sizing.diagnosis.Diagnosis.to_dict`;
    None for a joint with a unit). ``precision`` holds the precision figures
    (`hdselect.sizing.precision_records.precision_json`; None without them).
    """
    result = with_diagnoses(result)
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
            "effort_limit_nm": finite_or_none(float(
                result.robot.effort_limit[result.robot.joint_index(joint.name)]) or math.inf),
            "slowdown": None if slowdown is None else {
                "factor": slowdown.factor, "unit": slowdown.unit,
                "cycle_time_s": slowdown.cycle_time},
            "time_scales": None if joint.scales is None else {
                unit: [[lo, finite_or_none(hi)] for lo, hi in intervals]
                for unit, intervals in joint.scales.fits.items()},
            "candidates": [candidate_json(c) for c in joint.candidates],
            "diagnosis": None if (found := diagnosis_of(result, joint.name)) is None
            else found.to_dict(),
        }
        if joint.bearing is not None:
            rating = (joint.selected or joint.strongest).unit.bearing
            document["bearing"] = {**bearing_load_json(joint.bearing),
                                   "rated": rating is not None,
                                   "note": None if rating is not None else NOT_RATED}
            for candidate, entry in zip(joint.candidates, document["candidates"], strict=True):
                entry["bearing"] = candidate_bearing_json(candidate)
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
        if joint.per_task:
            document.update(_mix_joint_json(result, joint))
        if any(task.carried is not None for task in result.counted):  # the peak's parts
            worst = peak_sample(result, joint)
            document["carrying"] = None if worst is None else list(carrying_at(result, worst))
        if slowdown is not None and slowdown.factor is not None and len(result.counted) > 1:
            # every task s times slower, at the same shares of the time
            document["slowdown"]["task_cycle_times_s"] = {
                task.label: slowdown.factor * task.trajectory.duration
                for task in result.counted}
        joints.append(document)
    mix: dict[str, Any] = {}
    if len(result.tasks) > 1 or result.mix is not None:
        mix = {"mix": None if result.mix is None else str(result.mix.path),
               "tasks": tasks_json(result), "idle_share": result.idle}
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
            "margin": options.margin, "max_inertia_ratio": options.max_inertia_ratio,
            "inertia_target": options.inertia_target,
            "mean_speed_rule": mean_speed_note(result.units),
            "joint_losses": JOINT_LOSSES_NOTE,
            "motors": ({name: [m.id for m in ms] for name, ms in result.motors.items()}
                       if result.motors else None),
            "motor_rules": MOTOR_MODEL_NOTE if result.motors else None,
            "bearing_offset_m": dict(options.bearing_offset),
            "bearing_loads": options.bearing_loads, "bearing_rule": BEARING_RULE_NOTE,
            "precision": options.precision, "precision_targets": targets_json(options),
            "payload_events": duty_events_text(result) or None},
        "motors": [motor_json(m) for m in _distinct(result.motors)],
        "joints": joints,
        "root_link": result.robot.root_link,
        "payload": payload_json(result.robot),
        "warnings": list(result.warnings),
        "joint_loads": [joint_load_json(load) for load in result.loads],
        "precision": precision_json(result),
        "events": event_records(result.counted[0]) if len(result.counted) == 1 else [],
        **mix,
    }


def _distinct(motors: Any) -> list[Motor]:
    """Every motor of a joint -> motors mapping once, in order of appearance."""
    seen: dict[tuple[str, str | None], Motor] = {}
    for candidates in motors.values():
        for motor in candidates:
            seen.setdefault((motor.id, str(motor.source)), motor)
    return list(seen.values())


def finite_or_none(value: Any) -> Any:
    """A float that is not finite as None (JSON has no infinity); anything else as it is."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
