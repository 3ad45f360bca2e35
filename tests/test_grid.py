"""The time grid: every move and dwell resolved, a log never skipped, the size checked first."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.motion.planning import plan
from hdselect.motion.planning.grid import (
    MIN_MOVE_SAMPLES,
    check_log_period,
    check_resolution,
    check_size,
    sample_count,
)
from test_plan import make_motion

MOTION = Path("motion.toml")


def test_a_move_of_exactly_the_minimum_samples_passes_and_a_shorter_one_names_itself():
    dt = 0.001
    check_resolution(MOTION, dt, [("the move a", MIN_MOVE_SAMPLES * dt)], [])
    moves = [("the move a", 0.2), ("the move b", 0.04), ("the move c", 0.0)]
    with pytest.raises(InputError) as info:
        check_resolution(MOTION, dt, moves, [])
    error = info.value
    assert error.field == "dt" and error.path == MOTION
    assert "does not resolve the move b, the shortest (0.04 s)" in error.reason
    advice = float(error.reason.rsplit("use dt <= ", 1)[1].split()[0])
    assert advice <= 0.04 / MIN_MOVE_SAMPLES  # following the advice resolves the move
    check_resolution(MOTION, advice, moves, [])


def test_a_dwell_shorter_than_dt_is_refused():
    check_resolution(MOTION, 0.01, [], [("the dwell at waypoint[1]", 0.01)])
    with pytest.raises(InputError, match=r"longer than the dwell at waypoint\[1\] \(0.005 s\)"):
        check_resolution(MOTION, 0.01, [], [("the dwell at waypoint[1]", 0.005),
                                            ("the dwell at waypoint[0]", 0.0)])


@pytest.mark.parametrize(("duration", "dt"), [(1.0, 0.001), (0.9995, 0.001), (3.825, 0.001)])
def test_the_count_is_the_grid_the_planners_build(duration, dt):
    count = check_size(MOTION, duration, dt, 2, 10**9)
    assert count == sample_count(duration, dt) == math.ceil(duration / dt - 1e-9) + 1
    assert (count - 1) * dt >= duration - 1e-12 and (count - 2) * dt < duration


@pytest.mark.parametrize("duration", [1e9, 1e308, math.inf])
def test_a_grid_beyond_the_limit_is_refused_with_its_size(duration):
    with pytest.raises(InputError) as info:
        check_size(MOTION, duration, 0.001, 6, 30_000_000)
    assert info.value.field == "dt" and "--max-samples" in info.value.reason
    assert "limit of 30,000,000" in info.value.reason


def test_the_memory_estimate_is_printed():
    with pytest.raises(InputError, match=r"that is 100,000,001 samples \(about 42 GB\)"):
        check_size(MOTION, 10.0, 1e-7, 6, 30_000_000)


def test_dt_coarser_than_the_log_is_refused():
    t = np.arange(100) * 0.002
    check_log_period(MOTION, Path("log.csv"), t, 0.002)
    with pytest.raises(InputError, match=r"coarser than the log's sample period \(0.002 s"):
        check_log_period(MOTION, Path("log.csv"), t, 0.005)


def test_planners_check_the_grid(tmp_path):
    for planner, jerk in (("ruckig", 10.0), ("toppra", None)):
        robot, motion = make_motion(tmp_path, planner, [[0.0, 0.0], [0.01, 0.0]], dt=0.01,
                                    velocity=1, acceleration=2, jerk=jerk)
        with pytest.raises(InputError, match="does not resolve"):
            plan(robot, motion)
        robot, motion = make_motion(tmp_path, planner, [[0.0, 0.0], [1.0, 0.0]],
                                    dwells=[0.0, 1e9], velocity=1, acceleration=2, jerk=jerk)
        with pytest.raises(InputError, match="limit of 1,000"):
            plan(robot, motion, max_samples=1000)
