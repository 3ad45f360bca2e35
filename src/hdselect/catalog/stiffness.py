"""A unit's torsional stiffness as numbers: its twist under a torque, and its resonance.

Harmonic Drive rates the twist of a unit with its input locked as three straight
segments (`hdselect.catalog.units.Stiffness`): at stiffness K1 up to the torque T1, at
K2 from T1 to T2, at K3 above T2. The twist of an output torque T is

    phi = T / K1                                          |T| <= T1
    phi = T1 / K1 + (|T| - T1) / K2                       T1 < |T| <= T2
    phi = T1 / K1 + (T2 - T1) / K2 + (|T| - T2) / K3      |T| > T2

signed as T. A segment whose corner torque or stiffness the catalog does not give is
not used: the segment before it goes on (the curve stiffens with torque, K1 < K2 < K3,
so this overstates the twist, never understates it).

The single-axis natural frequency of a joint is f_n = sqrt(K1 / J) / (2 pi), J the load
inertia on the output; the transmission error excites it twice per input revolution,
so the input speed f_n x 60 / 2 rpm runs at resonance.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from hdselect.catalog.units import Stiffness, Unit

EXCITATIONS_PER_INPUT_TURN = 2
"""Cycles of the transmission error per input revolution (the wave generator's two lobes)."""


def rates_torsion(stiffness: Stiffness | None) -> bool:
    """Whether a unit's stiffness gives its twist: K1 is rated."""
    return stiffness is not None and stiffness.k1 is not None


def _segments(stiffness: Stiffness) -> list[tuple[float, float]]:
    """(corner torque [N m], stiffness above it [N m/rad]) for each segment used, from 0."""
    if stiffness.k1 is None:
        raise ValueError("the unit's stiffness does not rate K1")
    segments = [(0.0, stiffness.k1)]
    if stiffness.t1 is not None and stiffness.k2 is not None:
        segments.append((stiffness.t1, stiffness.k2))
        if stiffness.t2 is not None and stiffness.k3 is not None:
            segments.append((stiffness.t2, stiffness.k3))
    return segments


def torsion(stiffness: Stiffness, torque: float | np.ndarray) -> np.ndarray:
    """The twist of a unit under output torque, signed as the torque [rad].

    Args:
        stiffness: The unit's stiffness; K1 must be rated (`rates_torsion`).
        torque: Output torque [N m], any shape.

    Returns:
        The twist phi(T) [rad], the shape of `torque`.
    """
    magnitude = np.abs(np.asarray(torque, dtype=float))
    twist = np.zeros_like(magnitude)
    segments = _segments(stiffness)
    for k, (corner, rate) in enumerate(segments):
        end = segments[k + 1][0] if k + 1 < len(segments) else math.inf
        twist += np.clip(magnitude - corner, 0.0, end - corner) / rate
    result: np.ndarray = np.sign(torque) * twist
    return result


def torque_at_torsion(stiffness: Stiffness, angle: float) -> float:
    """The output torque at which a unit twists by `angle` [N m]: the inverse of `torsion`.

    Args:
        stiffness: The unit's stiffness; K1 must be rated (`rates_torsion`).
        angle: The twist [rad], at least 0.
    """
    if angle < 0.0:
        raise ValueError(f"a twist magnitude is at least 0, got {angle!r}")
    segments = _segments(stiffness)
    reached = 0.0
    for k, (corner, rate) in enumerate(segments):
        end = segments[k + 1][0] if k + 1 < len(segments) else math.inf
        span = (end - corner) / rate
        if angle <= reached + span:
            return corner + (angle - reached) * rate
        reached += span
    raise AssertionError("the last segment is unbounded")


def natural_frequency(k1: float, inertia: float | np.ndarray) -> np.ndarray:
    """Harmonic Drive's single-axis natural frequency sqrt(K1 / J) / (2 pi) [Hz].

    Args:
        k1: The unit's stiffness K1 [N m/rad].
        inertia: The load inertia J on its output [kg m^2], any shape; 0 gives inf.
    """
    with np.errstate(divide="ignore"):
        result: np.ndarray = np.sqrt(k1 / np.asarray(inertia, dtype=float)) / (2.0 * math.pi)
    return result


def resonance_speed(frequency: float | np.ndarray) -> np.ndarray:
    """The input speed whose transmission error excites a natural frequency [rpm].

    The error runs `EXCITATIONS_PER_INPUT_TURN` times per input revolution, so the input
    speed f x 60 / 2 rpm excites f [Hz].
    """
    result: np.ndarray = np.asarray(frequency, dtype=float) * 60.0 / EXCITATIONS_PER_INPUT_TURN
    return result


def unit_k1(unit: Unit) -> float | None:
    """A unit's K1 [N m/rad], or None where its source does not rate it."""
    return unit.stiffness.k1 if unit.stiffness is not None else None


@dataclass(frozen=True)
class ApplicationClass:
    """One of Harmonic Drive's application classes: the resonance it asks of a joint.

    Attributes:
        frequency: The lowest single-axis natural frequency f_n recommended [Hz].
        words: The applications, in Harmonic Drive's words.
        source: Where the number comes from.
    """

    frequency: float
    words: str
    source: str


_CLASS_SOURCE = (
    "Harmonic Drive AG, Engineering Data, stiffness-based dimensioning (recommended "
    "resonance frequency by application; e.g. HFUS-2A Component Sets 1019658 11/2014, "
    "selection flowchart p. 18); numbers as transcribed in the public repository "
    "AimanHaidar/harmonic-drive-selector, data/reducers_tables.py (a transcription, not "
    "the vendor's page)")

APPLICATION_CLASSES: Mapping[str, ApplicationClass] = MappingProxyType({
    name: ApplicationClass(frequency, words, _CLASS_SOURCE) for name, frequency, words in (
        ("slow-turntables", 4.0, "slowly rotating turntables; slowly rotating welding "
                                 "turntables"),
        ("slow-welding-base-axes", 4.0, "base axes of slow moving welding robots (not laser "
                                        "welding)"),
        ("gantry-axes", 4.0, "gantry robot axes"),
        ("base-axes", 8.0, "base axes of revolute robots"),
        ("slow-hand-axes", 8.0, "hand axes of revolute robots with low requirements "
                                "regarding dynamic performance"),
        ("tool-magazines", 8.0, "tool revolvers; tool magazines"),
        ("measuring-axes", 8.0, "swivelling and positioning axes in medical and measuring "
                                "devices"),
        ("general", 15.0, "standard applications in general mechanical engineering"),
        ("tilting-axes", 15.0, "tilting axes"),
        ("pallet-changers", 15.0, "palette changers"),
        ("tool-changers", 15.0, "high dynamic tool changers; revolvers and magazines"),
        ("hand-axes", 15.0, "hand axes of revolute robots"),
        ("scara", 15.0, "SCARA robots"),
        ("gantry-robots", 15.0, "gantry robots"),
        ("polishing-robots", 15.0, "polishing robots"),
        ("welding-turntables", 15.0, "dynamic welding turntables"),
        ("laser-welding-base-axes", 15.0, "base axes of welding robots (laser welding)"),
        ("medical-axes", 15.0, "swivelling and positioning axes of medical equipment"),
        ("grinding-axes", 20.0, "B / C axes in 5 axis grinding machines"),
        ("laser-welding-hand-axes", 20.0, "welding robot hand axes (laser welding)"),
        ("milling-plastics", 20.0, "milling heads for plastics machining"),
        ("turning-c-axes", 25.0, "C axes in turning machines"),
        ("milling-light-metal", 25.0, "milling heads, light metal machining"),
        ("milling-chipboard", 25.0, "milling heads, wood machining (chipboards etc.)"),
        ("milling-hardwood", 30.0, "milling heads for woodworking (hardwood etc.)"),
    )})
"""Harmonic Drive's application classes by the name a user types (``hand-axes``): the
single-axis natural frequency each recommends [Hz], in its words, with its source."""


class ClassFrequency(float):
    """A frequency [Hz] given by an application class's name: the number, and the name.

    Where a target is given as a class, every report names the class and says where its
    number comes from (`class_note`).

    Attributes:
        name: The class's name in `APPLICATION_CLASSES`.
    """

    name: str

    def __new__(cls, name: str) -> ClassFrequency:
        """The frequency of the class named `name` (a key of `APPLICATION_CLASSES`)."""
        value = super().__new__(cls, APPLICATION_CLASSES[name].frequency)
        value.name = name
        return value

    def __reduce__(self) -> tuple[type, tuple[str]]:
        """Pickled by its name (a study's workers receive it)."""
        return ClassFrequency, (self.name,)


def class_note(*values: object) -> str:
    """The classes among targets' values, each with its frequency, and their source's kind.

    Args:
        *values: Each a frequency, a mapping (joint -> frequency), or None.

    Returns:
        E.g. ``"hand-axes 15 Hz: Harmonic Drive's application classes as publicly
        transcribed (...)"``; empty where no value came from a class.
    """
    found = [item for value in values
             for item in (value.values() if isinstance(value, Mapping) else (value,))]
    names = sorted({item.name for item in found if isinstance(item, ClassFrequency)})
    if not names:
        return ""
    return (", ".join(f"{name} {APPLICATION_CLASSES[name].frequency:g} Hz" for name in names)
            + ": Harmonic Drive's application classes as publicly transcribed "
              "(AimanHaidar/harmonic-drive-selector), not read from the vendor's page")
