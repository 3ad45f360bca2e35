"""Figures and the HTML report: the catalog's Figures 1 and 2 with the answer drawn on.

matplotlib is imported here only, so commands that draw nothing start fast.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from hdselect.codesign import FastestResult, RatioComparison  # noqa: E402
from hdselect.errors import InputError  # noqa: E402
from hdselect.export import write_output  # noqa: E402
from hdselect.outputs import Outputs  # noqa: E402
from hdselect.planning import Trajectory  # noqa: E402
from hdselect.report import ratio_text, utilization_text  # noqa: E402
from hdselect.rules import RPM_PER_RAD_S  # noqa: E402
from hdselect.sizing import JointSizing, SizingResult, at_rest  # noqa: E402

DEG_PER_RAD = 180.0 / np.pi
PLOT_POINTS = 20_000
"""Most points drawn per curve; a longer one is drawn by its extremes (`envelope`)."""


def envelope(t: np.ndarray, y: np.ndarray, points: int = PLOT_POINTS):
    """A curve thinned for drawing without losing its extremes.

    Up to `points` samples are drawn as they are; a longer curve is cut into
    `points` / 2 runs of equal length and each run drawn by its minimum and maximum (in
    time order), so every peak a reader looks for is still on the figure. NaN (a gap
    in the curve) is kept where a run holds nothing else.

    Returns:
        Times [s] and values, at most about `points` of each.
    """
    index = _extremes(y, points)
    return (t, y) if index is None else (t[index], y[index])


def _extremes(y: np.ndarray, points: int = PLOT_POINTS) -> np.ndarray | None:
    """Indices of each run's minimum and maximum (see `envelope`); None when short enough."""
    n = len(y)
    if n <= points:
        return None
    width = -(-n // (points // 2))
    runs = -(-n // width)
    padded = np.full(runs * width, np.nan)
    padded[:n] = y
    blocks = padded.reshape(runs, width)
    gaps = np.isnan(blocks)
    low = np.argmin(np.where(gaps, np.inf, blocks), axis=1)
    high = np.argmax(np.where(gaps, -np.inf, blocks), axis=1)
    first, second = np.minimum(low, high), np.maximum(low, high)
    index = np.column_stack([first, second]) + (np.arange(runs) * width)[:, None]
    return np.minimum(index.ravel(), n - 1)


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
        speed_ax.plot(*envelope(trajectory.t, trajectory.qd[:, j] * DEG_PER_RAD),
                      color="tab:blue", lw=1)
        speed_ax.set_ylabel(f"{name}\nspeed [deg/s]")
        torque_ax.plot(*envelope(trajectory.t, tau[:, j]), color="tab:red", lw=1)
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


def write_report(directory: str | Path, result: SizingResult, *,
                 command: Sequence[str] | None = None) -> None:
    """Write the HTML report into `directory`: ``index.html``, self-contained, and its figures.

    ``index.html`` embeds every figure, so it can be mailed or printed on its own;
    the figures are also written beside it as ``joint_<name>.png`` (and, for a joint
    with motors, its motor's torque-speed plane as ``motor_<name>.png``). Every file is
    written aside first and the whole report moved into place at the end
    (`hdselect.outputs`): a failure leaves no part of it, and puts back any file it
    would have replaced.

    Args:
        directory: Where to write; made (with its parents) if missing.
        result: The sizing result.
        command: The command line that made the result (program name first), recorded
            so that the report can be re-run; None from Python.

    Raises:
        InputError: The directory cannot be written.
    """
    with Outputs() as outputs:
        staging = outputs.directory(directory, "--report")
        report_files(staging, result, command=command)
        outputs.commit()


def report_files(directory: Path, result: SizingResult, *,
                 command: Sequence[str] | None = None) -> None:
    """Write the report's files into an existing (staging) directory, as `write_report` does.

    Raises:
        InputError: A file cannot be written.
    """
    from hdselect.html import slug

    page, figures, motor_figures = _report(result, command)
    try:
        for prefix, pngs in (("joint", figures), ("motor", motor_figures)):
            for name, png in pngs.items():
                (directory / f"{prefix}_{slug(name)}.png").write_bytes(png)
        (directory / "index.html").write_text(page, encoding="utf-8")
    except OSError as err:
        raise InputError(f"cannot write the report ({err.strerror})", path=directory,
                         field="--report") from err


def report_page(result: SizingResult, *, command: Sequence[str] | None = None) -> str:
    """The HTML report as one self-contained page, its figures embedded (``--report -``)."""
    return _report(result, command)[0]


def _report(result: SizingResult, command: Sequence[str] | None
            ) -> tuple[str, dict[str, bytes], dict[str, bytes]]:
    """The page, each joint's figure and each motor figure (PNG content by joint name)."""
    from hdselect.html import page
    from hdselect.provenance import provenance

    origin = provenance(result, command)
    figures = {joint.name: png_bytes(joint_figure(result, joint)) for joint in result.joints}
    motor_figures = {joint.name: png_bytes(motor_figure(result, joint))
                     for joint in result.joints if joint.motor_torque is not None}
    return page(result, figures, origin, motor_figures), figures, motor_figures


def png_bytes(fig: Figure, dpi: int = 130) -> bytes:
    """A figure as PNG content (and closed)."""
    stream = io.BytesIO()
    try:
        fig.savefig(stream, format="png", dpi=dpi, metadata={"Software": None})
    finally:
        plt.close(fig)
    return stream.getvalue()


_SHOW_BINDING = 0.25
"""From this utilization on, the binding rule's limit is always on the axis [-]."""
# Okabe and Ito's colour-blind-safe palette
_MOVING, _REST, _STOP, _MEAN, _ALLOWED = "#D55E00", "#0072B2", "#CC79A7", "#E69F00", "#009E73"


def joint_figure(result: SizingResult, joint: JointSizing) -> Figure:
    """Speed and output torque of one joint over the cycle, with its unit's limits.

    The speed panel gives the output speed on the left axis and the input speed on
    the right, scaled to the joint's own speeds. The torque panel separates the
    samples that count against the repeated-peak limit (moving) from those held at
    rest (static limit), marks the peak and the worst momentary event, and draws
    each limit that lies near the data; the others are listed as off the axis.

    Args:
        result: The sizing result.
        joint: One of its joints.

    Returns:
        The figure (the caller closes it).
    """
    traj = result.trajectory
    j = result.robot.joint_index(joint.name)
    chosen = joint.selected or joint.strongest
    unit = chosen.unit
    t = traj.t
    rest = at_rest(traj.qd[:, j], traj.qdd[:, j])
    fig, (speed_ax, torque_ax) = plt.subplots(2, 1, figsize=(11, 6.6), sharex=True,
                                              layout="constrained")
    for ax in (speed_ax, torque_ax):
        for start, end in _runs(rest, t, traj.dt):
            ax.axvspan(start, end, color="0.88", lw=0, zorder=0)
    output_rpm = np.abs(traj.qd[:, j]) * RPM_PER_RAD_S
    speed_ax.plot(*envelope(t, output_rpm), color=_MOVING, lw=1.2, label="|output speed|")
    top = float(output_rpm.max()) * 1.15
    if top == 0.0:
        top = 1.0
        speed_ax.text(0.5, 0.5, "this joint does not move in this cycle", ha="center",
                      va="center", transform=speed_ax.transAxes, color="0.3")
    speed_lines = [(unit.max_input_speed / unit.ratio, "k", "-",
                    f"max input speed {unit.max_input_speed:,.0f} rpm")]
    mean = chosen.checks["mean"].detail.get("mean_input_speed_rpm")
    if isinstance(mean, float) and mean > 0.0:
        speed_lines.append((mean / unit.ratio, _MEAN, ":",
                            f"mean input speed N_av {mean:,.0f} rpm"))
    binding = chosen.checks[chosen.binding]
    near = binding.utilization >= _SHOW_BINDING
    top = _limit_lines(speed_ax, speed_lines, top,
                       speed_lines[0][0] if near and chosen.binding == "speed" else None)
    speed_ax.set_ylim(0.0, top)
    speed_ax.set_ylabel("output speed [rpm]")
    right = speed_ax.secondary_yaxis("right", functions=(lambda x: x * unit.ratio,
                                                         lambda x: x / unit.ratio))
    right.set_ylabel(f"input speed [rpm] (x{unit.ratio})")

    torque = np.abs(joint.torque)
    moving = np.where(rest, np.nan, torque)
    held = np.where(rest, torque, np.nan)
    stop = np.abs(joint.stop_torque)
    torque_ax.plot(*envelope(t, stop), color=_STOP, lw=0.7, alpha=0.8,
                   label=f"emergency stop from each instant ({result.options.stop_time:g} s)")
    torque_ax.plot(*envelope(t, moving), color=_MOVING, lw=1.3,
                   label="|T| moving: repeated-peak limit")
    if np.any(rest):
        torque_ax.plot(*envelope(t, held), color=_REST, lw=2.2, label="|T| at rest: static limit")
    event = chosen.checks["momentary"]
    peak_at = int(np.nanargmax(moving)) if np.any(~rest) else None
    tops = [float(np.nanmax(torque)), float(stop.max())]
    if peak_at is not None:
        torque_ax.plot([t[peak_at]], [torque[peak_at]], "o", color=_MOVING, ms=7, mfc="none",
                       mew=1.8, label=f"peak {torque[peak_at]:.3g} N m at {t[peak_at]:.2f} s")
    when = event.detail.get("time_s")
    if isinstance(when, float) and event.value is not None:
        tops.append(event.value)
        torque_ax.plot([when], [event.value], "v", color=_STOP, ms=9, mec="k",
                       label=f"worst momentary: {event.detail.get('kind')} {event.value:.3g} N m "
                             f"at {when:.2f} s")
    lines = []
    if joint.load.mean_torque is not None:
        lines += [(joint.load.mean_torque, _MEAN, ":",
                   f"mean torque T_av {joint.load.mean_torque:.3g} N m"),
                  (chosen.checks["mean"].limit, _ALLOWED, ":",
                   f"allowed mean {chosen.checks['mean'].limit:.3g} N m")]
    for field, label, color, style in (("repeated_torque", "repeated-peak limit", "k", "-"),
                                       ("momentary_torque", "momentary limit", _STOP, "--"),
                                       ("static_torque", "static limit", _REST, "-.")):
        value = getattr(unit, field)
        kinds = {flag.kind for flag in unit.flags_for(field)}
        mark = " (stand-in)" if "fallback" in kinds else " (corrected)" if kinds else ""
        lines.append((value, color, style, f"{label} {value:.3g} N m{mark}"))
    keep = {"peak": unit.repeated_torque, "momentary": unit.momentary_torque,
            "static": unit.static_torque, "mean": chosen.checks["mean"].limit}.get(chosen.binding)
    top = _limit_lines(torque_ax, lines, max(max(tops), 1e-9) * 1.15, keep if near else None)
    torque_ax.set_ylim(0.0, top)
    torque_ax.set_ylabel("output torque [N m]")
    torque_ax.set_xlabel("time [s]")
    torque_ax.set_xlim(t[0], max(t[-1], t[0] + traj.dt))
    for ax in (speed_ax, torque_ax):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.09, 1.0), fontsize=8, frameon=False)
    state = "selected" if joint.selected else "no unit fits; the strongest shown"
    fig.suptitle(f"{joint.name}: {unit.id} ({state}), binding {chosen.binding} "
                 f"{utilization_text(binding.utilization, binding.ok)}", fontsize=12)
    return fig


def _limit_lines(ax, lines, top: float, keep: float | None = None) -> float:
    """Draw the lines near the data (within 1.6x of its top) and `keep`; list the others.

    Returns:
        The axis top that shows every line drawn.
    """
    if keep is not None:
        top = max(top, keep * 1.08)
    shown = [line for line in lines if line[0] <= 1.6 * top]
    top = max([top, *(value * 1.08 for value, *_ in shown)])
    for value, color, style, label in lines:
        if value in [line[0] for line in shown]:
            ax.axhline(value, color=color, ls=style, lw=1.2, label=label)
        else:
            ax.plot([], [], color=color, ls=style, lw=1.2, label=f"{label}: above the axis")
    return top


def motor_figure(result: SizingResult, joint: JointSizing) -> Figure:
    """The cycle's (input speed, motor torque) points over the motor's torque-speed limits.

    Every sample of the cycle as (|n|, |T_motor|) behind the selected pair's gearhead
    (the strongest pair's where none fits), under the motor's peak torque over speed
    (its curve, or flat), its rated torque (the RMS limit) and its maximum speed, with
    the cycle's RMS point and the worst sample against the peak marked.

    Args:
        result: The sizing result, with motors.
        joint: One of its joints that has motors (its ``motor_torque`` is set).

    Returns:
        The figure (the caller closes it).
    """
    traj = result.trajectory
    j = result.robot.joint_index(joint.name)
    chosen = joint.selected or joint.strongest
    motor, unit, demand = chosen.motor_unit, chosen.unit, chosen.motor
    assert motor is not None and demand is not None and joint.motor_torque is not None
    speed = np.abs(traj.qd[:, j]) * unit.ratio * RPM_PER_RAD_S
    torque = np.abs(joint.motor_torque)
    fig, ax = plt.subplots(figsize=(11, 5.2), layout="constrained")
    shown, fast = _extremes(torque), _extremes(speed)
    label = f"cycle: every {traj.dt * 1e3:g} ms sample (|n|, |T_motor|)"
    if shown is not None and fast is not None:  # a long cycle: each run's extremes
        shown = np.union1d(shown, fast)
        speed, torque = speed[shown], torque[shown]
        label = "cycle: the extreme samples of each stretch (|n|, |T_motor|)"
    ax.plot(speed, torque, ".", color=_REST, ms=2.5, alpha=0.35, label=label)
    top = max(motor.max_speed, float(speed.max())) * 1.08
    grid = np.linspace(0.0, motor.max_speed, 400)
    curve = "torque-speed curve" if motor.curve is not None else "flat: no curve given"
    ax.plot(grid, motor.peak_torque_at(grid), color="k", lw=1.6,
            label=f"peak torque ({curve}), up to {motor.peak_torque:.3g} N m")
    ax.axhline(motor.rated_torque, color=_ALLOWED, ls="--", lw=1.3,
               label=f"rated torque {motor.rated_torque:.3g} N m (limit of the RMS torque)")
    ax.axvline(motor.max_speed, color=_STOP, ls="-.", lw=1.2,
               label=f"max speed {motor.max_speed:,.0f} rpm")
    if demand.rms_speed is not None:
        ax.plot([demand.rms_speed], [demand.rms_torque], "D", color=_MOVING, ms=9, mec="k",
                label=f"RMS point ({demand.rms_speed:,.0f} rpm, {demand.rms_torque:.3g} N m)")
    worst = chosen.checks["motor_peak"]
    where = worst.detail.get("speed_rpm")
    if isinstance(where, float) and worst.value is not None:
        ax.plot([where], [worst.value], "v", color=_MEAN, ms=9, mec="k",
                label=f"worst sample: {utilization_text(worst.utilization, worst.ok)} of the "
                      "peak at that speed")
    ax.set_xlim(0.0, top)
    ax.set_ylim(0.0, max(motor.peak_torque, float(torque.max())) * 1.15)
    ax.set_xlabel("input speed |n| [rpm]")
    ax.set_ylabel("motor torque |T_motor| [N m]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    state = "selected" if joint.selected else "no pair fits; the strongest shown"
    side = chosen.motor_binding or "motor_peak"
    check = chosen.checks[side]
    ratio = joint.inertia_ratio(chosen)
    fig.suptitle(f"{joint.name}: motor {motor.id} behind {unit.id} ({state}), binding "
                 f"{side.removeprefix('motor_')} {utilization_text(check.utilization, check.ok)}"
                 + ("" if ratio is None else f", load/rotor {ratio_text(ratio)}"), fontsize=12)
    return fig


def _runs(mask: np.ndarray, t: np.ndarray, dt: float) -> list[tuple[float, float]]:
    """The time spans [s] where `mask` holds, each sample standing for one period."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return [(float(t[a]) - dt / 2, float(t[b - 1]) + dt / 2)
            for a, b in zip(edges[::2], edges[1::2], strict=True)]


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

    Speed against its limit (motion file, robot file or unit, whichever is lowest), torque
    against the unit's repeated-peak and momentary limits, the emergency-stop torque
    from each instant behind it.
    """
    trajectory, robot = result.trajectory, result.robot
    joints = result.check.joints
    fig, axes = plt.subplots(len(joints), 2, figsize=(11, 1.9 * len(joints) + 0.9),
                             sharex=True, squeeze=False)
    sources = {"motion": "motion file", "robot": "robot file", "unit": "unit"}
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


def write_study_png(path: str | Path, title: str, rows: Sequence[dict], first: str,
                    second: str | None, joints: Sequence[str]) -> None:
    """The unit selected and its L50 life per joint against a study's first varied parameter.

    One row of panels per joint: the selected unit (no unit fits: drawn at "none") and
    its L50 life, against `first`, one line per value of `second`.

    Args:
        path: PNG file to write.
        title: Figure title.
        rows: The study's rows (`hdselect.study`), typed values; failed cases are skipped.
        first: The parameter along x.
        second: The parameter of the lines, or None for one line.
        joints: Joints to draw, one row of panels each.
    """
    done = [row for row in rows if row["status"] == "ok"]
    xs = list(dict.fromkeys(_plain(row.get(first)) for row in done))
    numeric = all(isinstance(x, int | float) for x in xs)
    position = {x: (float(x) if isinstance(x, int | float) else float(k))  # type: ignore[misc]
                for k, x in enumerate(xs)}
    lines = list(dict.fromkeys(_plain(row.get(second)) for row in done)) if second else [None]
    units = sorted({row["unit"] for row in done if row["unit"]}, key=_natural)
    level = {unit: k for k, unit in enumerate(["none", *units])}
    colors = plt.get_cmap("viridis")(np.linspace(0.0, 0.9, max(len(lines), 1)))
    fig, axes = plt.subplots(len(joints), 2, figsize=(11, 1.7 * len(joints) + 1.2),
                             sharex=True, squeeze=False)
    for r, joint in enumerate(joints):
        unit_ax, life_ax = axes[r]
        for color, value in zip(colors, lines, strict=True):
            mine = [row for row in done if row["joint"] == joint
                    and (second is None or _plain(row.get(second)) == value)]
            x = [position[_plain(row.get(first))] for row in mine]
            label = None if second is None or r else f"{second} {value}"
            style = "o-" if len(set(x)) == len(x) else "o"  # a third parameter: points only
            unit_ax.plot(x, [level[row["unit"] or "none"] for row in mine], style, ms=3,
                         lw=1, color=color, label=label)
            life = [row["life_l50_h"] if row["unit"] else np.nan for row in mine]
            life_ax.plot(x, [np.nan if v is None else v for v in life], style, ms=3, lw=1,
                         color=color)
        unit_ax.set_yticks(range(len(level)), list(level))
        unit_ax.set_ylim(-0.5, len(level) - 0.5)
        unit_ax.set_ylabel(joint)
        if any(row["unit"] and row["life_l50_h"] for row in done if row["joint"] == joint):
            life_ax.set_yscale("log")
            life_ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        else:
            life_ax.set_yticks([])
            life_ax.text(0.5, 0.5, "unlimited (no load while moving)", ha="center",
                         va="center", transform=life_ax.transAxes, color="0.4")
        life_ax.set_ylabel("L50 life [h]")
        for ax in (unit_ax, life_ax):
            ax.grid(alpha=0.3)
    axes[0, 0].set_title("unit selected")
    axes[0, 1].set_title("its L50 life (unlimited: not drawn)")
    for ax in axes[-1]:
        ax.set_xlabel(_AXIS_LABELS.get(first, first))
        if not numeric:
            ax.set_xticks(range(len(xs)), [str(x) for x in xs])
    fig.suptitle(title)
    if second is not None:
        fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.93))
        fig.legend(loc="upper center", ncols=min(len(lines), 6), bbox_to_anchor=(0.5, 0.97),
                   fontsize="small", frameon=False)
    _save(fig, Path(path))


_AXIS_LABELS = {"payload": "payload [kg]", "time_scale": "time scale s: the cycle run s times "
                "slower [-]", "stop_time": "stop time [s]", "motor_mass": "motor mass [kg]",
                "rotor_inertia": "rotor inertia [kg m^2]", "life_hours": "required life [h]"}


def _plain(value: object) -> object:
    """A parameter value usable as a key and a label (lists become text)."""
    if isinstance(value, list | tuple | dict):
        return str(value)
    return value


def _natural(text: str) -> list[object]:
    """PSA-08-80 before PSA-08-100: numbers compared as numbers."""
    import re

    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", text)]
