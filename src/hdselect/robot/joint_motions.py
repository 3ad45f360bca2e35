"""How each joint of a robot moves, read from its Pinocchio model for the wrench pass.

A joint here is one rotation about, or one slide along, a constant axis of its
frame, driven by one coordinate: its own, or its leader's for a mimic follower.
That is every joint `hdselect.robot.model.load_robot` accepts (revolute, aligned
or not, bounded or continuous; prismatic; mimic followers of a single-coordinate
leader).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError

_ANGLE = ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned")
_UNBOUNDED = ("JointModelRUBX", "JointModelRUBY", "JointModelRUBZ",
              "JointModelRevoluteUnboundedUnaligned")
_SLIDE = ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned")
_MIMIC = "JointModelMimic"


@dataclass(frozen=True)
class JointMotion:
    """How one joint moves in its own frame.

    The joint's coordinate is ``scaling * x + offset`` [rad or m], x the driving
    coordinate: the joint's own (scaling 1, offset 0) or its mimic leader's.

    Attributes:
        name: Joint name.
        revolute: A rotation about `axis` (else a slide along it).
        axis: Unit axis in the joint frame, read-only, shape (3,).
        q_index: Row of the driving coordinate in Pinocchio's configuration.
        v_index: Row of the driving velocity in Pinocchio's velocity.
        unbounded: The driving coordinate is a (cos, sin) pair (a continuous joint).
        scaling: Mimic multiplier [-]; 1 for a joint of its own.
        offset: Mimic offset [rad or m]; 0 for a joint of its own.
    """

    name: str
    revolute: bool
    axis: np.ndarray
    q_index: int
    v_index: int
    unbounded: bool
    scaling: float = 1.0
    offset: float = 0.0

    def coordinate(self, q: np.ndarray) -> np.ndarray:
        """The joint's angle [rad] or slide [m] per sample, from configurations (nq, k)."""
        if self.unbounded:
            theta = np.arctan2(q[self.q_index + 1], q[self.q_index])
        else:
            theta = q[self.q_index]
        if self.scaling != 1.0 or self.offset != 0.0:
            theta = self.scaling * theta + self.offset
        return theta


def joint_motions(model: pin.Model, path: Path | None = None) -> tuple[JointMotion, ...]:
    """Every joint of a fixed-base model (the universe left out), in the model's order.

    Args:
        model: The Pinocchio model.
        path: The robot file, for messages.

    Returns:
        One `JointMotion` per joint, mimic followers included.

    Raises:
        InputError: A joint is of another kind (a floating base, a spherical joint),
            or a mimic follower's leader is a continuous joint.
    """
    leaders = {int(f): int(leader) for f, leader in zip(model.mimicking_joints,
                                                        model.mimicked_joints, strict=True)}
    neutral = pin.neutral(model)
    return tuple(_motion(model, i, leaders, neutral, path) for i in range(1, model.njoints))


def _motion(model: pin.Model, i: int, leaders: dict[int, int], neutral: np.ndarray,
            path: Path | None) -> JointMotion:
    """Joint i's kind, axis and driving coordinate."""
    joint, name = model.joints[i], model.names[i]
    kind = joint.shortname()
    if kind == _MIMIC:
        mimic = joint.extract()
        leader = leaders.get(i)
        scaling = float(mimic.scaling)
        if leader is None or model.joints[leader].nq != 1 or scaling == 0.0:
            raise InputError(f"joint '{name}' is a mimic follower with multiplier {scaling:g} "
                             "of a joint that is not one revolute or prismatic coordinate; "
                             "the joint loads need a non-zero multiplier of such a joint",
                             path=path, field=f"joint[{name}]")
        axis, revolute = _axis(model, i, neutral, scaling, path)
        return JointMotion(name, revolute, axis, model.joints[leader].idx_q,
                           model.joints[leader].idx_v, False, scaling, float(mimic.offset))
    if kind not in _ANGLE + _UNBOUNDED + _SLIDE:
        raise InputError(f"joint '{name}' is a {kind}; the joint loads handle fixed-base "
                         "trees of revolute, continuous, prismatic and mimic joints",
                         path=path, field=f"joint[{name}]")
    axis, revolute = _axis(model, i, neutral, 1.0, path)
    return JointMotion(name, revolute, axis, joint.idx_q, joint.idx_v, kind in _UNBOUNDED)


def _axis(model: pin.Model, i: int, neutral: np.ndarray, scaling: float,
          path: Path | None) -> tuple[np.ndarray, bool]:
    """Joint i's unit axis and whether it rotates, from its motion subspace S at `neutral`.

    Raises:
        InputError: Pinocchio's model moves the joint along no axis (an axis written so
            long that normalising it overflowed).
    """
    joint = model.joints[i]
    data = joint.createData()
    joint.calc(data, neutral)
    subspace = np.asarray(data.S).ravel() / scaling  # a follower's S carries its multiplier
    if not np.all(np.isfinite(subspace)) or not np.any(subspace):
        raise InputError(f"joint '{model.names[i]}': Pinocchio reads its axis as zero; write "
                         "a unit axis", path=path, field=f"joint[{model.names[i]}].axis")
    linear, angular = subspace[:3], subspace[3:]
    revolute = bool(np.any(angular))
    axis = angular if revolute else linear
    axis = axis / np.abs(axis).max()  # first to 1 at most: an axis written 1e308 long
    axis /= np.linalg.norm(axis)
    axis.setflags(write=False)
    return axis, revolute
