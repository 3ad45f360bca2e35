"""Read a robot file (URDF or MJCF) into a bare Pinocchio model, and say what was assumed.

Pinocchio decides what a valid robot file is; this module only makes its
answer usable. The parser's own messages (urdfdom prints them on the C++
standard error, MJCF errors carry them after ``message:``) are folded into one
line. Mimic joints are built as such: a follower has no degree of freedom and
moves with its leader. Only the bodies Pinocchio builds are checked
(`hdselect.robotcheck`), after it has merged every link on a fixed joint into
its moving body; an empty body (frame links such as ``tool0``) is skipped.
Armature, joint damping, friction and springs model the motor's and the joint's
own inertia and losses, not load on the gear output: they are set to zero and
reported. A second, lenient pass
over the XML (namespaces not resolved, so extensions such as ``drake:`` never
break it) only reads the order in which the file writes its joints.
"""

from __future__ import annotations

import logging
import os
import re
import sys
import tempfile
import xml.parsers.expat
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base.errors import InputError
from hdselect.robot.checks import check_bodies, check_geometry

logger = logging.getLogger(__name__)

LEG_MASS = 0.05
"""A chain leaving the root is a leg if it holds this fraction of the robot's mass [-] ..."""
LEG_DROP = 0.15
"""... and reaches this far below the root's centre of mass in the zero pose [m]."""

_MJCF_SUFFIXES = (".xml", ".mjcf")
_LOSSES = (("armature", "armature", "kg m^2"), ("damping", "damping", "N m s/rad"),
           ("friction", "friction", "N m"), ("rotorInertia", "rotor inertia", "kg m^2"))


@dataclass(frozen=True)
class Mimic:
    """A follower joint that moves with its leader: q = multiplier x q_leader + offset.

    Attributes:
        leader: The leading joint's name.
        multiplier: Follower motion per unit of leader motion [-].
        offset: Follower position when the leader is at zero [rad or m].
    """

    leader: str
    multiplier: float
    offset: float


@dataclass(frozen=True, eq=False)
class RobotFile:
    """What a robot file holds, as hdselect uses it.

    Attributes:
        model: Pinocchio model, mimic joints built, armature, damping and friction zero.
        root_link: The link held fixed to the world.
        mimic: Each follower joint's leader, by follower name.
        file_order: The movable, non-follower joints in the order the file writes them,
            or None when the file could not be scanned for it.
        notes: What was set aside or looks wrong, one line each.
        uncoupled_followers: Mimic followers Pinocchio could not couple to their leaders
            (it needs a leader before its followers in its tree order): independent joints
            of the model here, and noted so.
    """

    model: pin.Model
    root_link: str
    mimic: Mapping[str, Mimic]
    file_order: tuple[str, ...] | None
    notes: tuple[str, ...]
    uncoupled_followers: tuple[str, ...] = ()


def read_robot_file(path: Path) -> RobotFile:
    """Build the model of a robot file and check its bodies.

    Args:
        path: An existing URDF (``.urdf`` or any other suffix) or MJCF (``.xml``, ``.mjcf``).

    Returns:
        The model and what was assumed.

    Raises:
        InputError: Pinocchio rejects the file (the parser's reason folded into the
            message), or a body's inertia is not physical.
    """
    mjcf = path.suffix.lower() in _MJCF_SUFFIXES
    notes: list[str] = []
    uncoupled: tuple[str, ...] = ()
    try:
        model = _build(path, mjcf, mimic=not mjcf)
    except InputError as err:
        if mjcf or "mimic" not in err.reason:
            raise
        model = _build(path, mjcf, mimic=False)
        uncoupled = tuple(name for name in _mimic_followers(path) if model.existJointName(name))
        notes.append(f"Pinocchio cannot couple the mimic joints ({err.reason.split(': ', 1)[-1]}"
                     f"): {', '.join(uncoupled)} move as independent joints here, carry their "
                     "own load and are not sized unless named")
    losses = _set_aside_losses(model)
    notes += check_bodies(model, path)
    check_geometry(model, path)
    mimic = _mimic_joints(model)
    root = _root_link(model)
    notes += _free_body_note(model, root)
    order = None if mjcf else _file_joint_order(path, model, mimic)
    for note in notes:
        logger.warning("%s: %s", path, note)
    for note in losses:
        logger.info("%s: %s", path, note)
    notes = losses + notes
    return RobotFile(model, root, mimic, order, tuple(notes), uncoupled)


@contextmanager
def _stderr_captured() -> Iterator[list[str]]:
    """Collect what C++ code writes on standard error (file descriptor 2) meanwhile.

    Where descriptor 2 cannot be redirected (closed, say) the lines go where they
    always went.
    """
    lines: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield lines
        return
    with tempfile.TemporaryFile() as capture:
        os.dup2(capture.fileno(), 2)
        try:
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            capture.seek(0)
            lines.extend(capture.read().decode("utf-8", "replace").splitlines())


def _build(path: Path, mjcf: bool, *, mimic: bool) -> pin.Model:
    kind = "MJCF" if mjcf else "URDF"
    with _stderr_captured() as printed:
        try:
            if mjcf:
                model = pin.buildModelFromMJCF(str(path))
            else:
                model = pin.buildModelFromUrdf(str(path), mimic=mimic)
            error = None
        except (RuntimeError, ValueError) as err:
            error = err
    if error is not None:
        reason = _parser_reason(str(error), printed, path)
        raise InputError(f"not a valid {kind} robot: {reason}", path=path) from error
    for line in _messages(printed, path):
        logger.info("%s: parser: %s", path, line)
    return model


def _parser_reason(error: str, printed: list[str], path: Path) -> str:
    """One line from a parser's exception text and what it printed on standard error.

    Pinocchio's own text is generic ("does not contain a valid URDF model") or starts
    with C++ source locations; the reason is what urdfdom printed, or what follows
    ``message:`` in an MJCF error.

    Args:
        error: The exception's text.
        printed: Lines the parser wrote on standard error.
        path: The robot file (its line numbers are looked up for named joints and links).

    Returns:
        The reason, one line.
    """
    reasons = _messages(printed, path)
    if "message:" in error:
        reasons.append(" ".join(error.split("message:", 1)[1].split()))
    elif not reasons or "valid URDF model" not in error:
        lines = [line.strip() for line in error.strip().splitlines() if line.strip()]
        generic = [line for line in lines if not line.startswith(("From file:", "in function:",
                                                                  "at line:"))]
        reasons.append(" ".join(generic or lines[:1] or ["rejected by the parser"]))
    unique = list(dict.fromkeys(r.rstrip(".") for r in reasons if r))
    return "; ".join(unique)


_TINYXML = re.compile(r"Error=XML_ERROR_(\w+) ErrorID=\d+ \(0x[0-9a-f]+\) Line number=(\d+)"
                      r"(?::\s*(.*))?")
_NAMED = re.compile(r"(Joint|joint|Link|link) \[([^\]]+)\]")


def _messages(printed: list[str], path: Path) -> list[str]:
    """The parser's ``Error:`` and ``Warning:`` lines, without their C++ source locations."""
    messages = []
    for line in printed:
        text = line.strip()
        if not text or re.match(r"at line \d+ in \S+\.(cpp|hpp|h)$", text):
            continue
        text = re.sub(r"^(Error|Warning|Info|Debug):\s*", "", text)
        xml_error = _TINYXML.search(text)
        if xml_error:
            kind, line_no, detail = xml_error.groups()
            text = (f"malformed XML at line {line_no} ({kind.lower().replace('_', ' ')}"
                    f"{': ' + detail.strip() if detail else ''})")
        else:
            named = _NAMED.search(text)
            line_no = _element_line(path, named.group(1).lower(), named.group(2)) if named \
                else None
            if line_no is not None:
                text = f"{text} (line {line_no})"
        messages.append(text)
    return messages


def _element_line(path: Path, tag: str, name: str) -> int | None:
    """The line of the first ``<tag name="name">`` of a file, if a lenient scan finds it."""
    found: list[int] = []
    parser = xml.parsers.expat.ParserCreate()

    def start(element: str, attributes: dict[str, str]) -> None:
        if not found and element == tag and attributes.get("name") == name:
            found.append(parser.CurrentLineNumber)

    parser.StartElementHandler = start
    try:
        parser.Parse(path.read_bytes(), True)
    except (xml.parsers.expat.ExpatError, OSError):
        pass
    return found[0] if found else None


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


def _mimic_joints(model: pin.Model) -> dict[str, Mimic]:
    mimic = {}
    for follower, leader in zip(model.mimicking_joints, model.mimicked_joints, strict=True):
        joint = model.joints[follower].extract()
        mimic[model.names[follower]] = Mimic(model.names[leader], float(joint.scaling),
                                             float(joint.offset))
    return mimic


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


def _mimic_followers(path: Path) -> list[str]:
    """Names of the joints a URDF gives a ``<mimic>`` element, by a lenient scan."""
    followers: list[str] = []
    joint: list[str] = []
    parser = xml.parsers.expat.ParserCreate()

    def start(element: str, attributes: dict[str, str]) -> None:
        if element == "joint" and "name" in attributes:
            joint[:] = [attributes["name"]]
        elif element == "mimic" and joint:
            followers.append(joint[0])

    parser.StartElementHandler = start
    try:
        parser.Parse(path.read_bytes(), True)
    except (xml.parsers.expat.ExpatError, OSError):
        return followers
    return followers


def _file_joint_order(path: Path, model: pin.Model, mimic: Mapping[str, Mimic]
                      ) -> tuple[str, ...] | None:
    """The model's degrees of freedom in the order the URDF writes its ``<joint>`` elements."""
    names: list[str] = []
    depth = [0]
    parser = xml.parsers.expat.ParserCreate()

    def start(element: str, attributes: dict[str, str]) -> None:
        depth[0] += 1
        if depth[0] == 2 and element == "joint" and "name" in attributes:
            names.append(attributes["name"])

    def end(element: str) -> None:
        depth[0] -= 1

    parser.StartElementHandler, parser.EndElementHandler = start, end
    try:
        parser.Parse(path.read_bytes(), True)
    except (xml.parsers.expat.ExpatError, OSError):
        return None
    dofs = {model.names[j] for j in range(1, model.njoints)
            if model.joints[j].nv > 0 and model.names[j] not in mimic}
    order = tuple(n for n in dict.fromkeys(names) if n in dofs)
    return order if len(order) == len(dofs) else None
