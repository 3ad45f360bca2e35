"""A sized joint drawn on the catalog's Figures 1 and 2.

Its torque and speed over the cycle against the unit's limits, and its motor's
torque-speed demand.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from hdselect.catalog.rules import RPM_PER_RAD_S, Part, at_rest, rule
from hdselect.report.figures import ALLOWED, MEAN, MOVING, REST, STOP, envelope, extremes
from hdselect.report.terminal import binding_words, ratio_text, utilization_text
from hdselect.sizing.diagnosis import diagnosis_of
from hdselect.sizing.result import JointSizing, SizingResult

_SHOW_BINDING = 0.25
"""From this utilization on, the binding rule's limit is always on the axis [-]."""


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
    t, qd, rest, spans = timeline(result, j)
    fig = Figure(figsize=(11, 6.6), layout="constrained")
    speed_ax, torque_ax = fig.subplots(2, 1, sharex=True)
    for ax in (speed_ax, torque_ax):
        for start, end in rest_spans(rest, t, traj.dt):
            ax.axvspan(start, end, color="0.88", lw=0, zorder=0)
        for start, _, _ in spans[1:]:
            ax.axvline(start, color="0.3", lw=0.8, ls="--")
    for start, end, label in spans:
        speed_ax.text((start + end) / 2, 1.01, label, ha="center", va="bottom", fontsize=9,
                      transform=speed_ax.get_xaxis_transform())
    output_rpm = np.abs(qd) * RPM_PER_RAD_S
    speed_ax.plot(*envelope(t, output_rpm), color=MOVING, lw=1.2, label="|output speed|")
    top = float(output_rpm.max()) * 1.15
    if top == 0.0:
        top = 1.0
        speed_ax.text(0.5, 0.5, "this joint does not move in this cycle", ha="center",
                      va="center", transform=speed_ax.transAxes, color="0.3")
    speed_lines = [(unit.max_input_speed / unit.ratio, "k", "-",
                    f"max input speed {unit.max_input_speed:,.0f} rpm")]
    mean = chosen.checks["mean"].detail.get("mean_input_speed_rpm")
    if isinstance(mean, float) and mean > 0.0:
        speed_lines.append((mean / unit.ratio, MEAN, ":",
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
    torque_ax.plot(*envelope(t, stop), color=STOP, lw=0.7, alpha=0.8,
                   label=f"emergency stop from each instant ({result.options.stop_time:g} s)")
    torque_ax.plot(*envelope(t, moving), color=MOVING, lw=1.3,
                   label="|T| moving: repeated-peak limit")
    if np.any(rest):
        torque_ax.plot(*envelope(t, held), color=REST, lw=2.2, label="|T| at rest: static limit")
    event = chosen.checks["momentary"]
    peak_at = int(np.nanargmax(moving)) if np.any(~rest) else None
    tops = [float(np.nanmax(torque)), float(stop.max())]
    if peak_at is not None:
        torque_ax.plot([t[peak_at]], [torque[peak_at]], "o", color=MOVING, ms=7, mfc="none",
                       mew=1.8, label=f"peak {torque[peak_at]:.3g} N m at {t[peak_at]:.2f} s")
    when = event.detail.get("time_s")
    task = joint.setting_task("momentary")
    if isinstance(when, float) and task is not None:
        when += spans[task][0]  # a time within that task's cycle
    if isinstance(when, float) and event.value is not None:
        tops.append(event.value)
        torque_ax.plot([when], [event.value], "v", color=STOP, ms=9, mec="k",
                       label=f"worst momentary: {event.detail.get('kind')} {event.value:.3g} N m "
                             f"at {when:.2f} s")
    lines = []
    if joint.load.mean_torque is not None:
        lines += [(joint.load.mean_torque, MEAN, ":",
                   f"mean torque T_av {joint.load.mean_torque:.3g} N m"),
                  (chosen.checks["mean"].limit, ALLOWED, ":",
                   f"allowed mean {chosen.checks['mean'].limit:.3g} N m")]
    for field, label, color, style in (("repeated_torque", "repeated-peak limit", "k", "-"),
                                       ("momentary_torque", "momentary limit", STOP, "--"),
                                       ("static_torque", "static limit", REST, "-.")):
        value = getattr(unit, field)
        if value is None:  # not rated by the source
            continue
        kinds = {flag.kind for flag in unit.flags_for(field)}
        mark = " (stand-in)" if "fallback" in kinds else " (corrected)" if kinds else ""
        lines.append((value, color, style, f"{label} {value:.3g} N m{mark}"))
    setting = rule(chosen.binding)  # its limit line is kept where it is an output torque's
    keep = (chosen.checks[chosen.binding].limit
            if setting.part is Part.GEARHEAD and setting.unit == "N m" else None)
    top = _limit_lines(torque_ax, lines, max(max(tops), 1e-9) * 1.15, keep if near else None)
    torque_ax.set_ylim(0.0, top)
    torque_ax.set_ylabel("output torque [N m]")
    torque_ax.set_xlabel("time [s]" if not spans else
                         "time [s]: one cycle of each task in turn (dashed: where the next begins)")
    torque_ax.set_xlim(t[0], max(t[-1], t[0] + traj.dt))
    mark_events(result, (speed_ax, torque_ax))
    for ax in (speed_ax, torque_ax):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.09, 1.0), fontsize=8, frameon=False)
    if joint.selected is None:
        fig.suptitle(f"{joint.name}: {_no_unit(result, joint)}; the limits drawn: the "
                     f"strongest candidate, {unit.id}", fontsize=12)
    else:
        fig.suptitle(f"{joint.name}: {unit.id} (selected); closest to its limit: "
                     f"{binding_words(chosen)}", fontsize=12)
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
    if motor is None or demand is None or joint.motor_torque is None:
        raise RuntimeError(f"joint {joint.name}: no motor, motor demand or motor torque to draw")
    speed = np.abs(timeline(result, j)[1]) * unit.ratio * RPM_PER_RAD_S
    torque = np.abs(joint.motor_torque)
    fig = Figure(figsize=(11, 5.2), layout="constrained")
    ax = fig.subplots()
    shown, fast = extremes(torque), extremes(speed)
    label = f"cycle: every {traj.dt * 1e3:g} ms sample (|n|, |T_motor|)"
    if shown is not None and fast is not None:  # a long cycle: each run's extremes
        shown = np.union1d(shown, fast)
        speed, torque = speed[shown], torque[shown]
        label = "cycle: the extreme samples of each stretch (|n|, |T_motor|)"
    ax.plot(speed, torque, ".", color=REST, ms=2.5, alpha=0.35, label=label)
    top = max(motor.max_speed, float(speed.max())) * 1.08
    grid = np.linspace(0.0, motor.max_speed, 400)
    curve = "torque-speed curve" if motor.curve is not None else "flat: no curve given"
    ax.plot(grid, motor.peak_torque_at(grid), color="k", lw=1.6,
            label=f"peak torque ({curve}), up to {motor.peak_torque:.3g} N m")
    ax.axhline(motor.rated_torque, color=ALLOWED, ls="--", lw=1.3,
               label=f"rated torque {motor.rated_torque:.3g} N m (limit of the RMS torque)")
    ax.axvline(motor.max_speed, color=STOP, ls="-.", lw=1.2,
               label=f"max speed {motor.max_speed:,.0f} rpm")
    if demand.rms_speed is not None:
        ax.plot([demand.rms_speed], [demand.rms_torque], "D", color=MOVING, ms=9, mec="k",
                label=f"RMS point ({demand.rms_speed:,.0f} rpm, {demand.rms_torque:.3g} N m)")
    worst = chosen.checks["motor_peak"]
    where = worst.detail.get("speed_rpm")
    if isinstance(where, float) and worst.value is not None:
        ax.plot([where], [worst.value], "v", color=MEAN, ms=9, mec="k",
                label=f"worst sample: {utilization_text(worst.utilization, worst.ok)} of the "
                      "peak at that speed")
    ax.set_xlim(0.0, top)
    ax.set_ylim(0.0, max(motor.peak_torque, float(torque.max())) * 1.15)
    ax.set_xlabel("input speed |n| [rpm]")
    ax.set_ylabel("motor torque |T_motor| [N m]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    state = ("selected" if joint.selected
             else f"{_no_unit(result, joint)}; the strongest candidate shown")
    side = chosen.motor_binding or "motor_peak"
    ratio = joint.inertia_ratio(chosen)
    fig.suptitle(f"{joint.name}: motor {motor.id} behind {unit.id} ({state}); "
                 f"{binding_words(chosen, side)}"
                 + ("" if ratio is None else f"; load-to-rotor inertia {ratio_text(ratio)}"),
                 fontsize=12)
    return fig


def timeline(result: SizingResult, j: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple[float, float, str]]]:
    """A joint's samples as the result's torques follow them: each counted task in turn.

    Args:
        result: The sizing result.
        j: The joint's column.

    Returns:
        Time [s] (each task's cycle after the previous one's), the joint's speed
        [rad/s], where it is at rest, and each task's span (start [s], end [s], name);
        no spans for one task.
    """
    counted = result.counted
    if len(counted) < 2:
        traj = result.trajectory
        return traj.t, traj.qd[:, j], at_rest(traj.qd[:, j], traj.qdd[:, j]), []
    times, speeds, rests, spans = [], [], [], []
    start = 0.0
    for task in counted:
        traj = task.trajectory
        times.append(traj.t + start)
        speeds.append(traj.qd[:, j])
        rests.append(at_rest(traj.qd[:, j], traj.qdd[:, j]))
        spans.append((start, start + traj.duration, task.label))
        start += len(traj.t) * traj.dt
    return np.concatenate(times), np.concatenate(speeds), np.concatenate(rests), spans


EVENT = "#6a3d9a"
"""Colour of a payload event's line."""


def event_times(result: SizingResult) -> list[tuple[float, str]]:
    """Every counted task's payload events on the figures' time axis (`timeline`).

    Returns:
        (time [s], "attach PART" or "release PART"), each task's after the previous
        tasks' cycles.
    """
    out, start = [], 0.0
    several = len(result.counted) > 1
    for task in result.counted:
        if task.carried is not None:
            out += [(start + t, f"{'attach' if attached else 'release'} {part}")
                    for t, part, attached in task.carried.events]
        if several:
            start += len(task.trajectory.t) * task.trajectory.dt
    return out


def mark_events(result: SizingResult, axes) -> None:
    """Thin vertical lines at the payload events, labelled at the top of the first axis."""
    marks = event_times(result)
    if marks:
        axes[0].plot([], [], color=EVENT, lw=0.7, label="payload event (part attached or "
                                                       "released)")
    for when, label in marks:
        for ax in axes:
            ax.axvline(when, color=EVENT, lw=0.7, alpha=0.8, zorder=1)
        axes[0].text(when, 0.97, f" {label}", rotation=90, ha="right", va="top", fontsize=7,
                     color=EVENT, transform=axes[0].get_xaxis_transform())


def rest_spans(mask: np.ndarray, t: np.ndarray, dt: float) -> list[tuple[float, float]]:
    """The time spans [s] where `mask` holds, each sample standing for one period."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return [(float(t[a]) - dt / 2, float(t[b - 1]) + dt / 2)
            for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _no_unit(result: SizingResult, joint: JointSizing) -> str:
    """A figure title's words for a joint no unit holds: its headline shortfall."""
    found = diagnosis_of(result, joint.name)
    return "no unit holds it" if found is None else found.summary()
