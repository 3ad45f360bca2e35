"""Every joint of a robot over a cycle, sized or not, beside its robot file's limits.

The sizing chooses gearheads for the sized joints; this says what all the others
do too (prismatic joints, joints left out, mimic followers), and how each
joint's peak torque and top speed compare with the file's effort and velocity
limits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from hdselect.catalog.rules import at_rest
from hdselect.motion.logderivatives import peak_uncertainty
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot

PEAK_PROMISE = 0.01
"""How close a peak torque from a log of positions only is promised to be [-]: further than
this, the sizing states its uncertainty."""


@dataclass(frozen=True)
class JointLoad:
    """What one joint of the robot does over the cycle, sized or not, beside its file's limits.

    Torque is force and angles are lengths for a prismatic joint: [N m or N], [rad or m].

    Attributes:
        name: Joint name.
        kind: ``"revolute"``, ``"continuous"``, ``"prismatic"`` or ``"mimic"`` (a follower).
        sized: The joint gets a gearhead (it has a row in `SizingResult.joints`).
        note: Why it is not sized, or what drives it; None for a sized joint.
        peak: Largest torque over the cycle, gearheads carried [N m or N]; None for a
            follower (its leader carries its load).
        max_speed: Largest speed [rad/s or m/s].
        travel: Smallest and largest position reached [rad or m].
        effort_limit: The robot file's effort limit [N m or N]; inf when it gives none.
        velocity_limit: The robot file's velocity limit [rad/s or m/s]; inf when it gives none.
        leader: For a follower, the joint it follows.
        linear: A prismatic joint, or a follower of one: forces [N], lengths [m].
        peak_uncertainty: How far `peak`, and the peak while moving that the catalog's
            rules judge, may be off where the accelerations were derived from a log's
            positions [N m or N]; None where they are exact (planned) or logged.
    """

    name: str
    kind: str
    sized: bool
    note: str | None
    peak: float | None
    max_speed: float
    travel: tuple[float, float]
    effort_limit: float
    velocity_limit: float
    leader: str | None = None
    linear: bool = False
    peak_uncertainty: float | None = None

    @property
    def above_effort(self) -> bool:
        """The peak exceeds the robot file's effort limit."""
        return self.peak is not None and self.peak > self.effort_limit * (1.0 + 1e-9)

    @property
    def uncertain(self) -> bool:
        """The peak is known to no better than `PEAK_PROMISE` (accelerations from positions)."""
        return (self.peak is not None and self.peak_uncertainty is not None
                and self.peak_uncertainty > PEAK_PROMISE * self.peak)

    @property
    def above_velocity(self) -> bool:
        """The largest speed exceeds the robot file's velocity limit."""
        return self.max_speed > self.velocity_limit * (1.0 + 1e-6)

    def units(self, angle: str) -> tuple[str, str, float]:
        """Force unit, length unit and the factor from SI for showing this joint.

        Args:
            angle: ``"deg"`` or ``"rad"``, the unit a rotary joint's angles are shown in.

        Returns:
            ``("N", "m", 1)`` for a linear joint; ``("N m", angle, factor)`` for a rotary one.
        """
        if self.linear:
            return "N", "m", 1.0
        return "N m", angle, (180.0 / math.pi if angle == "deg" else 1.0)


def joint_loads(robot: Robot, trajectory: Trajectory, tau: np.ndarray,
                tau_spread: np.ndarray | None = None) -> tuple[JointLoad, ...]:
    """Every joint's peak torque, speed and travel beside its file's limits.

    Args:
        robot: The robot.
        trajectory: The trajectory, with the robot's joints.
        tau: Joint torques along it [N m or N], shape (n, dof).
        tau_spread: How far each of those torques may be off [N m or N], shape (n, dof)
            (`hdselect.robot.dynamics.torque_spread`); None where they are exact.

    Returns:
        One per joint of the model (followers included), in the model's order.
    """
    model = robot.model
    loads = []
    for joint_id in range(1, model.njoints):
        name = model.names[joint_id]
        if name in robot.mimic:
            mimic = robot.mimic[name]
            leader = robot.joint_index(mimic.leader)
            q = mimic.multiplier * trajectory.q[:, leader] + mimic.offset
            loads.append(JointLoad(
                name, "mimic", False, f"driven by {mimic.leader} (x {mimic.multiplier:g})", None,
                float(np.abs(mimic.multiplier * trajectory.qd[:, leader]).max()),
                (float(q.min()), float(q.max())), math.inf, math.inf, leader=mimic.leader,
                linear=not robot.revolute[leader]))
            continue
        j = robot.joint_index(name)
        kind = robot.joint_type(name)
        sized = name in robot.sized_joints
        if sized:
            note = None
        elif kind == "prismatic":
            note = "not sized: the catalog is rotary"
        elif name in robot.uncoupled_followers:
            note = "not sized: a mimic follower, moved on its own here"
        else:  # --joints leaves it out, or exclude does (which the payload's tip follows)
            note = ("not sized: not among the joints asked for" if name in robot.payload_chain
                    else "not sized: excluded")
        effort, velocity = robot.effort_limit[j], robot.velocity_limit[j]
        loads.append(JointLoad(
            name, kind, sized, note, float(np.abs(tau[:, j]).max()),
            float(np.abs(trajectory.qd[:, j]).max()),
            (float(trajectory.q[:, j].min()), float(trajectory.q[:, j].max())),
            float(effort) if effort > 0.0 else math.inf,
            float(velocity) if velocity > 0.0 else math.inf, linear=kind == "prismatic",
            peak_uncertainty=None if tau_spread is None else _uncertainty(
                tau[:, j], tau_spread[:, j], trajectory.qd[:, j], trajectory.qdd[:, j])))
    return tuple(loads)


def _uncertainty(tau: np.ndarray, spread: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> float:
    """How far a joint's peak |torque| may be off, over the cycle and while it moves [N m].

    The larger of the two: the peak over the cycle is `JointLoad.peak`, the peak while
    moving (`hdselect.catalog.rules.at_rest` excluded) the one the catalog's rules judge.
    A move starts or ends between two samples: its first and last samples may be off by
    as much as they differ from the rest beside them (a move that starts from a holding
    torque has it at its start, whichever sample the log has there).
    """
    moving = ~at_rest(qd, qdd)
    size = np.abs(tau)
    edge = spread.copy()
    for side in (1, -1):  # a moving sample beside a resting one
        beside = np.roll(moving, side) != moving
        beside[0 if side == 1 else -1] = False
        held = np.roll(size, side)
        edge = np.where(moving & beside, np.maximum(edge, held - size), edge)
    return max(peak_uncertainty(tau, spread), peak_uncertainty(tau[moving], edge[moving]))


def merged_loads(per_task: Sequence[tuple[JointLoad, ...]]) -> tuple[JointLoad, ...]:
    """Every joint's loads over several tasks: the largest peak and speed, the whole travel.

    Args:
        per_task: `joint_loads` of each task, joints in the same order.

    Returns:
        One per joint; one task's loads as they are.
    """
    if len(per_task) == 1:
        return per_task[0]
    merged = []
    for loads in zip(*per_task, strict=True):
        peaks = [load.peak for load in loads if load.peak is not None]
        merged.append(replace(
            loads[0], peak=max(peaks) if peaks else None,
            peak_uncertainty=_merged_uncertainty(loads),
            max_speed=max(load.max_speed for load in loads),
            travel=(min(load.travel[0] for load in loads),
                    max(load.travel[1] for load in loads))))
    return tuple(merged)


def _merged_uncertainty(loads: Sequence[JointLoad]) -> float | None:
    """The uncertainty of the largest of several tasks' peaks [N m]; None if all are exact."""
    known = [load for load in loads if load.peak is not None]
    if not known or all(load.peak_uncertainty is None for load in known):
        return None
    top = max(known, key=lambda load: load.peak or 0.0)
    above = max((load.peak or 0.0) + (load.peak_uncertainty or 0.0) for load in known)
    return max(above - (top.peak or 0.0), top.peak_uncertainty or 0.0)
