"""A joint's output-bearing loads drawn over the cycle: tilting moment, radial and axial force."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from hdselect.catalog.bearing_rules import NOT_RATED
from hdselect.report.figures import ALLOWED, MEAN, MOVING, envelope
from hdselect.report.joint_figures import rest_spans, timeline
from hdselect.sizing.result import JointSizing, SizingResult


def bearing_figure(result: SizingResult, joint: JointSizing) -> Figure | None:
    """M, F_r and F_a on a joint's output bearing over the cycle, with its unit's limits.

    The loads are about the output flange (the joint origin, or the options'
    ``bearing_offset``); each panel marks the largest value and the 10/3-power mean,
    and draws the allowable value where the shown unit's catalog rates it. Samples
    held at rest are shaded, as in the joint's torque figure.

    Args:
        result: The sizing result.
        joint: One of its joints.

    Returns:
        The figure (the caller closes it), or None where the loads were not computed.
    """
    load = joint.bearing
    if load is None or joint.wrench is None:
        return None
    traj = result.trajectory
    t, _, rest, spans = timeline(result, result.robot.joint_index(joint.name))
    axial, radial, moment = (values[:len(t)] for values in joint.wrench.loads(load.offset))
    shown = joint.selected or joint.strongest
    rating = shown.unit.bearing if joint.selected is not None else None
    fig = Figure(figsize=(11, 6.8), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    panels = ((moment, "tilting moment M [N m]", load.max_moment, load.mean_moment,
               None if rating is None else rating.max_moment, "N m"),
              (radial, "radial force F_r [N]", load.max_radial, load.mean_radial,
               None if rating is None else rating.max_radial, "N"),
              (np.abs(axial), "axial force |F_a| [N]", load.max_axial, load.mean_axial,
               None if rating is None else rating.max_axial, "N"))
    for ax, (values, label, largest, mean, limit, unit) in zip(axes, panels, strict=True):
        for start, end in rest_spans(rest, t, traj.dt):
            ax.axvspan(start, end, color="0.88", lw=0, zorder=0)
        for start, _, _ in spans[1:]:
            ax.axvline(start, color="0.3", lw=0.8, ls="--")
        ax.plot(*envelope(t, values), color=MOVING, lw=1.1, label=label.split(" [")[0])
        at = int(np.argmax(values))
        ax.plot([t[at]], [values[at]], "o", color=MOVING, ms=7, mfc="none", mew=1.8,
                label=f"largest {largest:.3g} {unit} at {t[at]:.2f} s")
        top = max(largest, 1e-9) * 1.15
        if mean is not None:
            ax.axhline(mean, color=MEAN, ls=":", lw=1.3,
                       label=f"10/3-power mean {mean:.3g} {unit}")
        if limit is not None:
            if limit <= 1.6 * top:
                ax.axhline(limit, color="k", lw=1.2, label=f"allowable {limit:.3g} {unit}")
                top = max(top, limit * 1.08)
            else:
                ax.plot([], [], color="k", lw=1.2,
                        label=f"allowable {limit:.3g} {unit}: above the axis")
        ax.set_ylim(0.0, top)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    for start, end, label in spans:
        axes[0].text((start + end) / 2, 1.01, label, ha="center", va="bottom", fontsize=9,
                     transform=axes[0].get_xaxis_transform())
    axes[-1].set_xlabel("time [s]")
    axes[-1].set_xlim(t[0], max(t[-1], t[0] + traj.dt))
    where = "joint origin" if load.offset == 0.0 else f"{load.offset:g} m along the axis"
    state = ("no unit holds this joint: loads not checked" if joint.selected is None
             else f"{shown.unit.id}: {NOT_RATED.split(':')[0]}" if rating is None
             else f"{shown.unit.id}'s rating")
    fig.suptitle(f"{joint.name}: output bearing loads about the flange ({where}); {state}",
                 fontsize=12)
    if rating is not None and shown.bearing is not None:
        figures = shown.bearing
        facts = [f"L10 {figures.life_hours:,.0f} h" if figures.life_hours is not None else "",
                 f"static safety {figures.static_safety:.2f}"
                 if figures.static_safety is not None else ""]
        text = ", ".join(fact for fact in facts if fact)
        if text:
            axes[0].set_title(text, fontsize=9, color=ALLOWED, loc="right")
    return fig

