"""What a study computes per case: a registry keyed by name, and the ``size`` computation.

A computation takes the cases of one group (same robot file, motion file, mounting
and payload shape) and yields one `Outcome` per case as each completes; a case whose
inputs are bad, or whose motion cannot be planned, fails alone, with its message.
``size`` evaluates a group from one basis of batched passes (`hdselect.study.group`)
when it may, and each case on its own otherwise (`size_direct`): a group too small
to repay the basis, or a motion whose plan depends on the payload (TOPPRA under
torque limits). Either way the answer is the sizing core's, to rounding.
"""

from __future__ import annotations

import os
import socket
import time
from collections.abc import Callable, Generator, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from hdselect.catalog import Unit, load_catalog
from hdselect.errors import HdselectError, InputError
from hdselect.motion import Motion, load_motion, robot_file_named, robot_for_motion
from hdselect.options import Options, options_for
from hdselect.planning import Trajectory, plan
from hdselect.robot import Payload, Robot, load_robot
from hdselect.sizing import size_trajectory
from hdselect.study.group import build_basis, plan_depends_on_payload, size_case
from hdselect.study.spec import Case
from hdselect.summary import Summary, summarize

MIN_GROUP = 4
"""Cases of one robot and path from which a group is evaluated from a shared basis: below
it, sizing each case on its own costs less than the basis's passes."""


@dataclass(frozen=True)
class Outcome:
    """One case's result, as a worker reports it.

    Attributes:
        index: The case's index in the study.
        key: The case's key.
        ok: It ran to the end (whether or not a unit fits: see the result).
        error: Why it failed, one line, when it did.
        result: The computation's result as plain data (``size``: `Summary.to_dict`).
        method: ``grouped`` (from a group's basis) or ``direct`` (sized on its own).
        note: Why a case of a group was sized on its own, if it was.
        seconds: Time the case took in its worker [s] (a grouped case: its share of the basis).
        host: The worker's host name and process id.
    """

    index: int
    key: str
    ok: bool
    error: str | None
    result: dict[str, Any] | None
    method: str
    note: str | None
    seconds: float
    host: str


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
                "cycle_time_s", "carried_mass_kg", "slowdown", "flags")
"""Per-joint columns of a ``size`` row."""


def size_rows(result: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per joint of a ``size`` result (`Summary.to_dict`)."""
    return [{
        "joint": joint["name"], "unit": joint["unit"], "feasible": joint["feasible"],
        "binding": joint["binding"], "utilization": joint["utilization"][joint["binding"]],
        "life_l50_h": joint["life_l50_hours"], "life_l10_h": joint["life_l10_hours"],
        "motor_peak_nm": joint["motor_peak_torque"], "motor_rms_nm": joint["motor_rms_torque"],
        "motor_max_rpm": joint["motor_max_speed"], "cycle_time_s": result["cycle_time"],
        "carried_mass_kg": joint["carried_mass"], "slowdown": joint["slowdown"],
        "flags": " ".join(joint["flags"]),
    } for joint in result["joints"]]


class _Inputs:
    """Robots, motions and catalogs read once per worker task, keyed by file."""

    def __init__(self) -> None:
        self.robots: dict[Path, Robot] = {}
        self.motions: dict[tuple[Path, Path], Motion] = {}
        self.units: dict[tuple[tuple[Path, ...], int | None], tuple[Unit, ...]] = {}

    def case(self, case: Case) -> tuple[Robot, Motion, Payload | None]:
        """The bare robot, the motion and the case's payload."""
        robot_file = case.robot if case.robot is not None else robot_file_named(case.motion)
        if robot_file not in self.robots:
            self.robots[robot_file] = load_robot(robot_file)
        robot = self.robots[robot_file]
        if (case.motion, robot_file) not in self.motions:
            self.motions[case.motion, robot_file] = load_motion(case.motion, robot)
        motion = self.motions[case.motion, robot_file]
        return robot, motion, case.payload_for(motion.payload)

    def catalog(self, case: Case) -> tuple[Unit, ...]:
        """The case's candidate units (its catalogs, only its ratio if it gives one)."""
        key = (case.catalog, case.ratio)
        if key not in self.units:
            units = load_catalog(case.catalog)
            if case.ratio is not None:
                chosen = tuple(u for u in units if u.ratio == case.ratio)
                if not chosen:
                    ratios = sorted({u.ratio for u in units})
                    raise InputError(f"no unit has ratio {case.ratio}; the catalog's ratios "
                                     f"are: {', '.join(map(str, ratios))}", field="ratio")
                units = chosen
            self.units[key] = units
        return self.units[key]


def case_options(case: Case, motion: Motion) -> Options:
    """The case's options over the motion file's, one thread for the dynamics."""
    return options_for(motion, **case.options, threads=1)


def scaled(trajectory: Trajectory, time_scale: float) -> Trajectory:
    """The same path run s times slower [-]: times times s, speeds / s, accelerations / s^2."""
    if time_scale == 1.0:
        return trajectory
    y = 1.0 / time_scale
    return replace(trajectory, dt=trajectory.dt * time_scale,
                   duration=trajectory.duration * time_scale, t=trajectory.t * time_scale,
                   qd=trajectory.qd * y, qdd=trajectory.qdd * y**2)


def size_direct(case: Case, inputs: _Inputs | None = None) -> Summary:
    """One case on its own: `hdselect.size`'s load, plan and size, the path time-scaled.

    Raises:
        HdselectError: An input is bad or the motion cannot be planned.
    """
    inputs = inputs or _Inputs()
    robot, motion, payload = inputs.case(case)
    units = inputs.catalog(case)
    options = case_options(case, motion)
    carrying = robot_for_motion(robot, motion, payload=payload, mounting=case.mounting)
    trajectory = scaled(plan(carrying, motion), case.time_scale)
    result = size_trajectory(carrying, trajectory, units, options)
    return summarize(replace(result, motion=motion))


def run_size(cases: Sequence[Case], grouped: bool) -> Iterator[Outcome]:
    """``size`` for the cases of one group: from a shared basis where it may, else each alone."""
    inputs = _Inputs()
    host = f"{socket.gethostname()}:{os.getpid()}"
    if grouped and len(cases) >= MIN_GROUP:
        pending = yield from _grouped(list(cases), inputs, host)
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


_PAYLOAD_PLAN = "TOPPRA plans under torque limits with the payload's dynamics: sized on its own"


def _grouped(cases: list[Case], inputs: _Inputs,
             host: str) -> Generator[Outcome, None, list[tuple[Case, str | None]]]:
    """Yield the outcomes of the cases that share a basis; return the ones that do not."""
    start = time.perf_counter()
    loaded: list[tuple[Case, Robot, Motion, Payload | None]] = []
    for case in cases:
        try:
            loaded.append((case, *inputs.case(case)))
        except HdselectError as err:
            yield _failed(case, err, "grouped", start, host)
    alone: list[tuple[Case, str | None]] = []
    shapes: dict[Any, list[tuple[Case, Robot, Motion, Payload | None]]] = {}
    for item in loaded:
        case, _, motion, payload = item
        if plan_depends_on_payload(motion):
            alone.append((case, _PAYLOAD_PLAN))
            continue
        shape = None if payload is None else (payload.com, payload.inertia, payload.frame)
        shapes.setdefault(shape, []).append(item)
    for members in shapes.values():
        case, robot, motion, payload = members[0]
        begin = time.perf_counter()
        try:
            mounted = robot_for_motion(robot, replace(motion, payload=None),
                                       mounting=case.mounting)
            basis = build_basis(mounted, motion, payload)
        except HdselectError as err:
            for member in members:
                yield _failed(member[0], err, "grouped", begin, host)
            continue
        share = (time.perf_counter() - begin) / len(members)
        for case, _, motion, payload in members:
            started = time.perf_counter()
            try:
                summary = size_case(basis, None if payload is None else payload.mass,
                                    case.time_scale, inputs.catalog(case),
                                    case_options(case, motion))
            except HdselectError as err:
                yield _failed(case, err, "grouped", started, host)
                continue
            yield Outcome(case.index, case.key, True, None, summary.to_dict(), "grouped", None,
                          share + time.perf_counter() - started, host)
    return alone


def _failed(case: Case, err: HdselectError, method: str, start: float, host: str) -> Outcome:
    return Outcome(case.index, case.key, False, str(err), None, method, None,
                   time.perf_counter() - start, host)


SIZE = Computation("size", "choose a gearhead for every joint (hdselect size)", run_size,
                   size_rows, SIZE_COLUMNS)
COMPUTATIONS: dict[str, Computation] = {"size": SIZE}
"""Every computation a study can ask for, by name."""
