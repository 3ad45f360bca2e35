"""A gearhead's limits as TOPPRA constraints along a piece of the path, and their diagnosis.

Along q = p(s), with u = s'' and x = s'^2, each joint j is held to the motion file's
and the robot file's limits and to the bounds of every rule with a path form
(`path_bounds`, `hdselect.catalog.rules.Rule.path_rows`), by kind:

    speed           |p'_j| s' <= v_j                files; unit, motor (input speed / ratio)
    acceleration    |p'_j u + p''_j x| <= a_j        motion file
    torque          |a_j u + b_j x + c_j| <= T_j     repeated peak (static: in a piece where
                                                     the joint does not move); limits.torque
    motor torque    |k (a_j u + b_j x + c_j) + J N (p'_j u + p''_j x)| <= P_j, for
                    k = 1 / (N eta_low) and eta_high / N, J = J_in + J_m (its curve: after)
    emergency stop  |c_j + v_j x - a_j s' / t_stop| <= M_j      momentary limit
    crash           |a_j u + b_j x + c_j| + K_j |p'_j| s' <= M_j,  K = (J_in + J_m) N^2 / t_stop

with a, b, c the torque coefficients (`hdselect.motion.planning.constraints`) and
v = RNEA(p, p', 0) - c. The emergency stop depends on s' alone: it becomes an exact
bound on s' at each gridpoint (the first root of two quadratics). The crash term
is concave in x, which TOPPRA cannot take: it is replaced by its tangent at a
guess x0, K |p'| (sqrt(x0) / 2 + x / (2 sqrt(x0))), which lies above it everywhere
(so the answer stays feasible) and touches it at x0 (`crash_rows`; the rounds that
move x0 are in `hdselect.codesign.fastpath`). A rule on single samples without a path form is
checked on the planned cycle (`hdselect.codesign.cyclerules.after_solve`).

Where no profile exists, `diagnose` names the joint, the limit and where.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hdselect.base.errors import InputError, PlanningError
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import RULES, Scope
from hdselect.catalog.rules.forms import PathBound, PathCase, PathKind
from hdselect.catalog.units import Unit
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.toppra import PathPiece, Profile, kinematic_constraints, solve_piece
from hdselect.robot.model import Robot
from hdselect.sizing.options import Options

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
        velocity_source: ``"motion"`` (the motion file), ``"robot"`` (the robot file) or
            ``"unit"`` (its maximum input speed over its ratio).
        acceleration: Acceleration limit, the motion file's [rad/s^2 or m/s^2].
        torque: Torque limit while the joint moves [N m]: the unit's repeated peak
            (times a derating, see `hdselect.codesign`) or the motion file's limit.
        static: Torque limit in a piece where the joint does not move [N m].
        momentary: Momentary limit for the emergency stop and the crash [N m].
        crash_gain: K = (J_in + J_m) N^2 / t_stop [N m s]: crash torque per rad/s.
        motor_torque: The motor's peak torque P [N m] (math.inf without a motor).
        motor_factors: The two gear factors k of the motor torque, 1 / (N eta_low) and
            eta_high / N [-] (`efficiency_range`).
        motor_inertia: (J_in + J_m) N [kg m^2]: the motor torque per rad/s^2 of output
            acceleration.
        unbounded: The per-sample rules of its unit that give no path form (`path_bounds`):
            checked forward on the planned cycle.
    """

    velocity: float
    velocity_source: str
    acceleration: float
    torque: float = math.inf
    static: float = math.inf
    momentary: float = math.inf
    crash_gain: float = 0.0
    motor_torque: float = math.inf
    motor_factors: tuple[float, float] = (0.0, 0.0)
    motor_inertia: float = 0.0
    unbounded: tuple[str, ...] = ()


def joint_limits(robot: Robot, motion: Motion, units: Mapping[str, Unit], options: Options,
                 derating: Mapping[str, float] | None = None, *,
                 motors: Mapping[str, Motor] | None = None) -> list[JointLimits]:
    """The files' limits and the rules' bounds (`path_bounds`) on each joint, in order.

    Args:
        robot: The robot (its robot file's velocity limits).
        motion: The motion (its velocity, acceleration and torque limits).
        units: The unit of every sized joint.
        options: Stop time, efficiency and motor rotor inertia.
        derating: Fraction of the repeated-peak limit per joint (default none) [-].
        motors: The motor behind the unit of some joints: its maximum speed over the
            ratio bounds the joint's speed, its peak torque the motor torque, and its
            rotor inertia replaces the options'.
    """
    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    if velocity is None or acceleration is None:
        raise InputError("a path needs velocity and acceleration limits",
                         path=motion.path, field="limits")
    out = []
    for j, name in enumerate(robot.joint_names):
        urdf = float(robot.velocity_limit[j])
        from_file = math.isfinite(urdf) and urdf > 0.0
        # a joint the motion file gives no speed for runs at the robot file's: that is its source
        speeds = ([] if from_file and name in motion.velocity_from_robot
                  else [(float(velocity[j]), "motion")])
        if from_file:
            speeds.append((urdf, "robot"))
        torque = math.inf if motion.torque_limit is None else float(motion.torque_limit[j])
        unit = units.get(name)
        bounds: list[PathBound] = []
        unbounded: tuple[str, ...] = ()
        if unit is not None:  # the limits less the design margin (`Rule.derate`)
            motor = (motors or {}).get(name)
            rotor = motor.rotor_inertia if motor is not None else options.rotor_inertia
            bounds, unbounded = path_bounds(PathCase(
                unit, options.margin, options.stop_time, options.efficiency, rotor, motor,
                max_torsion=options.joint_value("max_torsion", name)))
        out.append(bounded(speeds, float(acceleration[j]), torque, bounds, unbounded,
                           (derating or {}).get(name, 1.0)))
    return out


def bounded(speeds: Sequence[tuple[float, str]], acceleration: float, torque: float,
            bounds: Sequence[PathBound], unbounded: tuple[str, ...] = (),
            derating: float = 1.0) -> JointLimits:
    """One joint's limits: the files' and the rules' (`path_bounds`), met.

    `speeds`: the files' speed limits and their sources [rad/s or m/s], at least one;
    `acceleration` [rad/s^2 or m/s^2] and `torque` [N m] the motion file's; the rules'
    torque bound while moving is held to `derating` of itself [-].
    """
    speeds = list(speeds)
    static, momentary, gain = torque, math.inf, 0.0
    peak, factors, reflected = math.inf, (0.0, 0.0), 0.0
    for bound in bounds:
        if bound.kind is PathKind.SPEED:
            speeds.append((bound.limit, bound.source))
        elif bound.kind is PathKind.TORQUE:
            torque = min(torque, bound.limit * derating)
        elif bound.kind is PathKind.STATIC:
            static = min(static, bound.limit)
        elif bound.kind is PathKind.MOMENTARY:
            momentary, gain = min(momentary, bound.limit), max(gain, bound.gain)
        else:  # the motor's torque
            peak, factors, reflected = min(peak, bound.limit), bound.factors, bound.inertia
    limit, source = min(speeds)
    return JointLimits(limit, source, acceleration, torque, static, momentary, gain, peak,
                       factors, reflected, unbounded)


def path_bounds(case: PathCase) -> tuple[list[PathBound], tuple[str, ...]]:
    """Every registered rule's bounds along the path for one joint's unit (and motor).

    Returns:
        The bounds of the rules with a path form (`Rule.path_rows`), and the names of the
        per-sample rules without one: those are checked forward on the planned cycle
        (`hdselect.codesign.cyclerules`), as the rules on the whole cycle are.
    """
    bounds: list[PathBound] = []
    unbounded = []
    for rule in RULES:
        found = rule.path_rows(case)
        if found is None:
            if rule.scope is Scope.SAMPLE:
                unbounded.append(rule.name)
        else:
            bounds.extend(found)
    return bounds, tuple(unbounded)


Group = tuple[str, str | None, list[Any]]
"""Constraints of one kind on one joint: (limit, joint name or None for all, constraints)."""


def constraint_groups(piece: PathPiece, names: Sequence[str], limits: Sequence[JointLimits],
                      coefficients: Coefficients,
                      stops: Mapping[int, np.ndarray]) -> list[Group]:
    """The constraints of a piece, kinematic ones first, then each joint's torque and stop."""
    from hdselect.motion.planning.constraints import SecondOrderBounds, SpeedBound

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
        if math.isfinite(lim.motor_torque):
            groups.append(("motor torque", names[j], [
                SecondOrderBounds.two_sided(piece.gridpoints, *row,
                                            np.array([-lim.motor_torque]),
                                            np.array([lim.motor_torque]))
                for row in motor_rows(piece, lim, coefficients, j)]))
        if j in stops and np.isfinite(stops[j]).any():
            groups.append(("emergency stop", names[j], [SpeedBound(piece.gridpoints, stops[j])]))
    return groups


def motor_rows(piece: PathPiece, lim: JointLimits, coefficients: Coefficients,
               j: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The motor torque k tau + J N qdd of joint j as (a, b, c) columns, one per factor k.

    Returns:
        Per gear factor k, the coefficients of s'', s'^2 and 1, each shape (m, 1).
    """
    a, b, c, _ = coefficients
    return [(k * a[:, [j]] + lim.motor_inertia * piece.dq[:, [j]],
             k * b[:, [j]] + lim.motor_inertia * piece.ddq[:, [j]], k * c[:, [j]])
            for k in lim.motor_factors]


def flatten(groups: Sequence[Group]) -> list[Any]:
    """Every constraint of the groups, in one list."""
    return [item for _, _, items in groups for item in items]


def stop_bound(coefficients: Coefficients, j: int, limit: float,
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


def speed_cap(piece: PathPiece, limits: Sequence[JointLimits],
              stops: Mapping[int, np.ndarray]) -> np.ndarray:
    """The largest s' [1/s] the velocity and emergency-stop bounds allow at each gridpoint."""
    velocity = np.array([lim.velocity for lim in limits])
    with np.errstate(divide="ignore"):
        cap = np.min(velocity / np.abs(piece.dq), axis=1)
    for bound in stops.values():
        cap = np.minimum(cap, bound)
    return np.minimum(cap, 1e8)


def crash_rows(piece: PathPiece, limits: Sequence[JointLimits], coefficients: Coefficients,
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
    from hdselect.motion.planning.constraints import SecondOrderBounds

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


def meets(profile: Profile, piece: PathPiece, limits: Sequence[JointLimits],
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
        for j, lim in enumerate(limits):
            for ma, mb, mc in (motor_rows(piece, lim, coefficients, j)
                               if math.isfinite(lim.motor_torque) else ()):
                motor = ma[at, 0] * u + mb[at, 0] * xs + mc[at, 0]
                if np.any(np.abs(motor) > lim.motor_torque):
                    return False
    return all(np.all(x <= np.square(bound)) for bound in stops.values())


def crash_binds(piece: PathPiece, limits: Sequence[JointLimits], coefficients: Coefficients,
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


def diagnose(motion: Motion, names: Sequence[str], piece: PathPiece, groups: Sequence[Group],
             limits: Sequence[JointLimits], coefficients: Coefficients) -> PathInfeasible:
    """Which limit makes the piece infeasible, for which joint, and where.

    Args:
        motion: The motion (its file, for the message).
        names: The joint names, in the order of `limits`.
        piece: The piece without a profile.
        groups: Its constraints, as `constraint_groups` made them.
        limits: Each joint's limits.
        coefficients: The piece's a, b, c, v.
    """
    where = f"{motion.path}: the path from waypoint[{piece.first}] to waypoint[{piece.last}]"
    kinematic = groups[0][2]
    if solve_piece(piece, kinematic, where=where) is None:
        return PathInfeasible(f"{where}: the velocity and acceleration limits make it "
                              "infeasible", joint=None, limit="velocity and acceleration",
                              gravity=False)
    names = list(names)
    c = coefficients[2]
    for limit, name, items in groups[1:]:
        if solve_piece(piece, [*kinematic, *items], where=where) is not None:
            continue
        if name is None:
            raise RuntimeError("only the first constraint group is unnamed")
        j = names.index(name)
        lim = limits[j]
        bound = {"emergency stop": lim.momentary, "static": lim.static,
                 "motor torque": lim.motor_torque}.get(limit, lim.torque)
        unit = math.isfinite(lim.momentary)  # a joint with a gearhead; else limits.torque
        what = {"emergency stop": "momentary limit (emergency stop)",
                "static": "static limit" if unit else "limits.torque",
                "torque": "repeated-peak limit" if unit else "limits.torque",
                "motor torque": "motor's peak torque"}[limit]
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

    from hdselect.motion.planning.path import quiet as _quiet

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
