"""A logged trajectory put on the motion's time grid."""

from __future__ import annotations

import numpy as np

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError
from hdselect.motion.logderivatives import derivatives, spline_values
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.grid import check_log_period, check_size
from hdselect.motion.planning.trajectory import Trajectory, trajectory
from hdselect.robot.model import Robot


def plan_samples(robot: Robot, motion: Motion, *,
                 max_samples: int = DEFAULT_MAX_SAMPLES) -> Trajectory:
    """Put a logged trajectory on the dt grid.

    Every log alike: a CSV file, a ROS bag's joint states, or a planned
    ``JointTrajectory``'s points (`hdselect.motion.bagfile`).
    Time is shifted to start at 0. When the log is uniformly spaced (within 1e-6
    relative) at the motion's dt, its samples are used as they are; otherwise
    positions (and logged velocities, accelerations) are resampled onto the grid
    with a not-a-knot cubic spline (``scipy.interpolate.CubicSpline``). Velocities
    and accelerations that were not logged come from the positions (`derivatives`:
    exactly 0 where a joint rests, a spline with zero end velocities through each
    stretch where it moves); accelerations from the spline through logged velocities
    when those exist. Differentiation amplifies measurement noise: filter the log
    first. Accelerations derived from positions carry their uncertainty
    (`derivatives`) as the trajectory's ``qdd_uncertainty``.

    Raises:
        InputError: dt is coarser than the log's sample period, or the grid would
            exceed `max_samples`.
    """
    log = motion.samples
    if log is None:
        raise InputError("the samples planner needs the logged samples (a log file)",
                         path=motion.path, field="planner")
    t = log.t - log.t[0]
    dof = len(motion.joint_names)
    if np.all(np.abs(np.diff(t) - motion.dt) <= 1e-6 * motion.dt):
        count = check_size(motion.path, (len(t) - 1) * motion.dt, motion.dt, dof, max_samples)
        uniform, grid, at = True, np.arange(count) * motion.dt, t
        duration, inside = float(grid[-1]), np.ones(len(t), dtype=bool)
    else:
        check_log_period(motion.path, log.path, t, motion.dt)
        duration = float(t[-1])
        count = check_size(motion.path, duration, motion.dt, dof, max_samples)
        uniform, grid = False, np.arange(count) * motion.dt
        at, inside = np.minimum(grid, duration), grid <= duration

    def resample(values, order=0):
        if uniform and order == 0:
            return values  # read-only already: shared with the log, not copied
        result = spline_values(t, values, at, order)
        result[~inside] = values[-1] if order == 0 else 0.0
        return result

    q = resample(log.q)
    spread = None
    if log.qd is None:
        qd, qdd, spread = derivatives(t, log.q, at, inside)
    else:
        qd = resample(log.qd)
        qdd = resample(log.qdd) if log.qdd is not None else resample(log.qd, 1)
    return trajectory(motion, duration, grid, q, qd, qdd, qdd_uncertainty=spread)
