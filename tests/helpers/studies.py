"""Studies and mixes: a scratch copy of the shipped files, a small study file, mix files
of the index table and the bang-bang motion, and `differences` between two sizings.
"""

from __future__ import annotations

import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np

from hdselect import plan, size_trajectory
from hdselect.sizing.summary import summarize
from hdselect.sizing.tasks import task_of
from hdselect.study.pooled import diagnosed, scaled, slower_events
from helpers import REPO


def workspace(tmp_path: Path) -> Path:
    """Copies of the shipped robots and motions, free to edit."""
    for name in ("robots", "trajectories"):
        shutil.copytree(REPO / name, tmp_path / name)
    return tmp_path


def small_study(root: Path, extra: str = "") -> Path:
    """2 robots x 3 payloads x 2 speeds: 12 cases, two groups of 6."""
    path = root / "study.toml"
    path.write_text(f"""title = "small"
[grid]
motion = ["trajectories/planar2_pick_place.toml", "trajectories/index_table_indexing.toml"]
payload = [0.2, 0.4, 0.6]
time_scale = [1.0, 1.25]
{extra}""")
    return path


TABLE = REPO / "robots" / "index_table.urdf"


PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"


INSPECT = REPO / "trajectories" / "benchtop6_inspect.toml"


PICK_INSPECT = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"


DT = 0.001


BANG_BANG = {"fast": (30.0, 150, 250, 0.05), "slow": (10.0, 300, 400, 0.02)}
"""Per task: acceleration a [rad/s^2], samples accelerating n (and as many braking),
samples dwelling m, and the part's inertia about the table axis [kg m^2]."""


def bang_bang(a: float, n: int, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """qd, qdd of one bang-bang index and its dwell, sampled every DT: qd = a i DT up, then down.

    qd_i = a i DT for i < n (qdd = +a), a (2n - i) DT for n <= i < 2n (qdd = -a), then m
    samples at rest (qd = qdd = 0).
    """
    i = np.arange(2 * n + m)
    qd = np.where(i < n, a * i * DT, np.where(i < 2 * n, a * (2 * n - i) * DT, 0.0))
    qdd = np.where(i < n, a, np.where(i < 2 * n, -a, 0.0))
    return qd, qdd, i * DT


def write_index_mix(folder: Path, *, shares=None, cycles_per_hour=None) -> Path:
    """Two logged index-table tasks (`BANG_BANG`), each with its part's inertia, and their mix."""
    lines = ['robot = "' + str(TABLE) + '"']
    for k, (name, (a, n, m, inertia)) in enumerate(BANG_BANG.items()):
        qd, qdd, t = bang_bang(a, n, m)
        q = np.concatenate(([0.0], np.cumsum(qd[:-1]) * DT))
        rows = "\n".join(",".join(repr(float(v)) for v in (t[i], q[i], qd[i], qdd[i]))
                         for i in range(len(t)))
        (folder / f"{name}.csv").write_text("t,q_table,qd_table,qdd_table\n" + rows + "\n")
        (folder / f"{name}.toml").write_text(
            f'robot = "{TABLE}"\nplanner = "samples"\nangle_unit = "rad"\ndt = {DT}\n'
            f'[samples]\nfile = "{name}.csv"\n[payload]\nmass = 1.0\ncom = [0.0, 0.0, 0.03]\n'
            f"inertia = [[{inertia / 2}, 0, 0], [0, {inertia / 2}, 0], [0, 0, {inertia}]]\n"
            'frame = "disk"\n')
        how = (f"share = {shares[k]}" if shares is not None
               else f"cycles_per_hour = {cycles_per_hour[k]}")
        lines.append(f'[[task]]\nname = "{name}"\nmotion = "{name}.toml"\n{how}')
    mix = folder / "mix.toml"
    mix.write_text("\n".join(lines) + "\n")
    return mix


def mix_text(folder: Path, *tasks: tuple[str, Path, float]) -> Path:
    text = "".join(f'[[task]]\nname = "{name}"\nmotion = "{motion}"\nshare = {share}\n'
                   for name, motion, share in tasks)
    path = folder / "mix.toml"
    path.write_text(text)
    return path


def plain_text(result):
    """A result as nested plain values (its summary), without warnings."""
    return replace(summarize(result), warnings=(), tasks=()).to_dict()  # tasks: listed apart


BEARING_LOADS = ("bearing_max_moment", "bearing_max_radial", "bearing_max_axial",
                 "bearing_mean_moment", "bearing_mean_radial", "bearing_mean_axial")


def differences(grouped, separate, path=""):
    """Largest relative difference of two summaries as dicts; raises on any other mismatch.

    A joint's bearing loads are parts of one wrench: each is compared relative to the
    joint's largest of them (a component that is zero but for rounding differs in its
    rounding only).
    """
    if isinstance(grouped, dict):
        assert grouped.keys() == separate.keys(), path
        found = [differences(grouped[k], separate[k], f"{path}.{k}") for k in grouped
                 if k != "threads" and k not in BEARING_LOADS]
        if grouped.get("bearing_max_moment") is not None:
            scale = max(abs(v) for k in BEARING_LOADS for v in (grouped[k], separate[k])
                        if v is not None)
            for k in BEARING_LOADS:
                a, b = grouped[k], separate[k]
                assert (a is None) == (b is None), f"{path}.{k}"
                found.append(0.0 if a is None else abs(a - b) / scale)
        else:
            found += [differences(grouped[k], separate[k], f"{path}.{k}")
                      for k in BEARING_LOADS if k in grouped]
        return max(found, default=0.0)
    if isinstance(grouped, list | tuple):
        assert len(grouped) == len(separate), path
        return max([differences(a, b, f"{path}[{i}]")
                    for i, (a, b) in enumerate(zip(grouped, separate, strict=True))], default=0.0)
    if isinstance(grouped, float) and isinstance(separate, float):
        scale = max(abs(grouped), abs(separate))
        return 0.0 if grouped == separate else abs(grouped - separate) / scale
    assert grouped == separate, (path, grouped, separate)
    return 0.0


def separate(robot, motion, mass, time_scale, units, options, motors=None):
    """A study case sized alone: the motion's ``[payload]`` at `mass` [kg], planned, run
    `time_scale` times slower, each sample with the parts its payload events carry."""
    carrying = robot.with_payload(None if mass is None else replace(motion.payload, mass=mass))
    task = task_of(carrying, plan(carrying, motion), motion)
    trajectory = scaled(task.trajectory, time_scale)
    return summarize(diagnosed(replace(size_trajectory(
        task.robot, trajectory, units, options, motors=motors,
        carried=slower_events(task.carried, time_scale)), motion=motion)))
