"""The precision figures in the HTML report: each unit's twist and resonance, the worst poses."""

from __future__ import annotations

import base64
import math
from collections.abc import Mapping

from hdselect.report.html_tables import esc, number, table
from hdselect.report.precision_tables import pose_text, raised_text, target_text
from hdselect.sizing.precision import JointPrecision, Precision
from hdselect.sizing.precision_records import (
    ARCMIN_PER_RAD,
    MM_PER_M,
    NO_UNIT_NOTE,
    NOT_RATED_NOTE,
    SERIES_HINT,
    STIFFNESS_NOT_RATED,
    pose_of,
    unheld,
)
from hdselect.sizing.result import SizingResult

CAPTIONS = {
    "tool": ("The tool frame's deflection from its commanded pose at each evaluated pose: "
             "moving along the cycle (the joints' torques and the bearings' moments) and "
             "holding each pose still (gravity and the payload only), its largest marked."),
    "modes": ("The arm's lowest natural frequencies at each evaluated pose (K v = w&sup2; M(q) "
              "v, each unit's K1 a spring, the inputs held by their servos), the lowest "
              "marked; dotted, each joint's single-axis f_n = sqrt(K1 / M_jj) / 2 pi (off the "
              "axis where far above the arm's modes)."),
}
"""Each figure's caption, by its name in `hdselect.report.precision_figures`."""

ALTS = {"tool": "the tool's deflection along the cycle, moving and holding still",
        "modes": "the arm's lowest natural frequencies along the cycle"}
"""Each figure's text alternative."""


def precision_section(result: SizingResult, figures: Mapping[str, bytes]) -> str:
    """The "Precision" section: per joint its twist and f_n, the tool, the arm's lowest mode.

    Args:
        result: The sizing result; empty without precision figures.
        figures: PNG content of the section's figures by name (``tool``, ``modes``).
    """
    found = result.precision
    if found is None or not found.joints:
        return ""
    header = ["joint", "unit", "twist max [arcmin]", "twist holding [arcmin]",
              "hysteresis loss [arcmin]", "lost motion [arcmin]", "lowest f_n [Hz]",
              "at", "resonance input speed [rpm]", "near resonance [s per cycle]"]
    missing = unheld(result)
    rows = [[esc(joint.name), "none", f"<td class='t wrap'>{esc(NO_UNIT_NOTE)}</td>",
             *("-",) * (len(header) - 3)] if joint.name in missing else _row(result, joint)
            for joint in found.joints]
    intro = ("<p>Each unit twists under its joint's torque, on its catalog's three segments "
             "(K1 up to T1, K2 up to T2, K3 above): the largest twist along the cycle, and "
             "holding each pose still. Its single-axis natural frequency f_n = sqrt(K1 / "
             "M_jj) / 2 pi, M_jj the load inertia the joint sees (carried units included), at "
             f"each of {len(found.poses):,} evaluated poses; the transmission error excites it "
             "at the input speed f_n x 30 rpm, and the time per cycle within 10 % of that "
             "speed is given.</p>")
    return (f"<section id=precision><h2>Precision</h2>{intro}"
            f"{table(header, rows, left=2, text=[7])}{_whole(result, found)}"
            f"{_poses(result, found)}"
            + "".join(_figure(name, png) for name, png in figures.items()) + "</section>")


def _row(result: SizingResult, joint: JointPrecision) -> list[str]:
    unit = "-" if joint.unit is None else esc(joint.unit.id)
    catalog = [_arcmin(joint.hysteresis_loss), _arcmin(joint.lost_motion)]
    if not joint.rated:
        words = f"<td class='t wrap'>{esc(STIFFNESS_NOT_RATED)}</td>"
        return [esc(joint.name), unit, words, "-", *catalog, "-", "-", "-", "-"]
    when = ("-" if joint.lowest_frequency_sample is None
            else _when(result, joint.lowest_frequency_sample))
    speed = joint.resonance_speed
    return [esc(joint.name), unit, _arcmin(joint.max_torsion), _arcmin(joint.holding_torsion),
            *catalog, _hz(joint.lowest_frequency), when,
            "-" if speed is None or not math.isfinite(speed) else number(speed),
            number(joint.near_resonance_time)]


def _when(result: SizingResult, sample: int) -> str:
    """A pooled sample's time (and task), escaped, the number kept beside its unit."""
    pose = pose_of(result, sample)
    return (f"{pose.time:.2f}&nbsp;s"
            + (f" ({esc(pose.label)})" if len(result.counted) > 1 else ""))


def _arcmin(angle: float | None) -> str:
    return "-" if angle is None else number(angle * ARCMIN_PER_RAD)


def _hz(frequency: float | None) -> str:
    if frequency is None:
        return "-"
    return "inf" if not math.isfinite(frequency) else number(frequency)


def _whole(result: SizingResult, found: Precision) -> str:
    """The tool, the arm's lowest mode, the targets, the raised units and what is not rated."""
    items = []
    tool = found.tool
    if tool is not None:
        items.append(f"<b>Tool '{esc(tool.frame)}'</b>: sags {tool.max_holding * MM_PER_M:.3g} "
                     "mm holding the payload still (the static accuracy), "
                     f"{esc(pose_text(result, int(tool.samples[tool.worst_holding])))}; up to "
                     f"{tool.max_translation * MM_PER_M:.3g} mm along the cycle, "
                     f"{esc(pose_text(result, int(tool.samples[tool.worst])))}."
                     + (f" The output bearings' tilt M / K_B is included for "
                        f"{esc(', '.join(tool.bearing_tilt))}." if tool.bearing_tilt else ""))
    modes = found.modes
    if modes is not None:
        items.append(f"<b>Arm</b>: lowest mode {_hz(float(modes.frequencies[modes.lowest, 0]))} "
                     f"Hz, {esc(pose_text(result, int(modes.samples[modes.lowest])))}.")
    items += [esc(target_text(target)) for target in found.targets]
    items += [esc(raised_text(raised)) for raised in found.raised]
    if found.not_rated:
        items.append(f"{esc(', '.join(found.not_rated))}: {esc(NOT_RATED_NOTE)}; the whole "
                     f"arm's figures need every joint's. {esc(SERIES_HINT)}.")
    if found.rigid:
        items.append(f"Taken as rigid (moving, with no unit): {esc(', '.join(found.rigid))}.")
    return "<ul>" + "".join(f"<li>{item}</li>" for item in items) + "</ul>"


def _poses(result: SizingResult, found: Precision) -> str:
    """The worst poses tabled by joint name: the tool's sag held and moving, the lowest mode."""
    columns = []
    if found.tool is not None:
        tool = found.tool
        columns += [(f"tool's worst holding still: {tool.max_holding * MM_PER_M:.3g} mm",
                     int(tool.samples[tool.worst_holding])),
                    (f"tool's worst along the cycle: {tool.max_translation * MM_PER_M:.3g} mm",
                     int(tool.samples[tool.worst]))]
    if found.modes is not None:
        columns.append((f"lowest arm mode: {_hz(found.modes.lowest_frequency)} Hz",
                        int(found.modes.samples[found.modes.lowest])))
    if not columns:
        return ""
    poses = [pose_of(result, sample) for _, sample in columns]
    robot = result.robot
    rows = [["time", *(_when(result, sample) for _, sample in columns)]]
    for name in poses[0].q:
        revolute = robot.revolute[robot.joint_index(name)]
        rows.append([esc(name), *(f"{pose.q[name] * 180.0 / math.pi:.1f}&deg;" if revolute
                                  else f"{pose.q[name]:.4g} m" for pose in poses)])
    header = ["joint", *(esc(words) for words, _ in columns)]
    shape = ""
    if found.modes is not None:
        shape = ("<p>The lowest mode's shape (largest 1): "
                 + ", ".join(f"{esc(name)} {value:.2f}" for name, value in
                             zip(found.modes.joints, found.modes.shape, strict=True)) + ".</p>")
    return f"<h3>The worst poses</h3>{table(header, rows)}{shape}"


def _figure(name: str, png: bytes) -> str:
    data = base64.b64encode(png).decode("ascii")
    return (f"<figure><img src='data:image/png;base64,{data}' alt='{esc(ALTS[name])}'>"
            f"<figcaption>{CAPTIONS[name]}</figcaption></figure>")
