"""A study drawn: the unit selected and its life per joint against the varied parameters."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib
import matplotlib.patches
import matplotlib.ticker
import numpy as np
from matplotlib.figure import Figure

from hdselect.catalog.checks import LIFE_CAP
from hdselect.motion.option_specs import OPTIONS
from hdselect.report.figures import save


def write_study_png(path: str | Path, title: str, rows: Sequence[dict], first: str,
                    second: str | None, joints: Sequence[str], *,
                    required_life: float | None = None, life_basis: str = "L50",
                    others: Sequence[str] = ()) -> None:
    """Per joint, a map of the unit selected and its life, against the varied parameters.

    A study that varies more than two parameters gets one row of panels per joint and
    combination of the `others`' values, each row labelled with them: no cell stands
    for several cases.

    Left, the unit selected at every case: a grid of the first varied parameter (across)
    by the second (up; one row when only one is varied), each cell coloured by its unit
    on one discrete colour per unit, named in the legend; a cell where no unit fits is
    grey, hatched and marked ✗, a failed case is left white. Right, the selected unit's
    life on the required basis against the first parameter, one series per value of the
    second (points; a line joins only neighbours with the same unit), lives above
    `LIFE_CAP` drawn on the cap as "> 1e6 h", the required life as a red line.

    Args:
        path: PNG file to write.
        title: Figure title.
        rows: The study's rows (`hdselect.study`), typed values; failed cases are skipped.
        first: The parameter across.
        second: The parameter up the map and of the life series, or None.
        joints: Joints to draw, one row of panels each.
        required_life: The life required [h] on `life_basis`, drawn; None draws none.
        life_basis: ``"L50"`` or ``"L10"``: the life drawn.
        others: The further varied parameters, each value drawn in panels of its own.
    """
    from matplotlib.patches import Patch

    done = [row for row in rows if row["status"] == "ok"]
    xs = list(dict.fromkeys(_plain(row.get(first)) for row in rows))
    ys: list[object] = (list(dict.fromkeys(_plain(row.get(second)) for row in rows))
                        if second else [None])
    numeric = all(isinstance(x, int | float) for x in xs)
    units = sorted({row["unit"] for row in done if row["unit"]}, key=_natural)
    palette = matplotlib.colormaps["tab10" if len(units) <= 10 else "tab20"]
    colour = {unit: palette(k % palette.N) for k, unit in enumerate(units)}
    series = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.9, max(len(ys), 1)))
    key = "life_l10_h" if life_basis == "L10" else "life_l50_h"
    groups = list(dict.fromkeys(_group(row, others) for row in rows)) or [()]
    panels = [(joint, group) for joint in joints for group in groups]
    height = max(2.0, 0.22 * len(ys) + 1.2)
    tall = height * len(panels) + 1.6
    fig = Figure(figsize=(12, tall))
    axes = fig.subplots(len(panels), 2, squeeze=False,
                        gridspec_kw={"width_ratios": (1.0, 1.15)})
    for r, (joint, group) in enumerate(panels):
        map_ax, life_ax = axes[r]
        mine = [row for row in rows if row["joint"] == joint and _group(row, others) == group]
        name = "\n".join([joint, *(f"{_SHORT_LABELS.get(other, other)} = {_tick(value)}"
                                    for other, value in zip(others, group, strict=True))])
        for row in mine:
            i, k = xs.index(_plain(row.get(first))), ys.index(_plain(row.get(second)))
            if row["status"] != "ok":
                continue  # a failed case: left white
            unit = row["unit"]
            face = colour[unit] if unit else "0.85"
            map_ax.add_patch(matplotlib.patches.Rectangle(
                (i - 0.5, k - 0.5), 1.0, 1.0, facecolor=face, edgecolor="white", lw=0.8,
                hatch=None if unit else "///"))
            if not unit:
                map_ax.text(i, k, "✗", ha="center", va="center", fontsize=8, color="0.2")
        map_ax.set_xlim(-0.5, len(xs) - 0.5)
        map_ax.set_ylim(-0.5, len(ys) - 0.5)
        map_ax.set_xticks(range(len(xs)), [_tick(x) for x in xs], fontsize=7,
                          rotation=45 if len(xs) > 8 else 0)
        if second is None:
            map_ax.set_yticks([])
        else:
            map_ax.set_yticks(range(len(ys)), [_tick(y) for y in ys], fontsize=7)
            map_ax.set_ylabel(f"{name}\n{_AXIS_LABELS.get(second, second)}", fontsize=8)
        if second is None:
            map_ax.set_ylabel(name, fontsize=9)
        for k, (value, tone) in enumerate(zip(ys, series, strict=True)):
            points = [row for row in mine if row["status"] == "ok" and row["unit"]
                      and _plain(row.get(second)) == value]
            points.sort(key=lambda row: xs.index(_plain(row.get(first))))
            x = [_position(xs, row.get(first), numeric) for row in points]
            life = [row[key] for row in points]
            drawn = [LIFE_CAP if v is None or v >= LIFE_CAP else v for v in life]
            capped = [v is None or v >= LIFE_CAP for v in life]
            label = None if second is None or r else f"{_tick(value)}"
            life_ax.scatter([a for a, c in zip(x, capped, strict=True) if not c],
                            [b for b, c in zip(drawn, capped, strict=True) if not c],
                            s=12, color=tone, label=label, zorder=3)
            life_ax.scatter([a for a, c in zip(x, capped, strict=True) if c],
                            [LIFE_CAP] * sum(capped), s=18, marker="^", color=tone, zorder=3)
            for a, b in zip(range(len(points)), range(1, len(points)), strict=False):
                if points[a]["unit"] == points[b]["unit"] and not (capped[a] or capped[b]):
                    life_ax.plot([x[a], x[b]], [drawn[a], drawn[b]], color=tone, lw=0.8)
            del k
        life_ax.set_yscale("log")
        life_ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        life_ax.axhline(LIFE_CAP, color="0.5", ls=":", lw=0.8)
        life_ax.text(1.01, LIFE_CAP, "> 1e6 h", transform=life_ax.get_yaxis_transform(),
                     va="center", fontsize=7, color="0.4")
        if required_life is not None:
            life_ax.axhline(required_life, color="tab:red", lw=1.2)
            life_ax.text(1.01, required_life, f"required\n{required_life:,.0f} h",
                         transform=life_ax.get_yaxis_transform(), va="center", fontsize=7,
                         color="tab:red")
        life_ax.set_ylabel(f"{life_basis} life [h]", fontsize=8)
        life_ax.grid(alpha=0.3)
        if numeric:
            values = [float(x) for x in xs]  # type: ignore[arg-type]
            spread = 0.05 * ((max(values) - min(values)) or 1.0)
            life_ax.set_xlim(min(values) - spread, max(values) + spread)
        else:
            life_ax.set_xticks(range(len(xs)), [_tick(x) for x in xs], fontsize=7)
    axes[0, 0].set_title("unit selected at each case", fontsize=10)
    axes[0, 1].set_title(f"its {life_basis} life (▲: longer than 1e6 h)", fontsize=10)
    for ax in axes[-1]:
        ax.set_xlabel(_AXIS_LABELS.get(first, first), fontsize=8)
    handles = [Patch(facecolor=colour[u], label=u) for u in units]
    handles.append(Patch(facecolor="0.85", hatch="///", label="✗ no unit fits"))
    fig.suptitle(title, y=1.0 - 0.08 / tall, va="top")
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - 1.05 / tall))  # title and legends: 1.05 in
    fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.02, 1.0 - 0.4 / tall),
               ncols=min(len(handles), 5), fontsize="small", frameon=False, title="unit")
    if second is not None:
        fig.legend(*axes[0, 1].get_legend_handles_labels(), loc="upper right",
                   bbox_to_anchor=(0.98, 1.0 - 0.4 / tall), ncols=min(len(ys), 5),
                   fontsize="x-small", frameon=False, title=_AXIS_LABELS.get(second, second))
    save(fig, Path(path))


def _group(row: dict, others: Sequence[str]) -> tuple[object, ...]:
    """A row's values of the further varied parameters."""
    return tuple(_plain(row.get(other)) for other in others)


def _tick(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _position(xs: list, value: object, numeric: bool) -> float:
    value = _plain(value)
    return float(value) if numeric else float(xs.index(value))  # type: ignore[arg-type]


_AXIS_LABELS = {"payload": "payload [kg]", "time_scale": "time scale s: the cycle run s times "
                "slower [-]", **{option.name: option.label for option in OPTIONS}}


_SHORT_LABELS = {**_AXIS_LABELS, "time_scale": "time scale [-]"}
"""Names of the further varied parameters beside a row of panels."""


def _plain(value: object) -> object:
    """A parameter value usable as a key and a label (lists become text)."""
    if isinstance(value, list | tuple | dict):
        return str(value)
    return value


def _natural(text: str) -> list[object]:
    """PSA-08-80 before PSA-08-100: numbers compared as numbers."""
    import re

    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", text)]
