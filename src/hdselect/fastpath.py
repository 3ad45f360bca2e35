"""The motion's path run as fast as the joints' limits allow: TOPPRA under gearhead limits.

The path is the TOPPRA planner's (`hdselect.planning.toppra.path_pieces`): a
clamped cubic spline through the waypoints, split where the motion dwells. For a
motion planned otherwise (Ruckig), the knots sit at the time each segment takes at
the motion's velocity limits, so that joints in rad and in m weigh alike. Along
q = p(s), with u = s'' and x = s'^2, each joint j is held to

    velocity        |p'_j| s' <= v_j       motion file, URDF, unit (max input speed / ratio)
    acceleration    |p'_j u + p''_j x| <= a_j        motion file
    torque          |a_j u + b_j x + c_j| <= T_j     unit's repeated peak (its static limit in
                                                     a piece where the joint does not move),
                                                     the motion file's limits.torque
    emergency stop  |c_j + v_j x - a_j s' / t_stop| <= M_j      unit's momentary limit
    crash           |a_j u + b_j x + c_j| + K_j |p'_j| s' <= M_j,  K = (J_in + J_m) N^2 / t_stop

with a, b, c the torque coefficients (`hdselect.planning.constraints`) and
v = RNEA(p, p', 0) - c. The emergency stop depends on s' alone: it becomes an exact
bound on s' at each gridpoint (the first root of two quadratics). The crash term
is concave in x, which TOPPRA cannot take: it is replaced by its tangent at a
guess x0, K |p'| (sqrt(x0) / 2 + x / (2 sqrt(x0))), which lies above it everywhere
(so the answer stays feasible) and touches it at x0; the first guess is a quarter of
the speed the crash alone allows over gravity, and each later one is TOPPRA's
previous answer, round after round, each no slower than the one before
(`CRASH_ROUNDS`).

Torque is linear in a point mass carried at a joint (`PathModel`): the coefficients
for any choice of gearheads cost no further dynamics once each joint's per-kg part
is known.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from hdselect.dynamics import inverse_dynamics
from hdselect.errors import PlanningError
from hdselect.motion import Motion
from hdselect.planning.toppra import (
    PathPiece,
    Profile,
    kinematic_constraints,
    overshoot_scale,
    path_pieces,
    solve_piece,
)
from hdselect.planning.trajectory import Move, Trajectory, assemble
from hdselect.robot import Robot

GRID_PER_WAYPOINT = 100
"""TOPPRA gridpoints per waypoint of a piece (cosine-spaced). Measured on the shipped
arms with every gearhead limit binding: torque sampled between gridpoints exceeds its
limit by at most 0.5 %, and the cycle is within 0.4 % of the one on a four times finer
grid. The exact time scaling that follows removes the overshoot."""
CRASH_ROUNDS = 4
"""Most TOPPRA solves per piece while the crash bound's tangent settles."""
CRASH_SETTLED = 1e-4
"""A crash round that shortens the piece by less than this fraction ends them [-]."""

Coefficients = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""a, b, c, v along a piece, each (m, dof): torque = a s'' + b s'^2 + c, v = RNEA(p, p', 0) - c."""


class PathInfeasible(PlanningError):
    """No time parametrisation of the path meets the limits.

    Attributes:
        joint: The joint whose limit is at fault, or None.
        limit: Which limit (``"torque"``, ``"emergency stop"``, ``"crash"``, ``"velocity and
            acceleration"``, ``"static"``).
        gravity: The joint cannot hold the gravity load there at any speed.
    """

    def __init__(self, message: str, *, joint: str | None, limit: str, gravity: bool):
        super().__init__(message)
        self.joint, self.limit, self.gravity = joint, limit, gravity


@dataclass(frozen=True)
class JointLimits:
    """What bounds one joint along the path; math.inf where nothing does.

    Attributes:
        velocity: Speed limit [rad/s or m/s].
        velocity_source: ``"motion"`` (the motion file), ``"robot"`` (the URDF) or
            ``"unit"`` (its maximum input speed over its ratio).
        acceleration: Acceleration limit, the motion file's [rad/s^2 or m/s^2].
        torque: Torque limit while the joint moves [N m]: the unit's repeated peak
            (times a derating, see `hdselect.codesign`) or the motion file's limit.
        static: Torque limit in a piece where the joint does not move [N m].
        momentary: Momentary limit for the emergency stop and the crash [N m].
        crash_gain: K = (J_in + J_m) N^2 / t_stop [N m s]: crash torque per rad/s.
    """

    velocity: float
    velocity_source: str
    acceleration: float
    torque: float = math.inf
    static: float = math.inf
    momentary: float = math.inf
    crash_gain: float = 0.0


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
            assert motion.velocity_limit is not None  # waypoint planners require it
            speeds = motion.velocity_limit
        pieces = tuple(path_pieces(motion, grid_per_waypoint, speeds=speeds))
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
        assert base is not None
        out = [x.copy() for x in base]
        for name, mass in masses.items():
            part = self.per_kg[name][index]
            assert part is not None
            for total, x in zip(out, part, strict=True):
                total += mass * x
        return out[0], out[1], out[2], out[3]


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
    stops = {j: _stop_bound(coefficients, j, lim.momentary, stop_time)
             for j, lim in enumerate(limits) if math.isfinite(lim.momentary)}
    where = str(model.motion.path)
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    free = model.kinematic(index, velocity, acceleration, where)
    if free is not None and _meets(free, piece, limits, coefficients, stops):
        return free  # the fastest profile of fewer constraints meets them all: optimal
    groups = _groups(piece, model.robot.joint_names, limits, coefficients, stops)
    cap = _speed_cap(piece, limits, stops)
    crash = _crash_rows(piece, limits, coefficients, cap)
    profile = solve_piece(piece, [*_flatten(groups), *crash], where=where)
    if profile is None:
        raise _diagnose(model, piece, groups, limits, coefficients)
    for _ in range(CRASH_ROUNDS - 1):
        if not crash or not _crash_binds(piece, limits, coefficients, profile):
            break
        crash = _crash_rows(piece, limits, coefficients, cap, np.square(profile.sd))
        better = solve_piece(piece, [*_flatten(groups), *crash], where=where)
        if better is None or better.duration >= profile.duration:
            break
        settled = better.duration > profile.duration * (1.0 - CRASH_SETTLED)
        profile = better
        if settled:
            break
    return profile


Group = tuple[str, str | None, list[Any]]
"""Constraints of one kind on one joint: (limit, joint name or None for all, constraints)."""


def _groups(piece: PathPiece, names: Sequence[str], limits: Sequence[JointLimits],
            coefficients: Coefficients, stops: Mapping[int, np.ndarray]) -> list[Group]:
    """The constraints of a piece, kinematic ones first, then each joint's torque and stop."""
    from hdselect.planning.constraints import SecondOrderBounds, SpeedBound

    a, b, c, _ = coefficients
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    groups: list[Group] = [
        ("velocity and acceleration", None, kinematic_constraints(velocity, acceleration))]
    still = ~np.any(piece.dq != 0.0, axis=0) & ~np.any(piece.ddq != 0.0, axis=0)
    for j, lim in enumerate(limits):
        torque = lim.static if still[j] else lim.torque
        if math.isfinite(torque):
            groups.append(("static" if still[j] else "torque", names[j], [
                SecondOrderBounds.two_sided(piece.gridpoints, a[:, [j]], b[:, [j]], c[:, [j]],
                                            np.array([-torque]), np.array([torque]))]))
        if j in stops and np.isfinite(stops[j]).any():
            groups.append(("emergency stop", names[j], [SpeedBound(piece.gridpoints, stops[j])]))
    return groups


def _flatten(groups: Sequence[Group]) -> list[Any]:
    return [item for _, _, items in groups for item in items]


def _stop_bound(coefficients: Coefficients, j: int, limit: float,
                stop_time: float) -> np.ndarray:
    """Largest s' [1/s] up to which an emergency stop keeps |torque| <= limit, per gridpoint.

    The stop torque at path speed y is c + v y^2 - (a / t_stop) y; the bound is its first
    crossing of +-limit (0 where gravity alone is beyond it, inf where it never crosses).
    """
    a, _, c, v = (x[:, j] for x in coefficients)
    slope = -a / stop_time
    first = np.minimum(_first_root(v, slope, c - limit), _first_root(v, slope, c + limit))
    return np.where(np.abs(c) > limit, 0.0, first)


def _first_root(p2: np.ndarray, p1: np.ndarray, p0: np.ndarray) -> np.ndarray:
    """Smallest y > 0 with p2 y^2 + p1 y + p0 = 0, elementwise; inf where there is none."""
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = p1 * p1 - 4.0 * p2 * p0
        root = np.sqrt(np.maximum(disc, 0.0))
        q = -0.5 * (p1 + np.where(p1 >= 0.0, root, -root))
        r1 = np.where(p2 != 0.0, q / p2, -p0 / p1)
        r2 = np.where((p2 != 0.0) & (q != 0.0), p0 / q, np.nan)
        real = (p2 == 0.0) | (disc >= 0.0)
    roots = np.stack([r1, r2])
    roots = np.where(real & np.isfinite(roots) & (roots > 0.0), roots, np.inf)
    return roots.min(axis=0)


def _speed_cap(piece: PathPiece, limits: Sequence[JointLimits],
               stops: Mapping[int, np.ndarray]) -> np.ndarray:
    """The largest s' [1/s] the velocity and emergency-stop bounds allow at each gridpoint."""
    velocity = np.array([lim.velocity for lim in limits])
    with np.errstate(divide="ignore"):
        cap = np.min(velocity / np.abs(piece.dq), axis=1)
    for bound in stops.values():
        cap = np.minimum(cap, bound)
    return np.minimum(cap, 1e8)


def _crash_rows(piece: PathPiece, limits: Sequence[JointLimits], coefficients: Coefficients,
                cap: np.ndarray, guess: np.ndarray | None = None) -> list[Any]:
    """The crash rule as rows linear in (s'', s'^2), never weaker than the rule itself.

    |tau| + k sqrt(x) <= M with k = K |p'|: sqrt is concave, so its tangent at any
    x0 > 0 lies above it and touches it at x0, and |tau| + k (sqrt(x0) / 2 +
    x / (2 sqrt(x0))) <= M is a linear bound stricter than the rule. The first round's
    x0 is a quarter of the speed the crash alone allows over gravity,
    ((M - |c|) / (2 k))^2, which leaves three quarters of that torque margin at rest;
    later rounds take the previous round's answer, which meets the new bound, so each
    round is feasible and no slower.

    Args:
        piece: The piece.
        limits: Each joint's limits.
        coefficients: The piece's a, b, c, v.
        cap: The largest path speed the other bounds allow at each gridpoint [1/s].
        guess: x0 = s'^2 at each gridpoint [1/s^2], or None for the first round.
    """
    from hdselect.planning.constraints import SecondOrderBounds

    a, b, c, _ = coefficients
    rows = []
    for j, lim in enumerate(limits):
        if not math.isfinite(lim.momentary) or lim.crash_gain <= 0.0:
            continue
        gain = lim.crash_gain * np.abs(piece.dq[:, j])
        if float(np.max(gain * cap)) + min(lim.torque, lim.static) <= lim.momentary:
            continue  # the torque limit is the stricter one everywhere
        if guess is None:
            with np.errstate(divide="ignore", invalid="ignore"):
                first = np.square(np.maximum(lim.momentary - np.abs(c[:, j]), 0.0)
                                  / (2.0 * gain))
            x0 = np.minimum(np.where(gain > 0.0, first, 0.0), np.square(cap))
        else:
            x0 = guess
        root = np.sqrt(np.maximum(x0, 0.0))
        tangent = (root > 0.0) & (gain > 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(tangent, gain / (2.0 * root), 0.0)
        offset = np.where(tangent, gain * root / 2.0, 0.0)
        # where x0 = 0 the rows force x = 0 unless the joint does not move (k = 0)
        slope = np.where(~tangent & (gain > 0.0), 1e12, slope)
        rows.append(SecondOrderBounds(
            piece.gridpoints, np.column_stack([a[:, j], -a[:, j]]),
            np.column_stack([b[:, j] + slope, slope - b[:, j]]),
            np.column_stack([c[:, j] + offset, offset - c[:, j]]), np.eye(2),
            np.full(2, lim.momentary)))
    return rows


def _meets(profile: Profile, piece: PathPiece, limits: Sequence[JointLimits],
           coefficients: Coefficients, stops: Mapping[int, np.ndarray]) -> bool:
    """Whether a profile meets the torque, emergency-stop and crash limits at the gridpoints.

    As TOPPRA's interpolation discretization imposes them: each step's path acceleration
    at the gridpoint it leaves and at the one it reaches.
    """
    a, b, c, _ = coefficients
    x = np.square(profile.sd)
    u = profile.sdd
    still = ~np.any(piece.dq != 0.0, axis=0) & ~np.any(piece.ddq != 0.0, axis=0)
    torque = np.array([lim.static if still[j] else lim.torque for j, lim in enumerate(limits)])
    momentary = np.array([lim.momentary for lim in limits])
    gain = np.array([lim.crash_gain for lim in limits]) * np.abs(piece.dq)
    for at, xs in ((slice(None, -1), x[:-1]), (slice(1, None), x[1:])):
        tau = np.abs(a[at] * u[:, None] + b[at] * xs[:, None] + c[at])
        if np.any(tau > torque) or np.any(tau + gain[at] * np.sqrt(xs)[:, None] > momentary):
            return False
    return all(np.all(x <= np.square(bound)) for bound in stops.values())


def _crash_binds(piece: PathPiece, limits: Sequence[JointLimits], coefficients: Coefficients,
                 profile: Profile) -> bool:
    """Whether the crash rule (exact, not its tangent) is within 0.1 % of its limit somewhere.

    Where it is not, the tangent's slack cost nothing and another round cannot help.
    """
    a, b, c, _ = coefficients
    x = np.square(profile.sd)
    u = np.r_[profile.sdd, profile.sdd[-1:]]
    for j, lim in enumerate(limits):
        if math.isfinite(lim.momentary) and lim.crash_gain > 0.0:
            crash = (np.abs(a[:, j] * u + b[:, j] * x + c[:, j])
                     + lim.crash_gain * np.abs(piece.dq[:, j]) * profile.sd)
            if np.max(crash) >= lim.momentary * (1.0 - 1e-3):
                return True
    return False


def _diagnose(model: PathModel, piece: PathPiece, groups: Sequence[Group],
              limits: Sequence[JointLimits], coefficients: Coefficients) -> PathInfeasible:
    """Which limit makes the piece infeasible, for which joint, and where."""
    where = f"{model.motion.path}: the path from waypoint[{piece.first}] to waypoint[{piece.last}]"
    kinematic = groups[0][2]
    if solve_piece(piece, kinematic, where=where) is None:
        return PathInfeasible(f"{where}: the velocity and acceleration limits make it "
                              "infeasible", joint=None, limit="velocity and acceleration",
                              gravity=False)
    names = list(model.robot.joint_names)
    c = coefficients[2]
    for limit, name, items in groups[1:]:
        if solve_piece(piece, [*kinematic, *items], where=where) is not None:
            continue
        assert name is not None
        j = names.index(name)
        lim = limits[j]
        bound = {"emergency stop": lim.momentary, "static": lim.static}.get(limit, lim.torque)
        unit = math.isfinite(lim.momentary)  # a joint with a gearhead; else limits.torque
        what = {"emergency stop": "momentary limit (emergency stop)",
                "static": "static limit" if unit else "limits.torque",
                "torque": "repeated-peak limit" if unit else "limits.torque"}[limit]
        k = int(np.argmax(np.abs(c[:, j])))
        if abs(c[k, j]) > bound:
            lo, hi = piece.segment(float(piece.gridpoints[k]))
            return PathInfeasible(
                f"{where}: joint '{name}' cannot hold its gravity load at any speed: "
                f"{abs(c[k, j]):.3g} N m between waypoint[{lo}] and waypoint[{hi}] "
                f"(s = {piece.gridpoints[k]:.3f}) is beyond its {what} {bound:.3g} N m",
                joint=name, limit=limit, gravity=True)
        s = _first_infeasible(piece, [*kinematic, *items])
        lo, hi = piece.segment(s)
        return PathInfeasible(
            f"{where}: the {what} of joint '{name}' ({bound:.3g} N m) makes it infeasible "
            f"at any speed, first at s = {s:.3f} between waypoint[{lo}] and waypoint[{hi}]",
            joint=name, limit=limit, gravity=False)
    return PathInfeasible(f"{where}: the torque, emergency-stop and crash limits together make "
                          "it infeasible at any speed", joint=None, limit="together",
                          gravity=False)


def _first_infeasible(piece: PathPiece, constraints: list[Any]) -> float:
    """The first path position [-] where the constraints leave no path speed.

    From TOPPRA's feasible sets; where every gridpoint has some speed, the last one from
    which the piece cannot be brought to rest (its controllable sets).
    """
    import toppra.algorithm as algorithm

    from hdselect.planning.toppra import _quiet

    with _quiet():
        instance = algorithm.TOPPRA(constraints, piece.path, gridpoints=piece.gridpoints)
        feasible = instance.compute_feasible_sets()
        empty = np.flatnonzero(~np.all(np.isfinite(feasible), axis=1)
                               | (feasible[:, 1] < feasible[:, 0]))
        if empty.size:
            return float(piece.gridpoints[empty[0]])
        controllable = instance.compute_controllable_sets(0.0, 0.0)
    bad = np.flatnonzero(~np.all(np.isfinite(controllable), axis=1))
    return float(piece.gridpoints[bad[-1]] if bad.size else piece.gridpoints[0])


def cycle(motion: Motion, profiles: Sequence[Profile | None],
          scales: Sequence[float]) -> tuple[Trajectory, np.ndarray]:
    """The whole cycle: each piece run at its time scale [-], with the motion's dwells.

    Returns:
        The trajectory, sampled every ``motion.dt``, and a mask of its samples that
        lie in a dwell (or after the cycle), whose time does not scale.
    """
    moves = [Move(p.piece.first, p.piece.last, p.duration * scale,
                  partial(p.sample, scale=scale))
             for p, scale in zip(profiles, scales, strict=True) if p is not None]
    trajectory = assemble(motion, moves)
    held = np.ones(len(trajectory.t), dtype=bool)
    clock = motion.dwells[0]
    for move in moves:
        held &= ~((trajectory.t >= clock) & (trajectory.t < clock + move.duration))
        clock += move.duration + motion.dwells[move.last]
    return trajectory, held


def kinematic_scales(profiles: Sequence[Profile | None],
                     limits: Sequence[JointLimits]) -> list[float]:
    """Per piece, the slow-down r >= 1 [-] that keeps it within its speed and acceleration limits.

    TOPPRA meets them at the gridpoints; `hdselect.planning.toppra.overshoot_scale`
    measures the overshoot between them.
    """
    velocity = np.array([lim.velocity for lim in limits])
    acceleration = np.array([lim.acceleration for lim in limits])
    return [1.0 if p is None else overshoot_scale(p, velocity, acceleration) for p in profiles]
