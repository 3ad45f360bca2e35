"""The ordered registry of rules, and the check tables derived from it.

The order is that of results and reports: the gearhead's rules, its output bearing's,
its motor's, the pair's. The tables (`CHECKS`, `CHECK_LABELS`, ...) are live views of the
registry: a rule registered later (`register`, `registered`) is in every one of them,
wherever they were imported.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any, overload

from hdselect.catalog.rules.average_speed import AVERAGE_SPEED
from hdselect.catalog.rules.base import Part, Rule, Scope
from hdselect.catalog.rules.bearing import BEARING_RULES
from hdselect.catalog.rules.inertia_ratio import INERTIA_RATIO
from hdselect.catalog.rules.life import LIFE
from hdselect.catalog.rules.mean import MEAN
from hdselect.catalog.rules.momentary import MOMENTARY
from hdselect.catalog.rules.motor import MOTOR_RULES
from hdselect.catalog.rules.natural_frequency import NATURAL_FREQUENCY
from hdselect.catalog.rules.peak import PEAK
from hdselect.catalog.rules.speed import SPEED
from hdselect.catalog.rules.static import STATIC
from hdselect.catalog.rules.torsion import TORSION

_REGISTRY: list[Rule] = [PEAK, MEAN, SPEED, AVERAGE_SPEED, MOMENTARY, STATIC, LIFE, TORSION,
                         NATURAL_FREQUENCY, *BEARING_RULES, *MOTOR_RULES, INERTIA_RATIO]
_VIEWS: list[_View] = []
"""Every view of the registry, refreshed at each registration."""


class _View(Sequence[Any]):
    """A tuple-like view of the registry, refreshed whenever the registry changes."""

    def __init__(self, pick: Callable[[list[Rule]], tuple[Any, ...]]) -> None:
        self._pick = pick
        self._items: tuple[Any, ...] = pick(_REGISTRY)
        _VIEWS.append(self)

    def refresh(self) -> None:
        """Take the registry as it is now."""
        self._items = self._pick(_REGISTRY)

    @overload
    def __getitem__(self, index: int) -> Any: ...
    @overload
    def __getitem__(self, index: slice) -> tuple[Any, ...]: ...
    def __getitem__(self, index: int | slice) -> Any:
        return self._items[index]

    def __len__(self) -> int:
        return len(self._items)

    def __iter__(self) -> Iterator[Any]:
        return iter(self._items)

    def __contains__(self, item: object) -> bool:
        return item in self._items

    def __eq__(self, other: object) -> bool:
        return self._items == (tuple(other) if isinstance(other, _View) else other)

    __hash__ = None  # type: ignore[assignment]

    def __add__(self, other: Sequence[Any]) -> tuple[Any, ...]:
        return self._items + tuple(other)

    def __radd__(self, other: Sequence[Any]) -> tuple[Any, ...]:
        return tuple(other) + self._items

    def __repr__(self) -> str:
        return repr(self._items)


class _Names(_View):
    """The names of the registered rules that `keep` selects, in registry order."""

    def __init__(self, keep: Callable[[Rule], bool]) -> None:
        super().__init__(lambda rules: tuple(r.name for r in rules if keep(r)))


class _Table(Mapping[str, str]):
    """Rule name -> one of its attributes, for every registered rule, in registry order."""

    def __init__(self, attribute: str) -> None:
        self._rows = _View(lambda rules: tuple((r.name, getattr(r, attribute)) for r in rules))

    def _dict(self) -> dict[str, str]:
        return dict(self._rows)

    def __getitem__(self, name: str) -> str:
        for key, value in self._rows:
            if key == name:
                return str(value)
        raise KeyError(name)

    def __len__(self) -> int:
        return len(self._rows)

    def __iter__(self) -> Iterator[str]:
        return iter(key for key, _ in self._rows)

    def __repr__(self) -> str:
        return repr(self._dict())


RULES: Sequence[Rule] = _View(tuple)
"""Every registered rule, in the order of results and reports."""

CHECKS: Sequence[str] = _Names(lambda r: True)
"""Every check by name, in the order of results and reports: the gearhead's, its output
bearing's, its motor's, the pair's. ``life`` is present only when a life is required,
``torsion`` and ``natural_frequency`` only where the joint has such a target, the
output bearing's only where the catalog rates it (and its loads are known), the motor
checks only when a motor is given, ``inertia_ratio`` only when a largest inertia ratio is
given too; the others always, with value None where they do not apply."""

MOTOR_CHECKS: Sequence[str] = _Names(lambda r: r.part is Part.MOTOR)
"""The checks of the motor behind a gearhead, when one is given (`check_motor`)."""

BEARING_CHECKS: Sequence[str] = _Names(lambda r: r.part is Part.BEARING)
"""The checks of a rated output bearing, each present where the catalog gives its rating
and the bearing's loads are known (the life also needs a required life)."""

PAIR_CHECKS: Sequence[str] = _Names(lambda r: r.part is Part.PAIR)
"""The checks of a gearhead and motor pair as a whole: the load-to-rotor inertia ratio
against the largest allowed, present only when a largest ratio is given. The design margin
does not apply to it: the largest ratio is itself a design choice, not a rating."""

PER_SAMPLE_CHECKS: Sequence[str] = _Names(lambda r: r.scope is Scope.SAMPLE)
"""The checks of single samples (or single poses): over several tasks, the worst task's.
The inertia ratio and the natural frequency are among them: their load inertia is the
largest M_jj over every task's poses; the torsion, the bearing's largest moment and
forces are too. The others pool every task's
samples: mean torque, average speed, life, motor RMS, the bearing's life and its static
safety (whose load adds the largest radial force, moment and axial force over the duty,
which may come from different tasks)."""

LIFE_CHECKS: Sequence[str] = _Names(lambda r: r.life)
"""The checks whose value is a life [h], reported within `hdselect.catalog.checks.LIFE_CAP`."""

CHECK_LABELS: Mapping[str, str] = _Table("label")
"""Short names of the checks, for table headers (``b.``: the output bearing's, ``m.``: the
motor's)."""

CHECK_NAMES: Mapping[str, str] = _Table("words")
"""The checks in words, for figure titles and summaries read by people."""


_BY_NAME = _View(lambda rules: ({found.name: found for found in rules},))
_BY_PART = _View(lambda rules: ({part: tuple(found for found in rules if found.part is part)
                                 for part in Part},))


def rule(name: str) -> Rule:
    """The registered rule of this name.

    Raises:
        KeyError: No rule of that name is registered.
    """
    found: Rule | None = _BY_NAME[0].get(name)
    if found is None:
        raise KeyError(f"no rule {name!r}; the rules are: {', '.join(CHECKS)}")
    return found


def rules_of(part: Part) -> tuple[Rule, ...]:
    """The registered rules that judge `part`, in registry order."""
    found: tuple[Rule, ...] = _BY_PART[0][part]
    return found


def register(new: Rule, *, after: str | None = None) -> None:
    """Add a rule to the registry: every check, table, report and solver then has it.

    Args:
        new: The rule (its single instance).
        after: The rule it follows in results and reports; None puts it after the last
            rule of its part (a gearhead rule after ``life``).

    Raises:
        ValueError: A rule of that name is registered already.
    """
    if new.name in _BY_NAME[0]:
        raise ValueError(f"a rule {new.name!r} is registered already")
    if after is not None:
        at = _REGISTRY.index(rule(after)) + 1
    else:
        order = list(Part)
        at = sum(1 for found in _REGISTRY
                 if order.index(found.part) <= order.index(new.part))
    _REGISTRY.insert(at, new)
    _refresh()


def unregister(name: str) -> None:
    """Remove a registered rule (`register` undone).

    Raises:
        KeyError: No rule of that name is registered.
    """
    _REGISTRY.remove(rule(name))
    _refresh()


def _refresh() -> None:
    for view in _VIEWS:
        view.refresh()


@contextmanager
def registered(new: Rule, *, after: str | None = None) -> Iterator[Rule]:
    """The registry with `new` in it for the block (`register`), as shipped after it."""
    register(new, after=after)
    try:
        yield new
    finally:
        unregister(new.name)
