"""A URDF's numbers read from its XML as the format defines them, before Pinocchio reads it.

urdfdom, Pinocchio's URDF reader, drops a link's whole ``<inertial>`` when one of
its numbers does not parse (``nan``, ``0.243kg``, an empty value, a missing
``<mass>``, a two-number origin, an unexpanded ``${m1}``) and says so only on
standard error; it accepts a zero axis and a link with two parent joints. This
module reads every number urdfdom reads, the way urdfdom reads it (a number is
C's decimal notation, leading blanks allowed; a vector is three such numbers
separated by spaces), and refuses the file, naming the link or joint and the
attribute, where urdfdom would drop or misread something. `hdselect.robot.urdfcheck`
then checks Pinocchio's model against what is read here.

The XML is scanned by expat without namespace processing, so extensions such as
``drake:`` never break it. Only direct children ``<link>`` and ``<joint>`` of
``<robot>`` are read (a ``<transmission>``'s joints are not URDF joints); of
repeated elements the first counts, as in urdfdom.
"""

from __future__ import annotations

import math
import re
import xml.parsers.expat
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError

MOVABLE = ("revolute", "continuous", "prismatic")
"""URDF joint types with one degree of freedom."""
DROPPED = "urdfdom would drop the link's whole <inertial>"
"""What happens to a link whose inertial numbers do not parse, for messages."""
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


@dataclass
class Element:
    """An XML element as expat gave it: tag, attributes, children and line."""

    tag: str
    attributes: dict[str, str]
    line: int
    children: list[Element] = field(default_factory=list)

    def first(self, tag: str) -> Element | None:
        """The first child with this tag, as urdfdom (TinyXML's FirstChildElement) takes it."""
        return next((child for child in self.children if child.tag == tag), None)

    def all(self, tag: str) -> list[Element]:
        """Every child with this tag."""
        return [child for child in self.children if child.tag == tag]


@dataclass(frozen=True)
class Limit:
    """A joint's ``<limit>``: position [rad or m], effort [N m or N], velocity [rad/s or m/s]."""

    lower: float
    upper: float
    effort: float
    velocity: float


@dataclass(frozen=True)
class MimicSpec:
    """A joint's ``<mimic>``: q = multiplier x q_leader + offset [-, rad or m]."""

    leader: str
    multiplier: float
    offset: float


@dataclass(frozen=True)
class UrdfJoint:
    """One ``<joint>`` as the file writes it.

    Attributes:
        name: Joint name.
        kind: URDF type (``revolute``, ``continuous``, ``prismatic``, ``fixed``, ...).
        parent: Parent link.
        child: Child link.
        origin: Child frame in the parent link's frame (``<origin xyz rpy>``) [m].
        axis: The axis as written (default 1 0 0), in the joint frame [-].
        limit: The ``<limit>``, if any.
        mimic: The ``<mimic>``, if any.
    """

    name: str
    kind: str
    parent: str
    child: str
    origin: pin.SE3
    axis: np.ndarray
    limit: Limit | None
    mimic: MimicSpec | None


@dataclass(frozen=True, eq=False)
class UrdfTree:
    """A URDF's links and joints, every number parsed.

    Attributes:
        links: Each link's spatial inertia about its own frame's origin, in its frame
            (6 x 6, linear part first, as Pinocchio's ``Inertia.matrix()``) [kg, kg m,
            kg m^2]; None: no ``<inertial>``, massless. In file order.
        joints: Each joint by name, in file order.
    """

    links: Mapping[str, np.ndarray | None]
    joints: Mapping[str, UrdfJoint]

    @property
    def root(self) -> str | None:
        """The one link that is no joint's child, if there is exactly one."""
        children = {joint.child for joint in self.joints.values()}
        roots = [name for name in self.links if name not in children]
        return roots[0] if len(roots) == 1 else None


def parse_elements(data: bytes) -> Element | None:
    """The document's root element, or None when expat cannot parse it."""
    parser = xml.parsers.expat.ParserCreate()
    stack: list[Element] = []
    found: list[Element] = []

    def start(tag: str, attributes: dict[str, str]) -> None:
        element = Element(tag, attributes, parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(element)
        else:
            found.append(element)
        stack.append(element)

    def end(tag: str) -> None:
        stack.pop()

    parser.StartElementHandler, parser.EndElementHandler = start, end
    try:
        parser.Parse(data.lstrip(), True)  # a blank line before <?xml is common and harmless
    except xml.parsers.expat.ExpatError:
        return None
    return found[0] if found else None


def read_urdf_tree(root: Element, path: Path) -> UrdfTree:
    """Every number of the URDF's links and joints, read as urdfdom reads them.

    Args:
        root: The ``<robot>`` element.
        path: The robot file, for messages.

    Returns:
        The links and joints.

    Raises:
        InputError: A number urdfdom would drop or misread (the field names the link or
            joint and the attribute), a zero or non-finite axis, an out-of-range value, a
            link that is the child of two joints, or a mimic multiplier or offset out of range.
    """
    links: dict[str, np.ndarray | None] = {}
    for element in root.all("link"):
        name = element.attributes.get("name", "")
        if name and name not in links:
            links[name] = _inertial(element.first("inertial"), name, path)
    joints: dict[str, UrdfJoint] = {}
    parents: dict[str, list[str]] = {}
    for element in root.all("joint"):
        name = element.attributes.get("name", "")
        if not name or name in joints:
            continue  # urdfdom refuses these with its own message
        joint = _joint(element, name, path)
        joints[name] = joint
        parents.setdefault(joint.child, []).append(name)
    for link, names in parents.items():
        if len(names) > 1:
            raise InputError(f"is the child of {len(names)} joints ({', '.join(names)}); a URDF "
                             "is a tree, each link the child of one joint (urdfdom would keep "
                             "one of them and lose the rest)", path=path, field=f"link[{link}]")
    return UrdfTree(links, joints)


def _inertial(element: Element | None, link: str, path: Path) -> np.ndarray | None:
    """A link's spatial inertia about its frame's origin, in its frame [kg, kg m, kg m^2]."""
    if element is None:
        return None
    where = f"link[{link}].inertial"
    mass_element = element.first("mass")
    if mass_element is None:
        raise InputError(f"has no <mass>; {DROPPED}", path=path, field=where)
    if "value" not in mass_element.attributes:
        raise InputError(f"<mass> has no value; {DROPPED}", path=path, field=f"{where}.mass")
    mass = _scalar(mass_element.attributes["value"], path, f"{where}.mass", DROPPED)
    bounds.ADDED_MASS.check(mass, path=path, field=f"{where}.mass")
    placement = _origin(element.first("origin"), path, f"{where}.origin", DROPPED)
    tensor_element = element.first("inertia")
    if tensor_element is None:
        raise InputError(f"has no <inertia>; {DROPPED}", path=path, field=where)
    values = {}
    for key in _INERTIA:
        if key not in tensor_element.attributes:
            raise InputError(f"<inertia> has no {key}; {DROPPED}", path=path,
                             field=f"{where}.inertia")
        values[key] = _scalar(tensor_element.attributes[key], path, f"{where}.inertia.{key}",
                              DROPPED)
        bounds.INERTIA.check(values[key], path=path, field=f"{where}.inertia.{key}")
    local = np.array([[values["ixx"], values["ixy"], values["ixz"]],
                      [values["ixy"], values["iyy"], values["iyz"]],
                      [values["ixz"], values["iyz"], values["izz"]]])
    rotation, com = placement.rotation, placement.translation
    cross = pin.skew(com)
    return np.block([[mass * np.eye(3), -mass * cross],
                     [mass * cross, rotation @ local @ rotation.T - mass * cross @ cross]])


def _joint(element: Element, name: str, path: Path) -> UrdfJoint:
    where = f"joint[{name}]"
    kind = element.attributes.get("type", "")
    parent, child = element.first("parent"), element.first("child")
    failed = f"urdfdom would refuse joint '{name}'"
    origin = _origin(element.first("origin"), path, f"{where}.origin", failed)
    axis = np.array([1.0, 0.0, 0.0])
    axis_element = element.first("axis")
    if axis_element is not None and "xyz" in axis_element.attributes:
        axis = _vector(axis_element.attributes["xyz"], path, f"{where}.axis", failed)
    if kind in MOVABLE and direction(axis) is None:
        raise InputError(f"the axis {_text(axis)} has no direction; give a unit vector such as "
                         "0 0 1", path=path, field=f"{where}.axis")
    limit = None
    limit_element = element.first("limit")
    if limit_element is not None and kind in MOVABLE:
        limit = _limit(limit_element, path, f"{where}.limit", failed, kind != "continuous")
    mimic = None
    mimic_element = element.first("mimic")
    if mimic_element is not None and kind in MOVABLE:
        attributes = mimic_element.attributes
        multiplier = _scalar(attributes.get("multiplier", "1"), path, f"{where}.mimic.multiplier",
                             failed)
        bounds.MIMIC_MULTIPLIER.check(multiplier, path=path, field=f"{where}.mimic.multiplier")
        offset = _scalar(attributes.get("offset", "0"), path, f"{where}.mimic.offset", failed)
        bounds.POSITION.check(offset, path=path, field=f"{where}.mimic.offset")
        mimic = MimicSpec(attributes.get("joint", ""), multiplier, offset)
    return UrdfJoint(name, kind, "" if parent is None else parent.attributes.get("link", ""),
                     "" if child is None else child.attributes.get("link", ""), origin, axis,
                     limit, mimic)


def direction(axis: np.ndarray) -> np.ndarray | None:
    """The unit vector along `axis` (no overflow for huge components); None when too short."""
    largest = float(np.abs(axis).max())
    if not largest > 1e-12:
        return None
    scaled = axis / largest
    return scaled / np.linalg.norm(scaled)


def _limit(element: Element, path: Path, where: str, failed: str, positions: bool) -> Limit:
    """A ``<limit>``: lower and upper (0 if not given) in range where `positions`, the rest >= 0."""
    values = {}
    for key in ("lower", "upper", "effort", "velocity"):
        text = element.attributes.get(key, "0")
        values[key] = _scalar(text, path, f"{where}.{key}", failed)
    for key in ("lower", "upper") if positions else ():
        bounds.POSITION.check(values[key], path=path, field=f"{where}.{key}")
    for key in ("effort", "velocity"):
        if values[key] < 0.0:
            raise InputError(f"is {values[key]:g}; a limit's {key} is a magnitude, 0 or more "
                             f"(urdfdom refuses a negative one)", path=path,
                             field=f"{where}.{key}")
    return Limit(**values)


def _origin(element: Element | None, path: Path, where: str, failed: str) -> pin.SE3:
    """An ``<origin xyz rpy>`` as a placement; each coordinate within `bounds.LENGTH` [m]."""
    if element is None:
        return pin.SE3.Identity()
    xyz = np.zeros(3)
    rpy = np.zeros(3)
    if "xyz" in element.attributes:
        xyz = _vector(element.attributes["xyz"], path, f"{where}.xyz", failed)
        for x in xyz:
            bounds.LENGTH.check(float(x), path=path, field=f"{where}.xyz")
    if "rpy" in element.attributes:
        rpy = _vector(element.attributes["rpy"], path, f"{where}.rpy", failed)
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)


def _scalar(text: str, path: Path, where: str, failed: str) -> float:
    """One number as urdfdom reads it: leading blanks allowed, nothing after it, finite."""
    if not _NUMBER.fullmatch(text.lstrip(" \t\r\n")):
        raise InputError(_not_read(text, "is not a number as URDF reads it", failed),
                         path=path, field=where)
    value = float(text)
    if not math.isfinite(value):
        raise InputError(_not_read(text, "is too large for a number", failed), path=path,
                         field=where)
    return value


def _vector(text: str, path: Path, where: str, failed: str) -> np.ndarray:
    """Three numbers separated by spaces, as urdfdom reads a vector."""
    pieces = [piece for piece in text.split(" ") if piece]
    if len(pieces) != 3 or not all(_NUMBER.fullmatch(piece) for piece in pieces):
        raise InputError(_not_read(text, "is not 3 numbers separated by spaces as URDF reads "
                                   "them", failed), path=path, field=where)
    values = np.array([float(piece) for piece in pieces])
    if not np.all(np.isfinite(values)):
        raise InputError(_not_read(text, "holds a number too large", failed), path=path,
                         field=where)
    return values


def _not_read(text: str, problem: str, failed: str) -> str:
    """Why a value is refused: what it is, what is wrong and what urdfdom would do."""
    shown = repr(text) if len(text) <= 40 else repr(text[:37] + "...")
    if "${" in text or "$(" in text:
        return (f"{shown} is an unexpanded xacro expression; name the file .xacro (or "
                ".urdf.xacro) so hdselect expands it with xacro")
    return f"{shown} {problem}; {failed}"


def _text(values: np.ndarray) -> str:
    return " ".join(f"{x:g}" for x in values)
