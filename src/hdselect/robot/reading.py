"""Read a robot file (URDF, xacro or MJCF) into a bare Pinocchio model, and say what was assumed.

Each format is read as it defines itself. A URDF is built by Pinocchio
(`hdselect.robot.pinurdf`) and checked against the file's own numbers
(`hdselect.robot.urdfxml`, `hdselect.robot.urdfcheck`); a ``.xacro`` file (or one
holding xacro elements) is first expanded by the xacro package
(`hdselect.robot.xacrofile`); an MJCF file is compiled by MuJoCo and the model built
from MuJoCo's bodies and joints (`hdselect.robot.mjcf`). An SDF file is refused.
Mimic followers (a URDF's ``<mimic>``, an MJCF joint equality) have no degree of
freedom and move with their leader. Bodies are checked (`hdselect.robot.checks`)
as Pinocchio built them, after it merged every link on a fixed joint into its
moving body. Armature, joint damping, friction and springs model the motor's and
the joint's own inertia and losses, not load on the gear output: they are set to
zero and reported.
"""

from __future__ import annotations

import logging
import math
import xml.parsers.expat
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import read_input
from hdselect.base.tomlfile import toml_kind
from hdselect.robot.checks import check_bodies, check_geometry
from hdselect.robot.pinurdf import build_urdf
from hdselect.robot.urdfcheck import check_model, open_limits, unlimited
from hdselect.robot.urdfxml import Element, UrdfTree, parse_elements, read_urdf_tree
from hdselect.robot.xacrofile import blamed_argument, expand_xacro

logger = logging.getLogger(__name__)

LEG_MASS = 0.05
"""A chain leaving the root is a leg if it holds this fraction of the robot's mass [-] ..."""
LEG_DROP = 0.15
"""... and reaches this far below the root's centre of mass in the zero pose [m]."""

FORMATS = ("URDF", "xacro", "MJCF")
"""The robot file formats hdselect reads."""
_MJCF_SUFFIXES = (".xml", ".mjcf")
_MESH_SUFFIXES = (".obj", ".stl", ".dae", ".ply", ".glb", ".gltf", ".msh", ".mtl")
"""Mesh files a robot file names: given in its place, they are refused as what they are."""
_LOSSES = (("armature", "armature", "kg m^2"), ("damping", "damping", "N m s/rad"),
           ("friction", "friction", "N m"), ("rotorInertia", "rotor inertia", "kg m^2"))


@dataclass(frozen=True)
class Mimic:
    """A follower joint that moves with its leader: q = multiplier x q_leader + offset.

    Attributes:
        leader: The leading joint's name.
        multiplier: Follower motion per unit of leader motion [-].
        offset: Follower position when the leader is at zero [rad or m].
        lower: The follower's own lower position limit [rad or m] (-inf: none).
        upper: The follower's own upper position limit [rad or m] (+inf: none).
        revolute: The follower turns (False: it slides; its positions are in m).
    """

    leader: str
    multiplier: float
    offset: float
    lower: float = -math.inf
    upper: float = math.inf
    revolute: bool = True

    def follow(self, leader: np.ndarray) -> np.ndarray:
        """The follower's positions for the leader's [rad or m]."""
        return self.multiplier * leader + self.offset


@dataclass(frozen=True, eq=False)
class RobotFile:
    """What a robot file holds, as hdselect uses it.

    Attributes:
        model: Pinocchio model, mimic joints built, armature, damping and friction zero.
        root_link: The link held fixed to the world.
        mimic: Each follower joint's leader, by follower name.
        file_order: The movable, non-follower joints in the order the file writes them,
            or None when the file could not be scanned for it.
        notes: What was set aside or looks wrong, one line each (`set_aside` first).
        uncoupled_followers: Mimic followers Pinocchio could not couple to their leaders
            (it needs a leader before its followers in its tree order): independent joints
            of the model here, and noted so.
        format: ``"URDF"``, ``"xacro"`` or ``"MJCF"``.
        set_aside: The notes on the motor's and the joints' own inertia and losses (and
            MuJoCo's actuators, tendons, contacts) left out: expected, not warnings.
    """

    model: pin.Model
    root_link: str
    mimic: Mapping[str, Mimic]
    file_order: tuple[str, ...] | None
    notes: tuple[str, ...]
    uncoupled_followers: tuple[str, ...] = ()
    format: str = "URDF"
    set_aside: tuple[str, ...] = field(default=(), repr=False)


def read_robot_file(path: Path, xacro_args: Mapping[str, str] | None = None) -> RobotFile:
    """Build the model of a robot file and check it.

    Args:
        path: An existing URDF, ``.xacro`` or MJCF file (told apart by the suffix
            ``.xacro`` and by the document's root element; a file holding xacro
            elements is expanded too).
        xacro_args: Values of a xacro file's ``xacro:arg`` arguments, by name.

    Returns:
        The model and what was assumed.

    Raises:
        InputError: The file is SDF or TOML (a motion file given in its place); xacro,
            Pinocchio or MuJoCo rejects it (their reason in the message); a number of the
            file is not read as the format defines it; a body's inertia is not physical.
    """
    data = read_input(path)
    root = parse_elements(data)
    toml = toml_kind(data) if root is None else None
    if toml is not None:
        raise InputError(f"is {toml} (TOML), not a robot file (URDF, xacro or MJCF)", path=path)
    kind = _format(path, root)
    if xacro_args and kind != "xacro":
        raise InputError(f"xacro arguments given ({', '.join(xacro_args)}) for a {kind} file; "
                         "only a .xacro file takes them", path=path, field="xacro_args")
    if kind == "MJCF":
        file = _read_mjcf(path)
    else:
        text = None
        notes: list[str] = []
        if kind == "xacro":
            text, notes = expand_xacro(path, xacro_args or {})
            root = parse_elements(text.encode())
        try:
            file = _read_urdf(path, text, root, notes, kind)
        except InputError as err:
            if kind != "xacro" or not xacro_args or err.path != path:
                raise
            raise blamed_argument(err, path, xacro_args) from err
    for note in file.notes:
        if note in file.set_aside:
            logger.info("%s: %s", path, note)
        else:
            logger.warning("%s: %s", path, note)
    return file


def _format(path: Path, root: Element | None) -> str:
    """The file's format, from its suffix and its root element; SDF and meshes refused."""
    if path.suffix.lower() == ".xacro":
        return "xacro"
    tag = root.tag if root is not None else ""
    if path.suffix.lower() in _MESH_SUFFIXES and tag not in ("robot", "mujoco"):
        raise InputError(f"a mesh file ({path.suffix}), not a robot file: hdselect reads URDF, "
                         "xacro and MJCF; give the robot file that names the meshes", path=path)
    if tag == "sdf":
        raise InputError("an SDF file (root element <sdf>): SDF is not supported; hdselect reads "
                         "URDF, xacro and MJCF (convert it to URDF or MJCF)", path=path)
    if tag in ("mujoco", "mujocoinclude"):
        return "MJCF"
    if tag == "robot":
        return "xacro" if _has_xacro(root) else "URDF"
    return "MJCF" if path.suffix.lower() in _MJCF_SUFFIXES else "URDF"


def _has_xacro(element: Element | None) -> bool:
    """The document holds xacro elements (``<xacro:include>``, ``<xacro:property>``, ...)."""
    if element is None:
        return False
    return element.tag.startswith("xacro:") or any(_has_xacro(c) for c in element.children)


def _read_urdf(path: Path, text: str | None, root: Element | None, notes: list[str],
               kind: str) -> RobotFile:
    """A URDF (or expanded xacro) built by Pinocchio and checked against its XML."""
    if root is None or root.tag != "robot":
        build_urdf(path, text, mimic=False)  # Pinocchio's own reason, if it has one
        raise InputError("malformed XML: hdselect cannot read the numbers Pinocchio read "
                         f"({_expat_reason(text.encode() if text else read_input(path))})",
                         path=path)
    tree = read_urdf_tree(root, path)
    uncoupled: tuple[str, ...] = ()
    said: list[str] = []
    try:
        model = build_urdf(path, text, mimic=True, said=said)
    except InputError as err:
        if "mimic" not in err.reason:
            raise
        model = build_urdf(path, text, mimic=False, said=said)
        uncoupled = tuple(name for name, joint in tree.joints.items()
                          if joint.mimic is not None and model.existJointName(name))
        notes.append(f"Pinocchio cannot couple the mimic joints ({err.reason.split(': ', 1)[-1]}"
                     f"): {', '.join(uncoupled)} move as independent joints here, carry their "
                     "own load and are not sized unless named")
    try:
        check_model(model, tree, path)
    except InputError as err:
        if not said:
            raise
        raise InputError(f"{err.reason}; urdfdom said: {said[0]}", path=path,
                         field=err.field) from err
    mimic = _urdf_mimic(model, tree, path)
    notes += open_limits(model, tree)
    order = _file_joint_order(tree, model, mimic)
    return _finish(path, model, mimic, order, notes, [], uncoupled, kind)


def _urdf_mimic(model: pin.Model, tree: UrdfTree, path: Path) -> dict[str, Mimic]:
    """Each follower Pinocchio coupled, its own limits from the file (none: unlimited)."""
    mimic = {}
    for follower, leader in zip(model.mimicking_joints, model.mimicked_joints, strict=True):
        name = model.names[follower]
        joint = model.joints[follower].extract()
        written = tree.joints[name]
        given = written.mimic
        if given is None or given.leader != model.names[leader] or abs(
                float(joint.scaling) - given.multiplier) > 1e-12 * max(1, abs(given.multiplier)) \
                or abs(float(joint.offset) - given.offset) > 1e-12 * max(1, abs(given.offset)):
            raise InputError(f"Pinocchio couples it to '{model.names[leader]}' x "
                             f"{float(joint.scaling):g} + {float(joint.offset):g}, otherwise than "
                             "the file's <mimic>", path=path, field=f"joint[{name}].mimic")
        lower, upper = -math.inf, math.inf
        if not unlimited(written) and written.limit is not None:
            lower, upper = written.limit.lower, written.limit.upper
        mimic[name] = Mimic(model.names[leader], given.multiplier, given.offset, lower, upper,
                            written.kind != "prismatic")
    return mimic


def _read_mjcf(path: Path) -> RobotFile:
    """An MJCF file compiled by MuJoCo; its joint couplings made mimic where Pinocchio can."""
    from hdselect.robot.mjcf import model_from_mjcf  # MuJoCo is imported for MJCF only

    read = model_from_mjcf(path)
    model = read.model
    notes = list(read.notes)
    mimic: dict[str, Mimic] = {}
    uncoupled = []
    for follower, coupling in read.couplings.items():
        follower_id, leader_id = model.getJointId(follower), model.getJointId(coupling.leader)
        if leader_id > follower_id or model.joints[follower_id].nq != 1:
            uncoupled.append(follower)
            continue
        field = f"equality[{coupling.equality}]"
        bounds.MIMIC_MULTIPLIER.check(coupling.multiplier, path=path, field=f"{field}.polycoef")
        bounds.POSITION.check(coupling.offset, path=path, field=f"{field}.polycoef")
        iq = model.joints[follower_id].idx_q
        lower, upper = float(model.lowerPositionLimit[iq]), float(model.upperPositionLimit[iq])
        slides = model.joints[follower_id].shortname().startswith(("JointModelP",))
        mimic[follower] = Mimic(coupling.leader, coupling.multiplier, coupling.offset,
                                lower, upper, not slides)
    for follower in sorted(mimic, key=model.getJointId, reverse=True):
        model = _made_mimic(model, follower, mimic[follower])
    if mimic:
        notes.append("joint equalities made mimic followers (no gearhead of their own; the "
                     "leader carries their load): " + ", ".join(
                         f"{name} = {m.multiplier:g} x {m.leader} + {m.offset:g}"
                         for name, m in mimic.items()))
    if uncoupled:
        notes.append(f"joint equalities Pinocchio cannot couple (the leader comes after its "
                     f"follower in the tree): {', '.join(uncoupled)} move as independent joints "
                     "here, carry their own load and are not sized unless named")
    return _finish(path, model, mimic, None, notes, list(read.set_aside), tuple(uncoupled),
                   "MJCF", root=read.root_body)


def _made_mimic(model: pin.Model, follower: str, mimic: Mimic) -> pin.Model:
    """The model with `follower` turned into a mimic joint of its leader."""
    follower_id = model.getJointId(follower)
    iq = model.joints[follower_id].idx_q
    configurations = {entry.key(): np.delete(np.array(entry.data()), iq)
                      for entry in model.referenceConfigurations}
    model = pin.transformJointIntoMimic(model, model.getJointId(mimic.leader), follower_id,
                                        mimic.multiplier, mimic.offset)
    for name, q in configurations.items():
        model.referenceConfigurations[name] = q
    return model


def _finish(path: Path, model: pin.Model, mimic: dict[str, Mimic],
            order: tuple[str, ...] | None, notes: list[str], set_aside: list[str],
            uncoupled: tuple[str, ...], kind: str, root: str | None = None) -> RobotFile:
    """The checks every format shares, and the record."""
    losses = _set_aside_losses(model)
    notes += check_bodies(model, path)
    check_geometry(model, path)
    root = root or _root_link(model)
    notes += _free_body_note(model, root)
    aside = tuple(losses + set_aside)
    return RobotFile(model, root, mimic, order, aside + tuple(notes),
                     uncoupled, kind, aside)


def _expat_reason(data: bytes) -> str:
    parser = xml.parsers.expat.ParserCreate()
    try:
        parser.Parse(data.lstrip(), True)
    except xml.parsers.expat.ExpatError as err:
        return f"line {err.lineno}: {xml.parsers.expat.ErrorString(err.code)}"
    return "no <robot> root element"


def _set_aside_losses(model: pin.Model) -> list[str]:
    """Zero armature, damping, friction and rotor inertia; one note saying what the file had."""
    given = []
    for attr, label, unit in _LOSSES:
        values = np.array(getattr(model, attr), dtype=float)
        nonzero = np.flatnonzero(values)
        if nonzero.size:
            given.append(f"{label} on {nonzero.size} joint{'s' if nonzero.size > 1 else ''} "
                         f"(up to {np.abs(values).max():g} {unit})")
        setattr(model, attr, np.zeros(model.nv))
    if not given:
        return []
    return [f"the file's {', '.join(given)}: the motor's and the joints' own inertia and "
            "losses, not load on the gear output; left out of the gear torque (give a motor's "
            "rotor inertia with the motor)"]


def _root_link(model: pin.Model) -> str:
    bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY and f.parentJoint == 0]
    return bodies[0] if bodies else model.frames[0].name


def _free_body_note(model: pin.Model, root: str) -> list[str]:
    """A note when the fixed root looks like a free body standing on legs.

    A leg is a chain leaving the root that holds at least `LEG_MASS` of the robot's
    mass and reaches at least `LEG_DROP` below the root's centre of mass (base -z)
    in the file's zero pose. Two or more legs: the robot probably stands on them.
    """
    total = sum(float(body.mass) for body in model.inertias)
    if total <= 0.0:
        return []
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    top = float(model.inertias[0].lever[2])
    legs = []
    for joint_id in range(1, model.njoints):
        if model.parents[joint_id] != 0:
            continue
        subtree = list(model.subtrees[joint_id])
        mass = sum(float(model.inertias[k].mass) for k in subtree)
        drop = top - min(float(data.oMi[k].translation[2]) for k in subtree)
        if mass >= LEG_MASS * total and drop >= LEG_DROP:
            legs.append((mass, drop))
    if len(legs) < 2:
        return []
    masses = ", ".join(f"{m:.3g}" for m, _ in legs)
    return [f"the root link '{root}' is held fixed, yet {len(legs)} chains ({masses} kg) hang "
            f"{min(d for _, d in legs):.2g} m or more below it in the zero pose: if the robot "
            "stands on them, their torques depend on ground contacts that hdselect does not "
            "model"]


def _file_joint_order(tree: UrdfTree, model: pin.Model, mimic: Mapping[str, Mimic]
                      ) -> tuple[str, ...] | None:
    """The model's degrees of freedom in the order the URDF writes its ``<joint>`` elements."""
    dofs = {model.names[j] for j in range(1, model.njoints)
            if model.joints[j].nv > 0 and model.names[j] not in mimic}
    order = tuple(n for n in tree.joints if n in dofs)
    return order if len(order) == len(dofs) else None
