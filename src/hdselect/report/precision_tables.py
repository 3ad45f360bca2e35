"""The precision figures in the terminal: each unit's twist and resonance, the tool, the arm.

Tables format; they do not compute: every figure comes from
`hdselect.sizing.result.SizingResult.precision` (`hdselect.sizing.precision`).
"""

from __future__ import annotations

import math

import numpy as np
from rich.markup import escape

from hdselect.report.tables import Column, FittedTable, Paragraphs
from hdselect.sizing.precision import JointPrecision, Precision, Raise, TargetCheck
from hdselect.sizing.precision_records import (
    ARCMIN_PER_RAD,
    MM_PER_M,
    NO_UNIT_NOTE,
    NOT_RATED_NOTE,
    SERIES_HINT,
    STIFFNESS_NOT_RATED,
    pose_of,
    task_label,
    unheld,
)
from hdselect.sizing.result import SizingResult

PRECISION_COLUMNS = (Column("joint", "left"), Column("unit", "left"),
                     Column("twist arcmin\nmax / held"), Column("f_n Hz\nlowest"),
                     Column("at s", group="when"),
                     Column("resonance\ninput rpm", group="resonance"),
                     Column("near it\ns", group="resonance"),
                     Column("hyst. / lost\narcmin", group="catalog"))
"""The section's table: the twist and f_n stay; the time, the resonance and the catalog's
hysteresis and lost motion move below on a narrow terminal."""


def precision_tables(result: SizingResult) -> list[object]:
    """The "Precision" section: a table per joint, then the tool and the arm in words.

    Empty where the figures were not computed (``precision=False``); a paragraph alone
    where no sized joint's unit rates its stiffness.
    """
    found = result.precision
    if found is None or not found.joints:
        return []
    if not any(joint.rated for joint in found.joints):
        units = sorted({joint.unit.id for joint in found.joints if joint.unit is not None
                         and joint.name not in unheld(result)}) or ["no unit chosen"]
        return ["", Paragraphs((f"Precision: {STIFFNESS_NOT_RATED} ({', '.join(units)}): no "
                                "twist, tool deflection or natural frequency; "
                                f"{SERIES_HINT}.", *verdict_lines(found)))]
    missing = unheld(result)
    rows = tuple(_none(joint) if joint.name in missing else _row(result, joint)
                 for joint in found.joints)
    return ["", FittedTable(_title(result, found), PRECISION_COLUMNS, rows,
                            notes=tuple(precision_notes(result, found)))]


def _title(result: SizingResult, found: Precision) -> str:
    poses = len(found.poses)
    cycle = "the tasks' cycles" if len(result.counted) > 1 else "the cycle"
    return (f"Precision: each unit's twist under the joint's torque and its single-axis "
            f"natural frequency, over {poses:,} pose{'s' if poses != 1 else ''} of {cycle}")


def _none(joint: JointPrecision) -> tuple[str, ...]:
    """The row of a joint no unit fits: no unit named, no figure."""
    return (escape(joint.name), "[red]none[/red]", *("-",) * (len(PRECISION_COLUMNS) - 2))


def _row(result: SizingResult, joint: JointPrecision) -> tuple[str, ...]:
    unit = "-" if joint.unit is None else escape(joint.unit.id)
    catalog = f"{_arcmin(joint.hysteresis_loss)} / {_arcmin(joint.lost_motion)}"
    if not joint.rated:
        return (escape(joint.name), unit, "not rated", "-", "-", "-", "-", catalog)
    when = "-"
    if joint.lowest_frequency_sample is not None:
        pose = pose_of(result, joint.lowest_frequency_sample)
        when = f"{pose.time:.2f}" + (f" {escape(pose.label)}" if len(result.counted) > 1 else "")
    near = joint.near_resonance_time
    return (escape(joint.name), unit,
            f"{_arcmin(joint.max_torsion)} / {_arcmin(joint.holding_torsion)}",
            _hz(joint.lowest_frequency), when,
            "-" if joint.resonance_speed is None or not math.isfinite(joint.resonance_speed)
            else f"{joint.resonance_speed:,.0f}",
            "0" if near == 0.0 else f"{near:.3g}", catalog)


def _arcmin(angle: float | None) -> str:
    return "-" if angle is None else f"{angle * ARCMIN_PER_RAD:.3g}"


def _hz(frequency: float | None) -> str:
    if frequency is None:
        return "-"
    return "inf" if not math.isfinite(frequency) else f"{frequency:.3g}"


def pose_text(result: SizingResult, sample: int) -> str:
    """A pooled sample in words: its time (and task), and the arm's pose in degrees or m."""
    pose = pose_of(result, sample)
    robot = result.robot
    joints = ", ".join(
        f"{name} {value * 180.0 / math.pi:.1f} deg" if robot.revolute[robot.joint_index(name)]
        else f"{name} {value:.3g} m" for name, value in pose.q.items())
    task = f" of {pose.label}" if len(result.counted) > 1 else ""
    return f"at {pose.time:.2f} s{task} ({joints})"


def precision_notes(result: SizingResult, found: Precision) -> list[str]:
    """The section's notes: the tool, the arm's lowest mode, targets, raises, what is not rated."""
    notes = []
    tool = found.tool
    if tool is not None:
        turn = float(np.linalg.norm(tool.rotation, axis=1).max())
        tilt = (f"; bearing tilt M / K_B included for {', '.join(tool.bearing_tilt)}"
                if tool.bearing_tilt else "")
        notes.append(
            f"tool '{tool.frame}': sags {tool.max_holding * MM_PER_M:.3g} mm holding the "
            f"payload still, worst {pose_text(result, int(tool.samples[tool.worst_holding]))}; "
            f"along the cycle up to {tool.max_translation * MM_PER_M:.3g} mm and "
            f"{turn * ARCMIN_PER_RAD:.3g} arcmin, "
            f"{pose_text(result, int(tool.samples[tool.worst]))}{tilt}.")
    modes = found.modes
    if modes is not None:
        shape = ", ".join(f"{name} {value:.2f}" for name, value in zip(modes.joints, modes.shape,
                                                                      strict=True))
        notes.append(f"arm: lowest mode {_hz(float(modes.frequencies[modes.lowest, 0]))} Hz "
                     f"{pose_text(result, int(modes.samples[modes.lowest]))}; its shape "
                     f"{shape} (each unit's K1 a spring, the inputs held by their servos).")
    notes += verdict_lines(found)
    if found.not_rated:
        units = sorted({j.unit.id for j in found.joints if j.name in found.not_rated
                        and j.unit is not None and j.name not in unheld(result)})
        which = f"{', '.join(units)} on " if units else ""
        notes.append(f"not rated: {STIFFNESS_NOT_RATED} ({which}"
                     f"{', '.join(found.not_rated)}): no twist or f_n there, and no tool "
                     f"deflection or arm mode; {SERIES_HINT}.")
    if found.rigid:
        notes.append(f"rigid: {', '.join(found.rigid)} move with no unit and are taken as "
                     "rigid.")
    missing = [joint.name for joint in found.joints if joint.name in unheld(result)]
    if missing:
        notes.append(f"{', '.join(missing)}: {NO_UNIT_NOTE}.")
    windows = sorted({task_label(result, w.task) for j in found.joints for w in j.near_resonance})
    notes.append("twist: the unit's torsion under the joint torque on its catalog's three "
                 "segments, largest along the cycle / holding each pose still; f_n: sqrt(K1 / "
                 "M_jj) / 2 pi, M_jj the load inertia the joint sees (carried units "
                 "included); resonance: the input speed f_n x 30 rpm that excites it, near it: "
                 "seconds per cycle within 10 % of that speed"
                 + (f" (in {', '.join(windows)})" if len(result.counted) > 1 and windows else "")
                 + "; hyst. / lost: the catalog's hysteresis loss and lost motion.")
    return notes


def precision_warnings(result: SizingResult) -> list[str]:
    """What of the precision figures changes a decision, as lines for the review summary.

    A whole-arm target not met, the units raised for stiffness, and the chosen units whose
    catalog rates no stiffness (their figures unknown, as an unrated bearing's checks).
    """
    found = result.precision
    if found is None:
        return []
    lines = [target_text(target) for target in found.targets if not target.ok]
    lines += [raised_text(raised) for raised in found.raised]
    units = sorted({j.unit.id for j in found.joints if j.name in found.not_rated
                    and j.unit is not None and j.name not in unheld(result)})
    if units:
        lines.append(f"{', '.join(units)}: {NOT_RATED_NOTE} (precision).")
    return lines


def verdict_lines(found: Precision) -> list[str]:
    """Each whole-arm target's verdict and each unit raised for one, a line each."""
    return ([target_text(target) for target in found.targets]
            + [raised_text(raised) for raised in found.raised])


def raised_text(raised: Raise) -> str:
    """A unit raised for a whole-arm target, in a line."""
    mass = (f"+{raised.added_mass:.3g} kg" if raised.added_mass > 0.0
            else "no added mass" if raised.added_mass == 0.0
            else f"{raised.added_mass:.3g} kg")
    return (f"raised for stiffness ({raised.reason}): {raised.joint} {raised.chosen} -> "
            f"{raised.raised_to}, {mass}.")


def target_text(target: TargetCheck) -> str:
    """A whole-arm target's verdict in a line (plain text: the notes carry no markup).

    A target that could not be judged (no value: a unit rates no stiffness) says so.
    """
    value: float | None = target.value
    if target.name == "tool_deflection":
        reached = "not judged" if value is None else f"{value * MM_PER_M:.3g} mm"
        words = f"tool deflection {reached}, at most {target.limit * MM_PER_M:.3g} mm"
    else:
        reached = "not judged" if value is None else f"{_hz(value)} Hz"
        words = f"lowest arm mode {reached}, at least {target.limit:.3g} Hz"
    if target.ok:
        return f"target met: {words}."
    return f"target NOT met: {words}" + (f": {target.shortfall}." if target.shortfall else ".")
