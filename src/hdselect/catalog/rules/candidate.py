"""One gearhead (or gearhead and motor pair) against one joint's cycle: its checks and figures."""

from __future__ import annotations

from dataclasses import dataclass

from hdselect.catalog.bearing_rules import BearingFigures
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules.base import DEFAULT_MARGIN, Check
from hdselect.catalog.rules.load import MotorDemand
from hdselect.catalog.rules.registry import MOTOR_CHECKS, PAIR_CHECKS
from hdselect.catalog.units import L50_PER_L10, Flag, Unit


@dataclass(frozen=True)
class Candidate:
    """One gearhead against one joint's cycle.

    Attributes:
        unit: The gearhead.
        checks: Each rule by name, in the order of `CHECKS`.
        life_hours: L50 life [h]; None when unlimited (no load while moving).
        flags: Catalog stand-ins, corrections and assumed rules this result depends on.
        motor: What the motor behind it must deliver, when computed (hdselect size).
        motor_unit: The motor paired with the gearhead, when motors are given; its checks
            (`MOTOR_CHECKS`) are then among `checks`.
        inertia_ratio: For a pair, the load-to-rotor inertia ratio (J_load / N^2 + J_in) /
            J_m [-] where the load inertia is known; None otherwise.
        required_margin: The design margin every rule was judged with [-].
        bearing: The output bearing's figures where the catalog rates it and its loads
            are known (its checks, `BEARING_CHECKS`, are then among `checks`); else None.
    """

    unit: Unit
    checks: dict[str, Check]
    life_hours: float | None
    flags: tuple[Flag, ...]
    motor: MotorDemand | None = None
    motor_unit: Motor | None = None
    inertia_ratio: float | None = None
    required_margin: float = DEFAULT_MARGIN
    bearing: BearingFigures | None = None

    @property
    def feasible(self) -> bool:
        """Every rule holds."""
        return all(check.ok for check in self.checks.values())

    @property
    def binding(self) -> str:
        """Name of the rule with the highest utilization."""
        return max(self.checks, key=lambda name: self.checks[name].utilization)

    @property
    def gearhead_binding(self) -> str:
        """Name of the gearhead's rule with the highest utilization."""
        return max((name for name in self.checks
                    if name not in MOTOR_CHECKS and name not in PAIR_CHECKS),
                   key=lambda name: self.checks[name].utilization)

    @property
    def motor_binding(self) -> str | None:
        """Name of the motor's rule with the highest utilization; None without a motor."""
        names = [name for name in self.checks if name in MOTOR_CHECKS]
        return max(names, key=lambda name: self.checks[name].utilization) if names else None

    @property
    def label(self) -> str:
        """The gearhead's id, and the motor's after a ``+`` when one is paired."""
        return self.unit.id if self.motor_unit is None else f"{self.unit.id} + {self.motor_unit.id}"

    @property
    def l10_hours(self) -> float | None:
        """L10 life, L50 / 5 [h]; None when unlimited."""
        return None if self.life_hours is None else self.life_hours / L50_PER_L10

    @property
    def margin(self) -> float:
        """Worst-case margin, 1 minus the highest utilization [-]."""
        return 1.0 - self.checks[self.binding].utilization
