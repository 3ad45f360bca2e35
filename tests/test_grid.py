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
    PEAK_RESOLUTION,
    check_log_period,
    check_size,
    resolving_factor,
    sample_count,
)
from helpers.motions import make_motion, ruckig_move

MOTION = Path("motion.toml")


def test_a_move_of_exactly_the_minimum_samples_needs_no_refinement_and_a_shorter_one_does():
    dt = 0.001
    assert resolving_factor(dt, [("the move a", MIN_MOVE_SAMPLES * dt)], []) == (1, "")
    moves = [("the move a", 0.2), ("the move b", 0.04), ("the move c", 0.0)]
    factor, reason = resolving_factor(dt, moves, [])
    assert reason == "the move b (0.04 s)"
    assert 0.04 / (dt / factor) >= MIN_MOVE_SAMPLES > 0.04 / (dt / (factor - 1))


def test_a_dwell_shorter_than_dt_is_sampled_at_least_once():
    assert resolving_factor(0.01, [], [("the dwell at waypoint[1]", 0.01)]) == (1, "")
    factor, reason = resolving_factor(0.01, [], [("the dwell at waypoint[1]", 0.003),
                                                 ("the dwell at waypoint[0]", 0.0)])
    assert factor == 4 and reason == "the dwell at waypoint[1] (0.003 s)"


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


def test_planners_refine_a_coarse_grid_and_keep_its_points(tmp_path):
    """A move shorter than 50 dt is sampled every dt / k; the file's grid points stay samples."""
    for planner, jerk in (("ruckig", 10.0), ("toppra", None)):
        robot, motion = make_motion(tmp_path, planner, [[0.0, 0.0], [0.01, 0.0]], dt=0.01,
                                    velocity=1, acceleration=2, jerk=jerk)
        trajectory = plan(robot, motion)
        factor = motion.dt / trajectory.dt
        assert factor >= 2 and abs(factor - round(factor)) < 1e-9
        assert trajectory.duration / trajectory.dt >= MIN_MOVE_SAMPLES
        assert np.allclose(trajectory.t[::round(factor)], np.arange(
            len(trajectory.t[::round(factor)])) * motion.dt)


def test_the_samples_find_every_peak_acceleration(tmp_path):
    """Ruckig's exact peak |qdd| (its profile's knots) is found to PEAK_RESOLUTION."""
    robot, motion = make_motion(tmp_path, "ruckig", [[0.0, 0.0], [1.0, 0.3], [0.2, -0.4]],
                                dt=0.05, velocity=1, acceleration=2, jerk=20.0)
    trajectory = plan(robot, motion)
    exact = []
    for a, b in zip(motion.waypoints[:-1], motion.waypoints[1:], strict=True):
        traj = ruckig_move(a, b, [1, 1], [2, 2], [20, 20])
        times = np.linspace(0.0, traj.duration, 200_001)
        exact.append(np.max([np.abs(traj.at_time(t)[2]) for t in times[::100]], axis=0))
    peak = np.max(exact, axis=0)
    assert np.all(np.abs(trajectory.qdd).max(axis=0) >= peak * (1.0 - PEAK_RESOLUTION) - 1e-9)
    assert trajectory.dt < motion.dt


def test_a_refined_grid_too_large_names_the_refinement(tmp_path):
    robot, motion = make_motion(tmp_path, "ruckig", [[0.0, 0.0], [0.01, 0.0]], dt=0.01,
                                velocity=1, acceleration=2, jerk=10.0)
    with pytest.raises(InputError, match=r"dt = 0.01 s is refined to .* to resolve the move"):
        plan(robot, motion, max_samples=20)


def test_planners_check_the_grid_size(tmp_path):
    for planner, jerk in (("ruckig", 10.0), ("toppra", None)):
        robot, motion = make_motion(tmp_path, planner, [[0.0, 0.0], [1.0, 0.0]],
                                    dwells=[0.0, 1e9], velocity=1, acceleration=2, jerk=jerk)
        with pytest.raises(InputError, match="limit of 1,000"):
            plan(robot, motion, max_samples=1000)
