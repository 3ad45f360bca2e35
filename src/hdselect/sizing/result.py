"""What a sizing gives: every joint's candidates, the selection and why, as values."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hdselect.catalog.bearing_rules import BearingLoad
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import PER_SAMPLE_CHECKS, Candidate, CycleLoad, inertia_ratio
from hdselect.catalog.units import Unit
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.robot.model import Robot
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.loads import JointLoad
from hdselect.sizing.options import Options
from hdselect.sizing.precision import Precision
from hdselect.sizing.tasks import Task
from hdselect.sizing.timescale import JointScales, Slowdown

Motors = Mapping[str, Sequence[Motor]]
"""Candidate motors per joint name: the motors each joint's gearhead may be paired with."""

@dataclass(frozen=True, eq=False)
class JointSizing:
    """One joint: every unit (or every gearhead and motor pair) checked, the selection and why.

    Attributes:
        name: Joint name.
        load: Output-side summary of the cycle (with carried masses).
        candidates: One per catalog unit; where motors are given, one per (unit, motor)
            pair, unit by unit.
        selected: The chosen unit (or pair), or None when none fits.
        carried_mass: Gearhead and motor mass this joint carries from joints
            further out [kg].
        gravity_loaded: Gravity loads this joint somewhere in the cycle: a
            fail-safe device is needed where a falling load could injure.
        max_gravity_torque: Largest gravity torque over the cycle's poses [N m].
        torque: Output torque along the cycle [N m], shape (n,).
        stop_torque: Output torque of an emergency stop from each instant [N m], (n,).
        slowdown: For a joint with no feasible unit, the smallest slow-down that would
            fit (its factor rounded up to 0.001).
        scales: For a joint with no feasible unit, the time scales at which each unit
            would fit.
        load_inertia: Where motors are given or the joint has a natural frequency target
            (``min_natural_frequency``), the joint's output-side inertia: the largest
            diagonal entry M_jj of the joint-space inertia matrix over the cycle's poses
            (`hdselect.sizing.torques.inertia_poses`), carried masses and payload
            included [kg m^2].
        motor_torque: Where motors are given, the motor torque of the selected pair (else
            of the strongest) per sample [N m], shape (n,).
        per_task: Where several tasks count, the selected candidate (else the strongest)
            checked against each counted task's samples alone, in the order of the
            result's counted tasks; empty for one task.
        bearing: The loads on the joint's output bearing over the cycle, about its output
            flange (the joint origin, or the options' ``bearing_offset``); None where
            not computed. A unit that rates its bearing is checked about its own centre
            (`hdselect.catalog.rules.Candidate.bearing`).
        wrench: The force and moment through the joint along the samples, in its axis
            frame about the joint origin (`SampledWrench.full` gives them per sample,
            rows as `hdselect.robot.wrenches.axis_wrenches`); None where not computed.
    """

    name: str
    load: CycleLoad
    candidates: tuple[Candidate, ...]
    selected: Candidate | None
    carried_mass: float
    gravity_loaded: bool
    max_gravity_torque: float
    torque: np.ndarray
    stop_torque: np.ndarray
    slowdown: Slowdown | None = None
    scales: JointScales | None = None
    load_inertia: float | None = None
    motor_torque: np.ndarray | None = None
    per_task: tuple[Candidate, ...] = ()
    bearing: BearingLoad | None = None
    wrench: SampledWrench | None = None

    def setting_task(self, rule: str) -> int | None:
        """The counted task that sets a rule of single samples: its index, else None.

        None for a rule that pools every task (mean torque, average speed, life, motor
        RMS), for one task, or where no task gives the rule a value. On a tie, the first.
        """
        if not self.per_task or rule not in PER_SAMPLE_CHECKS:
            return None
        values = [c.checks[rule].utilization if rule in c.checks else 0.0
                  for c in self.per_task]
        best = max(values)
        return values.index(best) if best > 0.0 else None

    @property
    def strongest(self) -> Candidate:
        """The candidate with the highest repeated-peak limit.

        With motors: behind the motor with the highest peak, then rated torque.
        """
        return max(self.candidates, key=lambda c: (
            c.unit.repeated_torque, c.unit.momentary_torque or 0.0, c.unit.rated_torque,
            *((c.motor_unit.peak_torque, c.motor_unit.rated_torque)
              if c.motor_unit is not None else ())))

    def inertia_ratio(self, candidate: Candidate) -> float | None:
        """Load inertia at the motor shaft over the rotor inertia for one pair [-].

        (M_jj / N^2 + J_in) / J_m with M_jj the `load_inertia`; None without a motor, or
        for a motor without rotor inertia (`hdselect.catalog.motor_rules.inertia_ratio`).
        """
        if self.load_inertia is None or candidate.motor_unit is None:
            return None
        return inertia_ratio(self.load_inertia, candidate.unit, candidate.motor_unit)


@dataclass(frozen=True, eq=False)
class SizingResult:
    """Everything `hdselect size` prints, as values.

    Attributes:
        robot: The robot as sized (payload and mounting applied, no gearhead masses).
        trajectory: The trajectory sized.
        joints: One result per sized joint, in the robot's joint order.
        options: The assumptions used.
        units: The catalog.
        motion: The motion the trajectory was planned from, when `size` planned it.
        motors: The candidate motors per joint; empty where no motor data was given
            (then `options` say which rotor inertia and motor mass were assumed).
        loads: Every joint of the robot, sized or not, followers included, in the
            model's order: what it does beside its file's limits (over every task).
        tasks: Every task the robot was sized for, as given (shares included); empty
            where the result was not made from tasks (`robot` and `trajectory` are then
            the only task).
        idle: The fraction of the time no task runs [-] (a mix in cycles per hour).
        mix: The mix file the tasks came from, when `size` read one.
        diagnoses: For each joint no unit fits, why and what would give it one: joint
            name -> `hdselect.sizing.diagnosis.Diagnosis`, where the front end asked for
            them (`hdselect.sizing.diagnosis.with_diagnoses`); else empty.
        precision: The stiffness figures along the cycle (torsion, tool deflection,
            natural frequencies), with the chosen units' masses carried; None where the
            options turn them off (``precision``).
    """

    robot: Robot
    trajectory: Trajectory
    joints: tuple[JointSizing, ...]
    options: Options
    units: tuple[Unit, ...]
    motion: Motion | None = None
    motors: Mapping[str, tuple[Motor, ...]] = field(default_factory=dict)
    loads: tuple[JointLoad, ...] = ()
    tasks: tuple[Task, ...] = ()
    idle: float = 0.0
    mix: Mix | None = None
    diagnoses: Mapping[str, Any] = field(default_factory=dict)
    precision: Precision | None = None

    @property
    def counted(self) -> tuple[Task, ...]:
        """The tasks that count (share above 0), in order: what `JointSizing.per_task` follows."""
        return tuple(task for task in self.tasks if task.share > 0.0)

    def set_by(self, joint: JointSizing, rule: str) -> str | None:
        """Which task sets a rule of a joint's unit: its name, ``"pooled"``, or None for one task.

        A rule of single samples is set by the task whose samples reach the worst value;
        the mean torque, average speed, life and motor RMS pool every task.
        """
        if not joint.per_task:
            return None
        k = joint.setting_task(rule)
        if k is not None:
            return self.counted[k].label
        return "pooled" if rule not in PER_SAMPLE_CHECKS else None

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the robot file and the motion file raised, and what the cycle shows.

        The cycle's lines: limits it exceeds, and peaks a log of positions only does not
        fix to 1 % (with their uncertainty). Each line starts with where it comes from:
        ``robot file:``, ``motion file:`` or ``cycle:``.
        """
        asked = (self.mix.warnings if self.mix is not None
                 else self.motion.warnings if self.motion is not None else ())
        lines = [f"robot file: {note}" for note in self.robot.notes]
        lines += [f"motion file: {warning}" for warning in asked]
        planned = [task.trajectory for task in self.tasks] or [self.trajectory]
        lines += list(dict.fromkeys(f"cycle: {note}" for trajectory in planned
                                    for note in trajectory.notes))
        for load in self.loads:
            if load.above_effort:
                lines.append(f"cycle: joint '{load.name}' peaks at {load.peak:.3g} "
                             f"{'N' if load.linear else 'N m'}, above the robot file's effort "
                             f"limit {load.effort_limit:.3g}")
            if load.uncertain and load.peak is not None and load.peak_uncertainty is not None:
                unit = "N" if load.linear else "N m"
                share = f" ({load.peak_uncertainty / load.peak:.1%})" if load.peak > 0 else ""
                lines.append(f"cycle: joint '{load.name}' peaks at {load.peak:.3g} {unit} +- "
                             f"{load.peak_uncertainty:.2g} {unit}{share}: the log gives "
                             "positions only, and its sampling does not fix this peak to 1 %; "
                             "log the qd_ and qdd_ columns too (or sample faster)")
            if load.above_velocity and not any(f"'{load.name}'" in w for w in asked):
                per_s = "m/s" if load.linear else "rad/s"
                lines.append(f"cycle: joint '{load.name}' moves at up to {load.max_speed:.3g} "
                             f"{per_s}, above the robot file's velocity limit "
                             f"{load.velocity_limit:.3g}")
        return tuple(lines)

    @property
    def feasible(self) -> bool:
        """Every joint has a unit."""
        return all(joint.selected is not None for joint in self.joints)

    @property
    def targets_met(self) -> bool:
        """Every whole-arm precision target given is met (none given: True).

        A target that could not be judged (a unit rates no stiffness) is not met.
        """
        return self.precision is None or all(check.ok for check in self.precision.targets)

    @property
    def cycle_time(self) -> float:
        """Cycle time [s]."""
        return self.trajectory.duration

    @property
    def hold_only(self) -> bool:
        """No sized joint moves: a held pose, judged by the static and momentary checks only."""
        return all(joint.load.moving_time == 0.0 for joint in self.joints)

    @property
    def title(self) -> str:
        """What was sized, for headings: the robot file, the motion file and its planner."""
        if self.mix is not None:
            count = len(self.tasks)
            return f"{self.robot.path.name} running {self.mix.path.name} ({count} tasks)"
        if self.motion is None:
            return f"{self.robot.path.name} on a given trajectory"
        return f"{self.robot.path.name} running {self.motion.path.name} ({self.motion.planner})"
