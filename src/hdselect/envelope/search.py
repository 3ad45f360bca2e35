"""The global search for the worst state of every joint over the limit box.

Quasi-random starts (a scrambled Sobol sequence in the unit cube of positions and
velocities, `hdselect.envelope.box`) are evaluated in batched passes; the best few
distinct starts of every joint and demand are then refined together by a batched
quasi-Newton ascent (BFGS on a smooth map of the cube onto the real line, gradients
by forward differences). The acceleration needs no search: the demands take its
worst vertex exactly (`hdselect.envelope.demands`).

Convergence is measured, not assumed: the worst value refined from the first N
starts and from the first 4N must agree within `SearchSettings.tolerance`; where
they do not, 16N starts are taken (then 64N), and a demand still unsettled is
reported as not converged.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from hdselect.base.errors import InputError
from hdselect.envelope.box import LimitBox
from hdselect.envelope.demands import KINDS, all_demands, joint_demands
from hdselect.robot.model import Robot

ABSOLUTE = 1e-4
"""Worst values this close agree whatever their ratio [N m]: under 0.004 % of the smallest
PSA-G limit (2.6 N m), and how a demand that is nil everywhere (gravity on a vertical axis)
agrees."""
_STEP = 1e-7
"""Forward-difference step in the search's coordinates [-]."""
_GAIN = 1e-10
"""Smallest relative gain a refinement step must bring to count; below it the start has
converged (ten digits, far below the search's tolerance)."""
_STEPS = (4.0, 1.0, 0.3, 0.1, 0.01)
"""Fractions of the quasi-Newton step tried at once, in one batched evaluation."""


MAX_STARTS = 65536
"""The most starts of a first round. The default two more rounds take up to 64 times as
many states: 4,194,304 here; 1,048,576 states of a six-joint arm took 0.9 GB."""


@dataclass(frozen=True)
class SearchSettings:
    """How hard the search looks.

    Attributes:
        starts: N, the quasi-random starts of the first round: a power of 2 from 64 to
            `MAX_STARTS`.
        refine: Distinct best starts refined per joint and demand, from each round.
        tolerance: Largest relative difference between the worst values found from N and
            from 4N starts for the search to count as converged [-].
        rounds: Most rounds of four times more starts after the first comparison.
        iterations: Most quasi-Newton iterations of a refinement.
        seed: Seed of the scrambled Sobol sequence.
    """

    starts: int = 4096
    refine: int = 8
    tolerance: float = 0.005
    rounds: int = 2
    iterations: int = 60
    seed: int = 0

    def __post_init__(self) -> None:
        if (isinstance(self.starts, bool) or not isinstance(self.starts, int)
                or not 64 <= self.starts <= MAX_STARTS or self.starts & (self.starts - 1)):
            raise InputError(f"must be a power of 2 from 64 to {MAX_STARTS:,} (each later "
                             f"round takes four times as many), got {self.starts!r}",
                             field="starts")
        for name, low, high in (("refine", 1, 64), ("rounds", 0, 4), ("iterations", 1, 1000)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
                raise InputError(f"must be a whole number in [{low}, {high}], got {value!r}",
                                 field=name)
        if not (isinstance(self.tolerance, float | int) and 0.0 < self.tolerance < 1.0):
            raise InputError(f"must be a fraction in (0, 1), got {self.tolerance!r}",
                             field="tolerance")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError(f"must be a whole number >= 0, got {self.seed!r}", field="seed")


@dataclass(frozen=True)
class Worst:
    """The worst state found for one demand of one joint.

    Attributes:
        joint: Index of the joint in the robot's order.
        kind: The demand, one of `KINDS`.
        point: The state in the unit cube, shape (2 dof,).
        value: The demand there [N m or N].
        by_starts: (starts, worst value refined from the first that many) per round.
        converged: The last two rounds agree within the tolerance.
    """

    joint: int
    kind: str
    point: np.ndarray
    value: float
    by_starts: tuple[tuple[int, float], ...]
    converged: bool


Evaluate = Callable[[Robot, LimitBox, np.ndarray, Sequence[int], float], np.ndarray]
"""Computes `hdselect.envelope.demands.all_demands` (robot, box, points, joints, stop time)
somewhere: shape (n, joints, len(KINDS))."""


def search(robot: Robot, box: LimitBox, stop_time: float, joints: Sequence[int],
           settings: SearchSettings | None = None, *, threads: int | None = None,
           evaluate: Evaluate | None = None) -> tuple[dict[tuple[int, str], Worst], int]:
    """The worst state of every demand of the given joints.

    Round 0 evaluates the first N Sobol points and refines the best distinct starts of
    each demand; every later round takes four times as many points (evaluating only
    the joints still unsettled) and refines the best of them. The worst value of a
    round is the best refinement of any start among its points, so it never falls;
    a demand settles when two rounds agree within the tolerance.

    Args:
        robot: The robot (payload and carried masses included).
        box: The limit box.
        stop_time: The emergency-stop time [s].
        joints: Indices of the joints to search for.
        settings: How hard to look (default `SearchSettings()`).
        threads: Threads for the batched passes.
        evaluate: Computes `all_demands` of many points (to spread them over workers);
            None computes them here.

    Returns:
        The worst state by (joint index, demand), and the number of states evaluated.
    """
    settings = settings or SearchSettings()
    dof = box.dof

    def demands(x: np.ndarray, subset: Sequence[int]) -> np.ndarray:
        if evaluate is None:
            return all_demands(robot, box, x, subset, stop_time, threads=threads)
        return evaluate(robot, box, x, subset, stop_time)
    sampler = qmc.Sobol(box.dimension, scramble=True, seed=settings.seed)
    points = sampler.random_base2(int(math.log2(settings.starts)))
    joints = list(dict.fromkeys(int(j) for j in joints))
    values = dict(zip(joints, np.moveaxis(demands(points, joints), 1, 0), strict=True))
    evaluated = len(points) * 2 * len(joints)  # each joint's point, and its held point
    refined: dict[tuple[int, int, int], tuple[np.ndarray, float]] = {}
    rounds: dict[tuple[int, int], list[tuple[int, float]]] = {
        (j, k): [] for j in joints for k in range(len(KINDS))}
    open_ = list(rounds)
    size = settings.starts
    for round_ in range(settings.rounds + 2):
        if round_ > 0:
            more = sampler.random(3 * size)
            points = np.vstack([points, more])
            moving = sorted({j for j, _ in open_})
            extra = np.moveaxis(demands(more, moving), 1, 0)
            for j, block in zip(moving, extra, strict=True):
                values[j] = np.concatenate([values[j], block])
            evaluated += len(more) * 2 * len(moving)
            size *= 4
        starts = {key: _distinct_best(_fixed(points[:size], *key, dof),
                                      values[key[0]][:size, key[1]], settings.refine)
                  for key in open_}
        todo = [(key, i) for key in open_ for i in starts[key] if (*key, i) not in refined]
        if todo:
            found, count = _refine_starts(robot, box, stop_time, points, todo, settings,
                                          threads)
            evaluated += count
            refined.update(found)
        for key in open_:
            rounds[key].append((size, max(value for (j, k, i), (_, value) in refined.items()
                                          if (j, k) == key and i < size)))
        if round_ > 0:
            open_ = [key for key in open_ if not agree(rounds[key][-2][1], rounds[key][-1][1],
                                                        settings.tolerance)]
        if round_ > 0 and not open_:
            break
    out = {}
    for (j, k), history in rounds.items():
        point, value = max((found for key, found in refined.items() if key[:2] == (j, k)),
                           key=lambda item: item[1])
        converged = agree(history[-2][1], history[-1][1], settings.tolerance)
        out[(j, KINDS[k])] = Worst(j, KINDS[k], point, value, tuple(history), converged)
    return out, evaluated


def agree(first: float, second: float, tolerance: float) -> bool:
    """Two worst values agree: within `tolerance` of the larger, or within `ABSOLUTE`."""
    gap = abs(first - second)
    return gap <= ABSOLUTE or gap <= tolerance * max(abs(first), abs(second))


def _fixed(points: np.ndarray, joint: int, kind: int, dof: int) -> np.ndarray:
    """The points as a demand reads them: a held joint's speed, or every speed, set to 0."""
    if KINDS[kind] == "held":
        points = points.copy()
        points[:, dof + joint] = 0.5
    elif KINDS[kind] == "gravity":
        points = points.copy()
        points[:, dof:] = 0.5
    return points


def _free(joint: int, kind: int, dof: int) -> np.ndarray:
    """The coordinates a demand's search may move, shape (2 dof,)."""
    free = np.ones(2 * dof, dtype=bool)
    if KINDS[kind] == "held":
        free[dof + joint] = False
    elif KINDS[kind] == "gravity":
        free[dof:] = False
    return free


def _distinct_best(points: np.ndarray, values: np.ndarray, count: int) -> list[int]:
    """Indices of up to `count` best points, each at least 0.1 from the others (max norm)."""
    order = np.argsort(values)[::-1][: 64 * count]
    chosen: list[int] = []
    for i in order:
        if all(np.max(np.abs(points[i] - points[c])) >= 0.1 for c in chosen):
            chosen.append(int(i))
            if len(chosen) == count:
                break
    return chosen


def _refine_starts(robot: Robot, box: LimitBox, stop_time: float, points: np.ndarray,
                   todo: list[tuple[tuple[int, int], int]], settings: SearchSettings,
                   threads: int | None
                   ) -> tuple[dict[tuple[int, int, int], tuple[np.ndarray, float]], int]:
    """Refine the given starts together; each one's best point and value, and the count."""
    dof = box.dof
    joint = np.array([key[0] for key, _ in todo])
    kind = np.array([key[1] for key, _ in todo])
    start = np.array([_fixed(points[i][None], *key, dof)[0] for key, i in todo])
    free = np.array([_free(*key, dof) for key, _ in todo])
    periodic = np.concatenate([box.periodic, np.zeros(dof, dtype=bool)])
    ascent = _Ascent(start, free, periodic)
    count = 0

    def value_of(x: np.ndarray, rows: np.ndarray) -> np.ndarray:
        nonlocal count
        count += len(x)
        return joint_demands(robot, box, x, joint[rows], kind[rows], stop_time,
                             threads=threads)

    ascent.run(value_of, settings.iterations)
    found = {(*key, i): (ascent.best_point(r), float(ascent.f[r]))
             for r, (key, i) in enumerate(todo)}
    return found, count


class _Ascent:
    """Batched BFGS ascent of many rows at once, each on its own free coordinates.

    A bounded coordinate x in [0, 1] is moved through x = (1 - cos(pi u)) / 2, so that
    the search is unconstrained in u and a maximum on a bound is a smooth maximum in u;
    a periodic one (a continuous joint) through x = u mod 1.
    """

    def __init__(self, start: np.ndarray, free: np.ndarray, periodic: np.ndarray) -> None:
        self.free = free
        self.periodic = periodic
        self.fixed = start.copy()
        self.u = np.where(periodic, start, np.arccos(np.clip(1.0 - 2.0 * start, -1, 1))
                          / math.pi)
        m, d = start.shape
        self.f = np.full(m, -np.inf)
        self.h = np.zeros((m, d, d))
        self.fresh = np.ones(m, dtype=bool)

    def point(self, u: np.ndarray, rows: np.ndarray) -> np.ndarray:
        x = np.where(self.periodic, np.mod(u, 1.0), (1.0 - np.cos(math.pi * u)) / 2.0)
        return np.where(self.free[rows], x, self.fixed[rows])

    def best_point(self, row: int) -> np.ndarray:
        return self.point(self.u[row][None], np.array([row]))[0]

    def run(self, value_of: Callable[[np.ndarray, np.ndarray], np.ndarray],
            iterations: int) -> None:
        m, d = self.u.shape
        rows = np.arange(m)
        self.f = value_of(self.point(self.u, rows), rows)
        grad = self._gradient(value_of, rows)
        self._reset(rows, grad)
        active = rows[np.linalg.norm(grad, axis=1) > 0.0]
        for _ in range(iterations):
            if not active.size:
                return
            step = np.einsum("rij,rj->ri", self.h[active], grad[active])
            big = np.max(np.abs(step), axis=1, keepdims=True)
            step *= np.minimum(1.0, 0.25 / np.maximum(big, 1e-300))  # at most 1/4 turn of u
            trials = (self.u[active][:, None, :] + np.multiply.outer(_STEPS, step)
                      .transpose(1, 0, 2)).reshape(-1, d)
            owner = np.repeat(active, len(_STEPS))
            tried = value_of(self.point(trials, owner), owner).reshape(-1, len(_STEPS))
            pick = tried.argmax(axis=1)
            best = tried[np.arange(active.size), pick]
            better = best > self.f[active] + _GAIN * np.abs(self.f[active]) + 1e-15
            moved = active[better]
            stuck = active[~better]
            # no step helps: retry once from a fresh steepest-ascent scale, else stop
            self._reset(stuck[~self.fresh[stuck]], grad[stuck[~self.fresh[stuck]]])
            done = stuck[self.fresh[stuck]]
            if moved.size:
                old_u, old_g = self.u[moved].copy(), grad[moved].copy()
                self.u[moved] = trials.reshape(active.size, len(_STEPS), d)[
                    better.nonzero()[0], pick[better]]
                self.f[moved] = best[better]
                grad[moved] = self._gradient(value_of, moved)
                self._update(moved, self.u[moved] - old_u, old_g - grad[moved],
                             self.fresh[moved])
                self.fresh[moved] = False
            active = np.setdiff1d(active, done)
            active = active[np.linalg.norm(grad[active], axis=1) > 0.0]

    def _gradient(self, value_of: Callable[[np.ndarray, np.ndarray], np.ndarray],
                  rows: np.ndarray) -> np.ndarray:
        """Forward differences of every free coordinate, in one batched evaluation."""
        m, d = rows.size, self.u.shape[1]
        up = (self.u[rows][:, None, :] + np.eye(d) * _STEP).reshape(-1, d)
        owner = np.repeat(rows, d)
        ahead = value_of(self.point(up, owner), owner).reshape(m, d)
        return (ahead - self.f[rows][:, None]) / _STEP * self.free[rows]

    def _reset(self, rows: np.ndarray, grad: np.ndarray) -> None:
        """Steepest ascent, scaled so that the first step moves 0.05 in u."""
        if not rows.size:
            return
        norm = np.linalg.norm(grad, axis=1)
        scale = np.where(norm > 0.0, 0.05 / np.maximum(norm, 1e-300), 0.0)
        self.h[rows] = np.eye(self.u.shape[1]) * scale[:, None, None]
        self.fresh[rows] = True

    def _update(self, rows: np.ndarray, s: np.ndarray, y: np.ndarray,
                fresh: np.ndarray) -> None:
        """The BFGS update of the inverse Hessian of -f, where the curvature allows it.

        A row's first update first scales its steepest-ascent start to the curvature seen,
        H = (s.y / y.y) I (Nocedal and Wright, eq. 6.20).
        """
        sy = np.einsum("ri,ri->r", s, y)
        ok = sy > 1e-12 * np.linalg.norm(s, axis=1) * np.linalg.norm(y, axis=1)
        if not ok.any():
            return
        r, s, y, rho, fresh = rows[ok], s[ok], y[ok], 1.0 / sy[ok], fresh[ok]
        eye = np.eye(s.shape[1])
        if fresh.any():
            scale = sy[ok][fresh] / np.einsum("ri,ri->r", y[fresh], y[fresh])
            self.h[r[fresh]] = eye * (scale[:, None, None] * self.free[r[fresh]][:, None, :]
                                      * self.free[r[fresh]][:, :, None])
        left = eye - rho[:, None, None] * np.einsum("ri,rj->rij", s, y)
        self.h[r] = (left @ self.h[r] @ left.transpose(0, 2, 1)
                     + rho[:, None, None] * np.einsum("ri,rj->rij", s, s))
