"""How a robot is mounted: where its base sits in the world, and gravity in its base frame.

The world is where the work is: z points up, gravity is (0, 0, -g). A mounting places the
robot's base in that world (`BasePose`, the base-to-world transform), and gravity in the
base frame follows from it: g_base = R^T (0, 0, -g), R the base's rotation in the world.
That one definition serves both the dynamics (gravity) and the inverse kinematics of tool
poses written in the world (`hdselect.motion.toolposes`).

Named mountings:

- ``floor``: the base frame is the world frame; gravity along base -z.
- ``wall``: base origin at the world origin, base x axis pointing up (world +z), base z
  axis along world +x (out of the wall), so base y is world -y; gravity along base -x.
- ``ceiling``: turned upside down about the world x axis, base z pointing down; gravity
  along base +z.

A gravity vector alone (three numbers in the base frame) sets the dynamics but does not
place the base in the world: tool poses need a named mounting or a base pose.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError

STANDARD_GRAVITY = 9.80665
"""Standard gravity [m/s^2]."""

WORLD_GRAVITY = (0.0, 0.0, -STANDARD_GRAVITY)
"""Gravity in the world frame, z up [m/s^2]."""


@dataclass(frozen=True)
class BasePose:
    """Where the robot's base sits in the world: the base-to-world transform.

    A point p given in the base frame is ``rotation @ p + xyz`` in the world.

    Attributes:
        xyz: Position of the base origin in the world [m].
        rotation: The base axes in world coordinates, as the columns of a rotation
            matrix (rows of the tuple are the matrix rows) [-].
    """

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[tuple[float, float, float], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                                                         (0.0, 0.0, 1.0))

    def __post_init__(self) -> None:
        matrix = np.asarray(self.rotation, dtype=float)
        position = np.asarray(self.xyz, dtype=float)
        if matrix.shape != (3, 3) or position.shape != (3,) or not (
                np.all(np.isfinite(matrix)) and np.all(np.isfinite(position))):
            raise InputError("a base pose is three finite numbers [m] and a 3 x 3 rotation",
                             field="base")
        if not np.allclose(matrix @ matrix.T, np.eye(3), atol=1e-9) or \
                np.linalg.det(matrix) < 0.0:
            raise InputError("the base rotation must be a rotation matrix (orthonormal, "
                             "determinant +1)", field="base")
        object.__setattr__(self, "xyz", tuple(float(v) for v in position))
        object.__setattr__(self, "rotation", tuple(tuple(float(v) for v in row)
                                                   for row in matrix))

    @classmethod
    def from_xyz_rpy(cls, xyz: Sequence[float], rpy: Sequence[float]) -> BasePose:
        """A base pose from a position [m] and roll, pitch, yaw [rad] about fixed axes.

        The angles follow URDF's ``<origin rpy>``: R = Rz(yaw) Ry(pitch) Rx(roll).
        """
        return cls(tuple(xyz), tuple(map(tuple, rpy_matrix(rpy))))  # type: ignore[arg-type]

    @property
    def matrix(self) -> np.ndarray:
        """The rotation as an array, shape (3, 3) [-]."""
        return np.array(self.rotation)

    @property
    def position(self) -> np.ndarray:
        """The base origin in the world as an array, shape (3,) [m]."""
        return np.array(self.xyz)

    @property
    def gravity(self) -> np.ndarray:
        """Gravity in the base frame, R^T (0, 0, -g) [m/s^2], shape (3,)."""
        return self.matrix.T @ np.array(WORLD_GRAVITY)


def base_pose_from(values: Sequence[float], *, angle: float = 1.0, angle_unit: str = "rad",
                   field: str = "base") -> BasePose:
    """A base pose from six numbers: x, y, z [m], then roll, pitch, yaw [`angle_unit`].

    The angles are about fixed axes, as `BasePose.from_xyz_rpy`'s; each number is checked
    against its physical range (`hdselect.base.bounds.LENGTH`, `ANGLE`).

    Args:
        values: The six numbers as given.
        angle: Radians per unit of the angles [rad] (pi/180 for degrees).
        angle_unit: The angles' unit, for messages.
        field: Where the numbers were given (a key or an option), for messages.

    Raises:
        InputError: Not six numbers, or one that is not finite or out of range.
    """
    numbers = list(values)
    if len(numbers) != 6:
        raise InputError(f"expected 6 numbers {','.join(BASE_NUMBERS)} (m and {angle_unit}), "
                         f"got {len(numbers)}", field=field)
    checked = []
    for name, value, kind in zip(BASE_NUMBERS, numbers, ("length",) * 3 + ("angle",) * 3,
                                 strict=True):
        try:
            checked.append(bounds.LENGTH.check(value, field=field) if kind == "length" else
                           bounds.ANGLE.check(value, field=field, scale=angle, unit=angle_unit)
                           * angle)
        except InputError as err:
            raise InputError(f"{name} {err.reason}" if err.reason.startswith("must") else
                             f"{name}: {err.reason}", field=field) from err
    return BasePose.from_xyz_rpy(checked[:3], checked[3:])


BASE_NUMBERS = ("x", "y", "z", "roll", "pitch", "yaw")
"""The six numbers of a base pose given in a row (`base_pose_from`), in their order."""


def rpy_matrix(rpy: Sequence[float]) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll) for roll, pitch, yaw [rad] (URDF's fixed axes X, Y, Z)."""
    roll, pitch, yaw = (float(a) for a in rpy)
    return np.array(pin.rpy.rpyToMatrix(roll, pitch, yaw))


NAMED_BASES = {
    "floor": BasePose(),
    "ceiling": BasePose(rotation=((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0))),
    "wall": BasePose(rotation=((0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0))),
}
"""The base pose of each named mounting (columns of the rotation: base x, y, z in the world)."""


MOUNTINGS = {name: tuple(float(g) + 0.0 for g in base.gravity)
             for name, base in NAMED_BASES.items()}
"""Gravity in the base frame [m/s^2] for each named mounting, from its base pose: on the
floor (0, 0, -g), on the ceiling (0, 0, g), on a wall (-g, 0, 0)."""


Mounting = str | Sequence[float] | BasePose
"""A mounting: a name of `NAMED_BASES`, a gravity vector in the base frame [m/s^2], or a
`BasePose`."""


def gravity_of(mounting: Mounting) -> np.ndarray:
    """Gravity in the base frame [m/s^2] for a named mounting, a gravity vector or a base pose.

    Raises:
        InputError: The mounting is neither a known name, three finite numbers nor a
            base pose.
    """
    if isinstance(mounting, BasePose):
        return mounting.gravity + 0.0
    if isinstance(mounting, str):
        if mounting not in MOUNTINGS:
            raise InputError(f"unknown mounting '{mounting}'; choose one of: "
                             f"{', '.join(MOUNTINGS)} or a gravity vector", field="mounting")
        return np.array(MOUNTINGS[mounting])
    if isinstance(mounting, bytes) or (
            isinstance(mounting, Sequence) and any(isinstance(g, bool | str | bytes)
                                                   for g in mounting)):
        raise InputError("gravity must be three finite numbers [m/s^2]", field="mounting")
    try:
        gravity = np.asarray(mounting, dtype=float)
    except (TypeError, ValueError, OverflowError) as err:
        raise InputError("gravity must be three finite numbers [m/s^2]",
                         field="mounting") from err
    if gravity.shape != (3,) or not np.all(np.isfinite(gravity)):
        raise InputError("gravity must be three finite numbers [m/s^2]", field="mounting")
    for i, value in enumerate(gravity):
        bounds.GRAVITY.check(float(value), field=f"mounting[{i}]")
    return gravity


def base_pose_of(mounting: Mounting) -> BasePose | None:
    """The base pose of a mounting: a name's, the pose itself, or None for a gravity vector.

    Raises:
        InputError: An unknown name.
    """
    if isinstance(mounting, BasePose):
        return mounting
    if isinstance(mounting, str):
        gravity_of(mounting)  # the message for an unknown name
        return NAMED_BASES[mounting]
    return None


def mounting_name(base: BasePose | None) -> str:
    """The mounting in words: ``the wall mounting``, or the base pose's numbers."""
    if base is None:
        return "a mounting given as a gravity vector"
    for name, named in NAMED_BASES.items():
        if named == base:
            return f"the {name} mounting"
    rpy = np.degrees(pin.rpy.matrixToRpy(base.matrix))
    return (f"the base at ({shown_numbers(base.xyz)}) m, rpy ({shown_numbers(rpy, 180.0)}) deg")


def shown_numbers(values: Iterable[float], scale: float | None = None) -> str:
    """Numbers as a person reads them, 4 significant digits, comma-separated.

    A value within 1e-12 of `scale` (default: the largest magnitude among them) of zero
    is the rounding of a rotation (gravity on a ceiling, cos 180 deg) and reads 0, and
    -0 reads 0.
    """
    numbers = [float(v) for v in values]
    size = max((abs(v) for v in numbers), default=0.0) if scale is None else scale
    return ", ".join(f"{0.0 if abs(v) <= 1e-12 * size else v:.4g}" for v in numbers)
