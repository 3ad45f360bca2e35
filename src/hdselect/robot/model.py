"""Load a fixed-base arm (URDF, xacro or MJCF) into a Pinocchio model with payload and mounting.

Only kinematics and inertias are read; mesh files are never opened, so a robot
file whose meshes are absent still loads.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.arrays import frozen
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import readable
from hdselect.robot.checks import model_limit
from hdselect.robot.mounting import NAMED_BASES, BasePose, Mounting, base_pose_of, gravity_of
from hdselect.robot.payload import Payload, payload_frame, tip_frame
from hdselect.robot.reading import Mimic, read_robot_file
from hdselect.robot.xacrofile import xacro_arguments

logger = logging.getLogger(__name__)


_REVOLUTE = ("RX", "RY", "RZ", "RevoluteUnaligned", "RUBX", "RUBY", "RUBZ",
             "RevoluteUnboundedUnaligned")


_PRISMATIC = ("PX", "PY", "PZ", "PrismaticUnaligned")


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
        payload_chain: The joints whose longest chain ends where a payload without a frame
            goes: every rotary joint not excluded, whichever of them are sized (empty: the
            sized joints).
        lower: Lower position limit per degree of freedom [rad or m] (-inf if none).
        upper: Upper position limit per degree of freedom [rad or m] (+inf if none).
        velocity_limit: URDF velocity limit per degree of freedom [rad/s or m/s].
        effort_limit: URDF effort limit per degree of freedom [N m or N].
        gravity: Gravity in the base frame [m/s^2], shape (3,).
        payload: The attached payload, if any.
        parts: Parts carried besides the payload, each its own body (`with_parts`).
        gearhead_masses: Point mass mounted at each named joint's origin, on the link
            before it (a gearhead and its motor) [kg].
        root_link: The link held fixed to the world (the base).
        mimic: Follower joints (no degree of freedom of their own: each moves with its
            leader and gets no gearhead), by name.
        file_order: The degrees of freedom in the order the file writes them, when known.
        notes: What loading set aside or found suspicious in the file, one line each.
        uncoupled_followers: Mimic followers Pinocchio could not couple to their leaders:
            degrees of freedom here, not sized unless named.
        xacro_args: The xacro arguments the file was expanded with (a ``.xacro`` file).
        base_pose: Where the base sits in the world (z up), which `gravity` follows from;
            None when the mounting was given as a gravity vector alone.
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
    root_link: str = ""
    mimic: Mapping[str, Mimic] = field(default_factory=dict)
    file_order: tuple[str, ...] | None = None
    notes: tuple[str, ...] = ()
    uncoupled_followers: tuple[str, ...] = ()
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    base_pose: BasePose | None = NAMED_BASES["floor"]
    payload_chain: tuple[str, ...] = ()
    parts: tuple[Payload, ...] = ()
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
        bounds.expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
        return self._rebuilt(payload=payload)

    def with_parts(self, parts: Sequence[Payload]) -> Robot:
        """The same robot with `parts` as its parts, each a body at its frame (default: payload's).

        Raises:
            InputError: A part is not a Payload, or its frame does not exist or does not move.
        """
        if not isinstance(parts, tuple | list) or not all(isinstance(p, Payload) for p in parts):
            raise InputError(f"expected a sequence of Payloads, got {parts!r}", field="parts")
        return self._rebuilt(parts=tuple(parts))

    def with_mounting(self, mounting: Mounting) -> Robot:
        """The same robot mounted otherwise.

        Args:
            mounting: ``"floor"``, ``"wall"``, ``"ceiling"``, a `BasePose` in the world, or
                a gravity vector in the base frame [m/s^2] (which places no base in the
                world: tool poses then cannot be solved).

        Raises:
            InputError: The mounting is not one of these.
        """
        return self._rebuilt(gravity=frozen(gravity_of(mounting)),
                             base_pose=base_pose_of(mounting))

    def with_gearheads(self, masses: Mapping[str, float]) -> Robot:
        """The same robot carrying a point mass at the origin of each named joint.

        Each mass (a gearhead and its motor) is bolted to the link before its joint,
        centred on the joint axis: carried by every joint nearer the base and by none
        further out. Its rotor inertia spinning on a moving link is neglected.

        Args:
            masses: Mass mounted at each joint [kg]; replaces the current masses.
        """
        bounds.expect_type(masses, Mapping, "masses", "a mapping of joint name to mass [kg]")
        for name, mass in masses.items():
            bounds.expect_type(name, str, "masses", "joint names")
            self.joint_index(name, field="masses")
            bounds.ADDED_MASS.check(mass, field=f"masses.{name}")
        return self._rebuilt(gearhead_masses=MappingProxyType(dict(masses)))

    def with_sized_joints(self, joints: Sequence[str] | None,
                          exclude: Sequence[str] = ()) -> Robot:
        """The same robot with another choice of joints to size.

        Joints left out still move and load the others; they get no gearhead. A
        payload without a frame follows `default_payload_frame`, which `exclude`
        moves and `joints` does not.

        Args:
            joints: The joints to size; None: every revolute and continuous joint.
            exclude: Joints not to size, taken out of `joints` (or out of the default).

        Raises:
            InputError: A name is unknown, names a prismatic or a mimic follower joint,
                or no joint is left to size.
        """
        sized, chain = _sized(self, joints, exclude), _sized(self, None, exclude)
        if any(body.frame is None for body in (*self.parts, self.payload) if body is not None):
            return self._rebuilt(sized_joints=sized, payload_chain=chain)
        return replace(self, sized_joints=sized, payload_chain=chain)

    def joint_type(self, name: str) -> str:
        """``"revolute"``, ``"continuous"``, ``"prismatic"`` or ``"mimic"`` (a follower)."""
        if name in self.mimic:
            return "mimic"
        j = self.joint_index(name)
        if not self.revolute[j]:
            return "prismatic"
        return "continuous" if self._q_index[j][1] == 2 else "revolute"

    def moved_mass(self, joint: str) -> float:
        """Mass of everything `joint` moves: links, payload and gearheads further out [kg]."""
        model = self.model
        return float(sum(model.inertias[k].mass for k in model.subtrees[model.getJointId(joint)]))

    @property
    def default_payload_frame(self) -> str:
        """Where a payload without a frame goes: the tip of the longest chain of rotary joints.

        The chain is of the joints not excluded from sizing (`payload_chain`): choosing
        which of them to size does not move the payload or the tool. Its length counts
        those joints from the base; of equally long chains
        the first in the model's order wins. Its tip is a tool frame its last joint
        moves rigidly (a link named like ``tool0``, ``*_tcp``, ``ee_link``,
        ``end_effector``, ``flange``), else that joint's own link.
        """
        return tip_frame(self._bare_model, self.payload_chain or self.sized_joints)

    @property
    def payload_frame(self) -> str:
        """The frame the payload is (or a payload would be) attached to."""
        frame = self.payload.frame if self.payload is not None else None
        return frame or self.default_payload_frame

    def carried_mass(self, joint: str, masses: Mapping[str, float] | None = None) -> float:
        """Total of the gearhead masses mounted on links that `joint` moves [kg].

        Args:
            joint: The joint.
            masses: Mass mounted at each joint [kg] (as `with_gearheads` takes them);
                None: this robot's own.
        """
        model = self.model
        joint_id = model.getJointId(joint)
        total = 0.0
        for name, mass in (self.gearhead_masses if masses is None else masses).items():
            ancestor = model.parents[model.getJointId(name)]
            while ancestor > joint_id:
                ancestor = model.parents[ancestor]
            if ancestor == joint_id:
                total += mass
        return total

    @property
    def _bare_model(self) -> pin.Model:
        return self._bare if self._bare is not None else self.model

    def _rebuilt(self, **changes: object) -> Robot:
        """A copy with `changes` applied and its model rebuilt from the file's bare model."""
        robot = replace(self, **changes)  # type: ignore[arg-type]
        bare = self._bare_model
        model = pin.Model(bare)
        for body in filter(None, (robot.payload, *robot.parts)):
            default = robot.payload_frame if body.frame is None else ""
            frame = payload_frame(model, body, robot.path, default)
            model.appendBodyToJoint(frame.parentJoint, pin.Inertia(
                body.mass, np.array(body.com), np.array(body.inertia)), frame.placement)
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
    mounting: Mounting = "floor",
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] = (),
    xacro_args: Mapping[str, str | float] | None = None,
) -> Robot:
    """Load a fixed-base robot from a URDF, xacro or MJCF file.

    Args:
        path: The robot file: URDF, ``.xacro`` (expanded with the xacro package) or
            MJCF (compiled by MuJoCo); told apart by the suffix ``.xacro`` and the
            document's root element (``<robot>``, ``<mujoco>``).
        payload: A payload to attach, if any (same as `Robot.with_payload`).
        mounting: ``"floor"``, ``"wall"``, ``"ceiling"``, a `BasePose` or a gravity vector
            in the base frame [m/s^2] (same as `Robot.with_mounting`).
        joints: Joints to size; default every revolute and continuous joint that
            is not a mimic follower.
        exclude: Joints not to size (they still move and load the others).
        xacro_args: Values of a ``.xacro`` file's ``xacro:arg`` arguments, by name (as
            ``--xacro-arg name:=value`` gives them).

    Returns:
        The loaded robot.

    Raises:
        InputError: The file is missing or SDF; xacro, Pinocchio or MuJoCo rejects it
            (their reason in the message); a number of the file is not read as its
            format defines it; a body's inertia is not physical; a joint type is not
            supported; or an option names an unknown frame or joint.
    """
    path = bounds.file_argument(path, "path")
    bounds.expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    arguments = xacro_arguments(xacro_args)
    copy = readable(path)  # checked; a FIFO read once
    try:
        file = read_robot_file(copy, arguments)
    except InputError as err:
        if copy == path or err.path != copy:
            raise
        raise InputError(err.reason, path=path, field=err.field) from err
    model = file.model
    names, revolute, q_index = _joints(model, path)
    lower, upper = _position_limits(model, names, q_index, path)
    robot = Robot(
        path=path,
        model=model,
        joint_names=names,
        revolute=revolute,
        sized_joints=(),
        lower=frozen(lower),
        upper=frozen(upper),
        velocity_limit=frozen(model_limit(model, "upperVelocityLimit", "velocityLimit")),
        effort_limit=frozen(model_limit(model, "upperEffortLimit", "effortLimit")),
        gravity=frozen(gravity_of(mounting)),
        base_pose=base_pose_of(mounting),
        root_link=file.root_link,
        mimic=file.mimic,
        file_order=file.file_order,
        notes=file.notes,
        uncoupled_followers=file.uncoupled_followers,
        xacro_args=arguments,
        _q_index=q_index,
    )
    robot = replace(robot, sized_joints=_sized(robot, joints, exclude),
                    payload_chain=_sized(robot, None, exclude))
    skipped = [n for n, r in zip(names, revolute, strict=True) if not r]
    if skipped:
        logger.info("prismatic joints are reported but not sized: %s", ", ".join(skipped))
    return robot._rebuilt(payload=payload)


def _joints(model: pin.Model, path: Path):
    names: list[str] = []
    revolute: list[bool] = []
    q_index: list[tuple[int, int]] = []
    for joint_id in range(1, model.njoints):
        joint = model.joints[joint_id]
        kind = joint.shortname().removeprefix("JointModel")
        if kind == "Mimic":
            continue  # a follower: no degree of freedom of its own
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


def _position_limits(model: pin.Model, names: Sequence[str], q_index,
                     path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Each single-coordinate joint's limits as the file gives them (+-inf where it gives none).

    Raises:
        InputError: A limit is NaN, or a joint's lower limit is not below its upper one.
    """
    lower = np.full(len(q_index), -np.inf)
    upper = np.full(len(q_index), np.inf)
    for dof, (iq, nq) in enumerate(q_index):
        if nq != 1:  # a continuous joint: (cos, sin), no limits
            continue
        lo, hi = float(model.lowerPositionLimit[iq]), float(model.upperPositionLimit[iq])
        name = names[dof]
        if math.isnan(lo) or math.isnan(hi):
            raise InputError(f"joint '{name}' has a position limit that is not a number",
                             path=path, field=f"joint[{name}].limit")
        if hi <= lo:
            relation = "equals" if hi == lo else "is above"
            raise InputError(f"joint '{name}': the lower limit {lo:g} {relation} the upper limit "
                             f"{hi:g}; give lower < upper (a joint that cannot move is a fixed "
                             "joint)", path=path, field=f"joint[{name}].limit")
        for value in (lo, hi):
            if math.isfinite(value):
                bounds.POSITION.check(value, path=path, field=f"joint[{name}].limit")
        lower[dof], upper[dof] = lo, hi
    return lower, upper


def _sized(robot: Robot, joints: Sequence[str] | None, exclude: Sequence[str]
           ) -> tuple[str, ...]:
    """The joints to size: `joints` (default every rotary non-follower joint) minus `exclude`."""
    names, path = robot.joint_names, robot.path
    for option, given in (("joints", joints), ("exclude", exclude)):
        if given is not None and (isinstance(given, str | bytes) or not isinstance(given, Sequence)
                                  or any(not isinstance(name, str) for name in given)):
            raise InputError(f"expected a list of joint names, got {given!r}", path=path,
                             field=option)
        for name in given or ():
            _known(robot, name, option)
    if joints is None:
        chosen = {n for n, r in zip(names, robot.revolute, strict=True)
                  if r and n not in robot.uncoupled_followers}
    else:
        for name in joints:
            if not robot.revolute[names.index(name)]:
                raise InputError(f"joint '{name}' is prismatic; only rotary joints take a "
                                 "gearhead", path=path, field="joints")
        chosen = set(joints)
    chosen -= set(exclude)
    if not chosen and (joints is not None or exclude):
        raise InputError("no joint left to size; rotary joints are: "
                         + ", ".join(n for n, r in zip(names, robot.revolute, strict=True) if r),
                         path=path, field="exclude" if exclude else "joints")
    return tuple(n for n in names if n in chosen)


def _known(robot: Robot, name: str, option: str) -> None:
    """Reject a name that is not a degree of freedom, explaining a mimic follower."""
    if name in robot.mimic:
        raise InputError(f"joint '{name}' follows '{robot.mimic[name].leader}' (mimic) and gets "
                         "no gearhead of its own; its leader carries its load",
                         path=robot.path, field=option)
    if name not in robot.joint_names:
        raise InputError(f"unknown joint '{name}'; joints are: {', '.join(robot.joint_names)}",
                         path=robot.path, field=option)
