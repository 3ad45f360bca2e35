"""The sampled trajectory every planner produces, and the grid it is sampled on.

Grid: t_k = k dt for k = 0..ceil(T/dt), T the cycle time; samples past T hold
the final state at rest. The grid is checked (`hdselect.motion.planning.grid`) before
any array is allocated: it must resolve every move and dwell and stay within the
sample limit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError, PlanningError
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.grid import PEAK_RESOLUTION, check_size, resolving_factor

Sampler = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""Positions, velocities and accelerations [rad or m, per s, per s^2], each (n, dof), at
times [s] from the start of a move."""


@dataclass(frozen=True)
class Move:
    """One planned move between two waypoints, from rest to rest.

    Attributes:
        first: Index of the waypoint it starts from.
        last: Index of the waypoint it ends at.
        duration: Its duration [s].
        sample: Its state at given times, or None for a move of zero length.
        peak_acceleration: The largest |acceleration| of each joint over the move, exact
            (from the planner's profile) [rad/s^2 or m/s^2], shape (dof,); None when not
            known. The grid is refined until the samples find these peaks
            (`PEAK_RESOLUTION`).
        resolution: The longest sample period that resolves the move's shape [s] (TOPPRA:
            the median time between its gridpoints, where its acceleration steps), or None.
        passes: Time from its start at which it reaches each waypoint from `first` to
            `last` [s]; empty when only the ends are known (at 0 and `duration`).
    """

    first: int
    last: int
    duration: float
    sample: Sampler | None
    peak_acceleration: np.ndarray | None = None
    resolution: float | None = None
    passes: tuple[float, ...] = ()


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A joint trajectory sampled at t_k = k dt.

    Attributes:
        joint_names: Name of every degree of freedom, in the columns' order.
        dt: Sample period [s].
        duration: Cycle time T [s]; samples after it are at rest.
        t: Sample times [s], shape (n,).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        waypoint_times: When the arm reaches each waypoint of the motion it was planned
            from, before that waypoint's dwell [s], shape (k,); NaN where a planner does
            not say (an interior waypoint of a co-design piece); None for a log.
        qdd_uncertainty: How far each sample's acceleration may be off where it was derived
            from a log's positions (`hdselect.motion.logderivatives.derivatives`)
            [rad/s^2 or m/s^2], shape (n, dof); None where the accelerations are exact
            (planned) or logged.
        notes: What the planner noticed, one line each: a piece it slowed down by more
            than its tolerance, with the joint and the factor.
    """

    joint_names: tuple[str, ...]
    dt: float
    duration: float
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    waypoint_times: np.ndarray | None = None
    qdd_uncertainty: np.ndarray | None = None
    notes: tuple[str, ...] = ()


def trajectory(motion: Motion, duration: float, t: np.ndarray, q: np.ndarray, qd: np.ndarray,
               qdd: np.ndarray, *, dt: float | None = None,
               waypoint_times: np.ndarray | None = None,
               qdd_uncertainty: np.ndarray | None = None,
               notes: tuple[str, ...] = ()) -> Trajectory:
    """A read-only Trajectory of the motion's joints from sampled arrays (taken over).

    Its period is `dt` [s], by default the motion's; `waypoint_times` [s],
    `qdd_uncertainty` [per s^2] and `notes` as `Trajectory`'s.
    """
    for array in (t, q, qd, qdd, *(a for a in (waypoint_times, qdd_uncertainty)
                                   if a is not None)):
        array.setflags(write=False)
    return Trajectory(motion.joint_names, motion.dt if dt is None else dt, float(duration), t,
                      q, qd, qdd, waypoint_times, qdd_uncertainty, notes)


def assemble(motion: Motion, moves: Sequence[Move], *,
             max_samples: int = DEFAULT_MAX_SAMPLES, notes: tuple[str, ...] = ()) -> Trajectory:
    """Sample rest-to-rest moves and the waypoints' dwells on a grid that resolves them.

    The grid is the motion's dt divided by the smallest whole number k that resolves
    the cycle (`refinement`): every move spans `MIN_MOVE_SAMPLES` samples, every dwell
    at least one, and the samples find each joint's peak acceleration of every move to
    within `PEAK_RESOLUTION`. The file's own grid times k dt stay sample times.

    Args:
        motion: The motion (waypoints, dwells, dt).
        moves: One move per consecutive pair of the waypoints it joins, in order.
        max_samples: Most samples the grid may have.
        notes: The planner's notes (`Trajectory.notes`).

    Returns:
        The whole cycle: the first dwell, then each move followed by its last
        waypoint's dwell. A cycle in which nothing moves (every waypoint the same)
        is a hold: every sample at rest. Its ``dt`` is the period sampled, ``motion.dt``
        or a whole fraction of it.

    Raises:
        InputError: The cycle takes no time, or the grid that resolves it would exceed
            `max_samples` (the field is ``dt``).
        PlanningError: A planner gave a move a duration that is not finite.
    """
    piece = "path piece" if motion.planner == "toppra" else "move"
    for move in moves:
        if not math.isfinite(move.duration) or move.duration < 0.0:
            raise PlanningError(f"{motion.path}: the {motion.planner} {piece} from "
                                f"waypoint[{move.first}] to waypoint[{move.last}] has no finite "
                                f"duration ({move.duration})")
    what = [(f"the {piece} from waypoint[{m.first}] to waypoint[{m.last}]", m.duration)
            for m in moves]
    dwells = [(f"the dwell at waypoint[{i}]", float(d)) for i, d in enumerate(motion.dwells)]
    factor, reason = resolving_factor(motion.dt, what, dwells)
    for (name, _), move in zip(what, moves, strict=True):
        if move.resolution is not None and move.resolution > 0.0:
            need = math.ceil(motion.dt / move.resolution * (1.0 - 1e-9))
            if need > factor:
                factor, reason = need, f"{name} (its time steps of {move.resolution:.3g} s)"
    for _ in range(_MAX_ROUNDS):
        try:
            trajectory, miss = _sampled(motion, moves, motion.dt / factor, max_samples, notes)
        except InputError as err:
            if factor == 1:
                raise
            advice = "; or lengthen that dwell" if reason.startswith("the dwell") else ""
            raise InputError(f"dt = {motion.dt:g} s is refined to {motion.dt / factor:.3g} s "
                             f"to resolve {reason}: {err.reason}{advice}", path=motion.path,
                             field="dt") from err
        worst = int(np.argmax(miss)) if len(miss) else 0
        if not len(miss) or miss[worst] <= PEAK_RESOLUTION:
            return trajectory
        # a kink's peak is missed by up to (jerk) h / 2: the miss falls as the period
        factor = max(2 * factor, math.ceil(factor * miss[worst] / PEAK_RESOLUTION * 1.25))
        reason = f"the peak accelerations of {what[worst][0]}"
    return trajectory


_MAX_ROUNDS = 4
"""Refinements tried before the grid is taken as it is (each multiplies samples >= 2x)."""


def _sampled(motion: Motion, moves: Sequence[Move], dt: float, max_samples: int,
             notes: tuple[str, ...] = ()) -> tuple[Trajectory, np.ndarray]:
    """The cycle sampled every `dt` [s], and how much each move's samples miss of its peaks.

    A move's miss is the most any joint's sampled peak |acceleration| falls short of its
    exact one, as a fraction of the joint's largest peak over the cycle [-].
    """
    waypoints, dwells = motion.waypoints, motion.dwells
    starts, ends, rest = [], [], [waypoints[0]]
    reached = np.full(len(waypoints), np.nan)
    reached[0] = 0.0
    clock = float(dwells[0])
    for move in moves:
        starts.append(clock)
        ends.append(clock + move.duration)
        rest.append(waypoints[move.last])
        if len(move.passes) == move.last - move.first + 1:
            reached[move.first + 1:move.last + 1] = clock + np.asarray(move.passes[1:])
        reached[move.last] = clock + move.duration
        clock += move.duration + float(dwells[move.last])
    if clock == 0.0:
        raise InputError("the cycle takes no time: every waypoint is the same and none has a "
                         "dwell; give a dwell to size holding the pose", path=motion.path,
                         field="waypoint")
    count = check_size(motion.path, clock, dt, len(motion.joint_names), max_samples)
    t = np.arange(count) * dt
    q = np.asarray(rest)[np.searchsorted(ends, t, side="right")]
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    exact = [m.peak_acceleration for m in moves if m.peak_acceleration is not None]
    scale = np.max(exact, axis=0) if exact else None
    miss = np.zeros(len(moves))
    for i, (move, start, end) in enumerate(zip(moves, starts, ends, strict=True)):
        k0, k1 = np.searchsorted(t, [start, end], side="left")
        if k1 > k0 and move.sample is not None:
            q[k0:k1], qd[k0:k1], qdd[k0:k1] = move.sample(t[k0:k1] - start)
            if move.peak_acceleration is not None and scale is not None:
                found = np.abs(qdd[k0:k1]).max(axis=0)
                with np.errstate(divide="ignore", invalid="ignore"):
                    short = np.where(scale > 0.0, (move.peak_acceleration - found) / scale, 0.0)
                miss[i] = float(np.max(short, initial=0.0))
    return trajectory(motion, clock, t, q, qd, qdd, dt=dt, waypoint_times=reached,
                      notes=notes), miss
