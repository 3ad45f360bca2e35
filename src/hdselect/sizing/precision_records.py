"""The precision figures of a sizing as JSON, and the pose of the cycle each figure names.

`size_json`'s ``precision`` key (docs/precision.md lists every key): twists in arcmin,
the tool's deflection in mm and arcmin, frequencies in Hz, input speeds in rpm; every
figure that names a sample says which task, when in its cycle and, for the arm's
figures, the pose by joint name. The reports read the poses from here too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from hdselect.catalog.stiffness import class_note
from hdselect.motion.option_specs import EVERY_JOINT
from hdselect.sizing.options import Options
from hdselect.sizing.precision import ArmModes, JointPrecision, Precision, ToolDeflection
from hdselect.sizing.result import SizingResult

ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi
MM_PER_M = 1000.0

STIFFNESS_NOT_RATED = "not rated by the source"
"""A figure of a unit whose catalog rates no torsional stiffness K1 (PSA-G, CSF-2UH)."""

NOT_RATED_NOTE = ("stiffness not rated by the source: the catalog gives no torsional "
                  "stiffness K1, so no twist, tool deflection or natural frequency is "
                  "computed")
"""Why a joint (and, with it, the whole arm's figures) has no precision figures."""

NO_UNIT_NOTE = ("no unit holds this joint: it has no figures of its own, and the tool's "
                "deflection and the arm's modes take its strongest candidate")
"""Why a joint no unit fits has no precision figures of its own."""

SERIES_HINT = ("the SHG-2UH and HFUS-2UH series rate K1, CSG-2UH from size 17: e.g. "
               "--series shg-2uh")
"""Where the built-in catalogs rate the stiffness, for a result that has none."""


@dataclass(frozen=True)
class Pose:
    """Where a pooled sample lies: its task, its time in that task's cycle, the arm's pose.

    Attributes:
        task: Index of its task among the result's counted tasks.
        label: That task's name (`hdselect.sizing.tasks.Task.label`).
        time: Its time in the task's cycle [s].
        q: Every joint's position at it, by name [rad or m].
    """

    task: int
    label: str
    time: float
    q: dict[str, float]


def pose_of(result: SizingResult, sample: int) -> Pose:
    """The task, time and joint positions of a pooled sample (the counted tasks in turn).

    Raises:
        IndexError: `sample` is not a pooled sample of the result.
    """
    counted = result.counted or ()
    trajectories = [task.trajectory for task in counted] or [result.trajectory]
    offset = 0
    for k, traj in enumerate(trajectories):
        if 0 <= sample - offset < len(traj.t):
            local = sample - offset
            label = counted[k].label if counted else (
                result.motion.path.name if result.motion is not None else "task")
            return Pose(k, label, float(traj.t[local]),
                        {name: float(value) for name, value in zip(traj.joint_names,
                                                                   traj.q[local], strict=True)})
        offset += len(traj.t)
    raise IndexError(f"sample {sample} is not one of the {offset} pooled samples")


def unheld(result: SizingResult) -> set[str]:
    """The sized joints no unit fits (their figures are their strongest candidate's)."""
    return {joint.name for joint in result.joints if joint.selected is None}


def task_label(result: SizingResult, task: int) -> str:
    """The name of counted task `task` (the motion's name for a result of one trajectory)."""
    counted = result.counted
    if counted:
        return counted[task].label
    return result.motion.path.name if result.motion is not None else "task"


def finite(value: float | None) -> float | None:
    """A figure for JSON: None where it is None or not finite (an arm with no inertia)."""
    return None if value is None or not math.isfinite(value) else float(value)


def arcmin(angle: float | None) -> float | None:
    """An angle [rad] in arcmin; None stays None."""
    return None if angle is None else angle * ARCMIN_PER_RAD


def targets_text(options: Options) -> str:
    """The precision targets given, in the designer's units, for the assumptions; empty: none.

    A target given as an application class names it and where its number comes from.
    """
    parts = []
    for name, words, scale, unit in (("max_torsion", "twist at most", ARCMIN_PER_RAD, "arcmin"),
                                     ("min_natural_frequency", "f_n at least", 1.0, "Hz")):
        given = getattr(options, name)
        if given:
            parts.append(f"{words} " + ", ".join(
                f"{value * scale:.3g} {unit} ({'every joint' if joint == EVERY_JOINT else joint})"
                for joint, value in given.items()))
    if options.max_tool_deflection is not None:
        parts.append(f"tool sag held at most {options.max_tool_deflection * MM_PER_M:.3g} mm")
    if options.min_arm_frequency is not None:
        parts.append(f"arm's lowest mode at least {options.min_arm_frequency:.3g} Hz")
    note = class_note(options.min_natural_frequency, options.min_arm_frequency)
    return "; ".join(parts) + (f" ({note})" if note else "")


def targets_json(options: Options) -> dict[str, Any]:
    """The precision targets given, in the designer's units (null: none); the classes' note.

    A per-joint target is joint name -> value, ``"*"`` for every joint not named.
    """
    return {
        "max_torsion_arcmin": {joint: value * ARCMIN_PER_RAD
                               for joint, value in options.max_torsion.items()} or None,
        "min_natural_frequency_hz": dict(options.min_natural_frequency) or None,
        "max_tool_deflection_mm": (None if options.max_tool_deflection is None
                                   else options.max_tool_deflection * MM_PER_M),
        "min_arm_frequency_hz": options.min_arm_frequency,
        "classes": class_note(options.min_natural_frequency, options.min_arm_frequency) or None,
    }


def precision_json(result: SizingResult) -> dict[str, Any] | None:
    """The ``precision`` key of ``size --json``; None where the figures were not computed."""
    found: Precision | None = result.precision
    if found is None:
        return None
    missing = unheld(result)
    return {
        "joints": [_joint_json(result, joint, joint.name in missing) for joint in found.joints],
        "tool": None if found.tool is None else _tool_json(result, found.tool),
        "modes": None if found.modes is None else _modes_json(result, found.modes),
        "not_rated": list(found.not_rated),
        "note": NOT_RATED_NOTE if found.not_rated else None,
        "rigid": list(found.rigid),
        "poses": len(found.poses),
        "raised": [{"joint": r.joint, "chosen": r.chosen, "raised_to": r.raised_to,
                    "reason": r.reason, "added_mass_kg": r.added_mass} for r in found.raised],
        "targets": [target_json(target) for target in found.targets],
    }


def target_json(target: Any) -> dict[str, Any]:
    """A whole-arm target's verdict: the deflection in mm, the frequency in Hz."""
    scale, unit = (MM_PER_M, "mm") if target.name == "tool_deflection" else (1.0, "Hz")
    value = target.value  # None: not judged (a unit rates no stiffness)
    return {"name": target.name, "value": None if value is None else finite(value * scale),
            "limit": target.limit * scale,
            "unit": unit, "ok": target.ok, "shortfall": target.shortfall}


def _at(result: SizingResult, sample: int | None, prefix: str) -> dict[str, Any]:
    """The task and time of a pooled sample as ``<prefix>_task``, ``<prefix>_time_s``."""
    if sample is None:
        return {f"{prefix}_task": None, f"{prefix}_time_s": None}
    pose = pose_of(result, sample)
    return {f"{prefix}_task": pose.label, f"{prefix}_time_s": pose.time}


def _joint_json(result: SizingResult, joint: JointPrecision, missing: bool) -> dict[str, Any]:
    """One joint's figures; a joint no unit fits names none (its strongest candidate's)."""
    note = NO_UNIT_NOTE if missing else None if joint.rated else NOT_RATED_NOTE
    return {"name": joint.name,
            "unit": None if joint.unit is None or missing else joint.unit.id,
            "rated": joint.rated, "note": note,
            "max_torsion_arcmin": arcmin(joint.max_torsion),
            **_at(result, joint.max_torsion_sample, "max_torsion"),
            "holding_torsion_arcmin": arcmin(joint.holding_torsion),
            "hysteresis_loss_arcmin": arcmin(joint.hysteresis_loss),
            "lost_motion_arcmin": arcmin(joint.lost_motion),
            "lowest_frequency_hz": finite(joint.lowest_frequency),
            **_at(result, joint.lowest_frequency_sample, "lowest_frequency"),
            "resonance_speed_rpm": finite(joint.resonance_speed),
            "near_resonance_s": joint.near_resonance_time if joint.rated else None,
            "near_resonance": [{"task": task_label(result, w.task), "start_s": w.start,
                                "end_s": w.end} for w in joint.near_resonance]}


def _worst(result: SizingResult, sample: int, translation: np.ndarray,
           rotation: np.ndarray) -> dict[str, Any]:
    pose = pose_of(result, sample)
    return {"task": pose.label, "time_s": pose.time, "pose": pose.q,
            "translation_mm": [float(x) * MM_PER_M for x in translation],
            "rotation_arcmin": [float(x) * ARCMIN_PER_RAD for x in rotation]}


def _deflection(result: SizingResult, tool: ToolDeflection, translation: np.ndarray,
                rotation: np.ndarray, worst: int) -> dict[str, Any]:
    return {"max_translation_mm": float(np.linalg.norm(translation[worst])) * MM_PER_M,
            "max_rotation_arcmin": float(np.linalg.norm(rotation, axis=1).max())
            * ARCMIN_PER_RAD,
            "worst": _worst(result, int(tool.samples[worst]), translation[worst],
                            rotation[worst])}


def _tool_json(result: SizingResult, tool: ToolDeflection) -> dict[str, Any]:
    return {"frame": tool.frame, "poses": len(tool.samples),
            "bearing_tilt": list(tool.bearing_tilt),
            "cycle": _deflection(result, tool, tool.translation, tool.rotation, tool.worst),
            "holding": _deflection(result, tool, tool.holding_translation,
                                   tool.holding_rotation, tool.worst_holding)}


def _modes_json(result: SizingResult, modes: ArmModes) -> dict[str, Any]:
    pose = pose_of(result, int(modes.samples[modes.lowest]))
    return {"joints": list(modes.joints), "poses": len(modes.samples),
            "lowest_hz": finite(float(modes.frequencies[modes.lowest, 0])),
            "frequencies_hz": [finite(float(f)) for f in modes.frequencies[modes.lowest]],
            "task": pose.label, "time_s": pose.time, "pose": pose.q,
            "shape": {name: float(v) for name, v in zip(modes.joints, modes.shape,
                                                        strict=True)}}
