"""An envelope as a JSON document: the shape `hdselect envelope --json` writes.

Every number is SI: positions rad (m for a prismatic joint), speeds rad/s,
accelerations rad/s^2, torques N m (N), so a state can be fed back into inverse
dynamics as it is. The duty's own sizing is the `hdselect size --json` document.
A duty of several tasks (a mix) gives its figures over one cycle of each task in turn
(``cycle_time_s``, ``samples``) and each task's own (``tasks``).
An output bearing's largest loads are over the duty and the worst states, its means
over the duty (``bearing_note``). The precision figures (``precision``, as in
``hdselect size --json``) are along the duty with the envelope's units
(``precision_note``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hdselect.catalog.bearing_rules import NOT_RATED
from hdselect.envelope.dutycycle import Duty
from hdselect.envelope.result import EnvelopeResult, JointEnvelope, WorstState
from hdselect.envelope.torques import BEARING_NOTE, PARTS_NOTE, PRECISION_NOTE
from hdselect.sizing.diagnosis import diagnosis_of
from hdselect.sizing.records import (
    bearing_load_json,
    candidate_bearing_json,
    candidate_json,
    finite_or_none,
    joint_load_json,
    payload_json,
    size_json,
)

UNITS_NOTE = ("SI: q rad, qd rad/s, qdd rad/s^2 and torques N m (m, m/s, m/s^2 and N for a "
              "prismatic joint); each state lists every joint in the robot's order")


def envelope_json(result: EnvelopeResult) -> dict[str, Any]:
    """An envelope as JSON: the spec, the duty, the search, and every joint's verdict."""
    spec, box = result.spec, result.spec.box
    duty = result.duty
    sized = result.sizing
    selection = size_json(sized)
    return {
        "robot": str(result.robot.path),
        "spec_file": None if spec.file is None else str(spec.file.path),
        "units": UNITS_NOTE,
        "joint_names": list(box.joint_names),
        "limits": {name: {"lower": float(box.lower[j]), "upper": float(box.upper[j]),
                          "periodic": box.periodic[j], "velocity": float(box.velocity[j]),
                          "acceleration": float(box.acceleration[j]),
                          "duty_jerk": float(spec.jerk[j]),
                          "sources": {kind: spec.sources[kind][j] for kind in spec.sources}}
                   for j, name in enumerate(box.joint_names)},
        "duty": {"label": duty.label, "default": duty.default,
                 "motion": None if duty.path is None else str(duty.path),
                 "moves": duty.moves, "seed": duty.seed, **_duty_cycles(duty)},
        "search": {"starts": result.settings.starts, "refined_per_round": result.settings.refine,
                   "tolerance": result.settings.tolerance, "seed": result.settings.seed,
                   "states_evaluated": result.states, "rounds": result.rounds,
                   "masses_settled": result.settled, "converged": result.converged,
                   "seconds": result.seconds},
        "feasible": result.feasible,
        "assumptions": selection["assumptions"],
        "payload": payload_json(result.robot),
        "root_link": result.robot.root_link,
        "masses_kg": dict(result.masses),
        "bearing_note": (BEARING_NOTE if any(joint.sizing.bearing is not None
                                                  for joint in result.joints) else None),
        "joints": [_joint_json(joint, result) for joint in result.joints],
        "precision": selection.get("precision"),
        "precision_note": None if sized.precision is None else PRECISION_NOTE,
        "events_note": (PARTS_NOTE if any(task.carried is not None for task in duty.tasks)
                        else None),
        "joint_loads": [joint_load_json(load) for load in sized.loads],
        "warnings": list(sized.warnings),
        "duty_sizing": size_json(result.duty_sizing),
    }


def _duty_cycles(duty: Duty) -> dict[str, Any]:
    """The duty's cycle time [s] and samples: one cycle of each task in turn, and per task."""
    cycles = [(task.label, task.share, task.trajectory.duration, len(task.trajectory.t))
              for task in duty.tasks]
    document: dict[str, Any] = {"cycle_time_s": math.fsum(c[2] for c in cycles),
                                "samples": sum(c[3] for c in cycles)}
    if len(cycles) > 1:
        document["tasks"] = [{"name": name, "share": share, "cycle_time_s": time,
                              "samples": count} for name, share, time, count in cycles]
    return document


def _joint_json(joint: JointEnvelope, result: EnvelopeResult) -> dict[str, Any]:
    chosen = joint.selected
    j = result.robot.joint_index(joint.name)
    sizing = joint.sizing
    candidates = [candidate_json(c) for c in sizing.candidates]
    document: dict[str, Any] = {
        "name": joint.name,
        "selected": chosen.unit.id if chosen else None,
        "binding": chosen.binding if chosen else None,
        "carried_mass_kg": sizing.carried_mass,
        "gravity_loaded": sizing.gravity_loaded,
        "worst": {figure: _state_json(state) for figure, state in joint.worst.items()},
        "gravity": _state_json(joint.gravity),
        "max_speed": float(result.spec.box.velocity[j]),
        "mean_torque_nm": sizing.load.mean_torque,
        "convergence": {
            "converged": joint.convergence.converged, "note": joint.convergence.note,
            "demands": {kind: {"by_starts": [[n, value] for n, value in worst.by_starts],
                               "converged": worst.converged, "worst": worst.value}
                        for kind, worst in joint.convergence.by_demand.items()}},
        "duty_selected": joint.duty.unit.id if joint.duty else None,
        "duty_binding": joint.duty.binding if joint.duty else None,
        "candidates": candidates,
        "bearing": None,
        "diagnosis": None if (found := diagnosis_of(result.sizing, joint.name)) is None
        else found.to_dict(),
    }
    if sizing.bearing is not None:  # with the envelope's units' masses
        rating = (chosen or sizing.strongest).unit.bearing
        document["bearing"] = {**bearing_load_json(sizing.bearing),
                               "largest_over": "the duty and the worst states",
                               "means_over": "the duty",
                               "rated": rating is not None,
                               "note": None if rating is not None else NOT_RATED}
        for candidate, entry in zip(sizing.candidates, candidates, strict=True):
            entry["bearing"] = candidate_bearing_json(candidate)
    return document


def _state_json(state: WorstState) -> dict[str, Any]:
    return {"torque": state.torque, "q": _floats(state.q), "qd": _floats(state.qd),
            "qdd": _floats(state.qdd), "source": state.source}


def _floats(values: np.ndarray) -> list[float | None]:
    return [finite_or_none(float(v)) for v in values]
