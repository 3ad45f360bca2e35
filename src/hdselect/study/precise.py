"""A study case's precision figures: on every sample of its cycle, and as CSV cells.

The grouped selection (`hdselect.study.pooled`) reads each task's kept rows: a run of
identical states once, weighted by its length. The steps after the selection (the
precision figures along the cycle and the whole-arm targets) read every sample of every
task, pooled as `hdselect.sizing.core.size_tasks` pools them. `ExpandedTorques` gives the
case's torques on those samples: each sample takes its kept row's torque and wrench (its
state is that row's), so these steps see what they see in `hdselect.size` of the case.
`precision_fields` gives a case's figures (`hdselect.sizing.summary.precision_record`) as
a joint's CSV cells.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.catalog.units import RAD_PER_ARCMIN, Unit
from hdselect.sizing.bearing import SampledWrench
from hdselect.sizing.core import select_units
from hdselect.sizing.loads import JointLoad
from hdselect.sizing.options import Options
from hdselect.sizing.result import JointSizing, Motors
from hdselect.sizing.stiffening import Stiffened, stiffened
from hdselect.sizing.tasks import Samples, Task, pooled
from hdselect.sizing.torques import TorqueModel
from hdselect.study.group import BasisTorques


def kept_rows(models: Sequence[BasisTorques]) -> np.ndarray:
    """Each sample of the tasks' cycles, end to end: its kept row among the pooled rows, (n,).

    Args:
        models: One basis model per counted task, in task order.
    """
    parts, start = [], 0
    for model in models:
        basis = model.basis
        count = len(basis.rows)
        parts.append(start + np.repeat(np.arange(count), basis.weight.astype(np.intp)))
        start += count
    return _read_only(np.concatenate(parts))


class ExpandedTorques:
    """A grouped case's pooled model read on every sample of its tasks: a `TorqueModel`.

    Attributes:
        robot: The first counted task's robot (the pooled model's).
        samples: Every sample of every counted task, pooled at the shares
            (`hdselect.sizing.tasks.pooled`), as the core pools them.
        rows: Each sample's kept row in `grouped`'s samples, (n,).
    """

    def __init__(self, grouped: TorqueModel, rows: np.ndarray, tasks: Sequence[Task],
                 idle: float = 0.0) -> None:
        """Expand a grouped model.

        Args:
            grouped: The case's pooled model on kept rows.
            rows: Each sample's kept row (`kept_rows`).
            tasks: The case's tasks as `size` plans them: each its own payload, its
                trajectory run at the case's time scale (every row).
            idle: The fraction of the time no task runs [-].
        """
        self.grouped = grouped
        self.robot = grouped.robot
        self.rows = rows
        self.samples: Samples = pooled(tasks, idle)
        if len(self.samples) != len(rows):
            raise ValueError(f"{len(rows)} expanded rows for {len(self.samples)} samples")

    def torques(self, joint: str, masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's torque and emergency-stop torque along every sample [N m]."""
        tau, stop = self.grouped.torques(joint, masses)
        return tau[self.rows], stop[self.rows]

    def wrench(self, joint: str, masses: Mapping[str, float]) -> SampledWrench | None:
        """The force and moment through a sized joint along every sample [N, N m]."""
        return expanded_wrench(self.grouped.wrench(joint, masses), self.rows)

    def gravity_wrench(self, joint: str, masses: Mapping[str, float]) -> np.ndarray | None:
        """The wrench holding each sample's pose still [N, N m]."""
        held = self.grouped.gravity_wrench(joint, masses)
        return None if held is None else held[:, self.rows]

    def scaling_parts(self, joint: str,
                      masses: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """A joint's gravity and coasting parts along every sample [N m]."""
        gravity, coast = self.grouped.scaling_parts(joint, masses)
        return gravity[self.rows], coast[self.rows]

    def gravity(self, masses: Mapping[str, float]) -> np.ndarray:
        """Largest |gravity torque| of every joint over the gravity poses [N m], (dof,)."""
        return self.grouped.gravity(masses)

    def load_inertia(self, joint: str, masses: Mapping[str, float]) -> float:
        """The joint's largest M_jj over the gravity poses [kg m^2]."""
        return self.grouped.load_inertia(joint, masses)

    def task_inertias(self, joint: str, masses: Mapping[str, float]) -> tuple[float, ...]:
        """The joint's largest M_jj over each task's gravity poses [kg m^2]."""
        return self.grouped.task_inertias(joint, masses)

    def loads(self, masses: Mapping[str, float]) -> tuple[JointLoad, ...]:
        """Every joint against its file's limits over every task."""
        return self.grouped.loads(masses)


def expanded_wrench(wrench: SampledWrench | None, rows: np.ndarray) -> SampledWrench | None:
    """A wrench on kept rows read on every sample: each points at its kept row's state."""
    if wrench is None:
        return None
    index = rows if wrench.index is None else wrench.index[rows]
    return SampledWrench(wrench.rows, _read_only(np.array(index, dtype=np.intp)))


def expanded_joint(joint: JointSizing, rows: np.ndarray) -> JointSizing:
    """A joint sized on kept rows with its per-sample arrays on every sample."""
    return replace(joint, torque=frozen(joint.torque[rows]),
                   stop_torque=frozen(joint.stop_torque[rows]),
                   wrench=expanded_wrench(joint.wrench, rows),
                   motor_torque=None if joint.motor_torque is None
                   else frozen(joint.motor_torque[rows]))


def grouped_stiffened(grouped: TorqueModel, models: Sequence[BasisTorques],
                      tasks: Sequence[Task], units: Mapping[str, tuple[Unit, ...]],
                      joints: Sequence[JointSizing], masses: Mapping[str, float],
                      options: Options, motors: Motors) -> Stiffened:
    """A grouped case's step after the selection, as `hdselect.size` takes it for the case.

    The precision figures, and the units raised for a whole-arm target
    (`hdselect.sizing.stiffening.stiffened`), on every sample of the case's tasks.

    Args:
        grouped: The case's pooled model on kept rows (the selection's).
        models: Its basis model per counted task, in task order.
        tasks: The counted tasks as the case plans them: each its own payload, its
            trajectory run at the case's time scale (every row).
        units: Every sized joint's candidate units, as the selection took them.
        joints: The selection, on kept rows.
        masses: The mass each joint's unit and motor add [kg].
        options: The assumptions (``prefer`` resolved).
        motors: Candidate motors per sized joint, as the selection took them.

    Returns:
        The joints (their per-sample arrays on every sample), masses and figures.
    """
    rows = kept_rows(models)
    expanded = ExpandedTorques(grouped, rows, tasks)
    return stiffened(expanded, units, [expanded_joint(joint, rows) for joint in joints],
                     dict(masses), options, motors, select=select_units)


PRECISION_NOTE = ("the precision figures: the joint's unit's largest twist along the cycle "
                  "and holding each pose still [arcmin], its lowest single-axis natural "
                  "frequency [Hz]; the whole arm's largest tool deflection along the cycle "
                  "and holding each pose still [mm] and its lowest mode [Hz] (the same in "
                  "each row of a case); each whole-arm target's verdict (met, or not met "
                  "and why); the unit a joint's was raised from for a whole-arm target. "
                  "'not rated' where the catalog rates no stiffness for the unit (for the "
                  "arm's figures: some sized joint's); empty where not computed")
"""What the precision columns of a ``size`` row hold."""


NOT_RATED_CELL = "not rated"
"""A precision cell whose figure the unit's catalog does not rate."""


def precision_fields(name: str, record: dict[str, Any] | None) -> dict[str, Any]:
    """A joint's precision columns from a case's `hdselect.sizing.summary.precision_record`.

    Empty where the figures were not computed (``precision`` off, a record made before).
    """
    if record is None:
        return {}
    joint = next(item for item in record["joints"] if item["name"] == name)

    def rated(value: float | None, scale: float, is_rated: bool) -> Any:
        return (value * scale if value is not None else None) if is_rated else NOT_RATED_CELL

    arm = not record["not_rated"]
    targets = {check["name"]: "met" if check["ok"] else
               "not met" + (f": {check['shortfall']}" if check["shortfall"] else "")
               for check in record["targets"]}
    raised = next((item["chosen"] for item in record["raised"] if item["joint"] == name), None)
    return {"torsion_arcmin": rated(joint["max_torsion"], 1.0 / RAD_PER_ARCMIN, joint["rated"]),
            "holding_torsion_arcmin": rated(joint["holding_torsion"], 1.0 / RAD_PER_ARCMIN,
                                             joint["rated"]),
            "natural_frequency_hz": rated(joint["lowest_frequency"], 1.0, joint["rated"]),
            "tool_cycle_mm": rated(record["tool_deflection"], 1e3, arm),
            "tool_holding_mm": rated(record["tool_holding"], 1e3, arm),
            "arm_frequency_hz": rated(record["arm_frequency"], 1.0, arm),
            "tool_deflection_target": targets.get("tool_deflection"),
            "arm_frequency_target": targets.get("arm_frequency"),
            "raised_from": raised}


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array
