"""One case of a study, resolved, and its outcome as a worker reports it."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from hdselect.robot.payload import Payload


@dataclass(frozen=True)
class Case:
    """One case of a study, resolved.

    Attributes:
        index: Position in the study, from 0.
        compute: Name of what is computed (a key of `hdselect.study.compute.COMPUTATIONS`).
        values: The case's parameters as the study gives them (paths relative to the study
            file, payload as its mass [kg]); the columns of its rows.
        motion: The motion file.
        robot: The robot file, or None for the motion file's ``robot``.
        payload: The payload mass [kg], or None for the motion file's payload.
        payload_shape: Centre of mass [m], inertia about it [kg m^2] and frame, when the study
            gives them; None keeps the motion file's (or a point mass at the robot's
            default payload frame).
        time_scale: The motion run s times slower [-] (0.8: 1.25 times faster).
        mounting: Mounting overriding the motion file's, or None.
        catalog: Extra catalog files.
        ratio: Only units of this ratio are candidates, or None for every unit.
        options: Sizing options given (fields of `hdselect.Options`).
        key: Stable hash of everything the result depends on.
        files: The files the case reads, resolved (robot, motion, log, catalogs, motor files).
        motor_catalog: A motor file every sized joint chooses its motor from (replacing the
            motion file's ``[motor]``, as ``--motor-catalog`` does), or None.
        shares: For a mix file, each task's share of the time [-] in the file's task order,
            replacing the file's; None keeps them.
        payloads: For a mix file, (task name, payload mass [kg]) pairs: each mass in its
            task's payload shape; None keeps the file's payloads.
        series: Only units of these series are candidates (as ``--series``; a built-in
            catalog a name names is among `catalog`); empty: every unit loaded.
    """

    index: int
    compute: str
    values: Mapping[str, Any]
    motion: Path
    robot: Path | None
    payload: float | None
    payload_shape: tuple[tuple[float, ...], tuple[tuple[float, ...], ...], str | None] | None
    time_scale: float
    mounting: str | tuple[float, ...] | None
    catalog: tuple[Path, ...]
    ratio: int | None
    options: Mapping[str, Any]
    key: str
    files: tuple[Path, ...]
    motor_catalog: Path | None = None
    shares: tuple[float, ...] | None = None
    payloads: tuple[tuple[str, float], ...] | None = None
    series: tuple[str, ...] = ()

    def payload_for(self, file_payload: Payload | None) -> Payload | None:
        """The case's payload, given the motion file's.

        The study's mass replaces the file's; the study's shape (centre of mass, inertia
        about it, frame), else the file's, else a point mass at the robot's default payload frame
        (`hdselect.Robot.default_payload_frame`), goes with it.
        """
        if self.payload is None:
            return file_payload
        if self.payload_shape is not None:
            com, inertia, frame = self.payload_shape
            return Payload(self.payload, com, inertia, frame)  # type: ignore[arg-type]
        if file_payload is not None:
            return replace(file_payload, mass=self.payload)
        return Payload(self.payload)


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
