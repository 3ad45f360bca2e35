"""The output bearing's loads over a cycle, and the figures Harmonic Drive's checks compare.

A gearhead's output bearing (a cross-roller bearing) carries everything the joint
transmits except the torque about its axis: the axial force F_a, the radial force
F_r and the tilting moment M about the bearing centre. Where a catalog rates the
bearing (`hdselect.catalog.units.BearingRating`), Harmonic Drive's procedure checks:

- the largest loads against the allowable ones: M_max, F_r,max, F_a,max;
- the life: loads averaged as the 10/3-power mean weighted by |n| t (n the output
  speed, t the time), like the gear's cubic mean torque,
      F_av = ( sum |n_i| t_i |F_i|^(10/3) / sum |n_i| t_i )^(3/10),
  the dynamic equivalent load
      P_c = X (F_r,av + 2 M_av / d_p) + Y F_a,av,
  X = 1, Y = 0.45 where F_a,av / (F_r,av + 2 M_av / d_p) <= 1.5, else X = Y = 0.67,
  and the L10 life L = 10^6 / (60 N_av) (C / (f_w P_c))^(10/3) hours, N_av the mean
  output speed [rpm] as the series' rules average the gear's (PSA-G: over the
  moving part, the higher and so the conservative figure);
- the static safety C0 / P_0 >= the series' factor, P_0 = F_r,max + 2 M_max / d_p
  + 0.44 F_a,max.

The maxima are over every sample of the cycle, held poses included; the averages
over the moving part, as the mean torque's. No series' number lives here: f_w and
the static safety come from the series' ``[rules]``. The checks themselves are rules
(`hdselect.catalog.rules.bearing`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hdselect.catalog.units import BearingRating, SeriesRules

LIFE_EXPONENT = 10.0 / 3.0
"""Exponent of a roller bearing's life and of its mean loads [-]."""
AXIAL_RATIO = 1.5
"""F_a,av / (F_r,av + 2 M_av / d_p) up to which X = 1, Y = 0.45 [-]."""
LOAD_FACTORS = ((1.0, 0.45), (0.67, 0.67))
"""(X, Y) of the dynamic equivalent load, up to `AXIAL_RATIO` and above it [-]."""
STATIC_AXIAL_FACTOR = 0.44
"""Factor of F_a,max in the static equivalent load P_0 [-]."""
NOT_RATED = "bearing not rated by the source: its loads are reported, not checked"
"""What every result says of a unit whose catalog rates no output bearing."""
_CHUNK = 1 << 16
"""Samples summed at a time by `bearing_load`."""


@dataclass(frozen=True)
class BearingLoad:
    """The loads on one output bearing over a cycle.

    Attributes:
        max_axial: Largest |F_a| over every sample [N].
        max_radial: Largest F_r over every sample [N].
        max_moment: Largest tilting moment M over every sample [N m].
        mean_axial: F_a,av, the 10/3-power mean over the moving part weighted by |n| t
            [N]; None when the joint never moves.
        mean_radial: F_r,av, the same [N]; None when the joint never moves.
        mean_moment: M_av, the same [N m]; None when the joint never moves.
        offset: Where the moment is taken: the bearing centre along the joint axis from
            the joint origin [m].
        spread: For a unit whose bearing centre sits this far from `offset` on a side
            not known, the moment is the larger of both sides at each sample [m].
    """

    max_axial: float
    max_radial: float
    max_moment: float
    mean_axial: float | None
    mean_radial: float | None
    mean_moment: float | None
    offset: float = 0.0
    spread: float = 0.0


@dataclass(frozen=True)
class BearingFigures:
    """A rated bearing's figures for one cycle: what its checks compare.

    Attributes:
        load: Its loads, about its own centre.
        mean_speed: N_av, the mean output speed the life counts [rpm].
        equivalent_load: P_c [N]; None without the dynamic rating or when never moving.
        factors: (X, Y) of P_c [-]; None with P_c.
        life_hours: L10 life [h]; None when unlimited or not rated.
        static_load: P_0 [N]; None without the static rating.
        static_safety: C0 / P_0 [-]; None when not rated or P_0 is 0.
    """

    load: BearingLoad
    mean_speed: float
    equivalent_load: float | None
    factors: tuple[float, float] | None
    life_hours: float | None
    static_load: float | None
    static_safety: float | None


def bearing_load(axial: np.ndarray, radial: np.ndarray, moment: np.ndarray,
                 speed: np.ndarray, duration: np.ndarray | float, at_rest: np.ndarray, *,
                 offset: float = 0.0, spread: float = 0.0) -> BearingLoad:
    """Summarise one bearing's loads over a cycle: maxima and 10/3-power means.

    Args:
        axial: F_a per sample [N] (sign ignored).
        radial: F_r per sample [N].
        moment: Tilting moment M per sample about the bearing centre [N m].
        speed: Output speed per sample [rad/s] (sign ignored).
        duration: What each sample stands for [s].
        at_rest: True where the joint is held still: counted in the maxima, not in the
            means (as the gear's mean torque).
        offset: The bearing centre the moment is about (recorded) [m].
        spread: The side-unknown distance the moment allowed for (recorded) [m].

    Returns:
        The summary.
    """
    return weighted_bearing_load(axial, radial, moment, travel_weights(speed, duration, at_rest),
                                 offset=offset, spread=spread)


def travel_weights(speed: np.ndarray, duration: np.ndarray | float,
                   at_rest: np.ndarray) -> np.ndarray:
    """|n| t of each sample, 0 where the joint is held still: the means' weights [rad]."""
    weight = np.abs(np.asarray(speed, dtype=float))
    weight *= duration
    weight[np.broadcast_to(np.asarray(at_rest, dtype=bool), weight.shape)] = 0.0
    return weight


def weighted_bearing_load(axial: np.ndarray, radial: np.ndarray, moment: np.ndarray,
                          weight: np.ndarray, *, offset: float = 0.0,
                          spread: float = 0.0) -> BearingLoad:
    """`bearing_load` from each sample's weight |n| t (`travel_weights`) [rad].

    A state that several samples share may be given once, with their weights summed:
    the maxima and the means are the same.
    """
    peaks = [0.0, 0.0, 0.0]
    sums = [0.0, 0.0, 0.0]
    travel = float(weight.sum())
    for start in range(0, len(axial), _CHUNK):  # a long cycle in pieces of bounded memory
        part = slice(start, start + _CHUNK)
        for k, values in enumerate((axial, radial, moment)):
            load = np.abs(values[part])
            peaks[k] = max(peaks[k], float(load.max(initial=0.0)))
            power = np.cbrt(load)  # |F|^(10/3) = |F|^3 cbrt|F|, faster than a power
            power *= load
            power *= load
            power *= load
            sums[k] += float(np.dot(power, weight[part]))
    means: list[float | None] = [None, None, None]
    if travel > 0.0:
        means = [(total / travel) ** 0.3 for total in sums]
    return BearingLoad(peaks[0], peaks[1], peaks[2], means[0], means[1], means[2],
                       offset=offset, spread=spread)


def bearing_figures(load: BearingLoad, rating: BearingRating, rules: SeriesRules,
                    mean_speed: float) -> BearingFigures:
    """P_c, the L10 life, P_0 and the static safety of a rated bearing.

    Args:
        load: The bearing's loads over the cycle, about its centre.
        rating: What the catalog rates it for.
        rules: The series' rules (the load factor f_w).
        mean_speed: N_av, the mean output speed [rad/s].

    Returns:
        Its figures; each None where a rating it needs is not given.
    """
    rpm = mean_speed * 60.0 / (2.0 * math.pi)
    d_p = rating.pitch_diameter
    equivalent = factors = life = None
    if (rating.dynamic_rating is not None and d_p is not None and load.mean_axial is not None
            and load.mean_radial is not None and load.mean_moment is not None):
        radial = load.mean_radial + 2.0 * load.mean_moment / d_p
        factors = (LOAD_FACTORS[0] if load.mean_axial <= AXIAL_RATIO * radial
                   else LOAD_FACTORS[1])
        equivalent = factors[0] * radial + factors[1] * load.mean_axial
        life = l10_bearing_hours(rating.dynamic_rating, equivalent, rules.bearing_load_factor,
                                 rpm)
    static = safety = None
    if rating.static_rating is not None and d_p is not None:
        static = (load.max_radial + 2.0 * load.max_moment / d_p
                  + STATIC_AXIAL_FACTOR * load.max_axial)
        safety = rating.static_rating / static if static > 0.0 else None
    return BearingFigures(load, rpm, equivalent, factors, life, static, safety)


def l10_bearing_hours(dynamic_rating: float, equivalent_load: float, load_factor: float,
                      mean_speed_rpm: float) -> float | None:
    """L10 = 10^6 / (60 N_av) (C / (f_w P_c))^(10/3) [h]; None when unlimited.

    Args:
        dynamic_rating: C [N].
        equivalent_load: P_c [N].
        load_factor: f_w [-].
        mean_speed_rpm: N_av [rpm].
    """
    if equivalent_load <= 0.0 or mean_speed_rpm <= 0.0:
        return None
    try:
        life = 1e6 / (60.0 * mean_speed_rpm) * (
            dynamic_rating / (load_factor * equivalent_load)) ** LIFE_EXPONENT
    except OverflowError:
        return None
    return life if math.isfinite(life) else None
