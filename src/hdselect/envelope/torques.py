"""The envelope's torque model: the duty's samples, then the worst states, for the one core.

`hdselect.sizing.core.select_units` chooses every joint's unit from a `TorqueModel`'s
samples. Here they are the duty's samples (each standing for its time, as in any
sizing), followed by every worst state found (`hdselect.envelope.states`), each
standing for no time at all (dt = 0, weight 0). So the rules of one sample (repeated
peak, static, input speed, emergency stop, crash) see the worst states and the duty,
and the averaged rules (mean torque, mean speed, life, motor RMS) see the duty alone:
every rule is the core's own, implemented once.

The output bearing's loads follow the same rule (`BEARING_NOTE`): a worst state's
whole force and moment count in the bearing's largest loads and its static safety,
never in its means and life. The search looks for the worst torques, not for the
bearing's worst loads, so these largest loads bound what the duty and those states
carry, not every motion within the spec.

A worst state belongs to no task: its task index is -1 and its time NaN. Where the duty's
payload events move parts, a worst state carries every one of them (`carrying_every_part`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.envelope.states import StateRows
from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import cycle_torques, gravity_torques, joint_inertias
from hdselect.robot.model import Robot
from hdselect.robot.payload import Payload
from hdselect.robot.wrenches import axis_wrenches
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.loads import JointLoad, joint_loads, merged_loads
from hdselect.sizing.options import Options
from hdselect.sizing.precision import Precision, precision_of
from hdselect.sizing.result import JointSizing
from hdselect.sizing.tasks import Samples, Task, holding, pooled
from hdselect.sizing.torques import DirectTorques

BEARING_NOTE = ("output bearing: its largest loads are over the duty and the worst "
                "torque states, its means and life over the duty; the search bounds the "
                "torque, not the bearing's force and moment, so a motion within the spec "
                "may load the bearing more")
"""What every output of an envelope says of the output bearing's loads."""
PRECISION_NOTE = ("precision: the figures (each unit's twist and resonance, the tool's "
                  "deflection, the arm's modes) are along the duty, with the envelope's "
                  "units; a worst state is a state, not a motion, so none is among them, "
                  "while a per-joint target (max_torsion, min_natural_frequency) is judged "
                  "at the worst states too")
"""What every output of an envelope says of its precision figures."""
PARTS_NOTE = ("payload events: the worst states carry every part the duty's events move; "
              "the duty's averaged rules carry each part between its events")
"""What every output of an envelope with payload events says of them."""


class EnvelopeTorques:
    """Torques along a duty's samples and at the worst states, for any carried masses.

    Attributes:
        robot: The robot (payload and mounting; no gearhead masses).
        samples: The duty's samples, then one per worst state.
        rows: The worst states.
        q: Positions of every sample, the duty's and the worst states' [rad or m], (n, dof).
    """

    def __init__(self, tasks: Sequence[Task], rows: StateRows, stop_time: float, *,
                 threads: int | None = None, guess: Mapping[str, float] | None = None,
                 idle: float = 0.0, wrenches: bool = True, states: Robot | None = None) -> None:
        """Prepare the model; the duty's torques are computed when first asked for.

        Args:
            tasks: The duty's tasks.
            rows: The worst states.
            stop_time: The emergency-stop time [s].
            threads: Threads for the batched passes.
            guess: Masses [kg] expected per joint (the duty's passes use them where the
                core has not chosen yet).
            idle: The fraction of the time no task of the duty runs [-].
            wrenches: Also compute the sized joints' wrenches along the duty (the output
                bearings' loads).
            states: The robot the worst states are evaluated with (`carrying_every_part`);
                None: the duty's first task's.
        """
        duty = pooled(tasks, idle)
        self.duty = DirectTorques(duty.tasks, duty, stop_time, threads=threads, guess=guess,
                                  wrenches=wrenches)
        self.robot: Robot = self.duty.robot
        self.states: Robot = states if states is not None else self.robot
        self.rows = rows
        self.stop_time = stop_time
        self.threads = threads
        self.samples = appended(duty, rows)
        self.q = frozen(np.concatenate([*(task.trajectory.q for task in duty.tasks), rows.q]))

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along the samples [N m], each (n,)."""
        tau, stop = self.duty.torques(joint, masses)
        j = self.robot.joint_index(joint)
        extra = cycle_torques(self._carrying(masses), self.rows.q, self.rows.qd, self.rows.qdd,
                              self.stop_time, threads=self.threads, columns=[j])
        return (np.concatenate([tau, extra.tau[:, 0]]),
                np.concatenate([stop, extra.stop[:, 0]]))

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along the samples [N, N m].

        The duty's rows, then one per worst state (`BEARING_NOTE`); None when the
        model computes no wrenches.
        """
        duty = self.duty.wrench(joint, masses)
        if duty is None:
            return None
        states = axis_wrenches(self._carrying(masses), self.rows.q, self.rows.qd,
                               self.rows.qdd, [joint], threads=self.threads)[0]
        distinct = duty.rows.shape[1]
        rows = np.concatenate([duty.rows, states[:len(duty.rows)]], axis=1)
        own = np.arange(distinct) if duty.index is None else duty.index
        index = np.concatenate([own, distinct + np.arange(len(self.rows))])
        rows.setflags(write=False)
        index.setflags(write=False)
        return SampledWrench(rows, index)

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each pose of the samples still [N, N m], (6, n)."""
        held = self.duty.gravity_wrench(joint, masses)
        if held is None:
            return None
        still = np.zeros_like(self.rows.q)
        states = axis_wrenches(self._carrying(masses), self.rows.q, still, still, [joint],
                               threads=self.threads)[0]
        return np.concatenate([held, states], axis=1)

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity part RNEA(q, 0, 0) and coasting part RNEA(q, qd, 0) [N m]."""
        gravity, coast = self.duty.scaling_parts(joint, masses)
        j = self.robot.joint_index(joint)
        extra = cycle_torques(self._carrying(masses), self.rows.q, self.rows.qd, self.rows.qdd,
                              self.stop_time, split=True, threads=self.threads, columns=[j])
        if extra.gravity is None or extra.coasting is None:
            raise RuntimeError("cycle_torques(split=True) returned no gravity or coasting part")
        return (np.concatenate([gravity, extra.gravity[:, 0]]),
                np.concatenate([coast, extra.coasting[:, 0]]))

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over the duty's poses and the states [N m].

        The worst gravity poses are among the states. Shape (dof,).
        """
        held = np.abs(gravity_torques(self._carrying(masses), self.rows.q,
                                      threads=self.threads)).max(axis=0)
        return np.maximum(self.duty.gravity(masses), held)

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over the duty's poses and the worst states [kg m^2]."""
        here = float(joint_inertias(self._carrying(masses), self.rows.q, [joint],
                                    threads=self.threads).max())
        return max(self.duty.load_inertia(joint, masses), here)

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj over each duty task's poses [kg m^2] (a state is in none)."""
        return self.duty.task_inertias(joint, masses)

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint of the robot against its file's limits, over the duty and the states."""
        robot = self._carrying(masses)
        extra = cycle_torques(robot, self.rows.q, self.rows.qd, self.rows.qdd, self.stop_time,
                              threads=self.threads)
        states = Trajectory(self.robot.joint_names, 1.0, 0.0, np.zeros(len(self.rows)),
                            self.rows.q, self.rows.qd, self.rows.qdd)
        return merged_loads([self.duty.loads(masses),
                             joint_loads(self.robot, states, extra.tau)])

    def _carrying(self, masses: Mapping[str, float]) -> Robot:
        """The worst states' robot with the units' masses carried."""
        ordered = {name: masses[name] for name in self.robot.sized_joints if name in masses}
        return self.states.with_gearheads(ordered) if ordered else self.states


def carrying_every_part(robot: Robot, tasks: Sequence[Task]) -> Robot:
    """The robot with every part the duty's payload events move: the worst carried state.

    A worst state belongs to no task and no time, so it carries everything any task
    carries at some time (`PARTS_NOTE`); the duty's averaged rules keep its events.

    Args:
        robot: The robot as the envelope searches it (payload and mounting applied).
        tasks: The duty's tasks (each task's `Carried.parts`).
    """
    moved: dict[str, Payload] = {}
    for task in tasks:
        for part in () if task.carried is None else task.carried.parts:
            moved.setdefault(part.name, part)
    return holding(robot, [moved[name] for name in sorted(moved)])


def appended(samples: Samples, rows: StateRows) -> Samples:
    """A duty's samples followed by the worst states, each standing for no time.

    Args:
        samples: The duty's pooled samples.
        rows: The worst states.

    Returns:
        The samples: the states' dt and weight 0, time NaN, task -1, and a joint at rest
        where its speed and acceleration are exactly 0.
    """
    n, m = len(samples), len(rows)
    weight = np.ones(n) if samples.weight is None else samples.weight
    dt = np.broadcast_to(np.asarray(samples.dt, dtype=float), (n,))
    task = np.concatenate([samples.task, np.full(m, -1, dtype=np.intp)])
    task.setflags(write=False)
    rest = np.concatenate([samples.rest, rows.rest])
    rest.setflags(write=False)
    return Samples(frozen(np.concatenate([samples.t, np.full(m, np.nan)])),
                   frozen(np.concatenate([dt, np.zeros(m)])),
                   frozen(np.concatenate([weight, np.zeros(m)])),
                   frozen(np.concatenate([samples.qd, rows.qd])),
                   frozen(np.concatenate([samples.qdd, rows.qdd])),
                   rest, task, samples.tasks, samples.duration, samples.idle)


def duty_part(joint: JointSizing, count: int) -> JointSizing:
    """A joint sized on a duty and the worst states, its per-sample arrays on the duty's.

    Args:
        joint: The joint, sized on the duty's samples then the worst states.
        count: The duty's samples.
    """
    wrench = joint.wrench
    index = (None if wrench is None else
             np.arange(count) if wrench.index is None else wrench.index[:count])
    return replace(joint, torque=joint.torque[:count], stop_torque=joint.stop_torque[:count],
                   wrench=None if wrench is None else SampledWrench(wrench.rows, index),
                   motor_torque=None if joint.motor_torque is None
                   else joint.motor_torque[:count])


def duty_precision(model: EnvelopeTorques, sized: Sequence[JointSizing],
                   masses: Mapping[str, float], options: Options) -> Precision | None:
    """The precision figures along the duty, with the envelope's units (`PRECISION_NOTE`).

    Args:
        model: The envelope's model of its final selection.
        sized: That selection's joints.
        masses: The mass each joint's unit adds [kg].
        options: The assumptions; None is returned where they do not ask for the figures.
    """
    if not options.precision:
        return None
    count = len(model.duty.samples)
    return precision_of(model.duty, [duty_part(joint, count) for joint in sized], masses,
                        options)


def duty_time(samples: Samples, i: int) -> str:
    """When duty sample i happens: ``t = 3.141 s``, led by its task's name in a duty of several."""
    when = f"t = {samples.t[i]:.4g} s"
    if len(samples.tasks) < 2:
        return when
    return f"{samples.tasks[int(samples.task[i])].label} {when}"
