"""A logged trajectory put on the motion's time grid."""

from __future__ import annotations

import math

import numpy as np

from hdselect.motion import Motion
from hdselect.planning.trajectory import Trajectory, trajectory
from hdselect.robot import Robot


def plan_samples(robot: Robot, motion: Motion) -> Trajectory:
    """Put a logged trajectory on the dt grid.

    Time is shifted to start at 0. When the log is uniformly spaced (within 1e-6
    relative) at the motion's dt, its samples are used as they are; otherwise
    positions (and logged velocities, accelerations) are resampled onto the grid
    with a not-a-knot cubic spline (``scipy.interpolate.CubicSpline``). Velocities
    and accelerations that were not logged are the first and second derivatives
    of the cubic spline through the positions (accelerations from the spline
    through logged velocities when those exist). Differentiation amplifies
    measurement noise: filter the log first.
    """
    from scipy.interpolate import CubicSpline

    log = motion.samples
    assert log is not None  # load_motion reads it for the samples planner
    t = log.t - log.t[0]
    if np.all(np.abs(np.diff(t) - motion.dt) <= 1e-6 * motion.dt):
        uniform, grid, at = True, np.arange(len(t)) * motion.dt, t
        duration, inside = float(grid[-1]), np.ones(len(t), dtype=bool)
    else:
        duration = float(t[-1])
        uniform, grid = False, np.arange(math.ceil(duration / motion.dt - 1e-9) + 1) * motion.dt
        at, inside = np.minimum(grid, duration), grid <= duration

    def resample(values, order=0):
        if uniform and order == 0:
            return np.array(values)
        result = CubicSpline(t, values, axis=0)(at, order)
        result[~inside] = values[-1] if order == 0 else 0.0
        return result

    q = resample(log.q)
    qd = resample(log.q, 1) if log.qd is None else resample(log.qd)
    if log.qdd is not None:
        qdd = resample(log.qdd)
    else:
        qdd = resample(log.q if log.qd is None else log.qd, 2 if log.qd is None else 1)
    return trajectory(motion, duration, grid, q, qd, qdd)
