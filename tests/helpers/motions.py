"""Motions and catalog units built for the sizing tests: the index table's motion and
motor, the planar arm's slow and overloaded motions, one-move Ruckig and TOPPRA
motions, and catalog units and loads made by hand.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import ruckig

from hdselect.catalog.rules import CycleLoad
from hdselect.catalog.units import SeriesRules, Unit
from hdselect.motion.loading import load_case
from helpers import REPO
from helpers.robots import write_motion, write_robot

ETA = 0.70  # the default efficiency (no PSA-G unit has a table)


INDEX_URDF = REPO / "robots" / "index_table.urdf"


# index table trapezoid: 180 deg at 180 deg/s, 720 deg/s^2, jerk high enough to be a trapezoid
V, A = math.pi, 4 * math.pi  # [rad/s], [rad/s^2]


T_A = V / A  # 0.25 s to accelerate, and to decelerate


DWELL = 0.5  # [s] before and after the move


CYCLE = 2 * DWELL + math.pi / V + T_A  # 0.5 + (1 + 0.25) + 0.5 = 2.25 s


# a motor on a falling curve: flat 0.1 N m to 2000 rpm, then down to 0.05 N m at 6000 rpm
MOTOR = """\
id = "T1"
rated_torque_nm = 0.03
peak_torque_nm = 0.1
max_speed_rpm = 6000
rated_speed_rpm = 2000
rotor_inertia_kg_m2 = 5e-6
mass_kg = 0.2
torque_constant_nm_per_a = 0.025
resistance_ohm = 1.5
[motor.table.curve]
speed_rpm = [0, 2000, 6000]
peak_torque_nm = [0.1, 0.1, 0.05]
"""


def index_motion(directory: Path, motor: str = MOTOR, *, scale: float = 1.0,
                 name: str = "index.toml", header: str = "[motor.table]") -> Path:
    """The index table's trapezoid run `scale` times slower, with a motor block."""
    s = scale
    path = directory / name
    path.write_text(f"""\
robot = "{INDEX_URDF.as_posix()}"
planner = "ruckig"
angle_unit = "deg"
dt = 0.0005
[limits]
velocity = {180 / s!r}
acceleration = {720 / s**2!r}
jerk = {1e7 / s**3!r}
[safety]
stop_time = 0.1
[[waypoint]]
q = [0]
dwell = {DWELL * s!r}
[[waypoint]]
q = [180]
dwell = {DWELL * s!r}
{header}
{motor}""")
    return path


PLANAR2 = REPO / "robots" / "planar2.urdf"


def planar2_motion(path: Path, *waypoints: tuple[float, ...], payload: float | None = None,
                   frame: str | None = None,
                   limits: tuple[float, float, float] = (90, 300, 3000)) -> Path:
    """A planar2 motion through `waypoints` (q1, q2 [deg], and a dwell [s] if given).

    Ruckig at `limits` (velocity, acceleration, jerk [deg/s, deg/s^2, deg/s^3]), and a
    payload of `payload` [kg] on `frame` (the default frame where None) if given.
    """
    points = "".join(f"[[waypoint]]\nq = [{point[0]}, {point[1]}]\n"
                     + (f"dwell = {point[2]}\n" if len(point) > 2 else "")
                     for point in waypoints)
    carried = "" if payload is None else f"[payload]\nmass = {payload}\n" + (
        "" if frame is None else f'frame = "{frame}"\n')
    velocity, acceleration, jerk = limits
    path.write_text(f"""\
robot = "{PLANAR2.as_posix()}"
planner = "ruckig"
angle_unit = "deg"
{carried}[limits]
velocity = {velocity}
acceleration = {acceleration}
jerk = {jerk}
{points}""")
    return path


def slow_planar2_motion(path: Path, *waypoints: tuple[float, float]) -> Path:
    """A gentle planar2 motion through `waypoints` [deg], no payload."""
    return planar2_motion(path, *waypoints)


def gravity_overload_motion(path: Path) -> Path:
    """planar2 holding 8 kg at the tool, barely moving: gravity alone is too much."""
    return planar2_motion(path, (0, 0, 1.0), (5, 0, 1.0), payload=8.0, frame="tool",
                          limits=(30, 100, 1000))


def overload_motion(directory: Path, *, payload: float, velocity: float, acceleration: float,
                    jerk: float, stop_time: float, scale: float = 1.0,
                    waypoints=((60, -30), (-20, 40), (60, -30)),
                    name: str = "overload.toml") -> Path:
    """planar2 swinging a heavy payload between poses [deg], run `scale` times slower.

    Ruckig's time-optimal rest-to-rest profile for the limits (v/s, a/s^2, j/s^3) is
    exactly the original profile run s times slower, q_s(t) = q(t / s); dwells scale too.
    """
    s = scale
    path = directory / name
    points = "".join(f"[[waypoint]]\nq = {{shoulder = {a}, elbow = {b}}}\ndwell = {0.3 * s!r}\n"
                     for a, b in waypoints)
    path.write_text(f"""\
robot = "{PLANAR2.as_posix()}"
planner = "ruckig"
angle_unit = "deg"
dt = 0.001
[payload]
mass = {payload}
frame = "tool"
[limits]
velocity = {velocity / s!r}
acceleration = {acceleration / s**2!r}
jerk = {jerk / s**3!r}
[safety]
stop_time = {stop_time}
{points}""")
    return path


def make_motion(directory, planner, waypoints, *, dwells=None, velocity, acceleration,
                jerk=None, torque=None, dt=0.001, dof=None):
    """A robot and a motion in radians for a chain of revolute joints j1..jN (limits +-pi)."""
    dof = dof or len(waypoints[0])
    if not (directory / "arm.urdf").exists():
        write_robot(directory, dof)
    lines = ['robot = "arm.urdf"', f'planner = "{planner}"', 'angle_unit = "rad"', f"dt = {dt}",
             "[limits]", f"velocity = {velocity}", f"acceleration = {acceleration}"]
    lines += [f"jerk = {jerk}"] if jerk is not None else []
    lines += [f"torque = {torque}"] if torque is not None else []
    for i, q in enumerate(waypoints):
        lines += ["[[waypoint]]", f"q = {list(map(float, q))}"]
        if dwells is not None:
            lines.append(f"dwell = {dwells[i]}")
    return load_case(write_motion(directory, "\n".join(lines) + "\n"))


def ruckig_move(start, target, v, a, j, velocity=None):
    dof = len(start)
    inp = ruckig.InputParameter(dof)
    inp.current_position, inp.target_position = list(start), list(target)
    if velocity is not None:
        inp.current_velocity = list(velocity)
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = list(v), list(a), list(j)
    traj = ruckig.Trajectory(dof)
    assert ruckig.Ruckig(dof).calculate(inp, traj) == ruckig.Result.Working
    return traj


def dense_toppra_cycle(robot, motion) -> float:
    """The cycle on the dense grid (the oracle): every piece solved on 200 cosine-spaced
    gridpoints per waypoint and 8 per line sample, with every knot of its spline (and a
    point just before it where p'' steps there: a shape-preserving joint), then slowed down
    uniformly by its overshoot between them (asserted below 0.1 %: the grid resolves the
    path), plus the dwells."""
    from hdselect.motion.planning.toppra import (
        kinematic_constraints,
        overshoot_scale,
        path_pieces,
        solve_piece,
        with_gridpoints,
    )

    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    total = float(np.sum(motion.dwells))
    for piece in path_pieces(robot, motion, 200):
        if piece.path is not None:
            knots = piece.path.waypoints[0]
            before = knots[1:] - 1e-9 if piece.path.shape_preserving else []
            grid = np.union1d(piece.gridpoints, np.r_[knots, before])
            profile = solve_piece(with_gridpoints(piece, grid),
                                  kinematic_constraints(velocity, acceleration), where="test")
            scale = overshoot_scale(profile, velocity, acceleration)
            assert scale < 1.0 + 1e-3
            total += profile.duration * scale
    return total


RPM = 2.0 * math.pi / 60.0  # rad/s in one rpm


# The PSA-G page's rules, as psa_g.toml states them: T_N at 1750 rpm input, L50 = 35000 h,
# the speed-adjusted mean-torque limit, mean speed over the moving part, at most 1e4 events.
PSA_RULES = SeriesRules(rated_input_speed=1750.0, rated_life_hours=35000.0, life_basis="L50",
                        mean_torque_limit="speed-adjusted", mean_speed="moving",
                        max_momentary_events=1e4, source=Path("test.toml"))


def make_unit(**overrides: object) -> Unit:
    """A plain unit with round numbers: T_N 10, repeated 20, momentary and static 30 N m."""
    values: dict[str, object] = dict(
        id="T-10-50", series="T", size=10, ratio=50, rated_torque=10.0, repeated_torque=20.0,
        momentary_torque=30.0, static_torque=30.0, max_input_speed=6000.0,
        input_inertia=1e-6, mass=0.5, efficiency=None, rules=PSA_RULES, average_torque=None,
        max_average_input_speed=None, flags=(), source=Path("test.toml"))
    values.update(overrides)
    return Unit(**values)  # type: ignore[arg-type]


def make_load(peak: float = 8.0, mean: float | None = 8.0, mean_speed: float = 35 * RPM,
              max_speed: float | None = None, static: float | None = None) -> CycleLoad:
    return CycleLoad(peak_torque=peak, mean_torque=mean, mean_speed=mean_speed,
                     max_speed=mean_speed if max_speed is None else max_speed,
                     moving_time=1.0, cycle_time=1.0, static_torque=static)


def whole_cycle(path: Path, folder: Path) -> Path:
    """`path`'s motion with its payload events taken out (its parts carried the whole
    cycle), written into `folder` with its robot file's path made absolute."""
    text = re.sub(r"(?m)^\s*(attach|release)\s*=.*\n", "", path.read_text())
    text = re.sub(r'(?m)^robot\s*=\s*"([^"]*)"',
                  lambda m: f'robot = "{(path.parent / m.group(1)).resolve()}"', text)
    out = folder / path.name
    out.write_text(text)
    return out
