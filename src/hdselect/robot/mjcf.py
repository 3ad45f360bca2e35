"""Build a Pinocchio model from an MJCF file the way MuJoCo reads it.

MuJoCo's own compiler (`mujoco.MjModel.from_xml_path`) reads the file, so
``<default>`` classes, ``<include>``, inertias derived from geoms (also geoms with
``contype="0" conaffinity="0"``), ``<compiler angle=...>``, ``fusestatic``,
``fromto`` and the rest mean what they mean in MuJoCo. The Pinocchio model is
then built from MuJoCo's compiled bodies and joints (``body_pos``/``body_quat``,
``body_mass``/``body_ipos``/``body_iquat``/``body_inertia``, ``jnt_*``,
``qpos0``, ``opt.gravity``), so that its kinematics and rigid-body dynamics equal
MuJoCo's:

- A hinge is a revolute joint, a slide a prismatic one, about (along) MuJoCo's
  normalised axis, through the joint's anchor ``jnt_pos``. The Pinocchio
  coordinate equals MuJoCo's ``qpos`` (same numbers, same ranges): a joint's
  ``ref`` (``qpos0``) is built into the joint placement as a fixed rotation
  (translation) by ``-ref`` about (along) the axis.
- A body holding several joints becomes a chain of joints with massless
  intermediate bodies, each joint about its own anchor and axis in order, exactly
  as ``mj_kinematics`` composes them (a note names such bodies). Each joint then
  carries the torque about its own axis that MuJoCo's inverse dynamics gives it:
  sizing it is as meaningful as sizing a URDF joint whose child link is massless.
- Unlimited joints get position limits of -inf/+inf, as Pinocchio's own MJCF reader
  gives them; MuJoCo has no per-joint velocity or effort limit: both are +inf.
- MuJoCo bodies are BODY frames, named sites are OP_FRAME frames. MuJoCo's
  ``qpos0`` (the pose the file draws) and its keyframes are reference
  configurations of the model (``model.referenceConfigurations["qpos0"]``);
  ``pin.neutral`` (all zeros) is not the file's pose when a joint has a ``ref``.
- A free joint (MuJoCo allows one only on a body on the world) is held fixed at
  the file's pose; a ball joint in a kept tree is refused.

Armature, damping, friction loss, springs, actuators, tendons, contacts, fluid
forces and gravity compensation are MuJoCo's model of the motor and the world, not
load on the gear output: they are left out and each kind present gets one note.
"""

from __future__ import annotations

import math
import re
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.robot.mjcf_notes import (
    BALL,
    FREE,
    HINGE,
    SLIDE,
    JointCoupling,
    body_label,
    couplings,
    joint_label,
    joints,
    listed,
    mj_name,
    set_aside,
)

_LOCK = threading.Lock()
UNLIMITED = math.inf
"""Position bound of a joint without range, and every velocity and effort bound [rad, m, ...]."""


@dataclass(frozen=True, eq=False)
class MjcfRead:
    """What an MJCF file holds, as hdselect uses it.

    Attributes:
        model: Pinocchio model of the kept kinematic tree(s); gravity is MuJoCo's [m/s^2].
        root_body: The body held fixed to the world; ``"world"`` when several trees are kept
            or the tree's top body itself turns or slides.
        couplings: Active linear joint couplings by follower name (the model leaves
            both joints independent; `hdselect.robot.reading` makes the followers mimic).
        notes: What was assumed or left out that changes the torques, one line each.
        set_aside: MuJoCo's models of the motor and the world left out (armature,
            damping, friction loss, springs, actuators, tendons, contacts), one line each.
        qpos_index: MuJoCo ``qpos`` address of each Pinocchio configuration entry, shape (nq,).
        dof_index: MuJoCo dof address of each Pinocchio velocity entry, shape (nv,).
    """

    model: pin.Model
    root_body: str
    couplings: Mapping[str, JointCoupling]
    notes: tuple[str, ...]
    set_aside: tuple[str, ...]
    qpos_index: np.ndarray
    dof_index: np.ndarray


def model_from_mjcf(path: str | PathLike[str]) -> MjcfRead:
    """Compile an MJCF file with MuJoCo and build the Pinocchio model of its robot.

    Args:
        path: The MJCF file (includes and meshes resolved as MuJoCo resolves them).

    Returns:
        The model, its root body, joint couplings, notes and the qpos/dof mapping.

    Raises:
        InputError: MuJoCo's compiler rejects the file, no tree has a hinge or slide
            joint, or a kept tree holds a ball joint.
    """
    path = Path(path)
    mj, warnings, notes = _compile(path)
    notes += [f"MuJoCo's compiler warns: {w}" for w in warnings]
    kept, tree_notes = _kept_trees(mj, path)
    notes += tree_notes
    held = _check_joints(mj, kept, path)
    notes += [f"the free joint of body '{body_label(mj, b)}' is held fixed: hdselect sizes "
              "a fixed-base arm" for b in held]
    notes += [f"mocap body '{body_label(mj, b)}' is held at its pose in the file"
              for b in kept if mj.body_mocapid[b] >= 0]
    model, qpos_index, dof_index, unnamed = _build(mj, kept, path.stem)
    for k in range(mj.nkey):
        key = mj_name(mj, mujoco.mjtObj.mjOBJ_KEY, k) or f"key_{k}"
        model.referenceConfigurations[key] = np.array(mj.key_qpos[k, qpos_index])
    model.referenceConfigurations["qpos0"] = np.array(mj.qpos0[qpos_index])
    several = [b for b in kept
               if sum(int(mj.jnt_type[j]) in (HINGE, SLIDE) for j in joints(mj, b)) > 1]
    if several:
        held_joints = []
        for b in several:
            names = ", ".join(joint_label(mj, j) for j in joints(mj, b))
            held_joints.append(f"{body_label(mj, b)} ({names})")
        notes.append("bodies holding several joints, built as MuJoCo composes them (a chain "
                     "through massless frames; each joint sized on its own): "
                     + listed(held_joints))
    if unnamed:
        notes.append(f"{len(unnamed)} unnamed joint{'s' if len(unnamed) > 1 else ''} named "
                     f"here: {listed(unnamed)}")
    coupled, eq_notes = couplings(mj, model)
    notes += eq_notes
    roots = sorted({int(mj.body_rootid[b]) for b in kept})
    turns = len(roots) > 1 or any(int(mj.jnt_type[j]) in (HINGE, SLIDE)
                                  for j in joints(mj, roots[0]))
    root = "world" if turns else body_label(mj, roots[0])
    for array in (qpos_index, dof_index):
        array.setflags(write=False)
    return MjcfRead(model, root, coupled, tuple(notes), tuple(set_aside(mj, kept)), qpos_index,
                    dof_index)


def _compile(path: Path) -> tuple[mujoco.MjModel, list[str], list[str]]:
    """MuJoCo's compiled model of `path`, the warnings its compiler gave, and notes.

    A file whose mesh files are missing is compiled without the geoms using them when
    no body's mass comes from those meshes (`_without_missing_meshes`). MuJoCo's
    warning hook is process-wide: it is set for the compile and restored after, one
    compile at a time.
    """
    warnings: list[str] = []
    notes: list[str] = []
    with _LOCK:
        previous = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(lambda text: warnings.append(" ".join(str(text).split())))
        try:
            mj = mujoco.MjModel.from_xml_path(str(path))
        except ValueError as err:
            mj, notes = _without_missing_meshes(path, _refused(path, err))
        finally:
            mujoco.set_mju_user_warning(previous)
    return mj, warnings, notes


def _without_missing_meshes(path: Path, refused: InputError) -> tuple[mujoco.MjModel, list[str]]:
    """The file compiled without its mesh geoms whose files are missing, and the note saying so.

    A mesh geom adds its mass to its body where MuJoCo takes the body's inertia from
    its geoms (``<compiler inertiafromgeom="true">``, or ``"auto"`` and the body has
    no ``<inertial>``) and the geom's group is in ``inertiagrouprange``; elsewhere it
    is drawing and contact only, which the dynamics do not use.

    Raises:
        InputError: `refused` when no mesh file is missing (or the file does not parse);
            else, when a body's mass comes from a missing mesh, naming the body and mesh.
    """
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except ValueError:
        raise refused from None
    folder = Path(spec.meshdir)
    missing = {mesh.name: folder / mesh.file for mesh in spec.meshes
               if mesh.file and not (path.parent / folder / mesh.file).is_file()}
    if not missing:
        raise refused
    geoms = [g for g in spec.geoms if g.type == mujoco.mjtGeom.mjGEOM_MESH
             and g.meshname in missing]
    low, high = spec.compiler.inertiagrouprange
    from_geoms = spec.compiler.inertiafromgeom
    for geom in geoms:
        body = geom.parent
        if body.name != "world" and low <= geom.group <= high and (
                from_geoms == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
                or (from_geoms == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_AUTO
                    and not body.explicitinertial)):
            label = f"body '{body.name}'" if body.name else "an unnamed body"
            fix = ("or give the body an <inertial>" if not body.explicitinertial else
                   "or, to use the bodies' own <inertial>, drop the compiler's "
                   "inertiafromgeom=\"true\" (it takes every body's inertia from its geoms)")
            raise InputError(f"{label} takes its mass and inertia from mesh "
                             f"'{geom.meshname}', whose file {missing[geom.meshname]} is not "
                             f"found: put the mesh files where the file names them, {fix}",
                             path=path)
    for geom in geoms:
        spec.delete(geom)
    for mesh in [m for m in spec.meshes if m.name in missing]:
        spec.delete(mesh)
    try:
        mj = spec.compile()
    except ValueError as err:  # another reason, now that the meshes are not read
        raise _refused(path, err) from err
    files = listed(sorted({str(file) for file in missing.values()}))
    return mj, [f"mesh files not found ({files}): the {len(geoms)} geoms drawing them are left "
                "out; no body takes its mass from them (each gives its <inertial>), so the "
                "dynamics do not need them"]


def _refused(path: Path, err: ValueError) -> InputError:
    """MuJoCo's compiler's refusal of the file, one line."""
    return InputError(f"not a valid MJCF robot (MuJoCo's compiler): {_one_line(str(err))}",
                      path=path)


def _one_line(message: str) -> str:
    """MuJoCo's compiler message on one line: the reason, then where (element, line)."""
    lines = [line.strip() for line in message.strip().splitlines() if line.strip()]
    lines = [re.sub(r"^((XML Error|Error|ParseXML):\s*)+", "", line) for line in lines]
    lines = [re.sub(r"^Error=XML_ERROR_(\w+) ErrorID=\d+ \(0x[0-9a-f]+\) ",
                    lambda m: m.group(1).lower().replace("_", " ") + " ", line) for line in lines]
    head, where = lines[0] if lines else "no reason given", lines[1:]
    return f"{head} ({'; '.join(w[0].lower() + w[1:] for w in where)})" if where else head


def _actuated_bodies(mj: mujoco.MjModel) -> set[int]:
    """Bodies an actuator acts on directly (joint, site, body) or through a tendon."""
    trn = mujoco.mjtTrn
    bodies: set[int] = set()
    for u in range(mj.nu):
        kind, target = int(mj.actuator_trntype[u]), int(mj.actuator_trnid[u, 0])
        if kind in (trn.mjTRN_JOINT, trn.mjTRN_JOINTINPARENT):
            bodies.add(int(mj.jnt_bodyid[target]))
        elif kind in (trn.mjTRN_SITE, trn.mjTRN_SLIDERCRANK):
            bodies.add(int(mj.site_bodyid[target]))
        elif kind == trn.mjTRN_BODY:
            bodies.add(target)
        elif kind == trn.mjTRN_TENDON:
            for w in range(mj.tendon_adr[target], mj.tendon_adr[target] + mj.tendon_num[target]):
                obj, wrap = int(mj.wrap_objid[w]), int(mj.wrap_type[w])
                if wrap == mujoco.mjtWrap.mjWRAP_JOINT:
                    bodies.add(int(mj.jnt_bodyid[obj]))
                elif wrap == mujoco.mjtWrap.mjWRAP_SITE:
                    bodies.add(int(mj.site_bodyid[obj]))
    return bodies


def _kept_trees(mj: mujoco.MjModel, path: Path) -> tuple[list[int], list[str]]:
    """The bodies of the trees under the world to build, and notes on those left out.

    A tree is kept if it has a hinge or slide joint. When several do, the actuated
    ones are kept (all of them when none is actuated).
    """
    trees: dict[int, list[int]] = {}
    for b in range(1, mj.nbody):
        trees.setdefault(int(mj.body_rootid[b]), []).append(b)
    moving = {root: bodies for root, bodies in trees.items()
              if any(int(mj.jnt_type[j]) in (HINGE, SLIDE)
                     for b in bodies for j in joints(mj, b))}
    if not moving:
        kinds = sorted({mujoco.mjtJoint(int(t)).name[6:].lower() for t in mj.jnt_type})
        has = f"its only joints are {', '.join(kinds)} joints" if kinds else "it has no joint"
        raise InputError(f"no hinge or slide joint to size: {has}", path=path)
    actuated_bodies = _actuated_bodies(mj)
    actuated = [r for r, bodies in moving.items() if actuated_bodies.intersection(bodies)]
    keep = actuated if len(moving) > 1 and actuated else list(moving)
    notes = []
    if len(keep) > 1:
        which = "carry actuated joints" if actuated else "have hinge or slide joints, none actuated"
        notes.append(f"{len(keep)} kinematic trees {which} "
                     f"({', '.join(body_label(mj, r) for r in keep)}): all are kept, each fixed "
                     "to the world on its own")
    left_moving = [r for r in moving if r not in keep]
    if left_moving:
        notes.append("trees with hinge or slide joints but no actuator are left out: "
                     + listed(body_label(mj, r) for r in left_moving))
    loose = [r for r, bodies in trees.items()
             if r not in moving and any(mj.body_jntnum[b] for b in bodies)]
    if loose:
        notes.append("trees whose only joints are free or ball joints are left out (loose "
                     "objects, not robot links): " + listed(body_label(mj, r) for r in loose))
    static = [r for r in trees if r not in moving and r not in loose]
    if static:
        notes.append("bodies fixed to the world without joints are left out (scenery): "
                     + listed(body_label(mj, r) for r in static))
    return [b for r in sorted(keep) for b in trees[r]], notes


def _check_joints(mj: mujoco.MjModel, kept: list[int], path: Path) -> list[int]:
    """Refuse ball joints and ranges upside down; the root bodies whose free joint is held fixed.

    MuJoCo's compiler allows a free joint only as the one joint of a body on the world.
    """
    held = []
    for b in kept:
        for j in joints(mj, b):
            if int(mj.jnt_type[j]) == BALL:
                joint = joint_label(mj, j)
                raise InputError(f"body '{body_label(mj, b)}' holds the ball joint '{joint}': "
                                 "hdselect sizes hinge and slide joints only", path=path)
            if int(mj.jnt_type[j]) == FREE:
                held.append(b)
            lower, upper = mj.jnt_range[j]
            if int(mj.jnt_type[j]) in (HINGE, SLIDE) and lower > upper:  # auto: unlimited
                raise InputError(f"its range's lower end is above its upper end ({lower:g} > "
                                 f"{upper:g}): MuJoCo would leave it unlimited", path=path,
                                 field=f"joint[{joint_label(mj, j)}].range")
    return held


def _se3(pos: np.ndarray, quat: np.ndarray) -> pin.SE3:
    """The placement of a MuJoCo position and (w, x, y, z) quaternion."""
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, np.asarray(quat, dtype=float))
    return pin.SE3(rotation.reshape(3, 3), np.array(pos, dtype=float))


def _axis_rotation(axis: np.ndarray, angle: float) -> pin.SE3:
    """A rotation by `angle` [rad] about the unit `axis`, as MuJoCo builds it."""
    quat = np.zeros(4)
    mujoco.mju_axisAngle2Quat(quat, np.asarray(axis, dtype=float), angle)
    return _se3(np.zeros(3), quat)


def _joint_model(kind: int, axis: np.ndarray) -> pin.JointModel:
    """Pinocchio's joint for a MuJoCo hinge or slide about (along) the unit `axis`."""
    revolute = kind == HINGE
    for i, aligned in enumerate(("X", "Y", "Z")):
        if np.array_equal(axis, np.eye(3)[i]):
            return getattr(pin, f"JointModel{'R' if revolute else 'P'}{aligned}")()
    unaligned = pin.JointModelRevoluteUnaligned if revolute else pin.JointModelPrismaticUnaligned
    return unaligned(*(float(x) for x in axis))


def _build(mj: mujoco.MjModel, kept: list[int], model_name: str
           ) -> tuple[pin.Model, np.ndarray, np.ndarray, list[str]]:
    """The Pinocchio model of the kept bodies, its qpos and dof addresses, unnamed joints."""
    model = pin.Model()
    model.name = model_name
    gravity = np.zeros(3)
    if not mj.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY:
        gravity = np.array(mj.opt.gravity, dtype=float)
    model.gravity = pin.Motion(gravity, np.zeros(3))
    inf = np.array([UNLIMITED])
    attached: dict[int, tuple[int, pin.SE3, int]] = {0: (0, pin.SE3.Identity(), 0)}
    qpos_index, dof_index, unnamed = [], [], []
    for b in kept:
        joint_id, placement, parent_frame = attached[int(mj.body_parentid[b])]
        placement = placement * _se3(mj.body_pos[b], mj.body_quat[b])
        for j in joints(mj, b):
            kind = int(mj.jnt_type[j])
            if kind == FREE:  # held fixed at qpos0, which MuJoCo sets to body_pos/quat
                continue
            axis, anchor = np.array(mj.jnt_axis[j]), np.array(mj.jnt_pos[j])
            ref = float(mj.qpos0[mj.jnt_qposadr[j]])
            placement = placement * pin.SE3(np.eye(3), anchor)
            placement = placement * (_axis_rotation(axis, -ref) if kind == HINGE
                                     else pin.SE3(np.eye(3), -ref * axis))
            limits = mj.jnt_range[j] if mj.jnt_limited[j] else (-UNLIMITED, UNLIMITED)
            joint_name = joint_label(mj, j)
            if not mj_name(mj, mujoco.mjtObj.mjOBJ_JOINT, j):
                unnamed.append(joint_name)
            joint_id = model.addJoint(joint_id, _joint_model(kind, axis), placement, joint_name,
                                      inf, inf, np.array([limits[0]]), np.array([limits[1]]))
            parent_frame = model.addJointFrame(joint_id, parent_frame)
            qpos_index.append(int(mj.jnt_qposadr[j]))
            dof_index.append(int(mj.jnt_dofadr[j]))
            placement = pin.SE3(np.eye(3), -anchor)
        rotation = _se3(np.zeros(3), mj.body_iquat[b]).rotation
        inertia = pin.Inertia(float(mj.body_mass[b]), np.array(mj.body_ipos[b], dtype=float),
                              rotation @ np.diag(mj.body_inertia[b]) @ rotation.T)
        model.appendBodyToJoint(joint_id, inertia, placement)
        frame = model.addBodyFrame(body_label(mj, b), joint_id, placement, parent_frame)
        attached[b] = (joint_id, placement, frame)
        for s in np.flatnonzero(mj.site_bodyid == b):
            site = mj_name(mj, mujoco.mjtObj.mjOBJ_SITE, int(s))
            if site:  # an unnamed site cannot be asked for
                model.addFrame(pin.Frame(site, joint_id, frame,
                                         placement * _se3(mj.site_pos[s], mj.site_quat[s]),
                                         pin.FrameType.OP_FRAME))
    return model, np.array(qpos_index, dtype=int), np.array(dof_index, dtype=int), unnamed


