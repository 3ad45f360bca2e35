"""The precision figures drawn along the cycle: the tool's deflection and the arm's lowest modes."""

from __future__ import annotations

import itertools

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from hdselect.report.figures import ALLOWED, MOVING, REST
from hdselect.report.joint_figures import timeline
from hdselect.sizing.precision import TargetCheck
from hdselect.sizing.precision_records import ARCMIN_PER_RAD, MM_PER_M, pose_of
from hdselect.sizing.result import SizingResult

SINGLE_AXIS = ("#E69F00", "#CC79A7", "#999999", "#000000", "#56B4E9", "#F0E442")
"""The single-axis f_n lines' colours: the palette's others than the arm modes' three."""


def precision_figures(result: SizingResult) -> dict[str, Figure]:
    """The figures the report shows, by name (``tool``, ``modes``); none without the figures.

    The caller closes them.
    """
    found = result.precision
    if found is None:
        return {}
    figures = {}
    if found.tool is not None:
        figures["tool"] = tool_figure(result)
    if found.modes is not None:
        figures["modes"] = modes_figure(result)
    return figures


def _target(result: SizingResult, name: str) -> TargetCheck | None:
    found = result.precision
    return None if found is None else next((t for t in found.targets if t.name == name), None)


def _when(result: SizingResult, sample: int) -> str:
    """A pooled sample's time as the tables give it: in its own task's cycle."""
    pose = pose_of(result, int(sample))
    return f"at {pose.time:.2f} s" + (f" of {pose.label}" if len(result.counted) > 1 else "")


def _spans(result: SizingResult, axes: list[Axes]) -> np.ndarray:
    """The pooled samples' times along the drawn cycle [s]; each task's span marked and named."""
    t, _, _, spans = timeline(result, 0)
    for ax in axes:
        for start, _, _ in spans[1:]:
            ax.axvline(start, color="0.3", lw=0.8, ls="--")
        ax.grid(alpha=0.3)
    for start, end, label in spans:
        axes[0].text((start + end) / 2, 1.01, label, ha="center", va="bottom", fontsize=9,
                     transform=axes[0].get_xaxis_transform())
    axes[-1].set_xlabel("time [s]")
    axes[-1].set_xlim(t[0], max(t[-1], t[0] + result.trajectory.dt))
    return t


def tool_figure(result: SizingResult) -> Figure:
    """The tool frame's deflection at the evaluated poses: moving along the cycle and held still.

    The top panel gives |translation| [mm], the bottom |rotation| [arcmin]; the worst of
    each curve is marked, and a tool-deflection target is drawn where one is set.

    Raises:
        ValueError: The result has no tool deflection (`Precision.tool` is None).
    """
    found = result.precision
    if found is None or found.tool is None:
        raise ValueError("the result has no tool deflection to draw")
    tool = found.tool
    fig = Figure(figsize=(11, 6.2), layout="constrained")
    axes = list(fig.subplots(2, 1, sharex=True))
    t = _spans(result, axes)[tool.samples]
    panels = ((axes[0], tool.translation, tool.holding_translation, MM_PER_M, "mm",
               "|translation| [mm]"),
              (axes[1], tool.rotation, tool.holding_rotation, ARCMIN_PER_RAD, "arcmin",
               "|rotation| [arcmin]"))
    for ax, moving, held, scale, unit, label in panels:
        for values, colour, style, words in ((moving, MOVING, "-", "along the cycle"),
                                             (held, REST, "--", "holding the pose still")):
            size = np.linalg.norm(values, axis=1) * scale
            at = int(np.argmax(size))
            ax.plot(t, size, color=colour, lw=1.3, ls=style, label=words)
            ax.plot([t[at]], [size[at]], "o", color=colour, ms=7, mfc="none", mew=1.8,
                    label=f"largest {size[at]:.3g} {unit} {_when(result, tool.samples[at])}")
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0.0)
    target = _target(result, "tool_deflection")
    if target is not None:
        axes[0].axhline(target.limit * MM_PER_M, color="k", lw=1.2,
                        label=f"target: at most {target.limit * MM_PER_M:.3g} mm held")
        axes[0].set_ylim(0.0, max(axes[0].get_ylim()[1], target.limit * MM_PER_M * 1.1))
    for ax in axes:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    tilt = " and their bearings' tilt" if tool.bearing_tilt else ""
    fig.suptitle(f"Tool '{tool.frame}': its deflection from the commanded pose, from the "
                 f"units' twist{tilt}", fontsize=12)
    return fig


def modes_figure(result: SizingResult) -> Figure:
    """The arm's lowest natural frequencies at the evaluated poses, beside each joint's own.

    The arm's first modes (K v = w^2 M(q) v) are drawn as thick lines, each joint's
    single-axis f_n = sqrt(K1 / M_jj) / 2 pi thin and dotted; the lowest first mode is
    marked, and an arm-frequency target is drawn where one is set.

    Raises:
        ValueError: The result has no arm modes (`Precision.modes` is None).
    """
    found = result.precision
    if found is None or found.modes is None:
        raise ValueError("the result has no arm modes to draw")
    modes = found.modes
    fig = Figure(figsize=(11, 5.0), layout="constrained")
    ax = fig.subplots(1, 1)
    times = _spans(result, [ax])
    t = times[modes.samples]
    shown = min(3, modes.frequencies.shape[1])
    for k, colour in zip(range(shown), (MOVING, REST, ALLOWED), strict=False):
        ax.plot(t, modes.frequencies[:, k], color=colour, lw=2.0 if k == 0 else 1.2,
                label=f"arm mode {k + 1}")
    low = modes.lowest
    lowest = float(modes.frequencies[low, 0])
    ax.plot([t[low]], [lowest], "o", color="k", ms=8, mfc="none", mew=1.8,
            label=f"lowest {lowest:.3g} Hz {_when(result, modes.samples[low])}")
    target = _target(result, "arm_frequency")
    if target is not None:
        ax.axhline(target.limit, color="k", lw=1.2, label=f"target: at least {target.limit:.3g} Hz")
    drawn = modes.frequencies[:, :shown]
    top = 1.1 * max(float(drawn[np.isfinite(drawn)].max(initial=1.0)),
                    target.limit if target is not None else 0.0)
    alone = [(joint.name, joint.frequency, joint.lowest_frequency) for joint in found.joints
             if joint.frequency is not None and joint.lowest_frequency is not None]
    for (name, frequency, lowest_alone), colour in zip(alone, itertools.cycle(SINGLE_AXIS),
                                                       strict=False):
        if lowest_alone <= top:
            ax.plot(times[found.poses], frequency, color=colour, lw=1.0, ls=":",
                    label=f"{name} alone")
        else:  # far above the arm's modes: named, not drawn
            ax.plot([], [], color=colour, lw=1.0, ls=":",
                    label=f"{name} alone: from {lowest_alone:.3g} Hz, above the axis")
    ax.set_ylim(0.0, top)
    ax.set_ylabel("natural frequency [Hz]")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle("The arm's lowest natural frequencies along the cycle (each unit's K1 a "
                 "spring, the inputs held); dotted: each joint alone, sqrt(K1 / M_jj) / 2 pi",
                 fontsize=11)
    return fig
