"""What every figure shares: long curves drawn by their extremes, PNG output.

matplotlib is imported by the figure modules only, so commands that draw nothing start
fast; figures are made without pyplot, so no global state or backend is involved.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from hdselect.motion.planning import Trajectory
from hdselect.report.export import write_output

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
    index = extremes(y, points)
    return (t, y) if index is None else (t[index], y[index])


def extremes(y: np.ndarray, points: int = PLOT_POINTS) -> np.ndarray | None:
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
    fig = Figure(figsize=(11, 1.9 * len(joints) + 0.8))
    axes = fig.subplots(len(joints), 2, sharex=True, squeeze=False)
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
    save(fig, Path(path))


def png_bytes(fig: Figure, dpi: int = 130) -> bytes:
    """A figure as PNG content."""
    stream = io.BytesIO()
    fig.savefig(stream, format="png", dpi=dpi, metadata={"Software": None})
    return stream.getvalue()


# Okabe and Ito's colour-blind-safe palette
MOVING, REST, STOP, MEAN, ALLOWED = "#D55E00", "#0072B2", "#CC79A7", "#E69F00", "#009E73"


def save(fig: Figure, path: Path) -> None:
    """Write a figure as PNG to a path (an output file, or '-' for stdout)."""
    write_output(path, lambda stream: fig.savefig(stream, format="png", dpi=110,
                                                  bbox_inches="tight"), binary=True)
