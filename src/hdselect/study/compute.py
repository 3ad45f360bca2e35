"""What a study computes per case: a registry keyed by name: ``size``, ``fastest``, ``max-payload``.

A computation takes the cases of one group (same robot file, motion file, mounting
and payload shape) and yields one `Outcome` per case as each completes; a case whose
inputs are bad, or whose motion cannot be planned, fails alone, with its message.
``size`` evaluates a group from one basis of batched passes per task
(`hdselect.study.pooled`: a motion file is a duty of one task, a mix file several) when
it may, and each case on its own otherwise (`size_direct`): a group too small
to repay the basis, or a motion whose plan depends on the payload (TOPPRA under
torque limits). Either way the answer is the sizing core's, to rounding. A case's
motors (its motion file's ``[motor]``, or its ``motor_catalog``) are sized as pairs on
both paths.

``fastest`` and ``max-payload`` run each case on its own, through the same public
calls as their commands (`hdselect.fastest`, `hdselect.max_payload`), and record the
commands' JSON. A case's ``time_scale`` s runs the planned motion s times slower
before it is used: ``max-payload`` carries the payload along it; ``fastest`` takes the
units `size` selects for it (its candidates: the case's catalog and ratio) and then
finds the shortest cycle they allow, which does not depend on s otherwise.
"""

from __future__ import annotations

import math
import os
import socket
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any

from hdselect.base.errors import HdselectError
from hdselect.codesign.choice import NoUnit, choose, duty_of, no_fit
from hdselect.codesign.fastest_cycle import fastest
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.pathbounds import PathInfeasible
from hdselect.codesign.records import fastest_json, max_payload_json, no_fit_json
from hdselect.codesign.scaledpart import scaled_part, with_part
from hdselect.motion.loading import robot_for_motion
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import plan, solve_motion
from hdselect.sizing.arguments import checked_motors
from hdselect.sizing.core import size_problem
from hdselect.sizing.mixtasks import mix_tasks
from hdselect.sizing.problem import Problem
from hdselect.sizing.summary import Summary, summarize
from hdselect.sizing.tasks import task_of
from hdselect.study.case import Case, Outcome
from hdselect.study.casetasks import (
    Inputs,
    case_options,
    case_part,
    case_payloads,
    case_shares,
    is_mix_case,
)
from hdselect.study.group import plan_depends_on_payload
from hdselect.study.pooled import diagnosed, group_cases, scaled, slower_events
from hdselect.study.precise import precision_fields

MIN_GROUP = 4
"""Cases of one robot and path from which a group is evaluated from a shared basis: below
it, sizing each case on its own costs less than the basis's passes."""


@dataclass(frozen=True)
class Computation:
    """One thing a study can compute per case.

    Attributes:
        name: Its name in a study file's ``compute``.
        description: One line for help texts.
        run: Evaluates the cases of one group (grouped if the flag allows) and yields an
            outcome per case as it completes.
        rows: The per-joint fields of a result (the CSV columns after the parameters).
        columns: Those fields' names, in order.
    """

    name: str
    description: str
    run: Callable[[Sequence[Case], bool], Iterator[Outcome]]
    rows: Callable[[dict[str, Any]], list[dict[str, Any]]]
    columns: tuple[str, ...]


SIZE_COLUMNS = ("joint", "unit", "feasible", "binding", "utilization", "life_l50_h",
                "life_l10_h", "motor_peak_nm", "motor_rms_nm", "motor_max_rpm",
                "cycle_time_s", "carried_mass_kg", "slowdown", "flags", "motor",
                "motor_binding", "inertia_ratio", "bearing_max_moment_nm",
                "bearing_max_radial_n", "bearing_max_axial_n", "bearing_mean_moment_nm",
                "bearing_mean_radial_n", "bearing_mean_axial_n", "bearing",
                "bearing_life_l10_h", "binding_task", "shortfall", "torsion_arcmin",
                "holding_torsion_arcmin", "natural_frequency_hz", "tool_cycle_mm",
                "tool_holding_mm", "arm_frequency_hz", "tool_deflection_target",
                "arm_frequency_target", "raised_from")
"""Per-joint columns of a ``size`` row (after ``flags``: where motors are given, the motor
of the selected pair, else of the strongest; its binding rule; load over rotor inertia;
then the output bearing's loads about the flange, largest and 10/3-power means, whether
the unit's catalog rates the bearing (``rated`` / ``not rated``) and its L10 life; last,
``binding_task``: for a mix, the task that sets the binding rule; ``shortfall``: for a joint
without a unit, its diagnosis: each rule's demand against the strongest unit's limit, and
gravity alone where it exceeds every unit's); then the precision figures
(`hdselect.study.precise.PRECISION_NOTE`)."""


def size_rows(result: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per joint of a ``size`` result (`Summary.to_dict`)."""
    return [{
        "joint": joint["name"], "unit": joint["unit"], "feasible": joint["feasible"],
        "binding": joint["binding"], "utilization": joint["utilization"][joint["binding"]],
        "life_l50_h": joint["life_l50_hours"], "life_l10_h": joint["life_l10_hours"],
        "motor_peak_nm": joint["motor_peak_torque"], "motor_rms_nm": joint["motor_rms_torque"],
        "motor_max_rpm": joint["motor_max_speed"], "cycle_time_s": result["cycle_time"],
        "carried_mass_kg": joint["carried_mass"], "slowdown": joint["slowdown"],
        "flags": " ".join(joint["flags"]), "motor": joint["motor_candidate"],
        "motor_binding": joint["motor_binding"], "inertia_ratio": joint["inertia_ratio"],
        "binding_task": joint.get("binding_task"),
        **_bearing_fields(joint),
        "shortfall": _shortfall(joint.get("diagnosis")),
        **precision_fields(joint["name"], result.get("precision")),
    } for joint in result["joints"]]


def _shortfall(diagnosis: dict[str, Any] | None) -> str | None:
    """A joint without a unit: its diagnosis in words; else None."""
    if diagnosis is None:
        return None
    words = "; ".join(item["text"] for item in diagnosis["shortfalls"])
    gravity = diagnosis["gravity"]
    if gravity is not None and gravity["exceeds"]:
        words += (f"; gravity alone needs {gravity['torque_nm']:.3g} N m, over every unit's "
                  f"limit ({gravity['unit']}: {gravity['limit_nm']:.3g} N m)")
    return words


def _bearing_fields(joint: dict[str, Any]) -> dict[str, Any]:
    """A joint's output-bearing columns; empty for a record made before they existed."""
    rated = joint.get("bearing_rated")
    return {"bearing_max_moment_nm": joint.get("bearing_max_moment"),
            "bearing_max_radial_n": joint.get("bearing_max_radial"),
            "bearing_max_axial_n": joint.get("bearing_max_axial"),
            "bearing_mean_moment_nm": joint.get("bearing_mean_moment"),
            "bearing_mean_radial_n": joint.get("bearing_mean_radial"),
            "bearing_mean_axial_n": joint.get("bearing_mean_axial"),
            "bearing": None if rated is None else ("rated" if rated else "not rated"),
            "bearing_life_l10_h": joint.get("bearing_life_l10_hours")}


def case_problem(case: Case, inputs: Inputs | None = None) -> Problem:
    """One case's `Problem`, planned as `hdselect size` plans it (not yet run s times slower).

    A motion file is one task; a mix file's tasks take the case's shares and payloads.

    Raises:
        HdselectError: An input is bad or a motion cannot be planned.
    """
    inputs = inputs or Inputs()
    source: Motion | Mix
    if is_mix_case(case):
        robot, source = inputs.mix(case)
        options = case_options(case, source)
        tasks, idle = mix_tasks(robot, source, mounting=case.mounting, joints=robot.sized_joints,
                                exclude=(), max_samples=options.max_samples,
                                shares=case_shares(case, source),
                                payloads=case_payloads(case, source))
    else:
        bare, source, payload = inputs.case(case)
        options = case_options(case, source)
        part = case_part(case, source)  # the payload is the part the events move
        robot = robot_for_motion(bare, source, payload=None if part else payload,
                                 mounting=case.mounting)
        task = task_of(robot, plan(robot, source, max_samples=options.max_samples), source)
        tasks, idle = (with_part(task, payload) if part else task,), 0.0
    return Problem(robot, source, inputs.catalog(case), options,
                   inputs.motors(case, robot, source), tasks, idle)


def _slower(problem: Problem, time_scale: float) -> Problem:
    """The problem with every task run `time_scale` times slower [-]."""
    return replace(problem, tasks=tuple(
        replace(task, trajectory=scaled(task.trajectory, time_scale),
                carried=slower_events(task.carried, time_scale)) for task in problem.tasks))


def _codesign_problem(problem: Problem) -> Problem:
    """The problem as co-design takes it: its motors checked, one motion's tool poses solved."""
    source = problem.source
    return replace(problem, source=solve_motion(problem.robot, source)
                   if isinstance(source, Motion) else source,
                   motors=checked_motors(problem.robot, problem.motors, problem.options))


def size_direct(case: Case, inputs: Inputs | None = None) -> Summary:
    """One case on its own: its `Problem` (`case_problem`) run s times slower, sized.

    Its ``payload_mass`` is the mass the case's payload sets: the part the payload events
    move, where they move one (as a grouped case's).

    Raises:
        HdselectError: An input is bad or a motion cannot be planned.
    """
    problem = case_problem(case, inputs)
    summary = summarize(diagnosed(size_problem(_slower(problem, case.time_scale))))
    (task, *others) = problem.tasks
    if problem.mix is None and not others and task.motion is not None \
            and case_part(case, task.motion):
        part = scaled_part(task)
        return replace(summary, payload_mass=0.0 if part is None else part.mass)
    return summary


def run_size(cases: Sequence[Case], grouped: bool) -> Iterator[Outcome]:
    """``size`` for the cases of one group: from shared bases where it may, else each alone."""
    inputs = Inputs()
    host = f"{socket.gethostname()}:{os.getpid()}"
    if grouped and len(cases) >= MIN_GROUP:
        pending = yield from group_cases(cases, inputs, host)
    else:
        note = (f"a group of {len(cases)} case{'s' if len(cases) > 1 else ''} (under "
                f"{MIN_GROUP}): sized on its own") if grouped else None
        pending = [(case, note) for case in cases]
    for case, why in pending:
        start = time.perf_counter()
        try:
            summary = size_direct(case, inputs)
        except HdselectError as err:
            yield _failed(case, err, "direct", start, host)
            continue
        yield Outcome(case.index, case.key, True, None, summary.to_dict(), "direct", why,
                      time.perf_counter() - start, host)


def _failed(case: Case, err: HdselectError, method: str, start: float, host: str) -> Outcome:
    return Outcome(case.index, case.key, False, str(err), None, method, None,
                   time.perf_counter() - start, host)


SIZE = Computation("size", "choose a gearhead for every joint (hdselect size)", run_size,
                   size_rows, SIZE_COLUMNS)


def fastest_direct(case: Case, inputs: Inputs | None = None) -> dict[str, Any]:
    """One case's shortest cycle: ``hdselect fastest`` with `size`'s units for the case.

    The units (and the motor paired with each) are those `size` selects for the case's
    motion or mix run ``time_scale`` times slower, from the case's catalog and ratio; the
    result is `hdselect.codesign.records.fastest_json`.

    Where a joint has no unit that runs the path at any speed, the result is
    `hdselect.codesign.records.no_fit_json` (a row per such joint, with why; its
    diagnosis without next steps, as a ``size`` case's).

    Raises:
        HdselectError: An input is bad, a motion is a log, or TOPPRA fails.
    """
    problem = _codesign_problem(case_problem(case, inputs))
    duty, options, catalog, candidates = duty_of(_slower(problem, case.time_scale), None,
                                                 None, None, None)
    try:
        chosen, _, paired = choose(duty.robot, duty, None, catalog, options, candidates)
        motors = {**problem.motors, **{name: (motor,) for name, motor in paired.items()}}
        return fastest_json(fastest(replace(problem, motors=motors), units=chosen))
    except (NoUnit, PathInfeasible) as err:  # a result: a joint no unit runs at any speed
        if not no_fit(err):
            raise
        return _case_steps(no_fit_json(err, str(problem.robot.path), problem.source))


def _case_steps(document: dict[str, Any]) -> dict[str, Any]:
    """A record's joints without a unit as a case has them: the next steps left out.

    Their commands would size the motion file, not the case (as `diagnosed`); the
    ``reason`` is then the diagnosis's shortfall in words.
    """
    for row in document["no_unit"]:
        if row.get("diagnosis") is not None:
            row["diagnosis"] = {**row["diagnosis"], "next_steps": []}
            row["reason"] = _shortfall(row["diagnosis"])
    return document


def max_payload_direct(case: Case, inputs: Inputs | None = None) -> dict[str, Any]:
    """One case's largest payload: ``hdselect max-payload`` on the case's trajectories.

    One motion's payload shape (frame, centre of mass, inertia per kg) is the case's and
    its mass is what is found; a mix's payloads (the case's) scale by one factor. The
    tasks are run ``time_scale`` times slower. The result is
    `hdselect.codesign.records.max_payload_json` with the selection as
    `Summary.to_dict` (the shape a ``size`` case records).

    Raises:
        HdselectError: An input is bad or a motion's plan depends on the payload.
    """
    problem = _codesign_problem(case_problem(case, inputs))
    if case.time_scale != 1.0 and not any(plan_depends_on_payload(task.motion)
                                          for task in problem.tasks
                                          if task.motion is not None):  # else refused below
        problem = _slower(problem, case.time_scale)
    result = max_payload(problem)
    document = _case_steps(max_payload_json(replace(result, selection=None)))
    document["robot"] = str(problem.robot.path)
    if result.selection is not None:
        document["selection"] = summarize(result.selection).to_dict()
    return document


def run_fastest(cases: Sequence[Case], grouped: bool) -> Iterator[Outcome]:
    """``fastest`` for the cases of one group, each on its own (no grouped evaluation)."""
    return _each(cases, fastest_direct)


def run_max_payload(cases: Sequence[Case], grouped: bool) -> Iterator[Outcome]:
    """``max-payload`` for the cases of one group, each on its own (no grouped evaluation)."""
    return _each(cases, max_payload_direct)


def _each(cases: Sequence[Case],
          compute: Callable[[Case, Inputs], dict[str, Any]]) -> Iterator[Outcome]:
    """Each case on its own, its files read once per task; a case that fails fails alone."""
    inputs = Inputs()
    host = f"{socket.gethostname()}:{os.getpid()}"
    for case in cases:
        start = time.perf_counter()
        try:
            result = compute(case, inputs)
        except HdselectError as err:
            yield _failed(case, err, "direct", start, host)
            continue
        yield Outcome(case.index, case.key, True, None, result, "direct", None,
                      time.perf_counter() - start, host)


FASTEST_COLUMNS = ("joint", "unit", "feasible", "binding", "utilization", "life_l50_h",
                   "life_l10_h", "cycle_time_s", "carried_mass_kg", "flags", "optimum_s",
                   "lengthened_by", "derating", "velocity_limit", "velocity_limit_source",
                   "torque_limit_nm", "binds_longest", "binds_share", "shortfall")
"""Per-joint columns of a ``fastest`` row (``shortfall``: where no unit runs a joint at any
speed, a row per such joint says why, as ``size``'s does; nothing else is filled)."""


def fastest_rows(result: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per sized joint of a ``fastest`` result (``hdselect fastest --json``)."""
    if result.get("no_unit"):  # a joint no unit runs at any speed: its row says why
        return [{"joint": row["joint"], "unit": None, "feasible": False, "cycle_time_s": None,
                 "shortfall": _shortfall(row.get("diagnosis")) or row["reason"]}
                for row in result["no_unit"]]
    reason = result["lengthened_by"]
    rows = []
    for joint in result["joints"]:
        candidate = joint["candidate"]
        shares = joint["binding_share"]
        longest = max(shares, key=shares.get) if shares else None
        rows.append({
            "joint": joint["name"], "unit": joint["unit"], "feasible": candidate["feasible"],
            "binding": candidate["binding"],
            "utilization": candidate["checks"][candidate["binding"]]["utilization"],
            "life_l50_h": candidate["life_hours"], "life_l10_h": candidate["l10_hours"],
            "cycle_time_s": result["cycle_time_s"], "carried_mass_kg": joint["carried_mass_kg"],
            "flags": " ".join(candidate["flags"]), "optimum_s": result["optimum_s"],
            "lengthened_by": None if reason is None else f"{reason['joint']} {reason['rule']}",
            "derating": joint["derating"], "velocity_limit": joint["velocity_limit"],
            "velocity_limit_source": joint["velocity_limit_source"],
            "torque_limit_nm": joint["torque_limit_nm"], "binds_longest": longest,
            "binds_share": None if longest is None else shares[longest],
        })
    return rows


MAX_PAYLOAD_COLUMNS = (*SIZE_COLUMNS, "max_payload_kg", "payload_frame", "payload_limit",
                       "payload_factor")
"""Per-joint columns of a ``max-payload`` row: the selection at the largest payload; last,
``payload_factor``: for a mix, the largest factor on its tasks' payloads."""


def max_payload_rows(result: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per sized joint of the selection at the largest payload (one row without it).

    ``payload_limit`` names, on the joint that runs out of units, the unit and the rule
    it reaches; ``max_payload_kg`` is inf where no rule depends on the mass and empty
    where no mass, not even none, fits (or, in a mix, where several tasks' payloads
    scale: ``payload_factor`` is then the answer, each task's mass in the record). Where no
    mass fits, a row per joint no unit fits even without the payload, its ``shortfall``
    saying why.
    """
    unlimited = result["unlimited"]
    head = {"max_payload_kg": math.inf if unlimited else result["max_payload_kg"],
            "payload_frame": None if result["payload"] is None else result["payload"]["frame"],
            "payload_factor": None if "factor" not in result
            else math.inf if unlimited else result["factor"]}
    if result["selection"] is None:
        why = ("no rule depends on the payload mass" if unlimited else
               "no mass, not even none, leaves every joint a unit")
        stuck = result.get("no_unit") or []  # the joints no unit fits even without it
        return [{**head, "payload_limit": why, "joint": row["joint"], "feasible": False,
                 "shortfall": _shortfall(row["diagnosis"])}
                for row in stuck] or [{**head, "payload_limit": why}]
    binding = result["binding"] or {}
    return [{**row, **head, "payload_limit": f"{binding['unit']} {binding['rule']}"
             if row["joint"] == binding.get("joint") else None}
            for row in size_rows(result["selection"])]


FASTEST = Computation("fastest", "the shortest cycle the units `size` selects allow "
                      "(hdselect fastest)", run_fastest, fastest_rows,
                      FASTEST_COLUMNS)
MAX_PAYLOAD = Computation("max-payload", "the largest payload with a unit on every joint "
                          "(hdselect max-payload)", run_max_payload,
                          max_payload_rows, MAX_PAYLOAD_COLUMNS)
COMPUTATIONS: dict[str, Computation] = {"size": SIZE, "fastest": FASTEST,
                                        "max-payload": MAX_PAYLOAD}
"""Every computation a study can ask for, by name."""
