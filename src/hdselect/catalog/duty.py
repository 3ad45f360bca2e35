"""The catalog page's own sizing method: a torque-speed profile of phases."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hdselect.base import bounds
from hdselect.base.errors import InputError, deprecated
from hdselect.base.tomlfile import check_keys, number, read_toml, table_of
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    Candidate,
    CycleLoad,
    Momentary,
    check_unit,
    cycle_load,
)
from hdselect.catalog.select import select
from hdselect.catalog.units import LIFE_BASES, Unit

_TOP_KEYS = ["description", "phase", "momentary", "static", "requirements"]
_PHASE_KEYS = ["name", "torque", "time", "speed"]


@dataclass(frozen=True)
class Phase:
    """One phase of the catalog's torque-speed profile.

    Attributes:
        name: Label, e.g. ``"accelerate"``.
        torque: Output torque [N m] (sign ignored).
        time: Duration [s].
        speed: Mean output speed [rad/s]; 0 is a dwell (input locked).
    """

    name: str
    torque: float
    time: float
    speed: float


@dataclass(frozen=True)
class DutyCycle:
    """A validated duty-cycle profile.

    Attributes:
        path: The profile file.
        phases: The phases of one cycle.
        momentary: The momentary (T4) event, if given.
        static_torque: Torque applied with the input locked [N m], if given.
        life_hours: Required life [h] on `life_basis`, if given.
        life_basis: ``"L10"`` or ``"L50"``, the basis of `life_hours`.
    """

    path: Path
    phases: tuple[Phase, ...]
    momentary: Momentary | None
    static_torque: float | None
    life_hours: float | None
    life_basis: str = "L50"


@dataclass(frozen=True)
class DutyResult:
    """Every unit checked against a duty cycle, and the one selected.

    Attributes:
        cycle: The profile.
        load: The cycle's output-side summary (mean torque, mean speed, peak).
        candidates: One per catalog unit, in catalog order.
        selected: The chosen candidate, or None when no unit fits.
    """

    cycle: DutyCycle
    load: CycleLoad
    candidates: tuple[Candidate, ...]
    selected: Candidate | None

    @property
    def hold_only(self) -> bool:
        """No phase moves (every speed is 0): only the static and momentary checks apply."""
        return self.load.moving_time == 0.0


def load_duty(path: str | Path) -> DutyCycle:
    """Read a duty-cycle profile (TOML).

    Args:
        path: The profile file.

    Returns:
        The validated profile, in SI.

    Raises:
        InputError: The file is missing, malformed or inconsistent.
    """
    path = bounds.file_argument(path, "path")
    document = read_toml(path)
    check_keys(document, _TOP_KEYS, path, "")
    raw_phases = document.get("phase")
    if not isinstance(raw_phases, list) or not raw_phases:
        raise InputError("the cycle has no [[phase]] entries", path=path, field="phase")
    phases = []
    for i, raw in enumerate(raw_phases):
        where = f"phase[{i}]"
        table = table_of(raw, path, where)
        check_keys(table, _PHASE_KEYS, path, where)
        name = table.get("name", f"phase {i + 1}")
        if not isinstance(name, str):
            raise InputError(f"expected a label, got {name!r}", path=path, field=f"{where}.name")
        phases.append(Phase(
            name=name,
            torque=abs(number(table, "torque", path, where, bound=bounds.LOAD_TORQUE)),
            time=number(table, "time", path, where, bound=bounds.PHASE_TIME),
            speed=abs(number(table, "speed", path, where, bound=bounds.OUTPUT_SPEED))
            / RPM_PER_RAD_S,
        ))
    momentary = None
    if "momentary" in document:
        table = table_of(document["momentary"], path, "momentary")
        check_keys(table, ["torque", "speed", "time"], path, "momentary")
        speed = (number(table, "speed", path, "momentary", minimum=0.0,
                        bound=bounds.OUTPUT_SPEED) if "speed" in table else None)
        momentary = Momentary(
            torque=abs(number(table, "torque", path, "momentary", bound=bounds.LOAD_TORQUE)),
            kind="given",
            speed=None if speed is None else speed / RPM_PER_RAD_S,
            duration=number(table, "time", path, "momentary", bound=bounds.PHASE_TIME)
            if "time" in table else None,
        )
    static = None
    if "static" in document:
        table = table_of(document["static"], path, "static")
        check_keys(table, ["torque"], path, "static")
        static = abs(number(table, "torque", path, "static", bound=bounds.LOAD_TORQUE))
    life, basis = None, "L50"
    if "requirements" in document:
        table = table_of(document["requirements"], path, "requirements")
        check_keys(table, ["life_hours", "life_basis"], path, "requirements")
        life = number(table, "life_hours", path, "requirements", bound=bounds.LIFE)
        basis = table.get("life_basis", basis)
        if not isinstance(basis, str) or basis not in LIFE_BASES:
            raise InputError(f"expected one of {', '.join(map(repr, LIFE_BASES))}, got "
                             f"{basis!r}", path=path, field="requirements.life_basis")
    return DutyCycle(path, tuple(phases), momentary, static, life, basis)


def size_duty(cycle: DutyCycle, catalog: Sequence[Unit] | None = None, *,
              prefer: str = "size", margin: float = 0.0,
              units: Sequence[Unit] | None = None) -> DutyResult:
    """Check every unit against a duty cycle and select the smallest that fits.

    Args:
        cycle: The profile.
        catalog: The loaded units to choose from (default: the built-in catalog).
        prefer: Selection order, a key of `hdselect.catalog.select.PREFERENCES`.
        margin: Design margin [-], in [0, 0.9]: every rule must hold at (1 - margin) of
            its limit.
        units: Deprecated: the loaded catalog, now given as `catalog`.

    Returns:
        Every candidate and the selection.

    Raises:
        InputError: An argument is of the wrong type, or `prefer` is unknown.
    """
    bounds.expect_type(cycle, DutyCycle, "cycle", "a DutyCycle (hdselect.load_duty)")
    field = "catalog" if units is None else "units"
    if units is not None:
        if catalog is not None:
            raise InputError("give either catalog or units (its old spelling), not both",
                             field="units")
        catalog = units
    elif catalog is None:
        catalog = load_catalog()
    if isinstance(catalog, str | bytes) or not isinstance(catalog, Sequence) or not catalog:
        raise InputError("expected a non-empty sequence of catalog units", field=field)
    for unit in catalog:
        bounds.expect_type(unit, Unit, field, "catalog units (hdselect.load_catalog)")
    if units is not None:
        deprecated("size_duty(units=...)", "size_duty(catalog=...)")
    margin = bounds.MARGIN.check(margin, field="margin")
    phases = cycle.phases
    load = cycle_load(
        torque=np.array([p.torque for p in phases]),
        speed=np.array([p.speed for p in phases]),
        duration=np.array([p.time for p in phases]),
        at_rest=np.array([p.speed == 0.0 for p in phases]),
        static_torque=cycle.static_torque,
    )
    candidates = tuple(check_unit(load, unit, momentary=cycle.momentary,
                                  life_hours=cycle.life_hours, life_basis=cycle.life_basis,
                                  margin=margin)
                       for unit in catalog)
    return DutyResult(cycle, load, candidates, select(candidates, prefer))
