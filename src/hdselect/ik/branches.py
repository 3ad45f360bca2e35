"""Whether the joint move between two solved waypoints changes the arm's branch.

An arm reaches most poses in several ways (elbow up or down, wrist flipped, facing
front or back). Consecutive waypoints solved on different branches make the arm
reconfigure between them: a large joint move through a singularity that the tool motion
does not need, and a different task from the one written. `check_branch` flags the
joint-space move q_from -> q_to (the path the planner interpolates) by three criteria:

1. An indicator changes sign along the move (33 points). For 6 joints,
   det J = shoulder x elbow x wrist up to a positive factor on UR-type and
   spherical-wrist arms:

   - ``wrist``: det[w4 w5 w6] of the last three joint axes (0 where axes 4 and 6 align);
   - ``elbow``: z3 . ((p3 - p2) x (p4 - p3)) / (|p3 - p2| |p4 - p3|), p_k the origin of
     joint k and z3 the elbow axis: the sine of the angle between upper arm and forearm
     (0 stretched or folded);
   - ``shoulder``: sign(det J) wrist elbow (0 with the wrist over the base axis).

   A 2-joint arm has ``elbow`` from its two joints and the frame. Other arms (a
   redundant 7-joint arm has no discrete branches) rely on criteria 2 and 3.
2. The move passes a singularity: the scaled smallest singular value of the Jacobian
   (`FrameKinematics.sigma_min`) drops below `SINGULAR`.
3. A jump: the largest joint move exceeds 3 times the move the tool's displacement
   needs to first order (|J+ dx| at q_from) plus 0.5 rad or m: a reconfiguration
   without a singularity on the way, such as a 2 pi turn of a wrist.

The planner does not follow the straight joint move: `path_crossing` finds where a
planned path, sampled, passes a singularity by criteria 1 and 2, at a resolution of a
fraction of a degree (`PATH_STEP`, refined near every singularity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.robot.kinematics import FrameKinematics

SINGULAR = 1e-3
"""A scaled smallest singular value below this is a singularity [rad/rad]."""
JUMP_RATIO, JUMP_SLACK = 3.0, 0.5
"""A joint move above JUMP_RATIO times the first-order estimate plus JUMP_SLACK [rad or m]
is a jump."""
_ALONG = 33
"""Points of the joint-space move at which the indicators are evaluated."""


@dataclass(frozen=True)
class BranchCheck:
    """How the joint move between two solutions relates to the arm's branches.

    Attributes:
        flipped: A criterion fired: the move changes branch or reconfigures.
        changed: The indicators whose sign changes on the move, e.g. ``("elbow",)``.
        min_sigma: Smallest scaled singular value along the move [rad/rad].
        joint_move: Largest joint move [rad or m].
        needed_move: The joint move the tool's displacement needs, to first order.
        reasons: One phrase per criterion that fired.
    """

    flipped: bool
    changed: tuple[str, ...]
    min_sigma: float
    joint_move: float
    needed_move: float
    reasons: tuple[str, ...]


def indicators(kin: FrameKinematics, q: np.ndarray) -> dict[str, float]:
    """The branch indicators at `q` (values, not signs; see the module's doc)."""
    return _evaluate(kin, q)[1]


def _evaluate(kin: FrameKinematics, q: np.ndarray) -> tuple[np.ndarray, dict[str, float]]:
    """The base-aligned Jacobian at `q` (forward kinematics updated) and the indicators."""
    model, data = kin.model, kin.data
    jacobian = kin.jacobian(q, aligned=True)
    values: dict[str, float] = {}
    if jacobian.shape[1] not in (2, 6):
        return jacobian, values
    joints = [j for j, nv in enumerate(model.nvs) if j and nv == 1]
    if jacobian.shape[1] == 6 and len(joints) == 6:
        origin = [data.oMi[j].translation for j in joints]
        values["det"] = float(np.linalg.det(jacobian))
        values["wrist"] = float(np.linalg.det(jacobian[3:, 3:]))
        values["elbow"] = _sine(jacobian[3:, 2], origin[2] - origin[1], origin[3] - origin[2])
        values["shoulder"] = values["det"] * values["wrist"] * values["elbow"]
    elif jacobian.shape[1] == 2 and len(joints) == 2:
        origin = [data.oMi[j].translation for j in joints]
        tip = data.oMf[kin.frame_id].translation
        values["elbow"] = _sine(jacobian[3:, 1], origin[1] - origin[0], tip - origin[1])
    return jacobian, values


def _sine(axis: np.ndarray, upper: np.ndarray, fore: np.ndarray) -> float:
    """The sine of the elbow angle, axis . (upper x fore) / (|upper| |fore|) [-]."""
    (u0, u1, u2), (f0, f1, f2) = upper.tolist(), fore.tolist()  # no np.cross: it is slow
    cross = (u1 * f2 - u2 * f1, u2 * f0 - u0 * f2, u0 * f1 - u1 * f0)
    scale = math.hypot(u0, u1, u2) * math.hypot(f0, f1, f2) or 1.0
    return sum(a * c for a, c in zip(axis.tolist(), cross, strict=True)) / scale


def singularity_kind(kin: FrameKinematics, q: np.ndarray, sigma: float) -> str:
    """Name the singularity a 6-joint or 2-joint arm is at or near.

    Args:
        kin: The frame.
        q: Joint positions [rad or m].
        sigma: The scaled smallest singular value at `q` [rad/rad].

    Returns:
        ``"wrist"`` (axes 4 and 6 aligned), ``"elbow"`` (stretched or folded),
        ``"shoulder"`` (wrist over the base axis) or ``""``.
    """
    values = indicators(kin, q)
    wrist, elbow = abs(values.get("wrist", np.inf)), abs(values.get("elbow", np.inf))
    if wrist < 0.2 and wrist <= elbow:
        return "wrist"
    if elbow < 0.2:
        return "elbow"
    return "shoulder" if "shoulder" in values and sigma < 0.01 else ""


SINGULARITY_NAMES = {"wrist": "a wrist singularity (axes 4 and 6 aligned)",
                     "elbow": "an elbow singularity (arm stretched or folded)",
                     "shoulder": "a shoulder singularity (wrist over the base axis)",
                     "": "a singularity"}
"""How messages name each kind of `singularity_kind`."""


def check_branch(kin: FrameKinematics, q_from: np.ndarray, q_to: np.ndarray) -> BranchCheck:
    """Whether the joint-space move `q_from` -> `q_to` [rad or m] changes the arm's branch."""
    signs, sigma = [], np.inf
    for fraction in np.linspace(0.0, 1.0, _ALONG):
        jacobian, values = _evaluate(kin, (1.0 - fraction) * q_from + fraction * q_to)
        signs.append({name: int(np.sign(value)) for name, value in values.items()})
        jacobian[:3] /= kin.length
        sigma = min(sigma, float(np.linalg.svd(jacobian, compute_uv=False)[-1]))
    first = signs[0]
    changed = tuple(name for name in first if name != "det"
                    and any(s[name] != first[name] for s in signs[1:]))
    reasons = []
    if changed or any(s.get("det") != first.get("det") for s in signs[1:]):
        reasons.append(f"the {', '.join(changed) or 'Jacobian determinant'} "
                       f"{'indicators change' if len(changed) > 1 else 'indicator changes'} "
                       "sign")
    if sigma < SINGULAR:
        reasons.append(f"the move passes a singularity (scaled smallest singular value "
                       f"{sigma:.1e})")
    move = float(np.abs(q_to - q_from).max(initial=0.0))
    needed = _needed_move(kin, q_from, q_to)
    if move > JUMP_RATIO * needed + JUMP_SLACK:
        reasons.append(f"a joint moves {move:.2f} rad or m where the tool's move needs about "
                       f"{needed:.2f}")
    return BranchCheck(bool(reasons), changed, float(sigma), move, needed, tuple(reasons))


def _needed_move(kin: FrameKinematics, q_from: np.ndarray, q_to: np.ndarray) -> float:
    """The first-order move, max |J+ log6(T_from^-1 T_to)| at `q_from` [rad or m]."""
    twist = pin.log6(kin.placement(q_from).actInv(kin.placement(q_to))).vector
    jacobian = kin.jacobian(q_from)
    rows = jacobian.shape[0]
    step = jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + 1e-8 * np.eye(rows), twist)
    return float(np.abs(step).max(initial=0.0))


TURN_SLACK = 1e-3
"""Two configurations whose joints differ by whole turns within this [rad or m] are one
configuration turned."""


def whole_turns(kin: FrameKinematics, q_from: np.ndarray, q_to: np.ndarray) -> np.ndarray:
    """The whole turns [-] by which each joint of `q_to` differs from `q_from`.

    Zeros unless the two differ by whole turns of revolute joints alone (within
    `TURN_SLACK`); a joint of unbounded range (continuous) counts none: it may go on
    turning, where a bounded one has to turn back.

    Returns:
        Integer turns per joint, shape (dof,).
    """
    delta = np.asarray(q_to, dtype=float) - np.asarray(q_from, dtype=float)
    revolute = np.asarray(kin.robot.revolute, dtype=bool)
    turns = np.where(revolute, np.round(delta / (2.0 * np.pi)), 0.0)
    if np.abs(delta - 2.0 * np.pi * turns).max(initial=0.0) > TURN_SLACK:
        return np.zeros(len(delta), dtype=int)
    bounded = np.isfinite(kin.lower) & np.isfinite(kin.upper)
    return np.where(bounded, turns, 0.0).astype(int)


PATH_STEP = 0.005
"""Largest joint move [rad or m] between two points at which `path_crossing` evaluates a
path; it evaluates `FINE` times as densely where the path comes near a singularity."""
NEAR = 0.02
"""A local minimum of the scaled smallest singular value below this, at the `PATH_STEP`
points, is looked at `FINE` times as densely [rad/rad]: between two points the value
changes by at most a few times PATH_STEP."""
FINE = 16
"""Points per `PATH_STEP` where a path comes near a singularity [-]."""


@dataclass(frozen=True)
class PathCrossing:
    """Where a sampled joint path first passes a singularity.

    Attributes:
        position: Where along the samples: k + f is the fraction f of the straight move from
            sample k to sample k + 1 [-].
        q: The joint positions there [rad or m].
        sigma: The scaled smallest singular value there [rad/rad].
        changed: The indicators whose sign changes there (``"det"`` for the Jacobian's
            determinant); empty when the path only comes within `SINGULAR` of a singularity.
        kind: The singularity, as `singularity_kind` names it.
    """

    position: float
    q: np.ndarray
    sigma: float
    changed: tuple[str, ...]
    kind: str


def path_crossing(kin: FrameKinematics, q: np.ndarray) -> PathCrossing | None:
    """The first place a sampled joint path passes a singularity, or None.

    The path runs straight in joint space between samples. It passes a singularity where
    the scaled smallest singular value (`FrameKinematics.sigma_min`) drops below
    `SINGULAR`, or where a branch indicator changes sign (`check_branch`'s criteria 1
    and 2). The path is evaluated every `PATH_STEP` of joint move; around every local
    minimum below `NEAR`, and between two points whose indicators differ in sign, every
    `PATH_STEP / FINE`; a change of sign is then located by bisection.

    Args:
        kin: The frame.
        q: The samples [rad or m], shape (n, dof), n >= 1.

    Returns:
        The first crossing along the path, or None.
    """
    q = np.asarray(q, dtype=float)
    steps = np.abs(np.diff(q, axis=0)).max(axis=1, initial=0.0) if len(q) > 1 else np.zeros(0)
    travelled = np.r_[0.0, np.cumsum(steps)]
    moving = np.r_[True, steps > 0.0]  # np.interp needs increasing abscissae
    along = np.r_[np.arange(0.0, travelled[-1], PATH_STEP), travelled[-1]]
    coarse = np.interp(along, travelled[moving], np.flatnonzero(moving).astype(float))
    points = [_Point.at(kin, q, s) for s in np.unique(coarse)]
    for k, point in enumerate(points):
        before, after = points[max(k - 1, 0)], points[min(k + 1, len(points) - 1)]
        found = None
        if point.sigma < NEAR and point.sigma <= min(before.sigma, after.sigma):
            found = _fine(kin, q, before, after)  # a dip: look closely on both sides
        if found is None and point.signs != after.signs:
            found = _fine(kin, q, point, after)
        if found is not None:
            return found
    return None


@dataclass(frozen=True)
class _Point:
    """A point of a sampled path: its position, joints, scaled sigma and indicator signs."""

    position: float
    q: np.ndarray
    sigma: float
    signs: dict[str, int]

    @staticmethod
    def at(kin: FrameKinematics, q: np.ndarray, position: float) -> _Point:
        k = min(int(position), len(q) - 1)
        here = q[k] + (position - k) * (q[min(k + 1, len(q) - 1)] - q[k])
        jacobian, values = _evaluate(kin, here)
        jacobian[:3] /= kin.length
        sigma = float(np.linalg.svd(jacobian, compute_uv=False)[-1])
        return _Point(position, here, sigma, {n: int(np.sign(v)) for n, v in values.items()})


def _fine(kin: FrameKinematics, q: np.ndarray, first: _Point, last: _Point
          ) -> PathCrossing | None:
    """The first crossing between two points of a path, looked at `FINE` times as densely."""
    points = [first] + [_Point.at(kin, q, s) for s in np.linspace(
        first.position, last.position, 2 * FINE + 1)[1:-1]] + [last]  # at most 2 PATH_STEPs
    for left, right in zip(points[:-1], points[1:], strict=True):
        if left.sigma < SINGULAR:
            return _crossing(kin, left, ())
        if left.signs != right.signs:
            for _ in range(30):  # bisection on where the signs change
                middle = _Point.at(kin, q, 0.5 * (left.position + right.position))
                left, right = (middle, right) if middle.signs == left.signs else (left, middle)
            changed = tuple(n for n in right.signs if right.signs[n] != left.signs.get(n))
            return _crossing(kin, left if left.sigma < right.sigma else right, changed)
    return _crossing(kin, last, ()) if last.sigma < SINGULAR else None


def _crossing(kin: FrameKinematics, point: _Point, changed: tuple[str, ...]) -> PathCrossing:
    kind = singularity_kind(kin, point.q, point.sigma)
    if not kind and "elbow" in changed:
        kind = "elbow"
    return PathCrossing(point.position, point.q, point.sigma, changed, kind)
