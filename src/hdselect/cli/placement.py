"""Where the command line places the robot: ``--mounting`` or ``--base``, read once.

``--base X,Y,Z,ROLL,PITCH,YAW`` places the base as a file's ``base = {xyz, rpy}`` does,
in the file's units: metres, and the angle unit of the file given (a motion file's
``angle_unit``; a mix file's own, which its tasks' ``base`` keys use; the envelope's
``--angle-unit``). It overrides the files' mounting as ``--mounting`` does.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from hdselect.base.errors import InputError

if TYPE_CHECKING:
    from hdselect.robot.mounting import Mounting


def mounting_flag(args: argparse.Namespace, angle_unit: str) -> Mounting | None:
    """The mounting the command line gives: ``--mounting``'s, else ``--base``'s pose, else None.

    Args:
        args: The command's arguments.
        angle_unit: The unit of ``--base``'s angles: the file's (``"deg"`` or ``"rad"``).

    Raises:
        InputError: Both flags are given, or ``--base`` is not six finite numbers in range.
    """
    from hdselect.motion.motionfile import ANGLE_UNITS
    from hdselect.robot.mounting import BASE_NUMBERS, base_pose_from

    text = getattr(args, "base", None)
    if text is None:
        return args.mounting
    one_mounting(args)
    try:
        numbers = [float(part) for part in text.split(",")]
    except ValueError:
        raise InputError(f"expected 6 numbers {','.join(BASE_NUMBERS)} (m and {angle_unit}), "
                         f"got {text!r}", field="--base") from None
    return base_pose_from(numbers, angle=ANGLE_UNITS[angle_unit], angle_unit=angle_unit,
                          field="--base")


def one_mounting(args: argparse.Namespace) -> None:
    """Refuse ``--base`` beside ``--mounting``: each sets the mounting."""
    if getattr(args, "base", None) is not None and args.mounting is not None:
        raise InputError("give either --mounting or --base (which places the base, and so "
                         "sets the mounting), not both", field="--base")


def source_angle_unit(source) -> str:
    """The unit of ``--base``'s angles for a motion or a mix: the file's own ``angle_unit``.

    A mix file's ``angle_unit`` (default deg) is the one its tasks' ``base`` keys use; a
    motion file's applies to its waypoints and its ``base`` alike.
    """
    from hdselect.motion.mixfile import Mix

    return source.base_angle_unit if isinstance(source, Mix) else str(source.angle_unit)


def mounting_option(args: argparse.Namespace) -> str | None:
    """The flag that gave the mounting, or None: the files' holds."""
    if args.mounting is not None:
        return "--mounting"
    return "--base" if getattr(args, "base", None) is not None else None
