"""The motion's path run as fast as the joints' limits allow: TOPPRA under gearhead limits.

The path is the TOPPRA planner's (`hdselect.motion.planning.toppra.path_pieces`): a
clamped cubic spline through the waypoints, split where the motion dwells, on gridpoints
that resolve it (`_resolved`: every knot, refined where the motion's own limits break
between gridpoints). For a
motion planned otherwise (Ruckig), the knots sit at the time each segment takes at
the motion's velocity limits, so that joints in rad and in m weigh alike. Each piece
is first solved under its speed and acceleration limits alone: where that profile
meets every gearhead limit (`hdselect.codesign.pathbounds`) it is the answer, since no
profile under more constraints is faster. Otherwise TOPPRA solves the piece under
all of them; the crash bound's tangent starts at a quarter of the speed the crash
alone allows over gravity and then moves to TOPPRA's previous answer, round after
round, each no slower than the one before (`CRASH_ROUNDS`).

Torque is linear in a point mass carried at a joint (`PathModel`): the coefficients
for any choice of gearheads cost no further dynamics once each joint's per-kg part
is known.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.errors import InputError
from hdselect.codesign.pathbounds import (
    Coefficients,
    JointLimits,
    constraint_groups,
    crash_binds,
    crash_rows,
    flatten,
    meets,
    speed_cap,
    stop_bound,
)
from hdselect.codesign.pathdiagnosis import diagnose
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.path import bends_sharply, dense_grid, first_grid
from hdselect.motion.planning.toppra import (
    SLOWDOWN_NOTED,
    PathPiece,
    Profile,
    kinematic_constraints,
    overshoot,
    overshoot_scale,
    path_pieces,
    slowdown_note,
    solve_piece,
    solve_refined,
    step_excess,
    with_gridpoints,
)
from hdselect.motion.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.model import Robot

GRID_PER_WAYPOINT = 100
"""TOPPRA gridpoints per waypoint of a piece (cosine-spaced). Measured on the shipped
arms with every gearhead limit binding: torque sampled between gridpoints exceeds its
limit by at most 0.5 %, and the cycle is within 0.4 % of the one on a four times finer
grid. The exact time scaling that follows removes the overshoot."""
CRASH_ROUNDS = 4
"""Most TOPPRA solves per piece while the crash bound's tangent settles."""
CRASH_SETTLED = 1e-4
"""A crash round that shortens the piece by less than this fraction ends them [-]."""

@dataclass(frozen=True, eq=False)
class PathModel:
    """The motion's path and the dynamics along it, for any gearhead masses.

    Attributes:
        robot: The robot (payload and mounting applied, no gearhead masses).
        motion: The motion whose waypoints make the path.
        pieces: The path's pieces.
        base: Per piece, the coefficients without gearhead masses (None: no path).
        per_kg: Per joint that can carry a gearhead, per piece, the coefficients of
            1 kg at that joint's origin (on the link before it).
        grid_per_waypoint: TOPPRA gridpoints per waypoint of a piece.
    """

    robot: Robot
    motion: Motion
    pieces: tuple[PathPiece, ...]
    base: tuple[Coefficients | None, ...]
    per_kg: Mapping[str, tuple[Coefficients | None, ...]]
    grid_per_waypoint: int = GRID_PER_WAYPOINT
    _kinematic: dict[tuple, Profile | None] = field(default_factory=dict, repr=False)

    def kinematic(self, index: int, velocity: np.ndarray, acceleration: np.ndarray,
                  where: str) -> Profile | None:
        """TOPPRA's profile of a piece under speed and acceleration limits alone (memoised).

        It depends on nothing else, so every choice of units with the same speed limits
        shares it.
        """
        key = (index, velocity.tobytes(), acceleration.tobytes())
        if key not in self._kinematic:
            self._kinematic[key] = solve_piece(
                self.pieces[index], kinematic_constraints(velocity, acceleration), where=where)
        return self._kinematic[key]

    @classmethod
    def build(cls, robot: Robot, motion: Motion, joints: Sequence[str], *,
              grid_per_waypoint: int = GRID_PER_WAYPOINT,
              threads: int | None = None) -> PathModel:
        """The path of a motion and its torque coefficients, 4 (1 + joints) batched passes.

        Args:
            robot: The robot as the motion runs it, without gearhead masses.
            motion: A motion with waypoints (not a log).
            joints: Joints whose gearhead mass may be carried.
            grid_per_waypoint: TOPPRA gridpoints per waypoint.
            threads: Threads of the batched dynamics.
        """
        motion.check_joints(robot)
        speeds = None
        if motion.planner != "toppra":
            if motion.velocity_limit is None:
                raise InputError(f"the {motion.planner} planner needs a velocity limit",
                                 path=motion.path, field="limits.velocity")
            speeds = motion.velocity_limit
        pieces = tuple(_resolved(piece, motion) for piece in
                       path_pieces(robot, motion, grid_per_waypoint, speeds=speeds))
        base = _coefficients(robot, pieces, threads)
        per_kg = {}
        for name in joints:
            loaded = _coefficients(robot.with_gearheads({name: 1.0}), pieces, threads)
            per_kg[name] = tuple(None if one is None or zero is None else
                                 tuple(x - y for x, y in zip(one, zero, strict=True))
                                 for one, zero in zip(loaded, base, strict=True))
        return cls(robot, motion, pieces, base, per_kg,  # type: ignore[arg-type]
                   grid_per_waypoint)

    def coefficients(self, index: int, masses: Mapping[str, float]) -> Coefficients:
        """a, b, c, v of piece `index` with a mass [kg] carried at each named joint."""
        base = self.base[index]
        if base is None:
            raise RuntimeError(f"path piece {index} has no coefficients")
        out = [x.copy() for x in base]
        for name, mass in masses.items():
            part = self.per_kg[name][index]
            if part is None:
                raise RuntimeError(f"path piece {index} has no coefficients per kg at {name}")
            for total, x in zip(out, part, strict=True):
                total += mass * x
        return out[0], out[1], out[2], out[3]


def _resolved(piece: PathPiece, motion: Motion) -> PathPiece:
    """The piece on gridpoints that resolve its path, once for every choice of units.

    Every knot is a gridpoint, and the grid is refined where the motion's own speed
    and acceleration limits break between gridpoints (as the planner refines,
    `hdselect.motion.planning.toppra.solve_refined`): the path's shape, not the units,
    sets where TOPPRA's profile overshoots (a line's close samples, a shape-preserving
    joint's knots). Such a piece starts from the planner's dense grid, so that `fastest`
    times it as `plan` does.
    """
    if piece.path is None:
        return piece
    if bends_sharply(piece):
        piece = with_gridpoints(piece, dense_grid(piece))
    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    if velocity is None or acceleration is None:
        raise InputError("a path needs velocity and acceleration limits",
                         path=motion.path, field="limits")
    constraints = kinematic_constraints(velocity, acceleration)
    first = first_grid(piece, full=True)
    refined, found = solve_refined(first, lambda _: constraints,
                                   partial(step_excess, velocity=velocity,
                                           acceleration=acceleration), where=str(motion.path))
    return first if found is None else refined


def _coefficients(robot: Robot, pieces: Sequence[PathPiece],
                  threads: int | None) -> tuple[Coefficients | None, ...]:
    """The coefficients of every piece in four batched passes over all gridpoints."""
    moving = [p for p in pieces if p.path is not None]
    if not moving:
        return tuple(None for _ in pieces)
    q, dq, ddq = (np.concatenate([getattr(p, name) for p in moving])
                  for name in ("q", "dq", "ddq"))
    zero = np.zeros_like(dq)
    c = inverse_dynamics(robot, q, zero, zero, threads=threads)
    a = inverse_dynamics(robot, q, zero, dq, threads=threads) - c
    b = inverse_dynamics(robot, q, dq, ddq, threads=threads) - c
    v = inverse_dynamics(robot, q, dq, zero, threads=threads) - c
    ends = np.cumsum([len(p.gridpoints) for p in moving])[:-1]
    split = iter(zip(*(np.split(x, ends) for x in (a, b, c, v)), strict=True))
    return tuple(next(split) if p.path is not None else None for p in pieces)


def solve(model: PathModel, limits: Sequence[JointLimits], masses: Mapping[str, float], *,
          stop_time: float) -> list[Profile | None]:
    """The time-optimal profile of every piece under the joints' limits.

    Args:
        model: The path and its dynamics.
        limits: One per degree of freedom, in the robot's joint order.
        masses: Gearhead (and motor) mass carried at each joint [kg].
        stop_time: Emergency-stop and crash time [s].

    Returns:
        One profile per piece (None for a piece of zero length).

    Raises:
        PathInfeasible: No profile meets the limits; the message says which limit of
            which joint, and where.
    """
    return [None if piece.path is None else
            _solve_piece(model, index, limits, model.coefficients(index, masses), stop_time)
            for index, piece in enumerate(model.pieces)]


def _solve_piece(model: PathModel, index: int, limits: Sequence[JointLimits],
                 coefficients: Coefficients, stop_time: float) -> Profile:
    piece = model.pieces[index]
    stops = {j: stop_bound(coefficients, j, lim.momentary, stop_time)
             for j, lim in enumerate(limits) if math.isfinite(lim.momentary)}
    where = str(model.motion.path)
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    free = model.kinematic(index, velocity, acceleration, where)
    if free is not None and meets(free, piece, limits, coefficients, stops):
        return free  # the fastest profile of fewer constraints meets them all: optimal
    groups = constraint_groups(piece, model.robot.joint_names, limits, coefficients, stops)
    cap = speed_cap(piece, limits, stops)
    crash = crash_rows(piece, limits, coefficients, cap)
    profile = solve_piece(piece, [*flatten(groups), *crash], where=where)
    if profile is None:
        raise diagnose(model.motion, model.robot.joint_names, piece, groups, limits,
                       coefficients)
    for _ in range(CRASH_ROUNDS - 1):
        if not crash or not crash_binds(piece, limits, coefficients, profile):
            break
        crash = crash_rows(piece, limits, coefficients, cap, np.square(profile.sd))
        better = solve_piece(piece, [*flatten(groups), *crash], where=where)
        if better is None or better.duration >= profile.duration:
            break
        settled = better.duration > profile.duration * (1.0 - CRASH_SETTLED)
        profile = better
        if settled:
            break
    return profile


def cycle(motion: Motion, profiles: Sequence[Profile | None], scales: Sequence[float], *,
          max_samples: int = DEFAULT_MAX_SAMPLES,
          notes: tuple[str, ...] = ()) -> tuple[Trajectory, np.ndarray]:
    """The whole cycle: each piece run at its time scale [-], with the motion's dwells.

    The grid is checked as `hdselect.motion.planning.plan` checks it: it must resolve every
    piece and dwell and have at most `max_samples` samples. `notes` become the
    trajectory's (`Trajectory.notes`).

    Returns:
        The trajectory, sampled every ``motion.dt``, and a mask of its samples that
        lie in a dwell (or after the cycle), whose time does not scale.
    """
    moves = [Move(p.piece.first, p.piece.last, p.duration * scale,
                  partial(p.sample, scale=scale), p.peak_accelerations(scale),
                  p.time_step * scale)
             for p, scale in zip(profiles, scales, strict=True) if p is not None]
    trajectory = assemble(motion, moves, max_samples=max_samples, notes=notes)
    held = np.ones(len(trajectory.t), dtype=bool)
    clock = motion.dwells[0]
    for move in moves:
        held &= ~((trajectory.t >= clock) & (trajectory.t < clock + move.duration))
        clock += move.duration + motion.dwells[move.last]
    return trajectory, held


def kinematic_scales(profiles: Sequence[Profile | None],
                     limits: Sequence[JointLimits]) -> list[float]:
    """Per piece, the slow-down r >= 1 [-] that keeps it within its speed and acceleration limits.

    TOPPRA meets them at the gridpoints; `hdselect.motion.planning.toppra.overshoot_scale`
    measures the overshoot between them.
    """
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    return [1.0 if p is None else overshoot_scale(p, velocity, acceleration) for p in profiles]


def slowdown_notes(names: Sequence[str], profiles: Sequence[Profile | None],
                   limits: Sequence[JointLimits]) -> tuple[str, ...]:
    """The planner's line for every piece slowed down beyond its tolerance.

    That is by more than `hdselect.motion.planning.toppra.SLOWDOWN_NOTED` in
    `kinematic_scales`; each line names the joint (from `names`) and the factor.
    """
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    notes = []
    for profile in profiles:
        if profile is not None:
            scale, joint, limit = overshoot(profile, velocity, acceleration)
            if scale > 1.0 + SLOWDOWN_NOTED:
                notes.append(slowdown_note(profile.piece.first, profile.piece.last,
                                           names[joint], limit, scale))
    return tuple(notes)
