"""Figures and the HTML report: the catalog's Figures 1 and 2 with the answer drawn on.

matplotlib is imported here only, so commands that draw nothing start fast.
"""

from __future__ import annotations

import html
import shutil
import tempfile
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from hdselect.codesign import FastestResult, RatioComparison  # noqa: E402
from hdselect.errors import InputError  # noqa: E402
from hdselect.export import assumptions, write_output  # noqa: E402
from hdselect.planning import Trajectory  # noqa: E402
from hdselect.report import life_text, percent, time_scale_text, verdict  # noqa: E402
from hdselect.rules import CHECK_LABELS, CHECKS, RPM_PER_RAD_S  # noqa: E402
from hdselect.sizing import JointSizing, SizingResult  # noqa: E402

DEG_PER_RAD = 180.0 / np.pi


def write_profiles_png(path: str | Path, trajectory: Trajectory, tau: np.ndarray,
                       joints: Sequence[str], *, title: str = "") -> None:
    """Speed and torque over the cycle for each joint (the catalog's Figures 1 and 2).

    Args:
        path: PNG file to write.
        trajectory: The sampled trajectory.
        tau: Joint torques [N m], shape (n, dof).
        joints: Joints to draw, one row each.
        title: Figure title.
    """
    names = list(trajectory.joint_names)
    fig, axes = plt.subplots(len(joints), 2, figsize=(11, 1.9 * len(joints) + 0.8),
                             sharex=True, squeeze=False)
    for row, name in enumerate(joints):
        j = names.index(name)
        speed_ax, torque_ax = axes[row]
        speed_ax.plot(trajectory.t, trajectory.qd[:, j] * DEG_PER_RAD, color="tab:blue", lw=1)
        speed_ax.set_ylabel(f"{name}\nspeed [deg/s]")
        torque_ax.plot(trajectory.t, tau[:, j], color="tab:red", lw=1)
        torque_ax.set_ylabel("torque [N m]")
        for ax in (speed_ax, torque_ax):
            ax.axhline(0.0, color="0.6", lw=0.6)
            ax.grid(alpha=0.3)
    axes[0, 0].set_title("Figure 1: output speed")
    axes[0, 1].set_title("Figure 2: output torque")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(title)
    _save(fig, Path(path))


def write_report(directory: str | Path, result: SizingResult) -> None:
    """Write an HTML report with figures into `directory`.

    The page holds every joint's profiles with its unit's limits drawn, every
    candidate's utilization, and the assumptions. It is built in a temporary
    directory beside `directory` and moved into place file by file, so no file
    is ever half-written.

    Raises:
        InputError: The directory cannot be written.
    """
    target = Path(directory)
    if target.exists() and not target.is_dir():
        raise InputError("exists and is not a directory", path=target, field="--report")
    try:
        parent = target.resolve().parent
        parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(dir=parent, prefix=f".{target.name}."))
    except OSError as err:
        raise InputError(f"cannot write here ({err.strerror})", path=target,
                         field="--report") from err
    try:
        images = []
        for joint in result.joints:
            name = f"joint_{_slug(joint.name)}.png"
            _save(_joint_figure(result, joint), staging / name)
            images.append((joint, name))
        _save(_utilization_figure(result), staging / "utilization.png")
        write_output(staging / "index.html", lambda stream: stream.write(_page(result, images)))
        target.mkdir(exist_ok=True)
        for file in staging.iterdir():
            file.replace(target / file.name)
    except OSError as err:
        raise InputError(f"cannot write the report ({err.strerror})", path=target,
                         field="--report") from err
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _joint_figure(result: SizingResult, joint: JointSizing) -> Figure:
    """Input speed and output torque of one joint with the chosen unit's limits."""
    traj = result.trajectory
    j = result.robot.joint_index(joint.name)
    chosen = joint.selected or joint.strongest
    unit = chosen.unit
    fig, (speed_ax, torque_ax) = plt.subplots(2, 1, figsize=(10, 6.2), sharex=True)
    input_rpm = np.abs(traj.qd[:, j]) * unit.ratio * RPM_PER_RAD_S
    speed_ax.plot(traj.t, input_rpm, color="tab:blue", lw=1.2, label="input speed |n|")
    speed_ax.axhline(unit.max_input_speed, color="k", ls="-", lw=1.2,
                     label=f"max input speed {unit.max_input_speed:,.0f} rpm")
    mean = chosen.checks["mean"].detail.get("mean_input_speed_rpm")
    if isinstance(mean, float):
        speed_ax.axhline(mean, color="tab:blue", ls=":", lw=1.2,
                         label=f"mean speed N_av {mean:,.0f} rpm (moving part)")
    speed_ax.set_ylabel("input speed [rpm]")
    speed_ax.set_ylim(0, unit.max_input_speed * 1.12)
    torque_ax.plot(traj.t, np.abs(joint.stop_torque), color="tab:orange", lw=0.8, alpha=0.7,
                   label=f"emergency stop from each instant ({result.options.stop_time:g} s)")
    torque_ax.plot(traj.t, np.abs(joint.torque), color="tab:red", lw=1.3, label="|T| output")
    lines = [("repeated_torque", "repeated-peak limit", "k", "-"),
             ("momentary_torque", "momentary limit", "tab:purple", "--"),
             ("static_torque", "static limit", "tab:gray", "-.")]
    for field, label, color, style in lines:
        value = getattr(unit, field)
        kinds = {flag.kind for flag in unit.flags_for(field)}
        mark = " (stand-in)" if "fallback" in kinds else " (corrected)" if kinds else ""
        torque_ax.axhline(value, color=color, ls=style, lw=1.1,
                          label=f"{label} {value:.3g} N m{mark}")
    if joint.load.mean_torque is not None:
        torque_ax.axhline(joint.load.mean_torque, color="tab:red", ls=":", lw=1.2,
                          label=f"mean torque T_av {joint.load.mean_torque:.3g} N m")
        torque_ax.axhline(chosen.checks["mean"].limit, color="tab:green", ls=":", lw=1.2,
                          label=f"allowed mean {chosen.checks['mean'].limit:.3g} N m")
    event = chosen.checks["momentary"]
    when = event.detail.get("time_s")
    if isinstance(when, float) and event.value is not None:
        torque_ax.plot([when], [event.value], "v", color="tab:purple", ms=8,
                       label=f"worst T4: {event.detail.get('kind')} {event.value:.3g} N m")
    torque_ax.set_ylabel("output torque [N m]")
    torque_ax.set_xlabel("time [s]")
    top = max(unit.momentary_torque, unit.static_torque, float(np.abs(joint.stop_torque).max()))
    torque_ax.set_ylim(0, top * 1.1)
    for ax in (speed_ax, torque_ax):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    state = "selected" if joint.selected else "no unit fits; strongest shown"
    fig.suptitle(f"{joint.name}: {unit.id} ({state}), binding {chosen.binding} "
                 f"{percent(chosen.checks[chosen.binding].utilization)}")
    fig.tight_layout()
    return fig


def _utilization_figure(result: SizingResult) -> Figure:
    """Utilization of every rule for every unit and joint, the selection outlined."""
    rules = [r for r in CHECKS if any(r in c.checks and c.checks[r].value is not None
                                      for j in result.joints for c in j.candidates)]
    n = len(result.joints)
    cols = min(3, n)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 0.42 * len(result.units) * rows
                                                  + 1.6 * rows), squeeze=False)
    for ax, joint in zip(axes.flat, result.joints, strict=False):
        grid = np.array([[c.checks[r].utilization if r in c.checks else np.nan for r in rules]
                         for c in joint.candidates])
        ax.imshow(np.minimum(grid, 2.0), cmap="RdYlGn_r", vmin=0.0, vmax=2.0, aspect="auto")
        for (i, k), value in np.ndenumerate(grid):
            if np.isfinite(value):
                ax.text(k, i, f"{value * 100:.0f}", ha="center", va="center", fontsize=7)
        ax.set_xticks(range(len(rules)), [CHECK_LABELS[r] for r in rules], fontsize=8)
        ax.set_yticks(range(len(joint.candidates)),
                      [("▶ " if c is joint.selected else "") + c.unit.id
                       for c in joint.candidates], fontsize=8)
        ax.set_title(joint.name, fontsize=10)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle("Utilization [% of limit] of every unit (green fits, red fails; ▶ selected)")
    fig.tight_layout()
    return fig


def _page(result: SizingResult, images: list[tuple[JointSizing, str]]) -> str:
    esc = html.escape
    rows = []
    for joint in result.joints:
        c = joint.selected
        if c is None:
            cells = [joint.name, "none", verdict(joint.strongest) + f" ({joint.strongest.unit.id})",
                     "", "", "", ""]
        else:
            assert c.motor is not None
            binding = f"{c.binding} {percent(c.checks[c.binding].utilization)}"
            cells = [joint.name, c.unit.id, binding, life_text(c.life_hours),
                     f"{c.motor.peak_torque:.3g}", f"{c.motor.rms_torque:.3g}",
                     f"{c.motor.max_speed:,.0f}"]
        cells += [f"{joint.carried_mass:.2f}", "gravity-loaded: fail-safe needed"
                  if joint.gravity_loaded else ""]
        rows.append("<tr>" + "".join(f"<td>{esc(x)}</td>" for x in cells) + "</tr>")
    notes = sorted({f"{c.unit.id}: {f.note}" for j in result.joints for c in [j.selected]
                    if c is not None for f in c.flags})
    slow = [f"{j.name}: {time_scale_text(j)}" for j in result.joints if j.selected is None]
    items = "".join(f"<li><b>{esc(k)}</b>: {esc(v)}</li>"
                    for k, v in assumptions(result).items())
    figures = "".join(f'<h3>{esc(j.name)}</h3><img src="{name}" alt="{esc(j.name)}">'
                      for j, name in images)
    header = ("joint", "unit", "binding rule", "L50 life", "motor peak [N m]",
              "motor rms [N m]", "motor max [rpm]", "carries [kg]", "notes")
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>hdselect: {esc(result.title)}</title>
<style>body{{font-family:sans-serif;max-width:1150px;margin:2em auto;color:#222}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:left}}
td{{white-space:nowrap}}
img{{max-width:100%}}</style></head><body>
<h1>Gearhead selection: {esc(result.title)}</h1>
<p>Cycle {result.cycle_time:.3f} s,
{len(result.trajectory.t):,} samples every {result.trajectory.dt * 1e3:g} ms.
{"Every joint has a unit." if result.feasible else "<b>Some joints have no unit.</b>"}</p>
<table><tr>{"".join(f"<th>{esc(h)}</th>" for h in header)}</tr>{"".join(rows)}</table>
{"<ul>" + "".join(f"<li>{esc(s)}</li>" for s in slow) + "</ul>" if slow else ""}
<h2>Assumptions</h2><ul>{items}</ul>
<h2>Catalog stand-ins and corrections used</h2>
<ul>{"".join(f"<li>{esc(n)}</li>" for n in notes) or "<li>none</li>"}</ul>
<p>Harmonic Drive gearing backdrives when its input is free: a gravity-loaded joint needs a
fail-safe device on the output wherever a falling load could injure.</p>
<h2>Utilization of every candidate</h2><img src="utilization.png" alt="utilization">
<h2>Torque-speed profiles with the selected unit's limits</h2>{figures}
</body></html>
"""


def _slug(name: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)


def _save(fig: Figure, path: Path) -> None:
    try:
        write_output(path, lambda stream: fig.savefig(stream, format="png", dpi=110,
                                                      bbox_inches="tight"), binary=True)
    finally:
        plt.close(fig)


def write_ratios_png(path: str | Path, comparison: RatioComparison) -> None:
    """The shortest cycle against the unit on each joint compared, the others' units fixed.

    One panel per joint: each unit's cycle time, the unit `size` selects marked, the
    units that cannot drive the path at any speed drawn as a cross on the top edge.
    """
    joints = comparison.joints
    cols = min(3, len(joints))
    rows = -(-len(joints) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.4 * cols + 0.6, 3.3 * rows + 0.9),
                             squeeze=False)
    times = [row.cycle_time for joint in joints for row in joint.rows
             if row.cycle_time is not None]
    low, high = (min(times), max(times)) if times else (0.0, 1.0)
    pad = max(0.05 * (high - low), 0.005 * high)
    top = high + 3.0 * pad
    for ax, joint in zip(axes.flat, joints, strict=False):
        labels = [row.unit.id for row in joint.rows]
        x = np.arange(len(labels))
        fits = [(k, row.cycle_time) for k, row in enumerate(joint.rows)
                if row.cycle_time is not None]
        if fits:
            ax.plot([k for k, _ in fits], [t for _, t in fits], "o-", color="tab:blue", lw=1,
                    ms=5, label="shortest cycle")
        for k, row in enumerate(joint.rows):
            if row.cycle_time is None:
                ax.plot([k], [top - pad], "x", color="tab:red", ms=9, mew=2,
                        label="cannot drive the path" if k == next(
                            i for i, r in enumerate(joint.rows) if r.cycle_time is None)
                        else None)
            if row.unit.id == joint.selected and row.cycle_time is not None:
                ax.plot([k], [row.cycle_time], "*", color="tab:orange", ms=15, zorder=3,
                        label="selected by size")
        ax.axhline(comparison.base.cycle_time, color="0.5", ls=":", lw=1,
                   label=f"all units as given ({comparison.base.cycle_time:.3f} s)")
        ax.set_xticks(x, labels, rotation=45, ha="right", fontsize=8)
        ax.set_ylim(low - 2.0 * pad, top)
        ax.set_ylabel("cycle time [s]")
        ax.set_title(f"unit on {joint.joint}", fontsize=10)
        ax.grid(alpha=0.3)
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
    fig.suptitle(f"{comparison.robot.path.name} on the path of {comparison.motion.path.name}: "
                 "shortest cycle by unit, the other joints' units fixed", fontsize=11)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    _save(fig, Path(path))


def write_fastest_png(path: str | Path, result: FastestResult) -> None:
    """Speed and output torque of every sized joint along the fastest cycle, limits drawn.

    Speed against its limit (motion file, URDF or unit, whichever is lowest), torque
    against the unit's repeated-peak and momentary limits, the emergency-stop torque
    from each instant behind it.
    """
    trajectory, robot = result.trajectory, result.robot
    joints = result.check.joints
    fig, axes = plt.subplots(len(joints), 2, figsize=(11, 1.9 * len(joints) + 0.9),
                             sharex=True, squeeze=False)
    sources = {"motion": "motion file", "robot": "URDF", "unit": "unit"}
    for row, joint in enumerate(joints):
        j = robot.joint_index(joint.name)
        (candidate,) = joint.candidates
        unit, lim = candidate.unit, result.limits[joint.name]
        scale = DEG_PER_RAD if robot.revolute[j] else 1.0
        speed_ax, torque_ax = axes[row]
        speed_ax.plot(trajectory.t, trajectory.qd[:, j] * scale, color="tab:blue", lw=1)
        for sign in (1.0, -1.0):
            speed_ax.axhline(sign * lim.velocity * scale, color="k", ls="--", lw=0.8,
                             label=f"speed limit ({sources[lim.velocity_source]})"
                             if sign > 0 else None)
        speed_ax.set_ylabel(f"{joint.name}\nspeed [{'deg/s' if robot.revolute[j] else 'm/s'}]")
        torque_ax.plot(trajectory.t, joint.stop_torque, color="tab:orange", lw=0.7, alpha=0.6,
                       label="emergency stop from each instant")
        torque_ax.plot(trajectory.t, joint.torque, color="tab:red", lw=1, label="output torque")
        for sign in (1.0, -1.0):
            torque_ax.axhline(sign * unit.repeated_torque, color="k", ls="--", lw=0.8,
                              label=f"{unit.id} repeated peak" if sign > 0 else None)
            torque_ax.axhline(sign * unit.momentary_torque, color="tab:purple", ls=":", lw=0.8,
                              label=f"{unit.id} momentary" if sign > 0 else None)
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
    _save(fig, Path(path))
