"""MuJoCo's inverse dynamics of a robot file: the oracle for hdselect's torques.

MJCF is compiled as it is (MuJoCo's own semantics are the truth for MJCF). A URDF
is read by MuJoCo's own URDF importer from a copy without ``<visual>`` and
``<collision>`` (MuJoCo would open every mesh) and with a compiler block that keeps
every link a body of its own (``fusestatic="false"``) and every inertia as written
(``balanceinertia="false"``). Where MuJoCo refuses the file's inertias (a massless
moving link, A + B < C, a zero principal moment: MuJoCo checks what URDF does
not), the copy is compiled with placeholder inertials and every body's mass,
centre of mass and inertia is then set from the XML, read here with
ElementTree and ``float`` (not with hdselect's reader).

Everything but rigid-body dynamics is switched off: armature, damping, friction
loss, stiffness, gravity compensation, fluid; contacts, constraints, equalities,
limits, springs, dampers and actuation disabled; ``mj_setConst`` recomputes what
the compiler cached (a simple body's ``dof_M0`` holds its armature). Gravity is set
to the robot's. A mimic follower's position, velocity and acceleration follow its
leader, and its torque is carried by the leader, multiplied (virtual work).
"""

from __future__ import annotations

import math
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

import hdselect
from hdselect.robot.dynamics import inverse_dynamics

_DISABLED = (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
             | mujoco.mjtDisableBit.mjDSBL_EQUALITY | mujoco.mjtDisableBit.mjDSBL_LIMIT
             | mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS | mujoco.mjtDisableBit.mjDSBL_ACTUATION
             | mujoco.mjtDisableBit.mjDSBL_SPRING | mujoco.mjtDisableBit.mjDSBL_DAMPER)
_JOINT = mujoco.mjtObj.mjOBJ_JOINT


def compile_quietly(path: Path) -> mujoco.MjModel:
    """MuJoCo's model of `path`; its compiler warnings dropped (not written to MUJOCO_LOG.TXT)."""
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(lambda text: None)
    try:
        return mujoco.MjModel.from_xml_path(str(path))
    finally:
        mujoco.set_mju_user_warning(previous)


def rigid(mj: mujoco.MjModel, gravity: np.ndarray) -> mujoco.MjModel:
    """The model with everything but rigid-body dynamics switched off, `gravity` [m/s^2] set."""
    for name in ("dof_armature", "dof_damping", "dof_frictionloss", "jnt_stiffness",
                 "tendon_armature", "actuator_armature", "body_gravcomp"):
        getattr(mj, name)[:] = 0.0
    mj.opt.density = mj.opt.viscosity = 0.0
    mj.opt.disableflags |= _DISABLED
    mj.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)
    mj.opt.gravity[:] = gravity
    mujoco.mj_setConst(mj, mujoco.MjData(mj))
    return mj


def urdf_in_mujoco(text: bytes) -> mujoco.MjModel:
    """MuJoCo's model of a URDF document (see the module's docstring for the copy it reads).

    Raises:
        ValueError: MuJoCo cannot read it even with placeholder inertials.
        xml.etree.ElementTree.ParseError: ElementTree cannot parse it.
    """
    try:
        return _compile_urdf(_stripped(text, placeholders=False))
    except ValueError as err:
        if "inertia" not in str(err) and "mass" not in str(err):
            raise
    mj = _compile_urdf(_stripped(text, placeholders=True))
    for link in ET.fromstring(text.lstrip()).findall("link"):
        _set_inertial(mj, link)
    return mj


def _compile_urdf(text: bytes) -> mujoco.MjModel:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.urdf"
        path.write_bytes(text)
        return compile_quietly(path)


def _stripped(text: bytes, *, placeholders: bool) -> bytes:
    root = ET.fromstring(text.lstrip())
    for element in list(root):
        if element.tag in ("mujoco", "gazebo", "transmission"):
            root.remove(element)
    for joint in root.findall("joint"):
        for extra in joint.findall("axis")[1:]:  # urdfdom reads the first; MuJoCo refuses more
            joint.remove(extra)
    for link in root.findall("link"):
        for child in list(link):
            if child.tag in ("visual", "collision") or (placeholders and child.tag == "inertial"):
                link.remove(child)
        if placeholders:
            inertial = ET.SubElement(link, "inertial")
            ET.SubElement(inertial, "mass", value="1")
            ET.SubElement(inertial, "inertia", ixx="1", iyy="1", izz="1", ixy="0", ixz="0",
                          iyz="0")
    block = ET.Element("mujoco")
    ET.SubElement(block, "compiler", discardvisual="true", fusestatic="false",
                  balanceinertia="false")
    root.insert(0, block)
    return ET.tostring(root)


def _numbers(text: str | None, default: str = "0 0 0") -> np.ndarray:
    return np.array([float(x) for x in (text if text is not None else default).split()])


def _set_inertial(mj: mujoco.MjModel, link: ET.Element) -> None:
    """A body's mass, centre of mass and principal inertia set from its URDF link."""
    body = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, link.get("name"))
    inertial = link.find("inertial")
    mass, com, tensor = 0.0, np.zeros(3), np.zeros((3, 3))
    if inertial is not None:
        origin = inertial.find("origin")
        mass = float(inertial.find("mass").get("value"))
        com = _numbers(None if origin is None else origin.get("xyz"))
        r, p, y = _numbers(None if origin is None else origin.get("rpy"))
        rotation = (_about(2, y) @ _about(1, p) @ _about(0, r))
        i = {k: float(inertial.find("inertia").get(k)) for k in
             ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        local = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                          [i["ixz"], i["iyz"], i["izz"]]])
        tensor = rotation @ local @ rotation.T
    moments, axes = np.linalg.eigh(tensor)
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, axes.flatten())
    mj.body_mass[body], mj.body_ipos[body], mj.body_iquat[body] = mass, com, quat
    mj.body_inertia[body] = moments
    mj.body_sameframe[body] = 0  # compiled as 'inertia at the body frame': no longer
    mj.body_simple[body] = 0  # nor 'simple' (its inertia in dof_M0)


def _about(axis: int, angle: float) -> np.ndarray:
    """A rotation about a coordinate axis [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    rotation = np.eye(3)
    i, j = [k for k in range(3) if k != axis]
    rotation[i, i], rotation[i, j], rotation[j, i], rotation[j, j] = c, -s, s, c
    return rotation


def mujoco_of(robot: hdselect.Robot, text: bytes | None = None) -> mujoco.MjModel:
    """MuJoCo's rigid-body model of the robot's file (`text`: an expanded xacro instead)."""
    path = robot.path
    root = ET.fromstring(path.read_bytes().lstrip()).tag if text is None else "robot"
    mj = compile_quietly(path) if root in ("mujoco", "mujocoinclude") else urdf_in_mujoco(
        text if text is not None else path.read_bytes())
    return rigid(mj, np.array(robot.gravity))


def states(robot: hdselect.Robot, count: int, seed: int) -> tuple[np.ndarray, ...]:
    """Random states: q uniform within limits (within +-pi rad or +-1 m where none), qd and
    qdd standard normal [rad or m, per s, per s^2], each (count, dof)."""
    rng = np.random.default_rng(seed)
    low, high = np.array(robot.lower), np.array(robot.upper)
    free = ~(np.isfinite(low) & np.isfinite(high))
    low[free], high[free] = -math.pi, math.pi
    q = rng.uniform(low, high, size=(count, robot.dof))
    return q, rng.normal(size=(count, robot.dof)), rng.normal(size=(count, robot.dof))


def mujoco_torques(mj: mujoco.MjModel, robot: hdselect.Robot, q: np.ndarray, qd: np.ndarray,
                   qdd: np.ndarray) -> np.ndarray:
    """MuJoCo's ``mj_inverse`` torques of the robot's degrees of freedom, followers folded in.

    Joints are matched by name; every joint MuJoCo has beyond them stays at its qpos0, at
    rest (a free root joint held, as hdselect holds it).
    """
    data = mujoco.MjData(mj)
    address = {name: _address(mj, name) for name in (*robot.joint_names, *robot.mimic)}
    out = np.zeros(q.shape)
    for k in range(q.shape[0]):
        _inverse(mj, data, robot, address, q[k], qd[k], qdd[k])
        for j, name in enumerate(robot.joint_names):
            out[k, j] = data.qfrc_inverse[address[name][1]]
        for name, mimic in robot.mimic.items():
            out[k, robot.joint_index(mimic.leader)] += (
                mimic.multiplier * data.qfrc_inverse[address[name][1]])
    return out


def mujoco_joint_loads(mj: mujoco.MjModel, robot: hdselect.Robot, q: np.ndarray,
                       qd: np.ndarray, qdd: np.ndarray) -> dict[str, np.ndarray]:
    """MuJoCo's force and moment through each joint, as a bearing on its axis sees them.

    After ``mj_inverse`` and ``mj_rnePostConstraint``, ``cfrc_int[b]`` is the spatial
    force (moment; force) [N m; N] the parent applies to body b's subtree, in world axes
    about the subtree centre of mass of b's tree root, ``subtree_com[body_rootid[b]]``.
    Its moment is moved to the joint's origin p (``xanchor``; for a slide, moved on by
    the slide along ``xaxis``, where a prismatic joint's frame sits after its motion):
    ``n_p = n_c + (c - p) x f``. Joints of one body share the body's force (the frames
    between them are massless), each about its own origin and axis.

    Returns:
        By joint name (mimic followers included), rows (axial force F_a [N] signed along
        the axis, radial force F_r [N], tilting moment M [N m], moment along the axis
        [N m]), each (n,).
    """
    data = mujoco.MjData(mj)
    names = (*robot.joint_names, *robot.mimic)
    address = {name: _address(mj, name) for name in names}
    joint = {name: _joint_id(mj, name) for name in names}
    out = {name: np.empty((4, q.shape[0])) for name in names}
    for k in range(q.shape[0]):
        _inverse(mj, data, robot, address, q[k], qd[k], qdd[k])
        mujoco.mj_rnePostConstraint(mj, data)
        for name in names:
            j = joint[name]
            body = int(mj.jnt_bodyid[j])
            moment, force = data.cfrc_int[body, :3], data.cfrc_int[body, 3:]
            centre = data.subtree_com[int(mj.body_rootid[body])]
            axis = data.xaxis[j]
            origin = data.xanchor[j].copy()
            if mj.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE:
                qadr = address[name][0]
                origin += axis * (data.qpos[qadr] - mj.qpos0[qadr])
            moment = moment + np.cross(centre - origin, force)
            axial, twist = force @ axis, moment @ axis
            out[name][:, k] = (axial, np.linalg.norm(force - axial * axis),
                               np.linalg.norm(moment - twist * axis), twist)
    return out


def _inverse(mj: mujoco.MjModel, data: mujoco.MjData, robot: hdselect.Robot,
             address: dict[str, tuple[int, int]], q: np.ndarray, qd: np.ndarray,
             qdd: np.ndarray) -> None:
    """``mj_inverse`` at one state of the robot's degrees of freedom, followers moved."""
    data.qpos[:], data.qvel[:], data.qacc[:] = mj.qpos0, 0.0, 0.0
    for j, name in enumerate(robot.joint_names):
        qadr, vadr = address[name]
        data.qpos[qadr], data.qvel[vadr], data.qacc[vadr] = q[j], qd[j], qdd[j]
    for name, mimic in robot.mimic.items():
        j = robot.joint_index(mimic.leader)
        qadr, vadr = address[name]
        data.qpos[qadr] = mimic.multiplier * q[j] + mimic.offset
        data.qvel[vadr] = mimic.multiplier * qd[j]
        data.qacc[vadr] = mimic.multiplier * qdd[j]
    mujoco.mj_inverse(mj, data)
    assert not data.qfrc_constraint.any() and not data.qfrc_passive.any()


def _joint_id(mj: mujoco.MjModel, name: str) -> int:
    joint = mujoco.mj_name2id(mj, _JOINT, name)
    if joint < 0 and name.startswith("unnamed_joint_"):
        joint = int(name.removeprefix("unnamed_joint_"))
    assert joint >= 0, f"MuJoCo has no joint {name}"
    return joint


def _address(mj: mujoco.MjModel, name: str) -> tuple[int, int]:
    joint = _joint_id(mj, name)
    return int(mj.jnt_qposadr[joint]), int(mj.jnt_dofadr[joint])


def compare(robot: hdselect.Robot, count: int = 3, seed: int = 0,
            text: bytes | None = None) -> tuple[float, float]:
    """hdselect's torques against MuJoCo's at random states.

    Returns:
        The largest difference and the largest MuJoCo torque [N m or N].
    """
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(lambda text: None)  # e.g. a singular mass matrix: not ours
    try:
        mj = mujoco_of(robot, text)
        q, qd, qdd = states(robot, count, seed)
        theirs = mujoco_torques(mj, robot, q, qd, qdd)
    finally:
        mujoco.set_mju_user_warning(previous)
    ours = inverse_dynamics(robot, q, qd, qdd)
    return float(np.abs(ours - theirs).max()), float(np.abs(theirs).max())
