"""Pinocchio's model of a URDF checked against the file's own numbers, and its open limits.

`hdselect.robot.urdfxml` reads every number of the file; here the model Pinocchio
built is held against them: each joint's placement, parent, axis and limits, each
link's frame, and each moving body's inertia (the links Pinocchio merged on fixed
joints summed here the same way). A difference means Pinocchio read the file
otherwise than the format defines it, and the file is refused, naming what
differs. A revolute or prismatic joint whose ``<limit>`` gives no range (lower =
upper = 0, common in real files) gets no position limits, with a note.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.robot.checks import model_limit
from hdselect.robot.urdfxml import MOVABLE, UrdfJoint, UrdfTree, direction

TOLERANCE = 1e-9
"""Agreement asked of Pinocchio's numbers and the file's, relative to their scale [-]."""


def check_model(model: pin.Model, tree: UrdfTree, path: Path) -> None:
    """Refuse the file where Pinocchio's model differs from what the file says.

    A file with joints of other types than revolute, continuous, prismatic and fixed
    is not compared (hdselect refuses such joints when it lists the model's joints).

    Args:
        model: Pinocchio's model of the file (mimic followers coupled or not).
        tree: The file's links and joints, read by `hdselect.robot.urdfxml`.
        path: The robot file, for messages.

    Raises:
        InputError: A joint's placement, parent, axis or limits, a link's frame or a
            moving body's inertia differ (the field names the joint or link).
    """
    root = tree.root
    if root is None or any(j.kind not in (*MOVABLE, "fixed") for j in tree.joints.values()):
        return
    where: dict[str, tuple[int, pin.SE3]] = {root: (0, pin.SE3.Identity())}
    for joint in _from_root(tree, root):
        parent_id, parent_placement = where[joint.parent]
        placement = parent_placement * joint.origin
        if joint.kind == "fixed":
            where[joint.child] = (parent_id, placement)
            continue
        field = f"joint[{joint.name}]"
        if not model.existJointName(joint.name):
            raise InputError("Pinocchio's model has no such joint", path=path, field=field)
        joint_id = model.getJointId(joint.name)
        if model.parents[joint_id] != parent_id:
            raise InputError(f"Pinocchio attaches it to '{model.names[model.parents[joint_id]]}'"
                             f", the file to link '{joint.parent}'", path=path, field=field)
        _same_placement(model.jointPlacements[joint_id], placement, path, f"{field}.origin")
        _same_axis(model, joint_id, joint, path)
        _same_limits(model, joint_id, joint, path)
        where[joint.child] = (joint_id, pin.SE3.Identity())
    expected = [np.zeros((6, 6)) for _ in range(model.njoints)]
    for link, (joint_id, placement) in where.items():
        field = f"link[{link}]"
        if not model.existFrame(link, pin.FrameType.BODY):
            raise InputError("Pinocchio's model has no frame for this link", path=path,
                             field=field)
        frame = model.frames[model.getFrameId(link, pin.FrameType.BODY)]
        if frame.parentJoint != joint_id:
            raise InputError(f"Pinocchio moves it with '{model.names[frame.parentJoint]}', the "
                             f"file with '{model.names[joint_id]}'", path=path, field=field)
        _same_placement(frame.placement, placement, path, f"{field}.frame")
        inertia = tree.links.get(link)
        if inertia is not None:  # the spatial inertia seen from the joint's frame
            inverse = placement.toActionMatrixInverse()
            expected[joint_id] += inverse.T @ inertia @ inverse
    for joint_id in range(1, model.njoints):
        _same_inertia(model, joint_id, expected[joint_id], where, path)


def open_limits(model: pin.Model, tree: UrdfTree) -> list[str]:
    """Give joints whose file limits are 0 .. 0 no position limits; one note naming them.

    Args:
        model: Pinocchio's model; its position limits are changed in place.
        tree: The file's joints.

    Returns:
        The note, or nothing when no joint has limits 0 .. 0.
    """
    opened = []
    for joint in tree.joints.values():
        if not (unlimited(joint) and joint.kind != "continuous"
                and model.existJointName(joint.name)):
            continue
        pin_joint = model.joints[model.getJointId(joint.name)]
        if pin_joint.nq != 1 or pin_joint.shortname() == "JointModelMimic":
            continue
        model.lowerPositionLimit[pin_joint.idx_q] = -math.inf
        model.upperPositionLimit[pin_joint.idx_q] = math.inf
        opened.append(joint.name)
    if not opened:
        return []
    which = f"joint{'s' if len(opened) > 1 else ''} {', '.join(opened)}"
    return [f"{which}: the file's position limits are 0 .. 0 (no range given): treated as "
            "unlimited, as a continuous joint"]


def unlimited(joint: UrdfJoint) -> bool:
    """A joint without a position range: continuous, or lower = upper = 0 (none given)."""
    if joint.kind == "continuous" or joint.limit is None:
        return True
    return joint.limit.lower == 0.0 and joint.limit.upper == 0.0


def _from_root(tree: UrdfTree, root: str) -> Iterator[UrdfJoint]:
    """The joints, each after the joint carrying its parent link (breadth first)."""
    children: dict[str, list[UrdfJoint]] = {}
    for joint in tree.joints.values():
        children.setdefault(joint.parent, []).append(joint)
    queue = [root]
    seen = {root}
    while queue:
        link = queue.pop(0)
        for joint in children.get(link, []):
            if joint.child in seen:
                continue  # a loop: urdfdom refuses it itself
            seen.add(joint.child)
            queue.append(joint.child)
            yield joint


def _same_placement(theirs: pin.SE3, ours: pin.SE3, path: Path, field: str) -> None:
    scale = max(1.0, float(np.abs(ours.translation).max()))
    if (np.abs(theirs.rotation - ours.rotation).max() > TOLERANCE
            or np.abs(theirs.translation - ours.translation).max() > TOLERANCE * scale):
        raise InputError(f"Pinocchio places it at xyz {_text(theirs.translation)}, the file at "
                         f"{_text(ours.translation)} (or the rotations differ)", path=path,
                         field=field)


def _same_axis(model: pin.Model, joint_id: int, joint: UrdfJoint, path: Path) -> None:
    """The joint's motion subspace is the file's axis, normalised (angular for a rotation)."""
    pin_joint = model.joints[joint_id]
    if pin_joint.shortname() == "JointModelMimic":
        return  # the axis is the follower's own; its numbers were checked as read
    data = pin_joint.createData()
    pin_joint.calc(data, pin.neutral(model))
    subspace = np.array(data.S).ravel()
    axis = subspace[:3] if joint.kind == "prismatic" else subspace[3:]
    ours = direction(joint.axis)
    if ours is None:
        raise RuntimeError(f"joint {joint.name}: a zero axis passed the reader")
    if np.abs(axis - ours).max() > TOLERANCE:
        raise InputError(f"Pinocchio's axis is {_text(axis)}, the file's {_text(joint.axis)}",
                         path=path, field=f"joint[{joint.name}].axis")


def _same_limits(model: pin.Model, joint_id: int, joint: UrdfJoint, path: Path) -> None:
    pin_joint = model.joints[joint_id]
    if joint.limit is None or pin_joint.shortname() == "JointModelMimic":
        return
    values = [("effort", model_limit(model, "upperEffortLimit", "effortLimit")[pin_joint.idx_v],
               joint.limit.effort),
              ("velocity", model_limit(model, "upperVelocityLimit",
                                       "velocityLimit")[pin_joint.idx_v], joint.limit.velocity)]
    if joint.kind != "continuous":
        values += [("lower", model.lowerPositionLimit[pin_joint.idx_q], joint.limit.lower),
                   ("upper", model.upperPositionLimit[pin_joint.idx_q], joint.limit.upper)]
    for name, theirs, ours in values:
        if abs(float(theirs) - ours) > TOLERANCE * max(1.0, abs(ours)):
            raise InputError(f"Pinocchio reads {float(theirs):g}, the file says {ours:g}",
                             path=path, field=f"joint[{joint.name}].limit.{name}")


def _same_inertia(model: pin.Model, joint_id: int, ours: np.ndarray,
                  where: dict[str, tuple[int, pin.SE3]], path: Path) -> None:
    theirs = model.inertias[joint_id].matrix()
    if np.abs(theirs - ours).max() <= TOLERANCE * max(float(np.abs(ours).max()), 1e-12):
        return
    links = [link for link, (j, _) in where.items() if j == joint_id]
    raise InputError(f"Pinocchio's body moved by joint '{model.names[joint_id]}' has mass "
                     f"{float(model.inertias[joint_id].mass):g} kg, the file's links "
                     f"({', '.join(links)}) {float(ours[0, 0]):g} kg (or their centre of "
                     "mass or inertia differ)", path=path, field=f"link[{links[0]}].inertial"
                     if links else f"joint[{model.names[joint_id]}]")


def _text(values: np.ndarray) -> str:
    return " ".join(f"{x:.6g}" for x in values)
