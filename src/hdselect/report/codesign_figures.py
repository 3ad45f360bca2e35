"""Co-design drawn: the fastest cycle against its limits, the ratios on cycle time."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from hdselect.codesign.fastest_cycle import FastestResult, RatioComparison
from hdselect.motion.motionfile import ANGLE_UNITS
from hdselect.report.figures import save


def write_ratios_png(path: str | Path, comparison: RatioComparison) -> None:
    """The shortest cycle against the unit on each joint compared, the others' units fixed.

    One panel per joint: each unit that can drive the path as a point at its cycle time
    (categories, so no line joins them), the unit `size` selects marked; the units that
    cannot drive the path at any speed are not on the time axis but listed beside the
    panel.
    """
    joints = comparison.joints
    cols = min(3, len(joints))
    rows = -(-len(joints) // cols)
    fig = Figure(figsize=(5.6 * cols + 0.4, 3.4 * rows + 1.0))
    axes = fig.subplots(rows, cols, squeeze=False)
    times = [row.cycle_time for joint in joints for row in joint.rows
             if row.cycle_time is not None]
    low, high = (min(times), max(times)) if times else (0.0, 1.0)
    pad = max(0.05 * (high - low), 0.005 * high)
    for ax, joint in zip(axes.flat, joints, strict=False):
        fits = [row for row in joint.rows if row.cycle_time is not None]
        cannot = [row.unit.id for row in joint.rows if row.cycle_time is None]
        x = np.arange(len(fits))
        if fits:
            ax.plot(x, [row.cycle_time for row in fits], "o", color="tab:blue", ms=6,
                    label="shortest cycle with this unit")
        for k, row in enumerate(fits):
            if row.unit.id == joint.selected:
                ax.plot([k], [row.cycle_time], "*", color="tab:orange", ms=15, zorder=3,
                        label="the unit size selects")
        ax.axhline(comparison.base.mean_cycle_time, color="0.5", ls=":", lw=1,
                   label=f"every joint's unit as given ({comparison.base.mean_cycle_time:.3f} s)")
        ax.set_xticks(x, [row.unit.id for row in fits], rotation=45, ha="right", fontsize=8)
        ax.set_xlim(-0.6, max(len(fits), 1) - 0.4)
        ax.set_ylim(low - 2.0 * pad, high + 2.0 * pad)
        ax.set_ylabel("cycle time [s]")
        ax.set_title(f"unit on {joint.joint}", fontsize=10)
        ax.grid(alpha=0.3, axis="y")
        ax.text(1.03, 1.0, "cannot drive\nthe path:\n" + ("\n".join(cannot) if cannot else "none"),
                transform=ax.transAxes, va="top", ha="left", fontsize=8, color="tab:red")
    for ax in list(axes.flat)[len(joints):]:
        ax.axis("off")
    handles, names = {}, []
    for ax in axes.flat:
        for handle, name in zip(*ax.get_legend_handles_labels(), strict=True):
            if name not in handles:
                handles[name] = handle
                names.append(name)
    fig.legend([handles[n] for n in names], names, loc="lower center", ncol=min(4, len(names)),
               fontsize=8, frameon=False)
    what = (f"the path of {comparison.motion.path.name}" if comparison.mix is None else
            f"the paths of {comparison.mix.path.name} (cycles weighted by shares)")
    fig.suptitle(f"{comparison.robot.path.name} on {what}: shortest cycle by unit, the other "
                 "joints' units fixed", fontsize=11)
    fig.tight_layout(rect=(0, 0.06, 0.97, 1), w_pad=5.0)
    save(fig, Path(path))


def write_fastest_png(path: str | Path, result: FastestResult) -> None:
    """Speed and output torque of every sized joint along the fastest cycle, limits drawn.

    Speed (in the motion file's angle unit) against its limit (motion file, robot file or
    unit, whichever is lowest), torque against the unit's repeated-peak and momentary
    limits, the emergency-stop torque from each instant behind it.
    """
    trajectory, robot, angle = result.trajectory, result.robot, result.motion.angle_unit
    joints = result.check.joints
    fig = Figure(figsize=(11, 1.9 * len(joints) + 0.9))
    axes = fig.subplots(len(joints), 2, sharex=True, squeeze=False)
    sources = {"motion": "motion file", "robot": "robot file", "unit": "unit"}
    for row, joint in enumerate(joints):
        j = robot.joint_index(joint.name)
        (candidate,) = joint.candidates
        unit, lim = candidate.unit, result.limits[joint.name]
        speed_ax, torque_ax = axes[row]  # the file's angle unit, as the fastest table speaks
        scale = 1.0 / ANGLE_UNITS[angle] if robot.revolute[j] else 1.0
        speed_ax.plot(trajectory.t, trajectory.qd[:, j] * scale, color="tab:blue", lw=1)
        for sign in (1.0, -1.0):
            speed_ax.axhline(sign * lim.velocity * scale, color="k", ls="--", lw=0.8,
                             label=f"speed limit ({sources[lim.velocity_source]})"
                             if sign > 0 else None)
        speed_ax.set_ylabel(f"{joint.name}\nspeed [{angle if robot.revolute[j] else 'm'}/s]")
        torque_ax.plot(trajectory.t, joint.stop_torque, color="tab:orange", lw=0.7, alpha=0.6,
                       label="emergency stop from each instant")
        torque_ax.plot(trajectory.t, joint.torque, color="tab:red", lw=1, label="output torque")
        for sign in (1.0, -1.0):
            torque_ax.axhline(sign * unit.repeated_torque, color="k", ls="--", lw=0.8,
                              label=f"{unit.id} repeated peak" if sign > 0 else None)
            if unit.momentary_torque is not None:  # None: not rated by the source
                torque_ax.axhline(sign * unit.momentary_torque, color="tab:purple", ls=":",
                                  lw=0.8, label=f"{unit.id} momentary" if sign > 0 else None)
        torque_ax.set_ylabel("torque [N m]")
        for ax in (speed_ax, torque_ax):
            ax.axhline(0.0, color="0.6", lw=0.5)
            ax.grid(alpha=0.3)
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    axes[0, 0].set_title("output speed")
    axes[0, 1].set_title("output torque (gearhead masses carried)")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(f"{robot.path.name}: the fastest run of {result.motion.path.name}, cycle "
                 f"{result.cycle_time:.3f} s")
    fig.tight_layout()
    save(fig, Path(path))
