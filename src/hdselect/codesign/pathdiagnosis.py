"""Why TOPPRA finds no profile along a piece of the path: the joint, the limit and where.

`hdselect.codesign.fastpath` calls `diagnose` where a piece has no profile under the
limits of `hdselect.codesign.pathbounds`: it names the first constraint group that makes
it infeasible, the joint and the rule whose bound it is (the repeated peak, or a
precision target's torque), and whether gravity alone is over it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from hdselect.catalog.rules import rule
from hdselect.codesign.pathbounds import Coefficients, Group, JointLimits, PathInfeasible
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.toppra import PathPiece, solve_piece

_WORDS = {"peak": "repeated-peak limit", "static": "static limit"}
"""A torque bound in a message, by the rule whose it is (others: `_words`)."""


def _words(by: str) -> str:
    """A joint's torque bound in words: its rule's, else the motion file's limits.torque."""
    if not by:
        return "limits.torque"
    return _WORDS.get(by, f"torque limit of its {rule(by).words} target")


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
        what = {"emergency stop": "momentary limit (emergency stop)",
                "static": _words(lim.static_by),
                "torque": _words(lim.torque_by),
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
