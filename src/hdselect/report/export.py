"""Write results as JSON and CSV, atomically: a file is complete or absent."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hdselect.base.outputs import write_file
from hdselect.catalog.builtin import BuiltinCatalog
from hdselect.catalog.duty import DutyResult
from hdselect.catalog.rules import RPM_PER_RAD_S
from hdselect.catalog.units import NOT_RATED, Stiffness, Unit
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning import Trajectory
from hdselect.motion.planning.toolpath import LineDeviation
from hdselect.robot.joints import JointInfo
from hdselect.robot.model import Robot
from hdselect.sizing.records import (
    bearing_rating_json,
    candidate_json,
    finite_or_none,
    mean_speed_note,
)

_CSV_ROWS = 1 << 14
"""Rows of a trajectory CSV formatted at a time."""


def write_output(target: str | Path, write: Callable[[Any], None], *,
                 binary: bool = False) -> None:
    """Write a file atomically (temporary file, then rename); ``-`` is standard output.

    The same as `hdselect.base.outputs.write_file`: a symlink is followed and its target
    replaced; a character device or a FIFO (``/dev/null``, a named pipe) is written
    directly, never replaced. For several outputs that must appear together, see
    `hdselect.base.outputs.Outputs`.

    Args:
        target: The file, or ``-``.
        write: Writes the content to the open stream it is given.
        binary: Open the file in binary mode (text, UTF-8, otherwise).

    Raises:
        InputError: The file cannot be written.
    """
    write_file(target, write, binary=binary)


def write_json(target: str | Path, document: dict[str, Any]) -> None:
    """Write a JSON document to a file or ``-`` (standard output).

    Strict JSON: a number that is not finite is an error (ValueError), never ``NaN``.
    """
    text = json.dumps(document, indent=2, allow_nan=False) + "\n"

    def write(stream: Any) -> None:
        stream.write(text)

    write_output(target, write)


def duty_json(result: DutyResult) -> dict[str, Any]:
    """A duty-cycle result as JSON; each candidate's life on both bases (L50 and L10)."""
    load = result.load
    return {
        "profile": str(result.cycle.path),
        "mean_torque_nm": finite_or_none(load.mean_torque),
        "mean_output_speed_rpm": load.mean_speed * RPM_PER_RAD_S,
        "cycle_mean_output_speed_rpm": load.cycle_mean_speed * RPM_PER_RAD_S,
        "cycle_time_s": load.cycle_time,
        "peak_torque_nm": load.peak_torque,
        "required_life_hours": result.cycle.life_hours,
        "life_basis": result.cycle.life_basis,
        "mean_speed_rule": mean_speed_note(c.unit for c in result.candidates),
        "selected": result.selected.unit.id if result.selected else None,
        "hold_only": result.hold_only,
        "candidates": [candidate_json(c) for c in result.candidates],
    }


def catalog_json(units: Iterable[Unit]) -> dict[str, Any]:
    """The catalog as JSON, in SI, with flags, stiffness and where each number was read.

    A limit the source does not rate is null, and named in ``not_rated`` with the words.
    """
    return {"units": [{
        "unit": u.id, "series": u.series, "size": u.size, "ratio": u.ratio,
        "rated_torque_nm": u.rated_torque, "repeated_torque_nm": u.repeated_torque,
        "momentary_torque_nm": u.momentary_torque, "static_torque_nm": u.static_torque,
        "max_input_speed_rpm": u.max_input_speed, "input_inertia_kg_m2": u.input_inertia,
        "mass_kg": u.mass, "efficiency_table": u.efficiency is not None,
        "flags": [{"field": f.field, "kind": f.kind, "note": f.note} for f in u.flags],
        "source": str(u.source), "bearing": _bearing_json(u),
        "not_rated": {f"{f.field}_nm": NOT_RATED for f in u.flags if f.kind == "not-rated"},
        "average_torque_nm": u.average_torque,
        "max_average_input_speed_rpm": u.max_average_input_speed,
        "starting_torque_nm": u.starting_torque, "backdriving_torque_nm": u.backdriving_torque,
        "stiffness": _stiffness_json(u.stiffness), "catalog": u.catalog.name or None,
        "provenance": {key: {"title": s.title, "publisher": s.publisher, "edition": s.edition,
                             "copy": s.copy, "page": s.page, "table": s.table}
                       for key, s in sorted(u.provenance.items())},
    } for u in units]}


def _bearing_json(unit: Unit) -> dict[str, Any]:
    """`bearing_rating_json` with the bearing's moment stiffness [N m/rad] where rated."""
    document = bearing_rating_json(unit)
    if unit.bearing is not None:
        document["moment_stiffness_nm_per_rad"] = unit.bearing.moment_stiffness
    return document


def _stiffness_json(stiffness: Stiffness | None) -> dict[str, Any] | None:
    """A unit's torsional stiffness in SI (twists in rad), or None where not given."""
    if stiffness is None:
        return None
    return {"t1_nm": stiffness.t1, "t2_nm": stiffness.t2, "k1_nm_per_rad": stiffness.k1,
            "k2_nm_per_rad": stiffness.k2, "k3_nm_per_rad": stiffness.k3,
            "hysteresis_loss_rad": stiffness.hysteresis_loss,
            "lost_motion_rad": stiffness.lost_motion}


def catalog_list_json(catalogs: Iterable[tuple[BuiltinCatalog, Sequence[Unit]]]) -> dict[str, Any]:
    """The built-in catalogs (``hdselect catalog --list``): each one's units in brief.

    Args:
        catalogs: Each built-in catalog with its units.
    """
    listed = []
    for catalog, units in catalogs:
        documents = {(s.title, s.publisher, s.edition, s.copy) for u in units
                     for s in u.provenance.values()}
        rated = sum(u.bearing is not None for u in units)
        info = units[0].catalog
        listed.append({
            "name": catalog.name, "series": catalog.series, "title": catalog.title,
            "file": catalog.file.name, "units": len(units),
            "sizes": sorted({u.size for u in units}), "ratios": sorted({u.ratio for u in units}),
            "repeated_torque_nm": [min(u.repeated_torque for u in units),
                                   max(u.repeated_torque for u in units)],
            "bearing_rated": "all" if rated == len(units) else "some" if rated else "none",
            "documents": [dict(zip(("title", "publisher", "edition", "copy"), d, strict=True))
                          for d in sorted(documents)],
            "check": info.check or None, "transcription": info.transcription or None})
    return {"catalogs": listed}


def joints_json(robot: Robot, infos: Iterable[JointInfo]) -> dict[str, Any]:
    """A robot's joints as JSON (``hdselect joints --json``), in SI; null for no limit."""
    joints = []
    for info in infos:
        linear = info.kind == "prismatic"
        joints.append({
            "name": info.name, "index": info.index, "type": info.kind, "sized": info.sized,
            "lower": finite_or_none(info.lower), "upper": finite_or_none(info.upper),
            "unit": "m" if linear else "rad",
            "velocity_limit": finite_or_none(info.velocity_limit),
            "effort_limit": finite_or_none(info.effort_limit),
            "moved_mass_kg": info.moved_mass, "leader": info.leader,
            "multiplier": info.multiplier if info.leader else None,
            "offset": info.offset if info.leader else None})
    return {"robot": str(robot.path), "root_link": robot.root_link,
            "payload_frame": robot.default_payload_frame,
            "list_order": list(robot.joint_names),
            "file_order": None if robot.file_order is None else list(robot.file_order),
            "notes": list(robot.notes), "joints": joints}


def write_trajectory_csv(target: str | Path, trajectory: Trajectory, tau: Any,
                         joints: Iterable[str]) -> None:
    """One row per sample: t, then q_, qd_, qdd_, tau_ of every listed joint (SI).

    A prismatic joint's columns are in m, m/s, m/s^2 and N.
    """
    names = list(trajectory.joint_names)
    columns = [names.index(name) for name in joints]
    header = ["t"] + [f"{kind}_{names[j]}" for j in columns
                      for kind in ("q", "qd", "qdd", "tau")]

    def rows(part: slice) -> np.ndarray:
        return np.column_stack([trajectory.t[part]] + [
            array[part, j] for j in columns
            for array in (trajectory.q, trajectory.qd, trajectory.qdd, tau)])

    def write(stream: Any) -> None:
        stream.write(",".join(header) + "\n")
        for start in range(0, len(trajectory.t), _CSV_ROWS):  # bounded memory, any length
            np.savetxt(stream, rows(slice(start, start + _CSV_ROWS)), fmt="%.10g",
                       delimiter=",")

    write_output(target, write)


def write_line_errors_csv(target: str | Path, trajectory: Trajectory,
                          lines: Sequence[LineDeviation]) -> None:
    """One row per planned sample on a straight line: how far the tool strays from it.

    Columns: ``t`` [s], ``line`` (the waypoint the line ends at; it starts at the one
    before), ``distance`` [m] (the tool origin's distance from the line's segment),
    ``angle`` [rad] (the tool orientation's angle from the nearest orientation of the
    line's slerp) and ``fraction`` (the fraction of the line the sample is nearest).
    """
    rows = np.concatenate([np.column_stack([trajectory.t[found.index],
                                            np.full(len(found.index), found.last),
                                            found.position, found.orientation, found.fraction])
                           for found in lines]) if lines else np.zeros((0, 5))

    def write(stream: Any) -> None:
        stream.write("t,line,distance,angle,fraction\n")
        np.savetxt(stream, rows, fmt="%.10g", delimiter=",")

    write_output(target, write)


def write_waypoints_csv(target: str | Path, motion: Motion) -> None:
    """The solved motion's joint path: every waypoint, and every joint sample of a line.

    One row per point, in the order the path passes them: ``waypoint`` (a line sample:
    the waypoint its line ends at), ``fraction`` (of the way from the waypoint before:
    a line sample's fraction of its line, 1 at a waypoint), ``q_`` of every joint [rad
    or m], ``position_error`` [m] and ``orientation_error`` [rad]: the tool's distance
    from the pose asked for (a line sample: the line's pose at its fraction); 0 for a
    joint waypoint, which is where its joint positions put it.
    """
    solution = motion.solution
    nothing = np.zeros(len(motion.waypoints))
    position = (np.nan_to_num(solution.position_error) if solution is not None
                and len(solution.position_error) == len(nothing) else nothing)
    orientation = (np.nan_to_num(solution.orientation_error) if solution is not None
                   and len(solution.orientation_error) == len(nothing) else nothing)
    lines = {line.last: line for line in motion.lines}
    rows = []
    for i, q in enumerate(motion.waypoints):
        if i in lines:
            line = lines[i]
            for f, sample, p, o in zip(line.fractions[1:-1], line.interior,
                                       line.position_error[1:-1],
                                       line.orientation_error[1:-1], strict=True):
                rows.append([i, f, *sample, p, o])
        rows.append([i, 1.0, *q, position[i], orientation[i]])
    header = ["waypoint", "fraction", *(f"q_{name}" for name in motion.joint_names),
              "position_error", "orientation_error"]

    def write(stream: Any) -> None:
        stream.write(",".join(header) + "\n")
        np.savetxt(stream, np.array(rows), fmt="%.10g", delimiter=",")

    write_output(target, write)
