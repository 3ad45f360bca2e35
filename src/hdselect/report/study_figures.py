"""A study drawn: the unit selected and its life per joint against the varied parameters."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib
import matplotlib.ticker
import numpy as np
from matplotlib.figure import Figure

from hdselect.report.figures import save


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
    colors = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.9, max(len(lines), 1)))
    fig = Figure(figsize=(11, 1.7 * len(joints) + 1.2))
    axes = fig.subplots(len(joints), 2, sharex=True, squeeze=False)
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
    save(fig, Path(path))


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
