"""A study's figure: every case drawn in a cell of its own, whatever the study varies.

Oracle: the rows handed in. Each cell's colour is read back from the drawn figure and
compared with the unit of the one row behind it.
"""

from __future__ import annotations

import matplotlib.colors
import pytest

from hdselect.report import study_figures

UNITS = {  # (ratio, time scale, stop time) -> the shoulder's unit; one cell differs by stop
    (50, 0.8, 0.05): "", (50, 0.8, 0.1): "PSA-14-50",
    (50, 1.0, 0.05): "PSA-14-50", (50, 1.0, 0.1): "PSA-14-50",
    (80, 0.8, 0.05): "PSA-14-80", (80, 0.8, 0.1): "PSA-14-80",
    (80, 1.0, 0.05): "PSA-14-80", (80, 1.0, 0.1): "PSA-10-80",
}


def _rows():
    return [{"status": "ok", "joint": "shoulder", "ratio": ratio, "time_scale": scale,
             "stop_time": stop, "unit": unit, "life_l50_h": 5e4 if unit else None,
             "life_l10_h": 1e4 if unit else None}
            for (ratio, scale, stop), unit in UNITS.items()]


@pytest.fixture
def drawn(monkeypatch):
    figures = []
    monkeypatch.setattr(study_figures, "save", lambda fig, path: figures.append(fig))
    return figures


@pytest.mark.slow
def test_a_third_parameter_gets_panels_of_its_own(drawn):
    """Stop times 0.05 and 0.1 s: one row of panels each, labelled, each cell its own row."""
    study_figures.write_study_png("-", "t", _rows(), "ratio", "time_scale", ["shoulder"],
                                  others=("stop_time",))
    (fig,) = drawn
    maps = fig.axes[0::2][:2]
    assert len(fig.axes) == 4  # one joint x two stop times, a map and a life panel each
    assert ["stop time [s] = 0.05" in ax.get_ylabel() for ax in maps] == [True, False]
    assert ["stop time [s] = 0.1" in ax.get_ylabel() for ax in maps] == [False, True]
    units = sorted({u for u in UNITS.values() if u}, key=study_figures._natural)
    palette = matplotlib.colormaps["tab10"]
    for ax, stop in zip(maps, (0.05, 0.1), strict=True):
        cells = {(round(p.get_x() + 0.5), round(p.get_y() + 0.5)): p.get_facecolor()
                 for p in ax.patches}
        for (ratio, scale, given), unit in UNITS.items():
            if given != stop:
                continue
            cell = cells[([50, 80].index(ratio), [0.8, 1.0].index(scale))]
            expected = palette(units.index(unit)) if unit else matplotlib.colors.to_rgba("0.85")
            assert cell == pytest.approx(expected), (ratio, scale, stop)


@pytest.mark.slow
def test_two_parameters_draw_one_row_per_joint(drawn):
    rows = [row for row in _rows() if row["stop_time"] == 0.1]
    study_figures.write_study_png("-", "t", rows, "ratio", "time_scale", ["shoulder"])
    (fig,) = drawn
    assert len(fig.axes) == 2 and "stop time" not in fig.axes[0].get_ylabel()
