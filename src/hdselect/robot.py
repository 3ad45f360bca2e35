"""Load a fixed-base arm (URDF or MJCF) into a Pinocchio model with payload and mounting.

Only kinematics and inertias are read; mesh files are never opened, so a robot
file whose meshes are absent still loads.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pinocchio as pin

from hdselect.arrays import frozen
from hdselect.errors import InputError

logger = logging.getLogger(__name__)

STANDARD_GRAVITY = 9.80665
"""Standard gravity [m/s^2]."""

MOUNTINGS = {
    "floor": (0.0, 0.0, -STANDARD_GRAVITY),
    "ceiling": (0.0, 0.0, STANDARD_GRAVITY),
    "wall": (-STANDARD_GRAVITY, 0.0, 0.0),
}
"""Gravity in the base frame [m/s^2] for each named mounting. On a wall the base z
axis is horizontal and gravity points along the base's -x axis."""

_REVOLUTE = ("RX", "RY", "RZ", "RevoluteUnaligned", "RUBX", "RUBY", "RUBZ",
             "RevoluteUnboundedUnaligned")
_PRISMATIC = ("PX", "PY", "PZ", "PrismaticUnaligned")


@dataclass(frozen=True)
class Payload:
    """A rigid payload attached to a frame of the robot.

    Attributes:
        mass: Mass [kg], positive.
        com: Centre of mass in the frame it is attached to [m], shape (3,).
        inertia: Rotational inertia about the centre of mass, frame axes [kg m^2], (3, 3),
            symmetric positive semi-definite.
        frame: Name of the frame it is attached to; None means the last link.

    Raises:
        InputError: A value is not finite or not physical (the field names it).
    """

    mass: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[tuple[float, ...], ...] = ((0.0,) * 3,) * 3
    frame: str | None = None

    def __post_init__(self) -> None:
        mass = _finite_array(self.mass, (), "payload.mass")
        if not mass > 0.0:
            raise InputError(f"must be a positive mass [kg], got {float(mass):g}",
                             field="payload.mass")
        com = _finite_array(self.com, (3,), "payload.com")
        inertia = _finite_array(self.inertia, (3, 3), "payload.inertia")
        if not np.allclose(inertia, inertia.T) or np.linalg.eigvalsh(inertia)[0] < -1e-12:
            raise InputError("must be symmetric positive semi-definite [kg m^2]",
                             field="payload.inertia")
        if self.frame is not None and not isinstance(self.frame, str):
            raise InputError(f"expected a frame name, got {self.frame!r}", field="payload.frame")
        object.__setattr__(self, "mass", float(mass))
        object.__setattr__(self, "com", tuple(float(c) for c in com))
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in row)
                                                  for row in inertia))


def _finite_array(value: object, shape: tuple[int, ...], field: str) -> np.ndarray:
    """`value` as a float array of `shape` with every element finite.

    Raises:
        InputError: It is not.
    """
    if isinstance(value, bool | str) or (isinstance(value, Sequence)
                                          and any(isinstance(v, bool | str) for v in value)):
        raise InputError(f"expected numbers, got {value!r}", field=field)
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as err:
        raise InputError(f"expected numbers, got {value!r}", field=field) from err
    if array.shape != shape:
        raise InputError(f"expected shape {shape or 'a single number'}, got {value!r}",
                         field=field)
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        index = "".join(f"[{i}]" for i in bad[0])
        raise InputError(f"must be finite, got {array[tuple(bad[0])]}", field=field + index)
    return array


@dataclass(frozen=True, eq=False)
class Robot:
    """A loaded arm, ready for planning and inverse dynamics.

    A Robot is immutable. Payload, mounting, gearhead masses and the choice of
    joints to size are transformations that return a new Robot
    (`with_payload`, `with_mounting`, `with_gearheads`, `with_sized_joints`),
    so one loaded file serves any number of variants.

    Attributes:
        path: The robot file it came from.
        model: Pinocchio model with the payload and gearhead masses attached and gravity set.
        joint_names: Name of every degree of freedom, in the model's velocity order.
        revolute: True for revolute and continuous joints, per degree of freedom.
        sized_joints: Names of the joints that get a gearhead.
        lower: Lower position limit per degree of freedom [rad or m] (-inf if none).
        upper: Upper position limit per degree of freedom [rad or m] (+inf if none).
        velocity_limit: URDF velocity limit per degree of freedom [rad/s or m/s].
        effort_limit: URDF effort limit per degree of freedom [N m or N].
        gravity: Gravity in the base frame [m/s^2], shape (3,).
        payload: The attached payload, if any.
        gearhead_masses: Point mass mounted at each named joint's origin, on the link
            before it (a gearhead and its motor) [kg].
    """

    path: Path
    model: pin.Model
    joint_names: tuple[str, ...]
    revolute: tuple[bool, ...]
    sized_joints: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity_limit: np.ndarray
    effort_limit: np.ndarray
    gravity: np.ndarray
    payload: Payload | None = None
    gearhead_masses: Mapping[str, float] = field(default_factory=dict)
    _q_index: tuple[tuple[int, int], ...] = field(default=(), repr=False)
    _bare: pin.Model | None = field(default=None, repr=False)

    @property
    def dof(self) -> int:
        """Number of degrees of freedom."""
        return len(self.joint_names)

    def joint_index(self, name: str, *, source: str | Path | None = None, field: str = "") -> int:
        """Index of a joint in the velocity order.

        Raises:
            InputError: No joint has that name; the message lists the valid ones.
        """
        if name not in self.joint_names:
            raise InputError(
                f"unknown joint '{name}'; joints are: {', '.join(self.joint_names)}",
                path=source, field=field or None,
            )
        return self.joint_names.index(name)

    def configuration(self, positions: np.ndarray) -> np.ndarray:
        """Pinocchio configurations for joint positions.

        Args:
            positions: Joint positions [rad or m], shape (n, dof).

        Returns:
            Configurations, Fortran-ordered, shape (nq, n). Continuous joints
            become (cos, sin) pairs.
        """
        positions = np.atleast_2d(positions)
        config = np.empty((self.model.nq, positions.shape[0]), order="F")
        for dof, (iq, nq) in enumerate(self._q_index):
            if nq == 1:
                config[iq] = positions[:, dof]
            else:
                config[iq] = np.cos(positions[:, dof])
                config[iq + 1] = np.sin(positions[:, dof])
        return config

    def with_payload(self, payload: Payload | None) -> Robot:
        """The same robot carrying `payload` instead of its current one (None: no payload).

        Raises:
            InputError: The payload's frame does not exist or does not move.
        """
        return self._rebuilt(payload=payload)

    def with_mounting(self, mounting: str | Sequence[float]) -> Robot:
        """The same robot mounted otherwise.

        Args:
            mounting: ``"floor"``, ``"wall"``, ``"ceiling"`` or a gravity vector in the
                base frame [m/s^2].

        Raises:
            InputError: The mounting is not one of these.
        """
        return self._rebuilt(gravity=frozen(gravity_of(mounting)))

    def with_gearheads(self, masses: Mapping[str, float]) -> Robot:
        """The same robot carrying a point mass at the origin of each named joint.

        Each mass (a gearhead and its motor) is bolted to the link before its joint,
        centred on the joint axis: carried by every joint nearer the base and by none
        further out. Its rotor inertia spinning on a moving link is neglected.

        Args:
            masses: Mass mounted at each joint [kg]; replaces the current masses.
        """
        for name in masses:
            self.joint_index(name, field="gearhead_masses")
        return self._rebuilt(gearhead_masses=MappingProxyType(dict(masses)))

    def with_sized_joints(self, joints: Sequence[str] | None) -> Robot:
        """The same robot with another choice of joints to size (None: every rotary joint).

        Raises:
            InputError: A name is unknown or names a prismatic joint.
        """
        return replace(self, sized_joints=_sized(self.joint_names, self.revolute, joints,
                                                 self.path))

    def carried_mass(self, joint: str) -> float:
        """Total of the gearhead masses mounted on links that `joint` moves [kg]."""
        model = self.model
        joint_id = model.getJointId(joint)
        total = 0.0
        for name, mass in self.gearhead_masses.items():
            ancestor = model.parents[model.getJointId(name)]
            while ancestor > joint_id:
                ancestor = model.parents[ancestor]
            if ancestor == joint_id:
                total += mass
        return total

    @property
    def payload_frame(self) -> str | None:
        """The frame the payload is attached to: its own, or the last link; None without one."""
        if self.payload is None:
            return None
        return self.payload.frame or _last_link(self.model)

    @property
    def _bare_model(self) -> pin.Model:
        return self._bare if self._bare is not None else self.model

    def _rebuilt(self, **changes: object) -> Robot:
        """A copy with `changes` applied and its model rebuilt from the file's bare model."""
        robot = replace(self, **changes)  # type: ignore[arg-type]
        bare = self._bare_model
        model = pin.Model(bare)
        if robot.payload is not None:
            frame = _payload_frame(model, robot.payload, robot.path)
            model.appendBodyToJoint(frame.parentJoint, pin.Inertia(
                robot.payload.mass, np.array(robot.payload.com), np.array(robot.payload.inertia)),
                frame.placement)
        for name, mass in robot.gearhead_masses.items():
            joint_id = model.getJointId(name)
            parent = model.parents[joint_id]
            if mass > 0.0 and parent > 0:
                point = pin.Inertia(mass, np.zeros(3), np.zeros((3, 3)))
                model.appendBodyToJoint(parent, point, model.jointPlacements[joint_id])
        model.gravity.linear = np.array(robot.gravity)
        return replace(robot, model=model, _bare=bare)


def load_robot(
    path: str | Path,
    *,
    payload: Payload | None = None,
    mounting: str | Sequence[float] = "floor",
    joints: Sequence[str] | None = None,
) -> Robot:
    """Load a fixed-base robot from a URDF or MJCF file.

    Args:
        path: The robot file (``.urdf``; ``.xml`` or ``.mjcf`` for MJCF).
        payload: A payload to attach, if any (same as `Robot.with_payload`).
        mounting: ``"floor"``, ``"wall"``, ``"ceiling"`` or a gravity vector in the
            base frame [m/s^2] (same as `Robot.with_mounting`).
        joints: Joints to size; default every revolute and continuous joint.

    Returns:
        The loaded robot.

    Raises:
        InputError: The file is missing or malformed, a link's inertia is not
            physically consistent, a joint type is not supported, or an option
            names an unknown frame or joint.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError("file not found", path=path)
    model = _build_model(path)
    names, revolute, q_index = _joints(model, path)
    _check_inertias(model, path)
    lower, upper = _position_limits(model, q_index)
    robot = Robot(
        path=path,
        model=model,
        joint_names=names,
        revolute=revolute,
        sized_joints=_sized(names, revolute, joints, path),
        lower=frozen(lower),
        upper=frozen(upper),
        velocity_limit=frozen(model.velocityLimit),
        effort_limit=frozen(model.effortLimit),
        gravity=frozen(gravity_of(mounting)),
        _q_index=q_index,
    )
    skipped = [n for n, r in zip(names, revolute, strict=True) if not r]
    if skipped:
        logger.info("prismatic joints are reported but not sized: %s", ", ".join(skipped))
    return robot._rebuilt(payload=payload)


def _build_model(path: Path) -> pin.Model:
    try:
        if path.suffix.lower() in (".xml", ".mjcf"):
            return pin.buildModelFromMJCF(str(path))
        return pin.buildModelFromUrdf(str(path))
    except (RuntimeError, ValueError) as err:
        kind = "MJCF" if path.suffix.lower() in (".xml", ".mjcf") else "URDF"
        first_line = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise InputError(f"not a valid {kind} robot: {first_line}", path=path) from err


def _joints(model: pin.Model, path: Path):
    names: list[str] = []
    revolute: list[bool] = []
    q_index: list[tuple[int, int]] = []
    for joint_id in range(1, model.njoints):
        joint = model.joints[joint_id]
        kind = joint.shortname().removeprefix("JointModel")
        if kind not in _REVOLUTE + _PRISMATIC:
            raise InputError(
                f"joint '{model.names[joint_id]}' is of type {kind}; only revolute, continuous "
                "and prismatic joints of a fixed-base arm are supported",
                path=path,
            )
        names.append(model.names[joint_id])
        revolute.append(kind in _REVOLUTE)
        q_index.append((joint.idx_q, joint.nq))
    if not names:
        raise InputError("the robot has no movable joint", path=path)
    return tuple(names), tuple(revolute), tuple(q_index)


def _position_limits(model: pin.Model, q_index) -> tuple[np.ndarray, np.ndarray]:
    lower = np.full(len(q_index), -np.inf)
    upper = np.full(len(q_index), np.inf)
    for dof, (iq, nq) in enumerate(q_index):
        lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
        if nq == 1 and np.isfinite(lo) and np.isfinite(hi) and hi > lo:
            lower[dof], upper[dof] = lo, hi
    return lower, upper


def _sized(names, revolute, joints, path) -> tuple[str, ...]:
    if joints is None:
        return tuple(n for n, r in zip(names, revolute, strict=True) if r)
    if isinstance(joints, str):
        raise InputError(f"expected a list of joint names, got {joints!r}", path=path,
                         field="joints")
    chosen = []
    for name in joints:
        if name not in names:
            raise InputError(f"unknown joint '{name}'; joints are: {', '.join(names)}",
                             path=path, field="--joint")
        if not revolute[names.index(name)]:
            raise InputError(f"joint '{name}' is prismatic; only rotary joints take a gearhead",
                             path=path, field="--joint")
        chosen.append(name)
    return tuple(n for n in names if n in chosen)


def gravity_of(mounting: str | Sequence[float]) -> np.ndarray:
    """Gravity in the base frame [m/s^2] for a named mounting or a gravity vector.

    Raises:
        InputError: The mounting is neither a known name nor three finite numbers.
    """
    if isinstance(mounting, str):
        if mounting not in MOUNTINGS:
            raise InputError(f"unknown mounting '{mounting}'; choose one of: "
                             f"{', '.join(MOUNTINGS)} or a gravity vector", field="mounting")
        return np.array(MOUNTINGS[mounting])
    try:
        gravity = np.asarray(mounting, dtype=float)
    except (TypeError, ValueError) as err:
        raise InputError("gravity must be three finite numbers [m/s^2]",
                         field="mounting") from err
    if gravity.shape != (3,) or not np.all(np.isfinite(gravity)):
        raise InputError("gravity must be three finite numbers [m/s^2]", field="mounting")
    return gravity


def _payload_frame(model: pin.Model, payload: Payload, path: Path) -> pin.Frame:
    """The frame a payload is attached to: its own, or the last link's."""
    frame_name = payload.frame or _last_link(model)
    if not model.existFrame(frame_name):
        bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        raise InputError(f"unknown frame '{frame_name}' for the payload; links are: "
                         f"{', '.join(bodies)}", path=path, field="payload.frame")
    frame = model.frames[model.getFrameId(frame_name)]
    if frame.parentJoint == 0:
        raise InputError(f"frame '{frame_name}' does not move; a payload there loads no joint",
                         path=path, field="payload.frame")
    return frame


def _last_link(model: pin.Model) -> str:
    deepest = model.njoints - 1
    bodies = [f.name for f in model.frames
              if f.type == pin.FrameType.BODY and f.parentJoint == deepest]
    return bodies[-1]


def _check_inertias(model: pin.Model, path: Path) -> None:
    """Every moving link must have a physically consistent inertia."""
    moving = {f.name for f in model.frames
              if f.type == pin.FrameType.BODY and f.parentJoint != 0}
    if path.suffix.lower() == ".urdf":
        for link, mass, inertia in _urdf_inertials(path):
            if link in moving:
                _check_one(link, mass, inertia, path)
    else:
        for joint_id in range(1, model.njoints):
            body = model.inertias[joint_id]
            if body.mass > 0.0 or np.any(body.inertia != 0.0):
                _check_one(model.names[joint_id], body.mass, body.inertia, path)


def _urdf_inertials(path: Path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        raise InputError(f"not valid XML: {err}", path=path) from err
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        name = link.get("name", "?")
        mass_el, inertia_el = inertial.find("mass"), inertial.find("inertia")
        try:
            mass = float(mass_el.get("value", "nan")) if mass_el is not None else 0.0
            keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
            i = {k: float(inertia_el.get(k, "0")) for k in keys} if inertia_el is not None \
                else dict.fromkeys(keys, 0.0)
        except ValueError as err:
            raise InputError(f"link '{name}': inertial values must be numbers", path=path,
                             field=f"link[{name}].inertial") from err
        tensor = np.array([[i["ixx"], i["ixy"], i["ixz"]],
                           [i["ixy"], i["iyy"], i["iyz"]],
                           [i["ixz"], i["iyz"], i["izz"]]])
        yield name, mass, tensor


def _check_one(link: str, mass: float, inertia: np.ndarray, path: Path) -> None:
    field = f"link[{link}].inertial"
    if not np.isfinite(mass) or mass <= 0.0:
        raise InputError(f"link '{link}' has mass {mass:g} kg; a moving link with an "
                         "inertial must have positive mass", path=path, field=field)
    if not np.all(np.isfinite(inertia)):
        raise InputError(f"link '{link}' has a non-finite inertia", path=path, field=field)
    moments = np.linalg.eigvalsh(inertia)
    scale = max(float(moments[-1]), 1e-12)
    if moments[0] <= 1e-9 * scale:
        raise InputError(f"link '{link}' inertia is not positive definite (principal moments "
                         f"{', '.join(f'{m:.3g}' for m in moments)} kg m^2)", path=path,
                         field=field)
    if moments[0] + moments[1] < moments[2] * (1.0 - 1e-6):
        raise InputError(f"link '{link}' inertia violates the triangle inequality (principal "
                         f"moments {', '.join(f'{m:.3g}' for m in moments)} kg m^2)",
                         path=path, field=field)
