"""Payload events: the parts a motion attaches and releases, and the samples that carry them.

A motion file names parts (``[payloads.NAME]``, the ``[payload]`` table as ``"payload"``)
and moves them with events: ``attach``/``release`` on a waypoint (a name or a list of
names), or ``[[event]]`` tables at a time ``t`` of a log. A part no event names is carried
the whole cycle. A part events name is carried from the ARRIVAL at the waypoint that
attaches it to the END OF THE DWELL of the waypoint that releases it (both dwells carry
it); a log's part from its attach time to its release time; samples on a boundary carry
it. The cycle repeats: a part released before it is attached in the file's order is
carried from its attach to the end and from the start to its release. Events of one part
alternate attach and release, cyclically.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from hdselect.base.errors import InputError
from hdselect.base.tomlfile import check_keys, number, table_of
from hdselect.robot.payload import Payload

BOUNDARY = 1e-6
"""How close to an event's time a sample counts as on it, as a fraction of the period [-]."""


@dataclass(frozen=True)
class Event:
    """One event of a motion file: a part attached or released.

    Attributes:
        part: The part's name (``"payload"``: the ``[payload]`` table).
        attach: True where the event attaches the part, False where it releases it.
        waypoint: Index of the waypoint it happens at, or None (a log's event).
        time: When it happens, in the log's own time [s], or None (a waypoint's event).
    """

    part: str
    attach: bool
    waypoint: int | None = None
    time: float | None = None


@dataclass(frozen=True, eq=False)
class Carried:
    """Which of the parts events move each sample of a trajectory carries.

    Attributes:
        parts: The parts events move, in name order.
        mask: Whether sample k carries part i, shape (n, len(parts)), bool, read-only.
        events: Each event on the trajectory's time: (t [s], part name, True where it
            attaches), in time order.
    """

    parts: tuple[Payload, ...]
    mask: np.ndarray
    events: tuple[tuple[float, str, bool], ...]

    def states(self) -> tuple[tuple[tuple[int, ...], np.ndarray], ...]:
        """Each distinct set of parts carried (indices into `parts`) with its sample rows.

        Returns:
            (carried part indices, sorted sample rows (intp)) per set, in the order of each
            set's first sample.
        """
        sets, first, inverse = np.unique(self.mask, axis=0, return_index=True,
                                         return_inverse=True)
        inverse = np.asarray(inverse).reshape(-1)
        return tuple((tuple(int(i) for i in np.flatnonzero(sets[k])),
                      np.flatnonzero(inverse == k).astype(np.intp))
                     for k in np.argsort(first, kind="stable"))

    def names(self, row: int) -> tuple[str, ...]:
        """The names of the parts events move that sample `row` carries."""
        return tuple(part.name for part, held in zip(self.parts, self.mask[row], strict=True)
                     if held)

    def sampled(self, rows: slice | np.ndarray) -> Carried:
        """The same events at some of the samples (`rows` of the mask), as a thinned trajectory."""
        mask = self.mask[rows]
        mask.setflags(write=False)
        return replace(self, mask=mask)

    def with_part(self, part: Payload) -> Carried:
        """The same events moving `part` in place of the part of its name."""
        return replace(self, parts=tuple(part if p.name == part.name else p for p in self.parts))


class _Cycle(Protocol):
    """What `carried` reads of a motion (`hdselect.motion.motionfile.Motion`)."""

    @property
    def path(self) -> Path: ...
    @property
    def dwells(self) -> np.ndarray: ...
    @property
    def parts(self) -> Mapping[str, Payload]: ...
    @property
    def events(self) -> tuple[Event, ...]: ...
    @property
    def samples(self) -> Any: ...


class _Timeline(Protocol):
    """What `carried` reads of a trajectory (`hdselect.motion.planning.Trajectory`)."""

    @property
    def dt(self) -> float: ...
    @property
    def duration(self) -> float: ...
    @property
    def t(self) -> np.ndarray: ...
    @property
    def waypoint_times(self) -> np.ndarray | None: ...


def carried(motion: _Cycle, trajectory: _Timeline) -> Carried | None:
    """Which parts each sample of a motion's trajectory carries; None where no event exists.

    Args:
        motion: The motion (its parts, events and dwells; a log's first time).
        trajectory: Its planned trajectory (sample times and when it reaches each waypoint).

    Raises:
        InputError: The planner does not say when the arm reaches a waypoint an event is at.
    """
    if not motion.events:
        return None
    names = sorted({event.part for event in motion.events})
    t = np.minimum(trajectory.t, trajectory.duration)  # past the cycle: its last state
    tol = BOUNDARY * trajectory.dt
    mask = np.zeros((len(t), len(names)), dtype=bool)
    found = []
    for i, name in enumerate(names):
        mine = [e for e in motion.events if e.part == name]
        times = [_time(motion, trajectory, e) for e in mine]
        for k, event in enumerate(mine):
            found.append((times[k], name, event.attach))
            if not event.attach:
                continue
            end = times[(k + 1) % len(mine)]  # the next event releases it (alternation)
            after, before = t >= times[k] - tol, t <= end + tol
            mask[:, i] |= (after | before) if k + 1 == len(mine) else (after & before)
    mask.setflags(write=False)
    return Carried(tuple(motion.parts[name] for name in names), mask,
                   tuple(sorted(found, key=lambda e: (e[0], e[1]))))


def _time(motion: _Cycle, trajectory: _Timeline, event: Event) -> float:
    """When an event happens on the trajectory's time [s].

    An attach on arrival at its waypoint, a release at the end of its waypoint's dwell; a
    log's event at its time from the log's start.
    """
    if event.waypoint is None:
        return float(event.time or 0.0) - float(motion.samples.t[0])
    reached = trajectory.waypoint_times
    at = float(reached[event.waypoint]) if reached is not None else float("nan")
    if not np.isfinite(at):
        raise InputError(f"the planner does not say when the arm reaches waypoint"
                         f"[{event.waypoint}], so '{event.part}' cannot be moved there",
                         path=motion.path, field=f"waypoint[{event.waypoint}]."
                         + ("attach" if event.attach else "release"))
    return at if event.attach else at + float(motion.dwells[event.waypoint])


def payload_table(value: Any, path: Path, name: str = "") -> Payload:
    """A file's ``[payload]`` (or a part's ``[payloads.NAME]``) table, refused by field.

    Args:
        value: The table as read.
        path: The file, for messages.
        name: The part's name; empty for ``[payload]``.
    """
    where = f"payloads.{name}" if name else "payload"
    table = table_of(value, path, where)
    check_keys(table, ("mass", "com", "inertia", "frame"), path, where)
    if "mass" not in table:
        raise InputError("required key is missing", path=path, field=f"{where}.mass")
    try:
        return Payload(table["mass"], table.get("com", (0.0, 0.0, 0.0)),
                       table.get("inertia", ((0.0,) * 3,) * 3), table.get("frame"), name)
    except InputError as err:
        raise InputError(err.reason, path=path, field=err.field) from err


def read_events(doc: Mapping[str, Any], path: Path, payload: Payload | None,
                log_times: np.ndarray | None) -> tuple[dict[str, Payload], tuple[Event, ...]]:
    """A motion file's parts (``[payloads.*]``) and events, checked.

    Args:
        doc: The motion file.
        path: The file, for messages.
        payload: Its ``[payload]``, or None.
        log_times: A log's sample times [s] (planner ``samples``), else None.

    Returns:
        The parts by name (with ``"payload"`` where an event names it) and the events: a
        waypoint motion's in waypoint order, a log's in the file's order.

    Raises:
        InputError: A part or event is malformed, names an unknown part, a part's events do
            not alternate attach and release, or a log's event is outside the log.
    """
    named = table_of(doc.get("payloads", {}), path, "payloads")
    parts = {name: payload_table(value, path, name) for name, value in named.items()}
    if "" in parts:
        raise InputError("a part needs a name", path=path, field="payloads")
    if "payload" in parts:
        raise InputError("'payload' names the [payload] table; give the part another name",
                         path=path, field="payloads.payload")
    known = {**parts, **({"payload": payload} if payload is not None else {})}
    events: list[tuple[Event, str]] = []
    if log_times is None:
        if "event" in doc:
            raise InputError("[[event]] times a log's events (planner \"samples\"); on "
                             "waypoints, give attach or release", path=path, field="event")
        for i, item in enumerate(doc.get("waypoint") or ()):
            table = item if isinstance(item, dict) else {}
            for key in ("attach", "release"):
                for name in _names(table, key, path, f"waypoint[{i}]", known):
                    if key == "release" and name in _names(table, "attach", path, "", known):
                        raise InputError(f"'{name}' is both attached and released here",
                                         path=path, field=f"waypoint[{i}].release")
                    events.append((Event(name, key == "attach", waypoint=i),
                                   f"waypoint[{i}].{key}"))
    else:
        for k, item in enumerate(_event_tables(doc, path)):
            where = f"event[{k}]"
            table = table_of(item, path, where)
            check_keys(table, ("t", "attach", "release"), path, where)
            t = number(table, "t", path, where)
            if not log_times[0] <= t <= log_times[-1]:
                raise InputError(f"{t:g} s is outside the log ({log_times[0]:g} to "
                                 f"{log_times[-1]:g} s)", path=path, field=f"{where}.t")
            given = [key for key in ("attach", "release") if key in table]
            if len(given) != 1:
                raise InputError("give one of attach or release (a part's name or a list)",
                                 path=path, field=f"{where}.attach")
            events += [(Event(name, given[0] == "attach", time=t), f"{where}.t")
                       for name in _names(table, given[0], path, where, known)]
        events.sort(key=lambda item: item[0].time or 0.0)
    for name in sorted({event.part for event, _ in events}):
        _alternate([item for item in events if item[0].part == name], path)
    moved = {event.part for event, _ in events}
    return ({**parts, **({"payload": replace(payload, name="payload")}
                         if payload is not None and "payload" in moved else {})},
            tuple(event for event, _ in events))


def _event_tables(doc: Mapping[str, Any], path: Path) -> list[Any]:
    """The ``[[event]]`` tables (none: an empty list)."""
    value = doc.get("event", [])
    if not isinstance(value, list):
        raise InputError("expected [[event]] tables", path=path, field="event")
    return value


def _names(table: Mapping[str, Any], key: str, path: Path, where: str,
           known: Mapping[str, Payload | None]) -> tuple[str, ...]:
    """The part names of an ``attach`` or ``release`` key (absent: none), each known once."""
    if key not in table:
        return ()
    value = table[key]
    names = [value] if isinstance(value, str) else value
    field = f"{where}.{key}"
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputError(f"expected a part's name or a list of names, got {value!r}",
                         path=path, field=field)
    for name in names:
        if name not in known:
            choices = ", ".join(sorted(known)) or "none (give [payload] or [payloads.NAME])"
            raise InputError(f"unknown part '{name}'; parts are: {choices}", path=path,
                             field=field)
    if len(set(names)) != len(names):
        raise InputError(f"a part is named twice: {value!r}", path=path, field=field)
    return tuple(names)


def _alternate(events: list[tuple[Event, str]], path: Path) -> None:
    """Refuse one part's events (in time order) unless they alternate attach and release.

    Raises:
        InputError: Two events in a row (the cycle repeating) do the same, or two happen
            at the same time; the field names the later one.
    """
    name = events[0][0].part
    if all(event.attach == events[0][0].attach for event, _ in events):
        what = "never released" if events[0][0].attach else "released but never attached"
        raise InputError(f"'{name}' is {what}: a part's events alternate attach and release "
                         "(the cycle repeats)", path=path, field=events[0][1])
    for k, (event, field) in enumerate(events):
        before, before_field = events[k - 1]
        if event.attach == before.attach:
            verb = "attached" if event.attach else "released"
            where = "" if k else " (the cycle repeats)"
            raise InputError(f"'{name}' is {verb} again after {before_field}{where} with no "
                             f"{'release' if event.attach else 'attach'} between; a part's "
                             "events alternate", path=path, field=field)
        if k and event.time is not None and event.time == before.time:
            raise InputError(f"'{name}' is attached and released at the same time",
                             path=path, field=field)


def whole_cycle(parts: Mapping[str, Payload], events: tuple[Event, ...]) -> tuple[Payload, ...]:
    """The parts no event names (carried the whole cycle), in name order."""
    moved = {event.part for event in events}
    return tuple(parts[name] for name in sorted(parts) if name not in moved)
