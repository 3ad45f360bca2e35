"""A compact, picklable record of a sizing result: what studies keep and JSON carries.

The full `SizingResult` keeps every sample's torque for reports and figures
(megabytes for a long cycle); a `Summary` keeps the answer (a few kB).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, is_dataclass
from typing import Any

import numpy as np

from hdselect.base.bounds import expect_type
from hdselect.catalog.checks import life_capped, reported_life
from hdselect.catalog.rules import at_rest
from hdselect.robot.payload import Payload
from hdselect.sizing.diagnosis import diagnosis_of
from hdselect.sizing.result import JointSizing, SizingResult
from hdselect.sizing.tasks import Task


@dataclass(frozen=True)
class JointSummary:
    """One joint's answer.

    Attributes:
        name: Joint name.
        unit: The selected unit's id, or None when no unit fits.
        candidate: The unit the figures below describe: the selected one, else the strongest.
        feasible: A unit fits.
        binding: The check with the highest utilization for `candidate`.
        utilization: Demand over limit of every check for `candidate` [-] (life:
            required over expected).
        life_l50_hours: L50 life of `candidate` [h], at most
            `hdselect.catalog.checks.LIFE_CAP`; None when unlimited.
        life_l10_hours: L10 life of `candidate` [h], the same way.
        motor_peak_torque: Peak motor torque behind `candidate` [N m].
        motor_rms_torque: RMS motor torque over the cycle [N m].
        motor_max_speed: Largest input speed [rpm].
        carried_mass: Gearhead and motor mass carried from joints further out [kg].
        gravity_loaded: Gravity loads the joint (it backdrives when the input is free).
        flags: Catalog stand-ins and corrections the figures depend on.
        slowdown: Smallest uniform slow-down that would fit, when no unit fits; None otherwise
            or when none helps.
        motor: Where motors are given, the selected motor's id (None when no pair fits);
            None without motor data.
        motor_candidate: Where motors are given, the motor of `candidate`.
        motor_binding: The motor's check with the highest utilization for `candidate`.
        inertia_ratio: Load inertia at the motor shaft over the rotor inertia for
            `candidate` [-] (`hdselect.sizing.core.JointSizing.inertia_ratio`).
        bearing_max_moment: Largest tilting moment on the output bearing, about the
            output flange [N m]; None where the loads were not computed.
        bearing_max_radial: Largest radial force on it [N].
        bearing_max_axial: Largest axial force on it [N].
        bearing_mean_moment: Its 10/3-power mean tilting moment over the moving part,
            weighted by |n| t [N m]; None where the joint never moves.
        bearing_mean_radial: The same mean of the radial force [N].
        bearing_mean_axial: The same mean of the axial force [N].
        bearing_rated: `candidate`'s catalog rates its output bearing (its checks are
            then among `utilization`); None where the loads were not computed.
        bearing_life_l10_hours: `candidate`'s output bearing L10 life [h]; None when not
            rated, unlimited or not computed; at most the cap too.
        binding_task: For a duty of several tasks, the task that sets the binding rule
            (``"pooled"`` for a rule over every task); None for one task.
        life_capped: `life_l50_hours` is the cap, not the life (which is longer).
        diagnosis: For a joint no unit fits, its diagnosis as JSON
            (`hdselect.sizing.diagnosis.Diagnosis.to_dict`) where the result carries one
            (`hdselect.sizing.diagnosis.with_diagnoses`); else None.
    """

    name: str
    unit: str | None
    candidate: str
    feasible: bool
    binding: str
    utilization: dict[str, float]
    life_l50_hours: float | None
    life_l10_hours: float | None
    motor_peak_torque: float
    motor_rms_torque: float
    motor_max_speed: float
    carried_mass: float
    gravity_loaded: bool
    flags: tuple[str, ...]
    slowdown: float | None
    motor: str | None = None
    motor_candidate: str | None = None
    motor_binding: str | None = None
    inertia_ratio: float | None = None
    bearing_max_moment: float | None = None
    bearing_max_radial: float | None = None
    bearing_max_axial: float | None = None
    bearing_mean_moment: float | None = None
    bearing_mean_radial: float | None = None
    bearing_mean_axial: float | None = None
    bearing_rated: bool | None = None
    bearing_life_l10_hours: float | None = None
    binding_task: str | None = None
    life_capped: bool = False
    diagnosis: dict[str, Any] | None = None


@dataclass(frozen=True)
class Summary:
    """A sizing result without its samples.

    Attributes:
        robot: The robot file.
        motion: The motion file, or None for a trajectory sized directly.
        cycle_time: Cycle time [s].
        samples: Number of samples sized.
        feasible: Every joint has a unit.
        options: The assumptions (`hdselect.sizing.options.Options` as a dict).
        joints: One per sized joint, in the robot's order.
        root_link: The link held fixed to the world.
        payload_mass: The payload's mass [kg]; 0 without one. A study's case gives the mass
            its ``payload`` sets: the part its payload events move, where they move one.
        payload_frame: The frame the payload is (or would be) attached to.
        warnings: The result's warning lines (robot file, motion file, cycle).
        tasks: For a duty of several tasks (a mix), each task: ``name``, ``motion``,
            ``share`` [-], ``cycle_time`` [s] and ``payload_mass`` [kg]; empty for one.
        idle_share: The fraction of the time no task runs [-].
        precision: The precision figures (`precision_record`), or None where they were
            not computed.
    """

    robot: str
    motion: str | None
    cycle_time: float
    samples: int
    feasible: bool
    options: dict[str, Any]
    joints: tuple[JointSummary, ...]
    root_link: str = ""
    payload_mass: float = 0.0
    payload_frame: str = ""
    warnings: tuple[str, ...] = ()
    tasks: tuple[dict[str, Any], ...] = ()
    idle_share: float = 0.0
    precision: dict[str, Any] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain lists, dicts, strings and numbers, ready for strict JSON.

        A number that is not finite (the infinite life of a joint that carries no load)
        is None, as in the command line's JSON.
        """
        return _finite(self)


def summarize(result: SizingResult) -> Summary:
    """The compact record of a sizing result.

    Args:
        result: A result of `hdselect.size` or `hdselect.size_trajectory`.

    Returns:
        Its summary.

    Raises:
        InputError: `result` is not a SizingResult.
    """
    expect_type(result, SizingResult, "result", "a SizingResult (hdselect.size)")
    return Summary(
        robot=str(result.robot.path),
        motion=None if result.motion is None else str(result.motion.path),
        cycle_time=result.cycle_time,
        samples=len(result.trajectory.t),
        feasible=result.feasible,
        options=asdict(result.options),
        joints=tuple(_joint(joint, result) for joint in result.joints),
        root_link=result.robot.root_link,
        payload_mass=0.0 if result.robot.payload is None else result.robot.payload.mass,
        payload_frame=result.robot.payload_frame,
        warnings=result.warnings,
        tasks=tuple({"name": task.label,
                     "motion": None if task.motion is None else str(task.motion.path),
                     "share": task.share, "cycle_time": task.trajectory.duration,
                     "payload_mass": 0.0 if task.robot.payload is None
                     else task.robot.payload.mass}
                    for task in result.tasks) if len(result.tasks) > 1 else (),
        idle_share=result.idle,
        precision=precision_record(result),
    )


def precision_record(result: SizingResult) -> dict[str, Any] | None:
    """A sizing's precision figures in brief (`hdselect.sizing.precision.Precision`), SI.

    ``joints``: per sized joint ``name``, ``unit`` (the selected one, else the strongest),
    ``rated`` (its catalog rates K1; else its figures are None), ``max_torsion`` and
    ``holding_torsion`` [rad], ``lowest_frequency`` (single-axis) [Hz],
    ``resonance_speed`` [rpm] and ``near_resonance_time`` [s]; ``tool_frame``,
    ``tool_deflection`` (largest along the cycle) and ``tool_holding`` (holding a pose
    still) [m] and ``arm_frequency`` (the lowest mode) [Hz], each None where a sized
    joint's K1 is not rated; ``not_rated``, ``rigid``; ``targets`` (the whole-arm
    targets' ``name``, ``value``, ``limit``, ``ok``, ``shortfall``) and ``raised`` (the
    units raised for them). None where the figures were not computed.
    """
    found = result.precision
    if found is None:
        return None
    tool, modes = found.tool, found.modes
    return {
        "joints": [{"name": joint.name, "unit": None if joint.unit is None else joint.unit.id,
                    "rated": joint.rated, "max_torsion": joint.max_torsion,
                    "holding_torsion": joint.holding_torsion,
                    "lowest_frequency": joint.lowest_frequency,
                    "resonance_speed": joint.resonance_speed,
                    "near_resonance_time": joint.near_resonance_time}
                   for joint in found.joints],
        "tool_frame": None if tool is None else tool.frame,
        "tool_deflection": None if tool is None else tool.max_translation,
        "tool_holding": None if tool is None else tool.max_holding,
        "arm_frequency": None if modes is None else modes.lowest_frequency,
        "not_rated": list(found.not_rated),
        "rigid": list(found.rigid),
        "targets": [asdict(check) for check in found.targets],
        "raised": [asdict(raised) for raised in found.raised],
    }


def event_records(task: Task) -> list[dict[str, Any]]:
    """A task's payload events in time order: ``t`` [s], ``part``, ``event`` (attach, release).

    Empty where the task has none (every part carried the whole cycle).
    """
    if task.carried is None:
        return []
    return [{"t": t, "part": part, "event": "attach" if attached else "release"}
            for t, part, attached in task.carried.events]


def events_text(task: Task) -> str:
    """A task's payload events in words, e.g. ``part attached at t = 1.2 s, released at ...``.

    Empty where the task has none.
    """
    if task.carried is None:
        return ""
    words = [f"{part} {'attached' if attached else 'released'} at t = {t:.4g} s"
             for t, part, attached in task.carried.events]
    return ", ".join(words) + " (carried from its attach to its release, the cycle repeating)"


def duty_events_text(result: SizingResult) -> str:
    """Which parts each counted task carries when, where some task has events ("" if none)."""
    several = len(result.counted) > 1
    return "; ".join((f"{task.label}: " if several else "") + text for task in result.counted
                     if (text := events_text(task)))


def counted_at(result: SizingResult, sample: int) -> tuple[Task, int]:
    """The counted task of a pooled sample and its row in that task's trajectory.

    The pooled samples are the counted tasks' trajectories in turn (one task's alone).
    """
    start = 0
    for task in result.counted:
        n = len(task.trajectory.t)
        if sample < start + n:
            return task, sample - start
        start += n
    raise IndexError(f"sample {sample} is beyond the {start} pooled samples")


def carrying_at(result: SizingResult, sample: int) -> tuple[str, ...]:
    """The parts a pooled sample's task carries there, by name.

    The task's ``[payload]`` (named "payload") and parts no event names are carried the
    whole cycle; those its events move, between their events.
    """
    task, row = counted_at(result, sample)
    robot = task.robot
    always = (("payload",) if robot.payload is not None else ()) + tuple(
        part.name for part in robot.parts)
    return always + (() if task.carried is None else task.carried.names(row))


def moved_parts(result: SizingResult) -> tuple[Payload, ...]:
    """The parts the payload events of a result's one task move (none without events)."""
    carried = result.tasks[0].carried if len(result.tasks) == 1 else None
    return () if carried is None else carried.parts


def peak_sample(result: SizingResult, joint: JointSizing) -> int | None:
    """The pooled sample of the joint's largest |torque| while moving (the peak rule's worst).

    None where the joint never moves (or the result has no counted task).
    """
    if not result.counted:
        return None
    j = result.robot.joint_index(joint.name)
    rest = np.concatenate([at_rest(task.trajectory.qd[:, j], task.trajectory.qdd[:, j])
                           for task in result.counted])
    if rest.all() or len(rest) != len(joint.torque):
        return None
    return int(np.argmax(np.where(rest, -1.0, np.abs(joint.torque))))


def _joint(joint: JointSizing, result: SizingResult) -> JointSummary:
    chosen = joint.selected or joint.strongest
    motor = chosen.motor
    slowdown = joint.slowdown
    load = joint.bearing
    bearing: dict[str, Any] = {} if load is None else {
        "bearing_max_moment": load.max_moment, "bearing_max_radial": load.max_radial,
        "bearing_max_axial": load.max_axial, "bearing_mean_moment": load.mean_moment,
        "bearing_mean_radial": load.mean_radial, "bearing_mean_axial": load.mean_axial,
        "bearing_rated": chosen.unit.bearing is not None,
        "bearing_life_l10_hours": None if chosen.bearing is None
        else reported_life(chosen.bearing.life_hours)}
    return JointSummary(
        name=joint.name,
        unit=None if joint.selected is None else joint.selected.unit.id,
        candidate=chosen.unit.id,
        feasible=joint.selected is not None,
        binding=chosen.binding,
        utilization={name: float(check.utilization) for name, check in chosen.checks.items()},
        life_l50_hours=reported_life(chosen.life_hours),
        life_l10_hours=reported_life(chosen.l10_hours),
        life_capped=life_capped(chosen.life_hours),
        motor_peak_torque=0.0 if motor is None else motor.peak_torque,
        motor_rms_torque=0.0 if motor is None else motor.rms_torque,
        motor_max_speed=0.0 if motor is None else motor.max_speed,
        carried_mass=joint.carried_mass,
        gravity_loaded=joint.gravity_loaded,
        flags=tuple(sorted({flag.code for flag in chosen.flags})),
        slowdown=None if slowdown is None else slowdown.factor,
        motor=(joint.selected.motor_unit.id if joint.selected is not None
               and joint.selected.motor_unit is not None else None),
        motor_candidate=None if chosen.motor_unit is None else chosen.motor_unit.id,
        motor_binding=chosen.motor_binding,
        inertia_ratio=joint.inertia_ratio(chosen),
        binding_task=result.set_by(joint, chosen.binding),
        diagnosis=None if (found := diagnosis_of(result, joint.name)) is None
        else found.to_dict(),
        **bearing,
    )


def _finite(value: Any) -> Any:
    """`value` as plain data, every float that is not finite replaced by None.

    As ``dataclasses.asdict`` walks it (dataclasses become dicts), tuples become lists;
    containers are walked once and the leaves are not copied.
    """
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if value is None or isinstance(value, str | bool | int):
        return value
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(item) for item in value]
    if is_dataclass(value) and not isinstance(value, type):
        return {f.name: _finite(getattr(value, f.name)) for f in fields(value)}
    return value
