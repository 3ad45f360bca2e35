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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.motion.kinematics import FrameKinematics

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
    joints = [j for j in range(1, model.njoints) if model.joints[j].nv == 1]
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
    scale = float(np.linalg.norm(upper) * np.linalg.norm(fore)) or 1.0
    return float(axis @ np.cross(upper, fore)) / scale


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
