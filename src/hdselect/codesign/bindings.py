"""Which limit sets the pace along the fastest cycle, stretch by stretch.

At every moving sample each limit of each joint has a demand / limit ratio: speed
against its limit, acceleration against the motion file's, torque against the
repeated peak (or the motion file's limits.torque where lower; the static limit where the
joint is held), the emergency stop and the crash against the momentary limit. The
largest names the limit that binds there; consecutive samples with the same one make
a stretch, and a stretch under 1 % of the moving time joins its neighbour.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from hdselect.catalog.rules import at_rest
from hdselect.codesign.cyclerules import Leg
from hdselect.codesign.fastpath import PathModel
from hdselect.codesign.pathbounds import JointLimits
from hdselect.motion.planning import Trajectory
from hdselect.sizing.result import JointSizing


@dataclass(frozen=True)
class Binding:
    """A stretch of the cycle during which one limit of one joint is the closest to its bound.

    Attributes:
        start: Start of the stretch [s].
        end: End of the stretch [s].
        joint: The joint.
        limit: The limit: ``"velocity (motion file)"``, ``"velocity (robot file)"``, ``"max input
            speed"``, ``"acceleration"``, ``"torque"``, ``"emergency stop"`` or ``"crash"``.
        utilization: The largest demand / limit over the stretch [-] (torque: against its
            limit before any derating).
        waypoints: The waypoints between which the stretch starts.
        task: The task whose moves it is in, by name (empty for one motion).
    """

    start: float
    end: float
    joint: str
    limit: str
    utilization: float
    waypoints: tuple[int, int]
    task: str = ""


def bindings(model: PathModel, leg: Leg, scale: float, trajectory: Trajectory,
             joints: Sequence[JointSizing], held: np.ndarray, limits: Sequence[JointLimits],
             samples: slice = slice(None), task: str = "") -> tuple[Binding, ...]:
    """The limit closest to its bound at each moving sample of one task, grouped into stretches.

    Args:
        model: The task's path.
        leg: Its profiles run.
        scale: Their slow-down [-].
        trajectory: The task's trajectory as checked.
        joints: The sizing's check of the duty (its torques), each joint's samples of
            every task in the duty's order.
        held: The trajectory's samples in dwells.
        limits: Each joint's limits on this task's path, not derated.
        samples: This task's samples among the check's.
        task: The task's name, for a duty of several.
    """
    robot = model.robot
    names = list(robot.joint_names)
    labels = {"motion": "velocity (motion file)", "robot": "velocity (robot file)",
              "unit": "max input speed"}
    rows: list[tuple[str, str, np.ndarray]] = []
    for j, lim in enumerate(limits):
        name = names[j]
        rows.append((name, labels[lim.velocity_source], np.abs(trajectory.qd[:, j]) / lim.velocity))
        rows.append((name, "acceleration", np.abs(trajectory.qdd[:, j]) / lim.acceleration))
    for joint in joints:
        j = names.index(joint.name)
        lim = limits[j]
        torque, stop = joint.torque[samples], joint.stop_torque[samples]
        if len(torque) != len(trajectory.t):
            raise RuntimeError(f"{joint.name}: {len(torque)} checked samples for a task of "
                               f"{len(trajectory.t)}")
        still = at_rest(trajectory.qd[:, j], trajectory.qdd[:, j])  # held: the static limit
        rows.append((joint.name, "torque", np.abs(torque)
                     / np.where(still, lim.static, lim.torque)))
        rows.append((joint.name, "emergency stop", np.abs(stop) / lim.momentary))
        rows.append((joint.name, "crash", (np.abs(torque) + lim.crash_gain
                                           * np.abs(trajectory.qd[:, j])) / lim.momentary))
    table = np.stack([r[2] for r in rows])
    moving = ~held
    best = np.argmax(table, axis=0)
    best[~moving] = -1
    times = trajectory.t
    dt = trajectory.dt
    ends = np.minimum(times + dt, trajectory.duration)  # a sample stands for dt, up to the end
    stretches: list[list] = []
    for k in np.flatnonzero(moving):
        row = int(best[k])
        if stretches and stretches[-1][2] == row and stretches[-1][1] >= times[k] - 1.5 * dt:
            stretches[-1][1] = float(ends[k])
            stretches[-1][3] = max(stretches[-1][3], float(table[row, k]))
        else:
            stretches.append([float(times[k]), float(ends[k]), row, float(table[row, k])])
    total = sum(b - a for a, b, _, _ in stretches) or 1.0
    merged: list[list] = []
    for stretch in stretches:  # a stretch under 1 % of the moving time joins its neighbour
        joins = merged and merged[-1][1] >= stretch[0] - 1.5 * dt
        if joins and merged[-1][2] == stretch[2]:
            merged[-1][1], merged[-1][3] = stretch[1], max(merged[-1][3], stretch[3])
        elif joins and stretch[1] - stretch[0] < 0.01 * total:
            merged[-1][1] = stretch[1]
        elif joins and merged[-1][1] - merged[-1][0] < 0.01 * total:
            merged[-1][1:] = stretch[1:]
        else:
            merged.append(list(stretch))
    return tuple(Binding(float(a), float(b), rows[row][0], rows[row][1], float(peak),
                         _waypoints_at(model, leg, scale, (a + b) / 2.0), task)
                 for a, b, row, peak in merged)


def shares(stretches: Sequence[Binding],
           rates: Mapping[str, float] | None = None) -> list[tuple[str, str, float]]:
    """(joint, limit, share of the moving time) [-], longest first.

    Args:
        stretches: The stretches of one task, or of every task of a duty.
        rates: For a duty, each task's cycles per unit time relative to the others' [-]
            (share / cycle time): a stretch counts for the time it takes in the duty.
    """
    total: dict[tuple[str, str], float] = {}
    for b in stretches:
        weight = 1.0 if rates is None else rates[b.task]
        total[(b.joint, b.limit)] = (total.get((b.joint, b.limit), 0.0)
                                     + weight * (b.end - b.start))
    moving = sum(total.values()) or 1.0
    return sorted(((j, lim, t / moving) for (j, lim), t in total.items()),
                  key=lambda item: -item[2])


def _waypoints_at(model: PathModel, leg: Leg, scale: float,
                  time: float) -> tuple[int, int]:
    """The waypoints between which the path is at a time of the cycle [s]."""
    motion = model.motion
    clock = motion.dwells[0]
    for profile, r in zip(leg.profiles, leg.kinematic, strict=True):
        if profile is None:
            continue
        duration = profile.duration * r * scale
        if time < clock + duration:
            s = profile.path_state(np.array([max(time - clock, 0.0) / (r * scale)]))[0][0]
            return profile.piece.segment(float(s))
        clock += duration + motion.dwells[profile.piece.last]
    return len(motion.waypoints) - 2, len(motion.waypoints) - 1
