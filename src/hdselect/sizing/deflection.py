"""The tool's deflection along a cycle: every joint's unit turning its output, carried to the tool.

Each sized joint's unit twists by -phi(tau) and, where it rates K_B, its output bearing
tilts by -M / K_B (`hdselect.robot.compliance.unit_rotation`); carried through the
kinematics (`hdselect.robot.compliance.tool_deflection`) they move the tool frame, along
the cycle (the joint torques and wrenches of the motion) and holding each pose still
(gravity and payload alone: the static accuracy a designer quotes).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from hdselect.catalog.rules import Candidate
from hdselect.catalog.units import Unit
from hdselect.robot.compliance import Placements, tool_deflection, unit_rotation
from hdselect.robot.model import Robot
from hdselect.robot.wrenches import axis_wrenches
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.options import Options
from hdselect.sizing.tasks import Samples, by_state, task_rows


@dataclass(frozen=True, eq=False)
class ToolDeflection:
    """How far the tool frame moves from its commanded pose, at the evaluated poses.

    Attributes:
        frame: The tool frame.
        samples: The pooled samples evaluated, (m,).
        translation: Along the cycle (joint torques and wrenches) [m], (m, 3), world frame.
        rotation: Along the cycle, a rotation vector [rad], (m, 3).
        holding_translation: Holding each pose still (gravity, payload) [m], (m, 3).
        holding_rotation: Holding each pose still [rad], (m, 3).
        worst: Index into `samples` of the largest |translation|.
        worst_holding: Index into `samples` of the largest |holding_translation|.
        bearing_tilt: The joints whose bearing tilt -M / K_B is included.
    """

    frame: str
    samples: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray
    holding_translation: np.ndarray
    holding_rotation: np.ndarray
    worst: int
    worst_holding: int
    bearing_tilt: tuple[str, ...]

    @property
    def max_translation(self) -> float:
        """The largest |translation| along the cycle [m]."""
        return float(np.linalg.norm(self.translation[self.worst]))

    @property
    def max_holding(self) -> float:
        """The largest |translation| holding a pose of the cycle still [m]."""
        return float(np.linalg.norm(self.holding_translation[self.worst_holding]))


class SizedJoint(Protocol):
    """What `precision_of` reads of a sized joint (`hdselect.sizing.result.JointSizing`)."""

    @property
    def name(self) -> str: ...  # noqa: D102
    @property
    def torque(self) -> np.ndarray: ...  # noqa: D102
    @property
    def wrench(self) -> SampledWrench | None: ...  # noqa: D102
    @property
    def selected(self) -> Candidate | None: ...  # noqa: D102
    @property
    def strongest(self) -> Candidate: ...  # noqa: D102



def task_poses(poses: np.ndarray, rows: slice) -> np.ndarray:
    """Which of the evaluated poses (their indices) are among one task's pooled `rows`."""
    return np.flatnonzero((poses >= rows.start) & (poses < rows.stop))


@dataclass(frozen=True, eq=False)
class Piece:
    """The evaluated poses of one task in one carried state (`hdselect.sizing.tasks.by_state`).

    Attributes:
        robot: The task's robot in that state, the chosen units carried.
        task: The task's index among the counted tasks.
        local: The poses as rows of the task's own trajectory, (m_p,).
        at: Their indices into the evaluated poses, ascending, (m_p,).
    """

    robot: Robot
    task: int
    local: np.ndarray
    at: np.ndarray


def state_pieces(samples: Samples, poses: np.ndarray, robots: Sequence[Robot]) -> list[Piece]:
    """The evaluated poses split by task and carried state; their `at` cover every pose once.

    Args:
        samples: The pooled samples.
        poses: The evaluated pooled samples, sorted, (m,).
        robots: Each counted task's robot carrying the chosen units.
    """
    pieces = []
    for k, (task, robot) in enumerate(zip(samples.tasks, robots, strict=True)):
        rows = task_rows(samples, k)
        own = task_poses(poses, rows)
        local = poses[own] - rows.start
        for carrier, state in by_state(task, robot):
            keep = (np.ones(len(local), dtype=bool) if isinstance(state, slice)
                    else np.isin(local, state))
            if keep.any():
                pieces.append(Piece(carrier, k, local[keep], own[keep]))
    return pieces


def in_pose_order(parts: Sequence[np.ndarray], pieces: Sequence[Piece], axis: int = 0
                  ) -> np.ndarray:
    """Per-piece arrays joined along `axis` and put back in the evaluated poses' order."""
    joined = np.concatenate(parts, axis=axis)
    order = np.argsort(np.concatenate([piece.at for piece in pieces]), kind="stable")
    return np.take(joined, order, axis=axis)


def tool_frame(samples: Samples) -> str:
    """The first counted task's motion's ``[tool]`` frame, else its robot's payload frame."""
    task = samples.tasks[0]
    tool = task.motion.tool if task.motion is not None else None
    return tool.frame if tool is not None and tool.frame else task.robot.payload_frame


def tool_figures(pieces: Sequence[Piece], placed: Sequence[Placements], samples: Samples,
                 poses: np.ndarray, frame: str, joints: Sequence[SizedJoint],
                 units: Mapping[str, Unit], held: np.ndarray,
                 options: Options) -> ToolDeflection:
    """The tool's deflection along the cycle and holding still, at the evaluated poses.

    Each piece (a task in one carried state) is carried by its own robot; `placed` is
    each piece's placements and `held` the gravity torques at every pose, in pose order.
    """
    robot = pieces[0].robot
    tilted = tuple(j.name for j in joints if j.wrench is not None
                   and units[j.name].bearing is not None
                   and units[j.name].bearing.moment_stiffness is not None)  # type: ignore[union-attr]
    parts = []
    for piece, at in zip(pieces, placed, strict=True):
        mine = poses[piece.at]
        q = samples.tasks[piece.task].trajectory.q[piece.local]
        still = np.zeros_like(q)
        gravity = axis_wrenches(piece.robot, q, still, still, tilted) if tilted else None
        rotations, centres = {}, {}
        for joint in joints:
            wrenches = ((_rows(joint.wrench, mine), gravity[tilted.index(joint.name), :5])
                        if joint.name in tilted and joint.wrench is not None
                        and gravity is not None else None)
            rotations[joint.name], centres[joint.name] = unit_rotation(
                units[joint.name],
                np.stack((joint.torque[mine], held[piece.at, robot.joint_index(joint.name)])),
                None if wrenches is None else np.stack(wrenches),
                options.bearing_offset.get(joint.name, 0.0))
        parts.append(tool_deflection(piece.robot, q, frame, rotations, centres, placed=at))
    translation = in_pose_order([p[0] for p in parts], pieces, axis=1)
    rotation = in_pose_order([p[1] for p in parts], pieces, axis=1)
    for array in (translation, rotation):
        array.setflags(write=False)
    size = np.linalg.norm(translation, axis=2)
    return ToolDeflection(frame, poses, translation[0], rotation[0], translation[1],
                          rotation[1], int(np.argmax(size[0])), int(np.argmax(size[1])), tilted)


def _rows(wrench: SampledWrench, samples: np.ndarray) -> np.ndarray:
    """The first five rows of a joint's wrench at some samples [N, N m], (5, len(samples))."""
    columns = samples if wrench.index is None else wrench.index[samples]
    return wrench.rows[:5, columns]
