"""What an MJCF file holds beyond rigid bodies: joint couplings, and what is set aside.

MuJoCo's equality constraints of kind ``joint`` are linear joint couplings (hdselect
builds them as mimic joints) when their polynomial is of degree 1; every other
equality kind is named in a note. Armature, damping, friction loss, springs, actuators, tendons,
contacts, fluid forces and gravity compensation are MuJoCo's model of the motor
and the world, not load on the gear output: each kind present gets one note.
The small naming helpers shared with `mjcf_model` live here.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

HINGE, SLIDE = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
BALL, FREE = int(mujoco.mjtJoint.mjJNT_BALL), int(mujoco.mjtJoint.mjJNT_FREE)
_EQ_JOINT = int(mujoco.mjtEq.mjEQ_JOINT)
_LISTED = 6
"""Names listed in one note before the rest are counted."""


@dataclass(frozen=True)
class JointCoupling:
    """A MuJoCo ``<equality><joint>``: follower = offset + multiplier x leader.

    Attributes:
        leader: The leading joint (MuJoCo's ``joint2``).
        multiplier: Follower motion per unit of leader motion [-] (``polycoef[1]``).
        offset: Follower position when the leader is at 0 [rad or m]; MuJoCo's
            polynomial is about the joints' ``qpos0``, so this is
            ``qpos0_f + polycoef[0] - polycoef[1] x qpos0_l``.
        equality: The equality's name (``equality <index>`` when it has none).
    """

    leader: str
    multiplier: float
    offset: float
    equality: str


def mj_name(mj: mujoco.MjModel, kind: mujoco.mjtObj, index: int) -> str:
    """The name MuJoCo gives object `index` of `kind` ("" when it has none)."""
    return mujoco.mj_id2name(mj, kind, index) or ""


def listed(names: Iterable[str]) -> str:
    """The first few `names`, comma separated, and how many more there are."""
    names = list(names)
    shown = ", ".join(names[:_LISTED])
    return shown + (f" and {len(names) - _LISTED} more" if len(names) > _LISTED else "")


def body_label(mj: mujoco.MjModel, body: int) -> str:
    """A body's name, or ``unnamed_body_<id>`` (its frame name and the name in notes)."""
    return mj_name(mj, mujoco.mjtObj.mjOBJ_BODY, body) or f"unnamed_body_{body}"


def joint_label(mj: mujoco.MjModel, joint: int) -> str:
    """A joint's name, or ``unnamed_joint_<id>`` (its Pinocchio name and the name in notes)."""
    return mj_name(mj, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"unnamed_joint_{joint}"


def joints(mj: mujoco.MjModel, body: int) -> range:
    """MuJoCo's ids of the joints of `body`, in MuJoCo's order."""
    return range(int(mj.body_jntadr[body]), int(mj.body_jntadr[body] + mj.body_jntnum[body]))


def couplings(mj: mujoco.MjModel, model: pin.Model
              ) -> tuple[dict[str, JointCoupling], list[str]]:
    """Linear joint couplings between joints of the model, and notes on every other equality.

    MuJoCo's ``<equality><joint>`` holds y - y0 = a0 + a1 (x - x0) + ... + a4 (x - x0)^4,
    y the follower (``joint1``), x the leader (``joint2``), y0 and x0 their ``qpos0``.
    """
    found: dict[str, JointCoupling] = {}
    other: dict[str, list[str]] = {}
    notes = []
    for e in range(mj.neq):
        label = mj_name(mj, mujoco.mjtObj.mjOBJ_EQUALITY, e) or f"equality {e}"
        kind = int(mj.eq_type[e])
        if kind != _EQ_JOINT:
            other.setdefault(mujoco.mjtEq(kind).name[5:].lower(), []).append(label)
            continue
        follower_id, leader_id = int(mj.eq_obj1id[e]), int(mj.eq_obj2id[e])
        follower = joint_label(mj, follower_id)
        coef = np.array(mj.eq_data[e, :5], dtype=float)
        y0 = float(mj.qpos0[mj.jnt_qposadr[follower_id]])
        if leader_id < 0:
            notes.append(f"{label} holds joint '{follower}' at {y0 + coef[0]:g}: not a "
                         "coupling, the joint moves freely here")
            continue
        leader = joint_label(mj, leader_id)
        x0 = float(mj.qpos0[mj.jnt_qposadr[leader_id]])
        if not (model.existJointName(follower) and model.existJointName(leader)):
            notes.append(f"{label} couples '{follower}' to '{leader}', not both in the model")
        elif np.any(coef[2:] != 0.0):
            notes.append(f"{label} couples '{follower}' to '{leader}' by a polynomial of degree "
                         f"{int(np.flatnonzero(coef)[-1])}: not a linear coupling, both joints "
                         "move independently here")
        elif not mj.eq_active0[e]:
            notes.append(f"{label} couples '{follower}' to '{leader}' but is inactive in the file")
        else:
            found[follower] = JointCoupling(leader, float(coef[1]),
                                            y0 + float(coef[0]) - float(coef[1]) * x0, label)
    if other:
        kinds = "; ".join(f"{len(v)} {k} ({listed(v)})" for k, v in sorted(other.items()))
        notes.append(f"equality constraints that are not joint couplings are set aside: {kinds}; "
                     "torques are those of the open tree")
    return found, notes


def set_aside(mj: mujoco.MjModel, kept: list[int]) -> list[str]:
    """One note per kind of MuJoCo quantity that is not load on the gear output."""
    kept_set = set(kept)
    moving = [j for b in kept for j in joints(mj, b) if int(mj.jnt_type[j]) in (HINGE, SLIDE)]
    dofs = [int(mj.jnt_dofadr[j]) for j in moving]
    notes = []

    def per_joint(label: str, values: np.ndarray, unit: str, what: str) -> None:
        nonzero = np.flatnonzero(values)
        if nonzero.size:
            notes.append(f"{label} on {nonzero.size} joint{'s' if nonzero.size > 1 else ''} "
                         f"(up to {np.abs(values).max():g} {unit}): {what}; left out")

    per_joint("armature", mj.dof_armature[dofs], "kg m^2 or kg",
              "the motor's reflected inertia, not load on the gear output")
    per_joint("damping", mj.dof_damping[dofs], "N m s/rad or N s/m", "a joint loss")
    per_joint("frictionloss", mj.dof_frictionloss[dofs], "N m or N", "a joint loss")
    per_joint("springs (stiffness)", mj.jnt_stiffness[moving], "N m/rad or N/m",
              "joint springs about springref (qpos_spring)")
    clamped = [j for j in moving if mj.jnt_actfrclimited[j]]
    if clamped:
        ranges = ", ".join("{} [{:g}, {:g}]".format(mj_name(mj, mujoco.mjtObj.mjOBJ_JOINT, j),
                                                    *mj.jnt_actfrcrange[j]) for j in clamped)
        notes.append(f"actuatorfrcrange (MuJoCo's clamp of the actuator force at a joint, not a "
                     f"gear rating) left out: {ranges}")
    _actuator_note(mj, kept_set, notes)
    if mj.ntendon:
        names = [mj_name(mj, mujoco.mjtObj.mjOBJ_TENDON, t) or f"tendon {t}"
                 for t in range(mj.ntendon)]
        notes.append(f"{mj.ntendon} tendon{'s' if mj.ntendon > 1 else ''} set aside (their "
                     f"stiffness, damping, armature and limits): {listed(names)}")
    colliding = [g for g in range(mj.ngeom) if int(mj.geom_bodyid[g]) in kept_set
                 and (mj.geom_contype[g] or mj.geom_conaffinity[g])]
    if colliding or mj.npair:
        notes.append(f"contacts ({len(colliding)} colliding geoms on the robot, {mj.npair} "
                     "explicit pairs) are not modelled")
    gravcomp = [b for b in kept if mj.body_gravcomp[b]]
    if gravcomp:
        bodies = listed(body_label(mj, b) for b in gravcomp)
        notes.append(f"gravity compensation (gravcomp) on {bodies} is left out: the gear "
                     "carries the weight")
    if mj.opt.density or mj.opt.viscosity:
        notes.append(f"fluid forces (density {mj.opt.density:g} kg/m^3, viscosity "
                     f"{mj.opt.viscosity:g} Pa s) are left out")
    if mj.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY:
        notes.append("the file disables gravity (<flag gravity=\"disable\"/>); hdselect takes "
                     "gravity from the mounting (floor unless the motion says otherwise)")
    elif not np.array_equal(mj.opt.gravity, [0.0, 0.0, -9.81]):
        notes.append("the file's gravity ({:g} {:g} {:g} m/s^2) is not used; hdselect takes "
                     "gravity from the mounting (floor unless the motion says otherwise)"
                     .format(*mj.opt.gravity))
    return notes


def _actuator_note(mj: mujoco.MjModel, kept: set[int], notes: list[str]) -> None:
    """One note on the actuators acting on the kept bodies: gear, ctrlrange, forcerange."""
    trn = mujoco.mjtTrn
    described = []
    for u in range(mj.nu):
        kind, target = int(mj.actuator_trntype[u]), int(mj.actuator_trnid[u, 0])
        if kind in (trn.mjTRN_JOINT, trn.mjTRN_JOINTINPARENT):
            if int(mj.jnt_bodyid[target]) not in kept:
                continue
            on = f"joint {mj_name(mj, mujoco.mjtObj.mjOBJ_JOINT, target)}"
        elif kind == trn.mjTRN_TENDON:
            on = f"tendon {mj_name(mj, mujoco.mjtObj.mjOBJ_TENDON, target)}"
        elif kind == trn.mjTRN_BODY:
            on = f"body {body_label(mj, target)}"
        else:  # a site, slider-crank or other transmission
            on = f"{trn(kind).name[6:].lower()} {mj_name(mj, mujoco.mjtObj.mjOBJ_SITE, target)}"
        text = (f"{mj_name(mj, mujoco.mjtObj.mjOBJ_ACTUATOR, u) or f'actuator {u}'} on {on}, "
                f"gear {mj.actuator_gear[u, 0]:g}")
        if mj.actuator_ctrllimited[u]:
            text += ", ctrlrange [{:g}, {:g}]".format(*mj.actuator_ctrlrange[u])
        if mj.actuator_forcelimited[u]:
            text += ", forcerange [{:g}, {:g}]".format(*mj.actuator_forcerange[u])
        if mj.actuator_armature[u]:  # MuJoCo adds gear^2 x armature to the joint's inertia
            text += f", armature {mj.actuator_armature[u]:g}"
        if mj.actuator_damping[u]:
            text += f", damping {mj.actuator_damping[u]:g}"
        described.append(text)
    if described:
        notes.append(f"{len(described)} actuator{'s' if len(described) > 1 else ''} set aside "
                     "(hdselect sizes from the motion; MuJoCo's actuator limits are not gear "
                     f"ratings): {listed(described)}")
