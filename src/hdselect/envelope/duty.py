"""The duty an envelope judges its averaged rules on: a motion file, or random moves.

Mean torque, mean speed and life are averages over what the robot does, so no
worst state decides them. A given motion file stands for what it does; without one,
the default duty is `DUTY_MOVES` moves between poses drawn uniformly (seeded) in the
joint box, each joint moving at its own limits (Ruckig, jerk-limited, every joint as
fast as its limits allow, not slowed to arrive with the others). Either must stay
within the spec, so that its samples are states of the box too.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
import ruckig

from hdselect.base.errors import InputError, PlanningError
from hdselect.envelope.spec import Spec
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory, check_within_limits, plan
from hdselect.motion.planning.grid import MIN_MOVE_SAMPLES
from hdselect.motion.planning.ruckig import sample_profiles
from hdselect.motion.planning.trajectory import Move, assemble
from hdselect.robot.model import Robot
from hdselect.sizing.tasks import Task

DUTY_DT = 0.001
"""Finest sample period of the default duty [s]."""
DUTY_SAMPLES = 30_000
"""Samples of a default duty long enough to need a coarser period than `DUTY_DT`: its
averages stay exact to well under 0.1 %, and the per-sample motor torques of a cycle this
short are kept (`hdselect.sizing.reflect.CHUNK`)."""
WITHIN = 1e-3
"""How far beyond the spec's velocity and acceleration limits a given duty's samples may
go, as a fraction of the limit [-] (TOPPRA keeps its limits to about 1e-4)."""


@dataclass(frozen=True, eq=False)
class Duty:
    """What the averaged rules are judged on.

    Attributes:
        tasks: The robot's tasks (one, for a motion file or the default duty).
        label: What every output calls it, e.g. ``default duty: 20 random moves at the
            limits (seed 0), 27.1 s``.
        motion: The motion file's motion, or None for the default duty.
        moves: The default duty's moves, else None.
        seed: The default duty's seed, else None.
    """

    tasks: tuple[Task, ...]
    label: str
    motion: Motion | None = None
    moves: int | None = None
    seed: int | None = None

    @property
    def default(self) -> bool:
        """It is the default duty of random moves."""
        return self.motion is None

    @property
    def phrase(self) -> str:
        """The duty in a sentence: ``the default duty: ...`` or ``the duty FILE``."""
        return f"the {self.label}" if self.default else f"the duty {self.label}"


def default_duty(robot: Robot, spec: Spec, moves: int, seed: int, *,
                 max_samples: int) -> Duty:
    """Random point-to-point moves at the limits between poses drawn uniformly in the box.

    Args:
        robot: The robot as the envelope sizes it.
        spec: The limits (the box's ranges and limits, the jerk).
        moves: How many moves.
        seed: Seed of the poses.
        max_samples: Most samples the duty may have.

    Returns:
        The duty, one task.

    Raises:
        PlanningError: Ruckig rejects a move.
        InputError: The duty would exceed `max_samples`.
    """
    box = spec.box
    rng = np.random.default_rng(seed)
    poses = box.lower + rng.random((moves + 1, box.dof)) * (box.upper - box.lower)
    planned = []
    for i in range(moves):
        inp = ruckig.InputParameter(box.dof)
        inp.current_position, inp.target_position = poses[i].tolist(), poses[i + 1].tolist()
        inp.max_velocity = box.velocity.tolist()
        inp.max_acceleration = box.acceleration.tolist()
        inp.max_jerk = spec.jerk.tolist()
        inp.synchronization = ruckig.Synchronization.No  # every joint at its own limits
        traj = ruckig.Trajectory(box.dof)
        try:
            result = ruckig.Ruckig(box.dof).calculate(inp, traj)
        except (ruckig.RuckigError, RuntimeError) as err:
            raise PlanningError(f"the default duty's move {i} cannot be planned: {err}") from err
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise PlanningError(f"the default duty's move {i} cannot be planned ({result.name})")
        planned.append(Move(i, i + 1, traj.duration, partial(sample_profiles, traj)))
    durations = [move.duration for move in planned]
    dt = min(max(DUTY_DT, sum(durations) / DUTY_SAMPLES), min(durations) / MIN_MOVE_SAMPLES)
    motion = Motion(path=Path("default duty"), joint_names=robot.joint_names, planner="ruckig",
                    dt=dt, waypoints=poses, dwells=np.zeros(moves + 1),
                    velocity_limit=box.velocity, acceleration_limit=box.acceleration,
                    jerk_limit=spec.jerk, angle_unit="rad")
    trajectory = assemble(motion, planned, max_samples=max_samples)
    check_within_limits(robot, motion, trajectory, what="default duty")
    label = (f"default duty: {moves} random moves at the limits (seed {seed}), "
             f"{trajectory.duration:.1f} s sampled every {dt * 1e3:.3g} ms")
    return Duty((Task(robot, trajectory, name="default duty"),), label, None, moves, seed)


def motion_duty(robot: Robot, motion: Motion, *, max_samples: int) -> Duty:
    """A motion file as the duty: its trajectory, run by the envelope's robot.

    Raises:
        InputError: The motion cannot be planned on a grid of `max_samples`.
        PlanningError: The planner fails.
    """
    trajectory = plan(robot, motion, max_samples=max_samples)
    return Duty((Task(robot, trajectory, motion=motion),), motion.path.name, motion)


def check_within(duty: Duty, spec: Spec) -> None:
    """Refuse a duty that goes faster or accelerates harder than the spec allows.

    Raises:
        InputError: A joint of a task exceeds a limit by more than `WITHIN` (the message
            names the duty file, the joint, the value, the limit and when).
    """
    box = spec.box
    for task in duty.tasks:
        traj: Trajectory = task.trajectory
        for kind, values, limit in (("velocity", traj.qd, box.velocity),
                                    ("acceleration", traj.qdd, box.acceleration)):
            over = np.abs(values) / limit
            k, j = np.unravel_index(int(np.argmax(over)), over.shape)
            if over[k, j] > 1.0 + WITHIN:
                per = "/s" if kind == "velocity" else "/s^2"
                rotary = task.robot.revolute[j]
                scale, unit = (180.0 / np.pi, "deg" + per) if rotary else (1.0, "m" + per)
                raise InputError(
                    f"joint '{box.joint_names[j]}' reaches {abs(values[k, j]) * scale:.4g} "
                    f"{unit} at t = {traj.t[k]:.4g} s, above the spec's {kind} limit "
                    f"{limit[j] * scale:.4g} {unit}: a duty must run within the spec (raise "
                    "the limit, or slow the duty)",
                    path=task.motion.path if task.motion is not None else None,
                    field=f"limits.{kind}")

