"""Benchmarks of hdselect, each figure against a baseline measured in the same run.

Usage: ``python benchmarks/run.py [--quick] [--json FILE]`` (see benchmarks/README.md).

Every figure is the median of several repeats after a warm-up; candidate and
baseline calls alternate so that drift of the machine's speed hits both alike.
Targets are reported, never enforced: the exit status is nonzero only when a
row crashes or a correctness check (e.g. a maximum difference) fails.
To add a row, append a `Benchmark` in `benchmarks()`.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import importlib.metadata
import json
import os
import platform
import statistics
import subprocess
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
ROBOT = ROOT / "robots" / "benchtop6.urdf"
MOTION = ROOT / "trajectories" / "benchtop6_pick_place.toml"
CONTOUR = ROOT / "trajectories" / "benchtop6_contour.toml"
"""The shipped 6-axis TOPPRA motion."""
FAST_PICK = ROOT / "trajectories" / "benchtop6_fast_pick.toml"
"""The shipped 6-axis co-design motion (its limits at the arm's own)."""
SPEC = ROOT / "trajectories" / "envelopes" / "benchtop6_dispensing.toml"
"""The shipped 6-axis envelope file (its duty: the contour motion)."""
INSPECT = ROOT / "trajectories" / "benchtop6_inspect.toml"
"""The shipped 6-axis inspection sweep (the mix's second task)."""
POSES = ROOT / "trajectories" / "benchtop6_pick_place_poses.toml"
"""The shipped tool-pose motion (8 poses, 4 straight lines)."""
IK_TARGETS = 200
"""Random reachable poses of the IK row (50 in --quick mode)."""

QUICK_SAMPLES = 1_500
"""Samples per trajectory in --quick mode (the full mode uses the ~10,000 of the cycle); at
1,000 the shortest move (0.4 s) would get fewer than the 50 samples planning requires."""
QUICK_REPEATS = 3
"""Repeats of every row in --quick mode."""
HEAVY = ("pinocchio", "toppra", "scipy", "matplotlib", "ruckig", "numpy", "rich", "hdselect")
"""Top-level modules whose import by the CLI is reported."""
FLAGGED = ("toppra", "matplotlib", "scipy", "pinocchio")
"""Modules that `hdselect --help` and `hdselect catalog` should not need."""
SCALE = {"s": 1.0, "ms": 1e3, "us": 1e6}
"""Multiplier from seconds to each display unit."""


@dataclass(frozen=True)
class Check:
    """A correctness check: `run()` returns a value that must not exceed `tolerance`."""

    name: str
    run: Callable[[], float]
    tolerance: float


@dataclass(frozen=True)
class Benchmark:
    """One row of the table.

    Attributes:
        name: Row label.
        candidate: The code under test, called with no arguments.
        baseline: The reference, timed in the same run; None for none.
        target: Upper bound on candidate/baseline (or, with `absolute`, on the
            candidate's figure in `unit`); None for an informative row.
        unit: Display unit, a key of `SCALE`.
        per: Divide times by this (the sample count for per-sample figures).
        per_label: Name of what `per` counts, e.g. "sample".
        notes: One line of context for the table (or what gives it after the timing).
        check: Optional correctness check; the run fails when it fails.
        absolute: Whether `target` bounds the candidate's figure itself.
        repeats: Timed repeats in full mode (after one warm-up call).
        load: Print the machine's load average over the row's run (rows that need idle
            cores).
    """

    name: str
    candidate: Callable[[], object]
    baseline: Callable[[], object] | None
    target: float | None
    unit: str = "ms"
    per: int = 1
    per_label: str = ""
    notes: str | Callable[[], str] = ""
    check: Check | None = None
    absolute: bool = False
    repeats: int = 21
    load: bool = False


def machine() -> dict[str, Any]:
    """CPU, cores and library versions of this run."""
    import pinocchio

    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        cpu = platform.processor() or "unknown"
    affinity = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    env = {key: os.environ[key] for key in ("OPENBLAS_CORETYPE", "OMP_NUM_THREADS",
                                             "OPENBLAS_NUM_THREADS", "OMP_WAIT_POLICY")
           if key in os.environ}
    return {
        "cpu": cpu,
        "cpu_count": os.cpu_count(),
        "usable_cores": affinity,
        "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "pinocchio": pinocchio.__version__,
        "ruckig": _version("ruckig"),
        "hdselect": _version("hdselect"),
        "platform": platform.platform(),
        "environment": env,
    }


def _version(package: str) -> str:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


# --- fixtures -------------------------------------------------------------------------


def _every(n_total: int, quick: bool) -> int:
    """Stride that leaves about QUICK_SAMPLES samples in quick mode (1 in full mode)."""
    return max(1, n_total // QUICK_SAMPLES) if quick else 1


def _rnea_loop(robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Baseline inverse dynamics: one `pinocchio.rnea` call per sample [N m], (n, dof)."""
    import pinocchio as pin

    model = robot.model
    data = model.createData()
    config = robot.configuration(q)
    out = np.empty((q.shape[0], model.nv))
    for k in range(q.shape[0]):
        out[k] = pin.rnea(model, data, config[:, k], qd[k], qdd[k])
    return out


def _longest_ruckig_move(motion):
    """The longest of the motion's waypoint-to-waypoint Ruckig moves (6-DOF, rest to rest)."""
    import ruckig

    dof = len(motion.joint_names)
    best = None
    for start, end in zip(motion.waypoints[:-1], motion.waypoints[1:], strict=True):
        if np.array_equal(start, end):
            continue
        inp = ruckig.InputParameter(dof)
        inp.current_position, inp.target_position = start.tolist(), end.tolist()
        inp.max_velocity = motion.velocity_limit.tolist()
        inp.max_acceleration = motion.acceleration_limit.tolist()
        inp.max_jerk = motion.jerk_limit.tolist()
        traj = ruckig.Trajectory(dof)
        ruckig.Ruckig(dof).calculate(inp, traj)
        if best is None or traj.duration > best.duration:
            best = traj
    if best is None:
        raise RuntimeError(f"{MOTION}: no move between distinct waypoints")
    return best


def _sample_at_time(move, times: np.ndarray):
    """The baseline of the sampling row: Ruckig's own ``at_time``, one call per sample."""
    states = [move.at_time(float(time)) for time in times]
    shape = (len(states), move.degrees_of_freedom)
    return tuple(np.array([s[i] for s in states]).reshape(shape) for i in range(3))


def _max_difference(a, b) -> float:
    return max(float(np.max(np.abs(np.asarray(x) - np.asarray(y)))) for x, y in zip(a, b,
                                                                                  strict=True))


def benchmarks(quick: bool) -> list[Benchmark]:
    """Every row, with its fixtures built (imports and planning happen here, untimed)."""
    from hdselect import Options, Payload, load_case, plan, size, size_trajectory
    from hdselect.catalog.catalogfile import load_catalog
    from hdselect.motion.planning.ruckig import sample_profiles
    from hdselect.robot.dynamics import inverse_dynamics, torque_floor

    robot, motion = load_case(MOTION, ROBOT)
    full = plan(robot, motion)
    step = _every(len(full.t), quick)
    traj = full if step == 1 else replace(
        full, dt=full.dt * step, t=full.t[::step], q=full.q[::step], qd=full.qd[::step],
        qdd=full.qdd[::step])
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    n = len(traj.t)
    units = load_catalog()
    coupled, uncoupled = Options(), Options(mass_coupling=False)
    unloaded = Options(bearing_loads=False)
    motion_for_size = motion if step == 1 else replace(motion, dt=motion.dt * step)
    payloads = [Payload(0.1 * (k + 1), (0.0, 0.0, 0.03), frame="tool0") for k in range(10)]

    from hdselect.catalog.motors import load_motors

    motor_catalog = load_motors(ROOT / "motors" / "example_motors.toml")
    motors = {name: motor_catalog for name in robot.sized_joints}
    pairs = len(units) * len(motor_catalog)

    def sweep_core() -> None:
        for payload in payloads:
            size_trajectory(robot.with_payload(payload), traj, units, coupled)

    def sweep_size() -> None:
        for payload in payloads:
            size(ROBOT, motion_for_size, catalog=units, payload=payload)

    move = _longest_ruckig_move(motion)
    grid = np.linspace(0.0, move.duration, QUICK_SAMPLES if quick else 10_000)

    def rnea_loop() -> np.ndarray:
        return _rnea_loop(robot, q, qd, qdd)

    def batched() -> np.ndarray:
        return inverse_dynamics(robot, q, qd, qdd)

    floor = torque_floor(robot)  # torques below it are rounding, and the sizing takes 0

    def uncoupled_torque_error() -> float:
        joints = size_trajectory(robot, traj, units, uncoupled).joints
        reference = rnea_loop()
        reference[np.abs(reference) < floor] = 0.0
        return max(float(np.max(np.abs(joint.torque - reference[:, robot.joint_index(joint.name)])))
                   for joint in joints)

    def wrench_torque_error() -> float:
        """The bearing pass's axis row against the sizing's own torques [N m]."""
        errors = [0.0]
        for joint in size_trajectory(robot, traj, units, coupled).joints:
            if joint.wrench is not None:
                axis = joint.wrench.full()[5]
                axis = np.where(np.abs(axis) < floor[robot.joint_index(joint.name)], 0.0, axis)
                errors.append(float(np.max(np.abs(axis - joint.torque))))
        return max(errors)

    study_speed, study_workers = _studies(quick)
    from hdselect.study import run_study

    samples = f"{n:,} samples of {MOTION.name}" + (f" (every {step}th)" if step > 1 else "")
    codesign = _codesign_rows(quick, units, rnea_loop_for=_rnea_loop)
    tool_poses = _tool_pose_rows(quick)
    long_cycles = _long_cycle_rows(quick, units)
    cli = [sys.executable, "-m", "hdselect.cli"]
    return [
        Benchmark(
            "inverse dynamics", batched, rnea_loop, 0.33, unit="us", per=n,
            per_label="sample",
            notes=f"inverse_dynamics vs Python loop of pin.rnea; {samples}",
            check=Check("max |tau - loop| [N m]", lambda: _max_difference([batched()],
                                                                           [rnea_loop()]), 1e-9)),
        Benchmark(
            "ruckig sampling",
            lambda: sample_profiles(move, grid),
            lambda: _sample_at_time(move, grid), 0.2, unit="us", per=grid.size,
            per_label="sample",
            notes=f"sample_profiles vs at_time per sample; {grid.size:,} times over the longest "
                  f"move ({move.duration:.3g} s)",
            check=Check("max |profiles - at_time|", lambda: _max_difference(
                sample_profiles(move, grid), _sample_at_time(move, grid)), 1e-9)),
        Benchmark(
            "sizing (coupled)",
            lambda: size_trajectory(robot, traj, units, coupled), rnea_loop, 0.8,
            notes=f"size_trajectory, {len(units)} units, Options() vs Python loop of pin.rnea; "
                  f"{samples}", repeats=15),
        Benchmark(
            "coupled / uncoupled",
            lambda: size_trajectory(robot, traj, units, coupled),
            lambda: size_trajectory(robot, traj, units, uncoupled), 1.5,
            notes="Options() vs Options(mass_coupling=False)", repeats=15,
            check=Check("uncoupled max |tau - loop| [N m]", uncoupled_torque_error, 1e-9)),
        Benchmark(
            "size() incl. planning",
            lambda: size(robot, motion_for_size, catalog=units), rnea_loop, None,
            notes="size (plans, then sizes with the file's options) vs the rnea loop",
            repeats=15),
        Benchmark(
            "payload sweep x10", sweep_core, sweep_size, None, repeats=5,
            notes="10 payload masses: one load and one plan, then size_trajectory on "
                  "robot.with_payload(m), vs 10 size() calls from the files (load, plan, size)"),
        *codesign,
        Benchmark(
            "study: grouped vs one by one",
            lambda: run_study(study_speed, workers=0),
            lambda: run_study(study_speed, workers=0, grouping=False), 0.05, unit="ms",
            per=len(study_speed.cases), per_label="case", repeats=3,
            notes=f"{study_speed.title} ({len(study_speed.cases)} cases) in this process: "
                  "from one shared basis vs each case loaded, planned and sized on its own",
            check=Check("rows differ", lambda: float(
                _study_csv(study_speed, True) != _study_csv(study_speed, False)), 0.0)),
        Benchmark(
            "study: 2 workers vs 1",
            lambda: run_study(study_workers, workers=2, grouping=False),
            lambda: run_study(study_workers, workers=1, grouping=False), 0.56, unit="ms",
            per=len(study_workers.cases), per_label="case", repeats=3,
            notes=f"{len(study_workers.cases)} cases each sized on its own, worker processes "
                  "forked from the fork server (started once, at the warm-up) included; the "
                  "target is a throughput of at least 1.8x; needs 2 idle cores",
            load=True),
        Benchmark(
            "cold start: --help", lambda: _process(cli + ["--help"]),
            lambda: _process([sys.executable, "-c", "pass"]), 1.5, unit="s", absolute=True,
            notes="whole process, python -m hdselect.cli --help vs python -c pass", repeats=9),
        Benchmark(
            "cold start: catalog", lambda: _process(cli + ["catalog"]),
            lambda: _process([sys.executable, "-c", "pass"]), 1.5, unit="s", absolute=True,
            notes="whole process, python -m hdselect.cli catalog vs python -c pass", repeats=9),
        Benchmark(
            "sizing with motors",
            lambda: size_trajectory(robot, traj, units, coupled, motors=motors),
            lambda: size_trajectory(robot, traj, units, coupled), len(motor_catalog) / 2,
            notes=f"{pairs} (gearhead, motor) pairs per joint ({len(motor_catalog)} example "
                  f"motors) vs {len(units)} units alone, Options(); target: half the motor "
                  "count", repeats=9),
        *tool_poses,
        Benchmark(
            "bearing loads in a sizing",
            lambda: size_trajectory(robot, traj, units, coupled),
            lambda: size_trajectory(robot, traj, units, unloaded), 1.3,
            notes="Options() (every sized joint's force and moment along the cycle, its output "
                  "bearing's loads) vs Options(bearing_loads=False), the sizing without them",
            repeats=21,
            check=Check("max |wrench axis row - torque| [N m]", wrench_torque_error, 1e-9)),
        _mix_row(quick, units, coupled),
        _envelope_row(robot, motion_for_size, units),
        *long_cycles,
        _precision_row(robot, traj),
    ]


def _precision_row(robot, traj) -> Benchmark:
    """A sizing with the precision figures against the same without them (SHG-2UH, K1 rated)."""
    from hdselect import Options, size_trajectory
    from hdselect.catalog.catalogfile import load_catalog

    rated = load_catalog(["shg-2uh"], series=["shg-2uh"])
    on, off = Options(), Options(precision=False)

    def chosen_differ() -> float:
        """The figures are computed after the selection: they must not change it."""
        with_figures = size_trajectory(robot, traj, rated, on)
        without = size_trajectory(robot, traj, rated, off)
        if with_figures.precision is None or with_figures.precision.tool is None:
            return 1.0
        return float(sum(a.selected is None or b.selected is None
                         or a.selected.unit.id != b.selected.unit.id
                         for a, b in zip(with_figures.joints, without.joints, strict=True)))

    return Benchmark(
        "precision figures in a sizing",
        lambda: size_trajectory(robot, traj, rated, on),
        lambda: size_trajectory(robot, traj, rated, off), 1.3, repeats=15,
        notes=f"Options() with {len(rated)} SHG-2UH units (each joint's twist and f_n, the "
              "tool's deflection, the arm's modes) vs Options(precision=False)",
        check=Check("units chosen differ, or no tool deflection", chosen_differ, 0.0))


def _mix_row(quick: bool, units, options) -> Benchmark:
    """A two-task mix (pick 70 %, inspect 30 %) against the two tasks sized apart."""
    from hdselect import load_case, plan, size_trajectory
    from hdselect.sizing.core import size_tasks
    from hdselect.sizing.tasks import Task

    tasks = []
    for path, share in ((MOTION, 0.7), (INSPECT, 0.3)):
        robot, motion = load_case(path, ROBOT)
        full = plan(robot, motion)
        step = _every(len(full.t), quick)
        traj = full if step == 1 else replace(
            full, dt=full.dt * step, t=full.t[::step], q=full.q[::step], qd=full.qd[::step],
            qdd=full.qdd[::step])
        tasks.append(Task(robot, traj, share, motion, path.stem))
    count = sum(len(task.trajectory.t) for task in tasks)

    def apart() -> None:
        for task in tasks:
            size_trajectory(task.robot, task.trajectory, units, options)

    def alone_error() -> float:
        """A mix of shares (1, 0) against the first task sized alone: must be 0."""
        mixed = size_tasks((replace(tasks[0], share=1.0), replace(tasks[1], share=0.0)),
                           units, options)
        single = size_trajectory(tasks[0].robot, tasks[0].trajectory, units, options)
        return max(abs(a.selected.checks[r].utilization - b.selected.checks[r].utilization)
                   for a, b in zip(mixed.joints, single.joints, strict=True)
                   for r in a.selected.checks)

    return Benchmark(
        "two-task mix", lambda: size_tasks(tasks, units, options), apart, 1.1,
        repeats=9,
        notes=f"size_tasks of pick (70 %) and inspect (30 %), {count:,} samples, each joint's "
              "unit also checked per task, vs size_trajectory of each task apart, summed",
        check=Check("shares (1, 0) vs alone: max |utilization difference|", alone_error, 0.0))


def _envelope_row(robot, motion, units) -> Benchmark:
    """The whole envelope of the shipped 6-axis spec, against size() of its pick-and-place."""
    from hdselect import envelope, size

    found: list = []

    def run() -> None:
        found[:] = [envelope(SPEC, catalog=units)]

    def shortfall() -> float:
        result = found[0] if found else envelope(SPEC, catalog=units)
        return float(result.states < 100_000 or not result.converged)

    return Benchmark(
        "envelope (6-axis)", run, lambda: size(robot, motion, catalog=units), 10.0, unit="s",
        absolute=True, repeats=3,
        notes=f"hdselect.envelope of {SPEC.name}: 6 joints x {len(units)} units, every "
              "joint's worst states over the limit box (>= 1e5 states), the contour duty "
              f"planned and sized alone, vs size() of {MOTION.name}; target: under 10 s",
        check=Check("fewer than 1e5 states, or not converged", shortfall, 0.0))


def _codesign_rows(quick: bool, units, rnea_loop_for) -> list[Benchmark]:
    """TOPPRA planning, and co-design on the shipped 6-axis arm (fixtures built here)."""
    import toppra
    import toppra.algorithm as algorithm
    import toppra.constraint as constraint

    from hdselect import compare_ratios, fastest, load_case, plan, size
    from hdselect.motion.planning.toppra import path_pieces

    robot, motion = load_case(CONTOUR)
    velocity, acceleration = motion.velocity_limit, motion.acceleration_limit
    pieces = [p for p in path_pieces(robot, motion) if p.path is not None]
    knots = [(p.knots, motion.waypoints[list(p.waypoints)], p.gridpoints) for p in pieces]

    def plain_toppra() -> float:
        """toppra as its examples call it: spline, constraints, TOPPRA, trajectory."""
        duration = 0.0
        for ss, waypoints, grid in knots:
            path = toppra.SplineInterpolator(ss, waypoints, bc_type="clamped")
            limits = [constraint.JointVelocityConstraint(np.column_stack([-velocity, velocity])),
                      constraint.JointAccelerationConstraint(
                          np.column_stack([-acceleration, acceleration]),
                          discretization_scheme=constraint.DiscretizationType.Interpolation)]
            found = algorithm.TOPPRA(limits, path, parametrizer="ParametrizeConstAccel",
                                     gridpoints=grid).compute_trajectory()
            duration += found.duration
        return duration

    planned = plan(robot, motion)

    def contour_loop() -> np.ndarray:
        return rnea_loop_for(robot, planned.q, planned.qd, planned.qdd)

    def plan_gap() -> float:
        """Relative excess of plan's moving time over toppra's (its overshoot slow-down)."""
        moving = planned.duration - float(np.sum(motion.dwells))
        return moving / plain_toppra() - 1.0

    fast_robot, fast_motion = load_case(FAST_PICK)
    joints = ["shoulder_pan"] if quick else None
    comparisons = len(units) * (1 if quick else len(fast_robot.sized_joints))
    first = fastest(fast_robot, fast_motion)

    def infeasible() -> float:
        return 0.0 if first.feasible else 1.0

    gridpoints = sum(len(p.gridpoints) for p in pieces)
    solved = _gridpoints_solved(robot, motion)
    return [
        Benchmark(
            "plan (TOPPRA) vs toppra", lambda: plan(robot, motion), plain_toppra, 1.5,
            notes=f"plan of {CONTOUR.name} ({len(motion.waypoints)} waypoints; {solved} "
                  "gridpoints solved, refined where a limit is broken between them) vs the plain "
                  "toppra call (SplineInterpolator, velocity and acceleration constraints, "
                  f"TOPPRA, ParametrizeConstAccel) on the same path and {gridpoints} gridpoints "
                  "(200 per waypoint, the planner's grid before it refined)", repeats=9,
            check=Check("plan's moving time over toppra's, minus 1", plan_gap, 1e-3)),
        Benchmark(
            "size() of the TOPPRA motion", lambda: size(robot, motion, catalog=units),
            contour_loop, 3.0, repeats=9,
            notes=f"size() of {CONTOUR.name} (plans with TOPPRA, then sizes) vs the Python loop "
                  f"of pin.rnea over its {len(planned.t):,} samples"),
        Benchmark(
            "fastest (6-axis, torques)", lambda: fastest(fast_robot, fast_motion),
            lambda: size(fast_robot, fast_motion, catalog=units), 1.0, unit="s", absolute=True,
            repeats=5,
            notes=f"fastest on {FAST_PICK.name} with size's units (that selection included) vs "
                  "size() of the motion as planned",
            check=Check("fastest's result fails a rule", infeasible, 0.0)),
        Benchmark(
            f"compare ratios ({comparisons} units x joints)",
            lambda: compare_ratios(fast_robot, fast_motion, joints=joints),
            lambda: fastest(fast_robot, fast_motion), 5.0, unit="s", absolute=True, repeats=3,
            notes=f"--compare-ratios on {FAST_PICK.name}, {comparisons} unit-joint "
                  "configurations sharing one path model, vs one fastest() call"),
    ]


def _gridpoints_solved(robot, motion) -> int:
    """Gridpoints TOPPRA solves when `plan` plans the motion (every round of refinement)."""
    import hdselect.motion.planning.toppra as planner

    count = [0]
    solve = planner.solve_piece

    def counted(piece, constraints, *, where):
        count[0] += len(piece.gridpoints)
        return solve(piece, constraints, where=where)

    planner.solve_piece = counted
    try:
        from hdselect import plan

        plan(robot, motion)
    finally:
        planner.solve_piece = solve
    return count[0]


LONG_WAYPOINTS = 65
"""Waypoints of the long benchtop6 motion whose log the max-payload row reads (70 s)."""


def _long_log(folder: Path, quick: bool) -> Path:
    """A long log (69,877 samples at 1 ms; 5,170 in quick mode): a benchtop6 motion
    through random waypoints with dwells, planned with Ruckig and written as
    ``hdselect plan --out`` writes it, and a motion file that reads it.

    Seed 1: the waypoints of seeds 0, 2, 3 and 4 each hold a move Ruckig 0.19.4 cannot
    compute ("error in step 1", a numerical failure of its own on ordinary inputs).
    """
    from hdselect import load_case, plan
    from hdselect.report.export import write_trajectory_csv
    from hdselect.robot.dynamics import inverse_dynamics

    rng = np.random.default_rng(1)
    lines = [f'robot = "{ROBOT}"', 'planner = "ruckig"', 'angle_unit = "deg"', "dt = 0.001",
             "[payload]", "mass = 0.5", "com = [0.0, 0.0, 0.03]", 'frame = "tool0"',
             "[limits]", "velocity = 120", "acceleration = 600", "jerk = 6000"]
    low, high = np.array([-60, -80, 70, -150, 70, -90]), np.array([60, -30, 110, -90, 110, 90])
    for _ in range(LONG_WAYPOINTS // (10 if quick else 1)):
        q = np.round(rng.uniform(low, high), 1)
        lines += ["[[waypoint]]", f"q = {q.tolist()}",
                  f"dwell = {rng.choice([0.0, 0.0, 0.2, 0.5])}"]
    planned = folder / "long.toml"
    planned.write_text("\n".join(lines) + "\n")
    robot, motion = load_case(planned)
    trajectory = plan(robot, motion)  # written as `hdselect plan --out` writes it
    write_trajectory_csv(folder / "long.csv", trajectory, inverse_dynamics(
        robot, trajectory.q, trajectory.qd, trajectory.qdd), robot.joint_names)
    logged = folder / "long_log.toml"
    logged.write_text(f'robot = "{ROBOT}"\nplanner = "samples"\nangle_unit = "rad"\n'
                      'dt = 0.001\n[payload]\nmass = 0.5\ncom = [0.0, 0.0, 0.03]\n'
                      'frame = "tool0"\n[samples]\nfile = "long.csv"\n')
    return logged


def _derating_case(folder: Path) -> Path:
    """benchtop6_fast_pick.toml with 1 kg, 150,000 h and short dwells: the whole-cycle rules
    bind on most unit-joint configurations, so `fastest` derates them."""
    text = FAST_PICK.read_text().replace('"../robots/', f'"{ROOT}/robots/')
    text = text.replace("dwell = 3.0", "dwell = 0.2").replace("dwell = 1.5", "dwell = 0.1")
    text = text.replace("life_hours = 20000", "life_hours = 150000")
    text = text.replace("mass = 0.5                  # kg", "mass = 1.0                  # kg")
    path = folder / "derating.toml"
    path.write_text(text)
    return path


def _long_cycle_rows(quick: bool, units) -> list[Benchmark]:
    """max-payload on a long log, and compare-ratios where derating binds (fixtures here)."""
    import tempfile

    from hdselect import compare_ratios, fastest, load_case, size
    from hdselect.codesign.maxpayload import max_payload

    folder = Path(tempfile.mkdtemp(prefix="hdselect-bench-long-"))
    robot, motion = load_case(_long_log(folder, quick))
    samples = len(size(robot, motion, catalog=units).trajectory.t)
    derate_robot, derate_motion = load_case(_derating_case(folder))
    joints = ["shoulder_pan"] if quick else None
    comparisons = len(units) * (1 if quick else len(derate_robot.sized_joints))
    derated = [0]

    def compared() -> object:
        found = compare_ratios(derate_robot, derate_motion, joints=joints)
        derated[0] = sum(row.derating is not None for j in found.joints for row in j.rows)
        return found

    def exact_mass() -> float:
        """How far the largest payload is from where `size` changes its verdict [-]."""
        found = max_payload(robot, motion)
        assert found.mass is not None and found.payload is not None
        inside = size(robot, motion, catalog=units, payload=replace(
            found.payload, mass=found.mass * (1 - 1e-6))).feasible
        outside = size(robot, motion, catalog=units, payload=replace(
            found.payload, mass=found.mass * (1 + 1e-6))).feasible
        return 0.0 if inside and not outside else 1.0

    rows = [
        Benchmark(
            "max-payload on a long log", lambda: max_payload(robot, motion),
            lambda: size(robot, motion, catalog=units), 3.0, repeats=3,
            notes=f"max_payload of a {samples:,}-sample log (a {LONG_WAYPOINTS}-waypoint "
                  "benchtop6 motion written by plan --out) vs size() of the same log",
            check=Check("max-payload's mass not at size's verdict change (+-1e-6)",
                        exact_mass, 0.0)),
        Benchmark(
            f"compare ratios, derating ({comparisons} units x joints)", compared,
            lambda: fastest(derate_robot, derate_motion), 5.0, unit="s", absolute=True,
            repeats=1,
            notes=lambda: f"--compare-ratios on {FAST_PICK.name} with 1 kg, life 150,000 h "
                          "and short dwells, where the whole-cycle rules make most rows derate "
                          f"({derated[0]} of {comparisons}), vs one fastest()"),
    ]
    return rows


def _tool_pose_rows(quick: bool) -> list[Benchmark]:
    """Inverse kinematics of one pose, and a tool-pose motion solved (fixtures built here)."""
    import pinocchio as pin

    from hdselect import load_robot
    from hdselect.ik.poses import Tolerance, pose_error
    from hdselect.ik.solver import solve_pose
    from hdselect.motion.motionfile import load_motion
    from hdselect.motion.planning import plan, plan_motion
    from hdselect.motion.planning.solve import solve_motion
    from hdselect.robot.kinematics import FrameKinematics

    kin = FrameKinematics(load_robot(ROBOT), "tool0")
    rng = np.random.default_rng(0)
    lower, upper = np.maximum(kin.lower, -np.pi), np.minimum(kin.upper, np.pi)
    truths = rng.uniform(lower, upper, (50 if quick else IK_TARGETS, kin.dof))
    targets = [kin.placement(q) for q in truths]
    seeds = [kin.clip(q + rng.normal(0.0, 0.1, kin.dof)) for q in truths]
    tolerance = Tolerance()

    def solved() -> list:
        return [solve_pose(kin, t, s) for t, s in zip(targets, seeds, strict=True)]

    def textbook() -> list:
        """Pinocchio's clik example: damped least squares, fixed damping, no limits."""
        out = []
        for target, q in zip(targets, seeds, strict=True):
            q = q.copy()
            for _ in range(1000):
                current = kin.placement(q)
                error = pin.log6(current.actInv(target)).vector
                if tolerance.scaled(0.1).holds(*pose_error(current, target)):
                    break
                jacobian = -pin.Jlog6(target.actInv(current)) @ kin.jacobian(q)
                q = q - jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + 1e-12 * np.eye(6),
                                                     error)
            out.append(q)
        return out

    def worst_error() -> float:
        """Largest pose error of a solution over its tolerance (>1: failed) [-]."""
        return max(max(r.position_error / tolerance.position,
                       r.orientation_error / tolerance.orientation, 0.0 if r.converged else 2.0)
                   for r in solved())

    robot = load_robot(ROBOT)
    motion = load_motion(POSES, robot)
    robot = robot.with_payload(motion.payload)
    solved_motion = solve_motion(robot, motion)

    def line_deviation() -> float:
        """The planned tool's largest distance from a line over the tolerance [-]."""
        lines = plan_motion(robot, solved_motion).lines
        return max(float(d.position.max()) for d in lines) / tolerance.position

    return [
        Benchmark(
            "IK: one pose", solved, textbook, 2.0, unit="ms", per=len(targets),
            per_label="pose", repeats=5,
            notes=f"solve_pose on {len(targets)} random reachable benchtop6 poses from seeds "
                  "0.1 rad away (limits, active set) vs Pinocchio's clik example (fixed "
                  "damping, no limits) on the same poses and seeds",
            check=Check("largest error / tolerance", worst_error, 1.0)),
        Benchmark(
            "tool poses: solve vs plan", lambda: solve_motion(robot, motion),
            lambda: plan(robot, solved_motion), 1.5, repeats=5,
            notes=f"solve_motion of {POSES.name} (8 poses, 4 lines fitted to TOPPRA's spline) "
                  "vs planning the solved motion",
            check=Check("planned line deviation / tolerance", line_deviation, 1.0)),
    ]


def _studies(quick: bool):
    """The 10 x 10 payload x speed study (fewer, shorter cases in quick mode), and one to split."""
    import tempfile

    from hdselect.study import load_study

    folder = Path(tempfile.mkdtemp(prefix="hdselect-bench-"))
    motion = folder / "motion.toml"
    text = MOTION.read_text().replace('robot = "../robots/', f'robot = "{ROOT}/robots/')
    motion.write_text(text.replace("dt = 0.001", "dt = 0.005") if quick else text)
    payloads = "[0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5]"
    scales = "[0.9, 0.95, 1.0, 1.05, 1.1, 1.15, 1.2, 1.3, 1.4, 1.5]"
    if quick:
        payloads, scales = "[0.5, 1.0, 1.5, 2.0]", "[0.9, 1.0, 1.2]"
    speed = folder / "speed.toml"
    speed.write_text(f'title = "benchtop6 payload x speed"\n[base]\nmotion = "{motion}"\n'
                     f"[grid]\npayload = {payloads}\ntime_scale = {scales}\n")
    workers = folder / "workers.toml"
    workers.write_text(f'[base]\nmotion = "{motion}"\n[grid]\n'
                       f"payload = {'[0.5, 1.0]' if quick else '[0.5, 1.0, 1.5, 2.0]'}\n"
                       "time_scale = [1.0, 1.1, 1.2, 1.3, 1.4, 1.5]\n")
    return load_study(speed), load_study(workers)


def _study_csv(study, grouping: bool) -> str:
    """The CSV rows a study gives, grouped or each case on its own."""
    from hdselect.study import run_study
    from hdselect.study.store import csv_text

    return csv_text(study, run_study(study, workers=0, grouping=grouping).records)


def _process(command: list[str]) -> None:
    """Run a command to completion; raise if it fails."""
    done = subprocess.run(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode}: "
                           f"{done.stderr.decode(errors='replace').strip()[-500:]}")


# --- measurement ----------------------------------------------------------------------


def _timed(function: Callable[[], object]) -> float:
    gc.collect()
    enabled = gc.isenabled()
    gc.disable()
    try:
        start = time.perf_counter()
        function()
        return time.perf_counter() - start
    finally:
        if enabled:
            gc.enable()


def run_row(bench: Benchmark, quick: bool) -> dict[str, Any]:
    """Warm up, time candidate and baseline alternately, check; the row's figures."""
    repeats = min(QUICK_REPEATS, bench.repeats) if quick else bench.repeats
    scale = SCALE[bench.unit] / bench.per
    unit = f"{bench.unit}/{bench.per_label}" if bench.per_label else bench.unit
    row: dict[str, Any] = {"name": bench.name, "unit": unit, "repeats": repeats,
                           "notes": bench.notes if isinstance(bench.notes, str) else "",
                           "target": bench.target,
                           "target_on": "candidate" if bench.absolute else "ratio"}
    if bench.load and hasattr(os, "getloadavg"):
        row["load_before"] = list(os.getloadavg())
    try:
        bench.candidate()
        if bench.baseline is not None:
            bench.baseline()
        candidate, baseline = [], []
        for _ in range(repeats):
            candidate.append(_timed(bench.candidate) * scale)
            if bench.baseline is not None:
                baseline.append(_timed(bench.baseline) * scale)
        row["candidate"] = statistics.median(candidate)
        row["candidate_min"] = min(candidate)
        row["candidate_times"] = candidate
        if baseline:
            row["baseline"] = statistics.median(baseline)
            row["baseline_min"] = min(baseline)
            row["baseline_times"] = baseline
            row["ratio"] = row["candidate"] / row["baseline"]
            pairs = sorted(c / b for c, b in zip(candidate, baseline, strict=True))
            row["ratio_range"] = [pairs[0], pairs[-1]]
        figure = row["candidate"] if bench.absolute else row.get("ratio")
        row["met"] = None if bench.target is None or figure is None else figure <= bench.target
        if bench.load and hasattr(os, "getloadavg"):
            row["load_after"] = list(os.getloadavg())
        if callable(bench.notes):
            row["notes"] = bench.notes()
        if bench.check is not None:
            value = float(bench.check.run())
            row["check"] = {"name": bench.check.name, "value": value,
                            "tolerance": bench.check.tolerance,
                            "passed": bool(value <= bench.check.tolerance)}
    except Exception as err:  # a crash fails the run, but the other rows still run
        row["error"] = f"{type(err).__name__}: {err}"
        row["traceback"] = traceback.format_exc()
    return row


_PROBE = """
import contextlib, io, json, sys
from hdselect.cli.main import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        status = main(sys.argv[1:])
    except SystemExit as exit:
        status = exit.code
print(json.dumps({"status": status, "modules": sorted(m for m in sys.modules if "." not in m)}))
"""


def cli_imports(command: list[str]) -> dict[str, Any]:
    """Heavy modules a CLI command imports, and its slowest top-level imports.

    `sys.modules` after ``main(command)`` in a fresh interpreter gives what is
    imported; ``-X importtime`` of ``python -m hdselect.cli`` gives what it costs.
    """
    probe = subprocess.run([sys.executable, "-c", _PROBE, *command], cwd=ROOT,
                           capture_output=True, text=True, check=False)
    if probe.returncode != 0:
        raise RuntimeError(f"import probe of {command} failed: {probe.stderr.strip()[-500:]}")
    found = json.loads(probe.stdout.strip().splitlines()[-1])
    if found["status"] not in (0, None):
        raise RuntimeError(f"hdselect {' '.join(command)} returned {found['status']}")
    heavy = [name for name in HEAVY if name in found["modules"]]
    timing = subprocess.run([sys.executable, "-X", "importtime", "-m", "hdselect.cli", *command],
                            cwd=ROOT, capture_output=True, text=True, check=False)
    cumulative: dict[str, float] = {}
    top: list[tuple[str, float]] = []
    for line in timing.stderr.splitlines():
        if not line.startswith("import time:") or "|" not in line:
            continue
        fields = line.split("|")
        try:
            microseconds = float(fields[1])
        except ValueError:
            continue  # the header line
        raw = fields[2][1:]
        name = raw.strip()
        cumulative.setdefault(name, microseconds / 1e3)
        if raw == name:  # imported at depth 0, by the command itself
            top.append((name, microseconds / 1e3))
    top.sort(key=lambda item: -item[1])
    return {
        "command": command,
        "heavy": heavy,
        "flagged": [name for name in FLAGGED if name in heavy],
        "import_ms": {name: cumulative[name] for name in heavy if name in cumulative},
        "slowest_top_level_ms": dict(top[:6]),
        "total_top_level_ms": sum(ms for _, ms in top),
    }


# --- output ---------------------------------------------------------------------------


def _figure(value: float | None, unit: str) -> str:
    return "-" if value is None else f"{value:.3g} {unit}"


def print_report(info: dict[str, Any], rows: list[dict[str, Any]],
                 imports: list[dict[str, Any]], quick: bool) -> None:
    """The machine, the timing table and the CLI import table, with rich."""
    from rich import box
    from rich.console import Console
    from rich.table import Table

    out = Console(width=None if sys.stdout.isatty() else 120)  # CI logs: no folding at 80
    out.print(f"[bold]hdselect benchmarks[/bold] ({'quick' if quick else 'full'} mode)")
    load = " ".join(f"{x:.2f}" for x in info["load_average"] or [])
    after = " ".join(f"{x:.2f}" for x in info.get("load_average_after") or [])
    out.print(f"CPU: {info['cpu']}; cores: {info['cpu_count']} (usable {info['usable_cores']}); "
              f"load average before {load}, after {after}", highlight=False)
    out.print(f"Python {info['python']}, numpy {info['numpy']}, pinocchio {info['pinocchio']}, "
              f"ruckig {info['ruckig']}, hdselect {info['hdselect']}; {info['platform']}"
              + (f"; env {info['environment']}" if info["environment"] else ""))
    table = Table(box=box.SIMPLE_HEAVY, title="median of repeats; ratio = candidate / baseline")
    for column in ("#", "row", "candidate", "baseline", "ratio", "target", "met", "check"):
        table.add_column(column, justify="right" if column in ("#", "candidate", "baseline",
                                                               "ratio") else "left")
    notes = []
    for number, row in enumerate(rows, 1):
        notes.append(f"{number}. {row['name']}: {row['notes']}; {row['repeats']} repeats")
        if "error" in row:
            table.add_row(str(number), row["name"], "[red]CRASHED[/red]", "", "", "", "", "")
            notes.append(f"   [red]{row['error'][:300]}[/red]")
            continue
        ratio = row.get("ratio")
        ratio_text = "-" if ratio is None else f"{ratio:.3g}"
        if row["target"] is None:
            target = "-"
        elif row["target_on"] == "candidate":
            target = f"<= {row['target']:g} {row['unit']}"
        else:
            target = f"<= {row['target']:g}"
        met = {None: "-", True: "[green]yes[/green]", False: "[red]MISSED[/red]"}[row["met"]]
        check = row.get("check")
        check_text = "" if check is None else (
            f"{'[green]ok[/green]' if check['passed'] else '[red]FAILED[/red]'} "
            f"{check['value']:.2g}")
        if check is not None:
            notes.append(f"   check: {check['name']} = {check['value']:.3g} "
                         f"(tolerance {check['tolerance']:g})")
        if "load_after" in row:
            notes.append("   load average (1, 5, 15 min) at the row's start "
                         + " ".join(f"{x:.2f}" for x in row["load_before"]) + ", at its end "
                         + " ".join(f"{x:.2f}" for x in row["load_after"]))
        if "ratio_range" in row:
            low, high = row["ratio_range"]
            notes.append(f"   ratio of each candidate/baseline pair: {low:.3g} to {high:.3g}")
        table.add_row(str(number), row["name"], _figure(row["candidate"], row["unit"]),
                      _figure(row.get("baseline"), row["unit"]), ratio_text, target, met,
                      check_text)
    out.print(table)
    for line in notes:
        out.print(line, highlight=False)
    if imports:
        modules = Table(box=box.SIMPLE_HEAVY, title="modules imported by cold CLI commands")
        for column in ("command", "heavy modules (cumulative import ms)", "flagged",
                       "slowest top-level imports [ms]"):
            modules.add_column(column, overflow="fold")
        for item in imports:
            if "error" in item:
                modules.add_row(" ".join(item["command"]), "[red]CRASHED[/red]", "",
                                item["error"][:200])
                continue
            heavy = ", ".join(f"{name} ({item['import_ms'].get(name, 0.0):.0f})"
                              for name in item["heavy"])
            flagged = ("[red]" + ", ".join(item["flagged"]) + "[/red]" if item["flagged"]
                       else "[green]none[/green]")
            slowest = ", ".join(f"{name} {ms:.0f}"
                                for name, ms in item["slowest_top_level_ms"].items())
            modules.add_row("hdselect " + " ".join(item["command"]), heavy, flagged, slowest)
        out.print(modules)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmarks; 0 unless a row crashed or a correctness check failed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help=f"smoke run: {QUICK_REPEATS} repeats, ~{QUICK_SAMPLES:,} samples")
    parser.add_argument("--json", metavar="FILE", help="also write every figure to FILE")
    args = parser.parse_args(argv)
    info = machine()
    rows = [run_row(bench, args.quick) for bench in benchmarks(args.quick)]
    imports = []
    for command in (["--help"], ["catalog"]):
        try:
            imports.append(cli_imports(command))
        except Exception as err:  # reported, and fails the run
            imports.append({"command": command, "error": f"{type(err).__name__}: {err}"})
    if hasattr(os, "getloadavg"):
        info["load_average_after"] = list(os.getloadavg())
    print_report(info, rows, imports, args.quick)
    failed = [row["name"] for row in rows if "error" in row or
              not row.get("check", {}).get("passed", True)]
    failed += ["imports of hdselect " + " ".join(item["command"]) for item in imports
               if "error" in item]
    for row in rows:
        if "traceback" in row:
            print(row["traceback"], file=sys.stderr)
    if args.json:
        document = {"mode": "quick" if args.quick else "full", "machine": info, "rows": rows,
                    "cli_imports": imports, "failed": failed}
        Path(args.json).write_text(json.dumps(document, indent=2) + "\n")
    if failed:
        print(f"benchmarks: failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
