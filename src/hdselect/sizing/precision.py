"""How precise the sized arm is along its cycle: the units' twist, the tool's sag, its modes.

The second half of Harmonic Drive's procedure (stiffness), on the robot's own dynamics:
after the selection, with the chosen units' masses carried, `precision_of` gives

- per joint: its unit's twist along the cycle (`hdselect.catalog.stiffness.torsion` of
  the joint torque) and holding each pose still (of the gravity torque), the catalog's
  hysteresis loss and lost motion, the single-axis natural frequency sqrt(K1 / M_jj) / 2 pi
  at each evaluated pose, the input speed that excites the lowest, and where the motion's
  input speed runs within `NEAR_RESONANCE` of it;
- the tool's deflection: every joint's twist, and its output bearing's tilt -M / K_B
  where the unit rates K_B, carried to the tool frame (`hdselect.robot.compliance`),
  along the cycle and holding each pose still;
- the arm's modes K v = w^2 M(q) v at the evaluated poses.

A joint carrying torque tau turns by -phi(tau) from where its servo holds the input:
the load pushes it back. Poses: every pooled sample up to `PRECISION_POSES`, else that
many evenly spread, each task's first and last, and each joint's largest-|torque| sample.
Each pose is held and its modes found with the parts its task carries there (its carried
state, `hdselect.sizing.tasks.by_state`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from hdselect.catalog.rules import RPM_PER_RAD_S
from hdselect.catalog.stiffness import natural_frequency, rates_torsion, resonance_speed, torsion
from hdselect.catalog.units import Unit
from hdselect.robot.compliance import (
    arm_frequencies,
    arm_modes,
    mass_matrices,
    placements,
    unit_rotation,
)
from hdselect.robot.dynamics import NOISE_FLOOR, gravity_torques, torque_floor
from hdselect.robot.model import Robot
from hdselect.sizing.deflection import (
    Piece,
    SizedJoint,
    ToolDeflection,
    in_pose_order,
    state_pieces,
    task_poses,
    tool_figures,
    tool_frame,
)
from hdselect.sizing.options import Options
from hdselect.sizing.tasks import Samples, carrying, task_rows

PRECISION_POSES = 1000
"""Most poses at which the tool's deflection and the natural frequencies are evaluated."""
NEAR_RESONANCE = 0.10
"""An input speed within this fraction of a resonance speed runs near resonance [-]."""


@dataclass(frozen=True)
class Window:
    """A stretch of one task's cycle in which a joint runs near its resonance.

    Attributes:
        task: The task's index among the counted tasks.
        start: Its start, in the task's cycle [s].
        end: Its end (the last sample's time plus the task's dt) [s].
    """

    task: int
    start: float
    end: float


@dataclass(frozen=True, eq=False)
class JointPrecision:
    """One sized joint's stiffness figures along the cycle.

    Attributes:
        name: Joint name.
        unit: The selected unit, else the strongest candidate (where none fits).
        rated: Its K1 is rated; else every figure below but the catalog's is None.
        torsion: The output's angle from where the servo holds it, -phi(tau), along the
            pooled samples [rad], (n,).
        max_torsion: Largest |twist| over the cycle [rad].
        max_torsion_sample: Its pooled sample.
        holding_torsion: Largest |twist| holding each evaluated pose still [rad].
        hysteresis_loss: The catalog's hysteresis loss [rad], where it gives one.
        lost_motion: The catalog's lost motion [rad], where it gives one.
        frequency: Single-axis f_n = sqrt(K1 / M_jj) / 2 pi at each evaluated pose
            (`Precision.poses`) [Hz], (m,).
        lowest_frequency: The lowest of them [Hz].
        lowest_frequency_sample: Its pooled sample.
        resonance_speed: The input speed exciting the lowest f_n [rpm].
        near_resonance: Where |input speed| is within `NEAR_RESONANCE` of f_n x 30 (f_n of
            the nearest evaluated pose of the same task).
        near_resonance_time: Their total [s] (per cycle of each task, summed).
    """

    name: str
    unit: Unit | None
    rated: bool
    torsion: np.ndarray | None = None
    max_torsion: float | None = None
    max_torsion_sample: int | None = None
    holding_torsion: float | None = None
    hysteresis_loss: float | None = None
    lost_motion: float | None = None
    frequency: np.ndarray | None = None
    lowest_frequency: float | None = None
    lowest_frequency_sample: int | None = None
    resonance_speed: float | None = None
    near_resonance: tuple[Window, ...] = ()
    near_resonance_time: float = 0.0


@dataclass(frozen=True, eq=False)
class ArmModes:
    """The arm's natural frequencies, the units' K1 as springs, at the evaluated poses.

    Attributes:
        joints: The joints with a spring (every sized joint, K1 rated).
        samples: The pooled samples evaluated, (m,).
        frequencies: At each, ascending [Hz], (m, k).
        lowest: Index into `samples` of the lowest first mode.
        shape: That mode's shape by joint, largest |entry| 1, (k,).
    """

    joints: tuple[str, ...]
    samples: np.ndarray
    frequencies: np.ndarray
    lowest: int
    shape: np.ndarray

    @property
    def lowest_frequency(self) -> float:
        """The lowest first mode over the evaluated poses [Hz]."""
        return float(self.frequencies[self.lowest, 0])


@dataclass(frozen=True)
class Raise:
    """A unit raised for stiffness to meet a whole-arm target.

    Attributes:
        joint: The joint.
        chosen: The unit id the per-joint choice gave.
        raised_to: The unit id chosen instead.
        reason: ``"tool deflection"`` or ``"arm frequency"``.
        added_mass: The raised unit's mass over the chosen one's [kg].
    """

    joint: str
    chosen: str
    raised_to: str
    reason: str
    added_mass: float


@dataclass(frozen=True)
class TargetCheck:
    """A whole-arm target's verdict.

    Attributes:
        name: ``"tool_deflection"`` or ``"arm_frequency"``.
        value: What was reached [m or Hz]; None where it could not be judged.
        limit: The target [m or Hz].
        ok: It is met.
        shortfall: Where not met, why, with the best reached against the target.
    """

    name: str
    value: float | None
    limit: float
    ok: bool
    shortfall: str | None = None


@dataclass(frozen=True, eq=False)
class Precision:
    """The sized arm's stiffness figures along its cycle.

    Attributes:
        joints: Every sized joint, in the robot's order.
        tool: The tool's deflection; None where some sized joint's K1 is not rated.
        modes: The arm's modes; None where some sized joint's K1 is not rated.
        not_rated: Sized joints whose unit rates no K1.
        rigid: Joints that move in the cycle with no unit (not sized), taken as rigid.
        raised: Units raised for a whole-arm target.
        targets: The whole-arm targets' verdicts.
        poses: The pooled samples evaluated (`JointPrecision.frequency`'s), (m,).
    """

    joints: tuple[JointPrecision, ...]
    tool: ToolDeflection | None
    modes: ArmModes | None
    not_rated: tuple[str, ...]
    rigid: tuple[str, ...]
    raised: tuple[Raise, ...] = ()
    targets: tuple[TargetCheck, ...] = ()
    poses: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.intp))


class SampledModel(Protocol):
    """What `precision_of` reads of a torque model (`hdselect.sizing.torques.TorqueModel`)."""

    @property
    def robot(self) -> Robot: ...  # noqa: D102
    @property
    def samples(self) -> Samples: ...  # noqa: D102


def precision_of(model: SampledModel, joints: Sequence[SizedJoint], masses: Mapping[str, float],
                 options: Options, *, threads: int | None = None) -> Precision:
    """The stiffness figures of a sizing, with the chosen units' masses carried.

    Args:
        model: The sizing's torque model: its robot and pooled samples.
        joints: The sized joints (their torque and wrench along the samples, their unit).
        masses: The mass each sized joint's unit and motor add [kg], by joint.
        options: The assumptions (each joint's ``bearing_offset``, ``threads``).
        threads: Threads for the batched passes; None takes the options'.

    Returns:
        The figures.
    """
    threads = options.threads if threads is None else threads
    samples, robot = model.samples, model.robot
    units = {j.name: (j.selected or j.strongest).unit for j in joints}
    springs = tuple(j.name for j in joints if rates_torsion(units[j.name].stiffness))
    robots = [carrying(task, masses, robot.sized_joints) for task in samples.tasks]
    poses = evaluated_poses(samples, [j.torque for j in joints])
    moving = np.any(samples.qd != 0.0, axis=0)
    rigid = tuple(name for j, name in enumerate(robot.joint_names)
                  if name not in units and moving[j])
    not_rated = tuple(j.name for j in joints if j.name not in springs)
    if not springs:
        return Precision(tuple(_unrated(j.name, units[j.name]) for j in joints), None, None,
                         not_rated, rigid, poses=poses)
    pieces = state_pieces(samples, poses, robots)  # each task's poses by carried state
    held = in_pose_order([gravity_torques(piece.robot, _q(samples, piece), threads=threads)
                          for piece in pieces], pieces)
    floor = torque_floor(robot)
    held[np.abs(held) < floor] = 0.0  # the recursion's noise counts as zero, as in the selection
    placed = [placements(piece.robot, _q(samples, piece)) for piece in pieces]
    inertia = in_pose_order([mass_matrices(piece.robot, _q(samples, piece), springs, placed=at)
                             for piece, at in zip(pieces, placed, strict=True)], pieces)
    diagonal = np.diagonal(inertia, axis1=1, axis2=2)  # noise (`NOISE_FLOOR`) moves nothing
    diagonal = np.where(diagonal > NOISE_FLOOR * diagonal.max(initial=0.0), diagonal, 0.0)
    nearest = _nearest(samples, poses)
    figures = []
    for joint in joints:
        if joint.name not in springs:
            figures.append(_unrated(joint.name, units[joint.name]))
            continue
        k = springs.index(joint.name)
        j = robot.joint_index(joint.name)
        figures.append(_joint(joint, units[joint.name], samples, poses, nearest, held[:, j],
                              diagonal[:, k], samples.qd[:, j]))
    tool = modes = None
    if not not_rated:
        frame = tool_frame(samples)
        tool = tool_figures(pieces, placed, samples, poses, frame, joints, units, held, options)
        k1 = [units[name].stiffness.k1 for name in springs]  # type: ignore[union-attr]
        frequencies = arm_frequencies(inertia, k1)  # type: ignore[arg-type]
        lowest = int(np.argmin(frequencies[:, 0]))
        _, shapes = arm_modes(inertia[lowest:lowest + 1], k1)  # type: ignore[arg-type]
        modes = ArmModes(springs, poses, frequencies, lowest, shapes[0, :, 0])
    return Precision(tuple(figures), tool, modes, not_rated, rigid, poses=poses)


def evaluated_poses(samples: Samples, torques: Sequence[np.ndarray]) -> np.ndarray:
    """The pooled samples evaluated: all up to `PRECISION_POSES`, else spread (module doc).

    Args:
        samples: The pooled samples.
        torques: Each sized joint's torque along them [N m], (n,).

    Returns:
        Sorted pooled sample indices, (m,).
    """
    n = len(samples)
    if n <= PRECISION_POSES:
        return np.arange(n)
    ends = [end for k in range(len(samples.tasks))
            for end in (task_rows(samples, k).start, task_rows(samples, k).stop - 1)]
    worst = [int(np.argmax(np.abs(tau))) for tau in torques]
    spread = np.linspace(0, n - 1, PRECISION_POSES).round().astype(np.intp)
    return np.unique(np.concatenate([spread, ends, worst]).astype(np.intp))


def _q(samples: Samples, piece: Piece) -> np.ndarray:
    """A piece's poses [rad or m], (m_p, dof)."""
    return samples.tasks[piece.task].trajectory.q[piece.local]


def _unrated(name: str, unit: Unit) -> JointPrecision:
    """A joint whose unit rates no K1: the catalog's hysteresis and lost motion only."""
    stiffness = unit.stiffness
    return JointPrecision(name, unit, False,
                          hysteresis_loss=stiffness.hysteresis_loss if stiffness else None,
                          lost_motion=stiffness.lost_motion if stiffness else None)


def _nearest(samples: Samples, poses: np.ndarray) -> np.ndarray:
    """For every pooled sample, the index into `poses` of the nearest pose of its own task."""
    out = np.empty(len(samples), dtype=np.intp)
    for k in range(len(samples.tasks)):
        rows = task_rows(samples, k)
        own = task_poses(poses, rows)
        index = np.arange(rows.start, rows.stop)
        after = np.clip(np.searchsorted(poses[own], index), 0, own.size - 1)
        before = np.clip(after - 1, 0, own.size - 1)
        out[rows] = own[np.where(np.abs(poses[own][before] - index)
                                 < np.abs(poses[own][after] - index), before, after)]
    return out


def _joint(joint: SizedJoint, unit: Unit, samples: Samples, poses: np.ndarray,
           nearest: np.ndarray, holding: np.ndarray, inertia: np.ndarray,
           speed: np.ndarray) -> JointPrecision:
    """One rated joint's figures: twist, single-axis f_n at the poses, near resonance.

    `holding` and `inertia` are at the poses; `speed` is the output's along the samples
    [rad/s], and the sample's nearest pose gives its f_n.
    """
    stiffness = unit.stiffness
    if stiffness is None or stiffness.k1 is None:
        raise ValueError(f"{unit.id} rates no K1: its joint has no figures")
    twist = unit_rotation(unit, joint.torque)[0][:, 2]  # -phi(tau)
    twist.setflags(write=False)
    worst = int(np.argmax(np.abs(twist)))
    frequency = natural_frequency(stiffness.k1, inertia)
    frequency.setflags(write=False)
    low = int(np.argmin(frequency))
    windows = _near_resonance(samples, resonance_speed(frequency)[nearest],
                              np.abs(speed) * unit.ratio * RPM_PER_RAD_S)
    return JointPrecision(
        joint.name, unit, True, twist, float(abs(twist[worst])), worst,
        float(np.abs(torsion(stiffness, holding)).max()), stiffness.hysteresis_loss,
        stiffness.lost_motion, frequency, float(frequency[low]), int(poses[low]),
        float(resonance_speed(frequency[low])), windows,
        float(sum(w.end - w.start for w in windows)))


def _near_resonance(samples: Samples, excited: np.ndarray,
                    speed: np.ndarray) -> tuple[Window, ...]:
    """The stretches where the input speed [rpm] is within `NEAR_RESONANCE` of `excited`.

    `excited` is the resonance speed f_n x 30 at each sample [rpm] (inf: nothing rings).
    """
    near = np.isfinite(excited) & (np.abs(speed - excited) <= NEAR_RESONANCE * excited)
    windows = []
    for k, task in enumerate(samples.tasks):
        rows = task_rows(samples, k)
        edges = np.flatnonzero(np.diff(np.r_[0, near[rows].astype(np.int8), 0]))
        t, dt = samples.t[rows], task.trajectory.dt
        windows += [Window(k, float(t[a]), float(t[b - 1] + dt))
                    for a, b in zip(edges[::2], edges[1::2], strict=True)]
    return tuple(windows)
