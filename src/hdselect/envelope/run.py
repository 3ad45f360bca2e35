"""Size a robot for any motion within its spec: `envelope`, the one entry point.

The worst states depend on the masses carried (the units chosen further out), and
the units on the worst states. So: the duty alone is sized first (what `size` of it
selects); with its units' masses a quick, coarse search and selection guess the
envelope's units (`GUESS`); every joint's worst states are searched with the guessed
masses, and the core selects from the duty's samples and those states
(`hdselect.envelope.torques`); a joint whose carried units changed is searched again
with the new masses, until the units chosen are the ones searched with
(`MAX_ROUNDS`), which makes every reported worst state a worst state of the robot as
finally equipped.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES, expect_type
from hdselect.base.errors import InputError
from hdselect.base.scheduler import DEFAULT_TIMEOUT, timeout_seconds
from hdselect.catalog.select import DEFAULT_PREFER
from hdselect.catalog.units import Unit
from hdselect.envelope.box import Limits
from hdselect.envelope.demands import KINDS
from hdselect.envelope.dutycycle import (
    Duty,
    check_within,
    default_duty,
    duty_source,
    mix_robot,
    mounting_named,
    problem_duty,
    refuse_default_duty,
)
from hdselect.envelope.result import (
    Convergence,
    EnvelopeResult,
    JointEnvelope,
    WorstState,
    envelope_diagnoses,
)
from hdselect.envelope.search import Evaluate, SearchSettings, Worst, agree, search
from hdselect.envelope.spec import Spec, resolve_spec
from hdselect.envelope.specfile import (
    DUTY_MOVES,
    MAX_DUTY_MOVES,
    EnvelopeFile,
    envelope_robot_file,
    load_envelope_file,
    refuse_arm_targets,
)
from hdselect.envelope.states import StateRows, state_rows
from hdselect.envelope.torques import (
    EnvelopeTorques,
    carrying_every_part,
    duty_precision,
    duty_time,
)
from hdselect.envelope.workers import Spread, default_workers
from hdselect.motion.loading import load_case
from hdselect.motion.mixfile import Mix
from hdselect.motion.motionfile import Motion
from hdselect.motion.option_specs import given_by
from hdselect.robot.dynamics import gravity_torques
from hdselect.robot.model import Robot, load_robot
from hdselect.robot.mounting import Mounting
from hdselect.robot.payload import Payload
from hdselect.sizing.arguments import OptionValues, options_argument, units_as_catalog
from hdselect.sizing.core import added_mass, decimated_task, select_units, size_problem
from hdselect.sizing.options import Options
from hdselect.sizing.problem import (
    Catalog,
    Problem,
    catalog_argument,
    catalog_units,
    plan_tasks,
    problem_of,
    source_options,
)
from hdselect.sizing.result import JointSizing, SizingResult

if TYPE_CHECKING:
    from typing_extensions import Unpack

MAX_ROUNDS = 5
"""Most searches with new carried masses before the result says they did not settle."""
GUESS = SearchSettings(starts=256, refine=2, rounds=0, iterations=30)
"""The quick search whose selection gives the full search its first carried masses."""
GUESS_SAMPLES = 2000
"""Duty samples the quick selection is judged on."""


def envelope(
    robot: Robot | str | Path | None = None,
    spec: str | Path | None = None,
    *,
    velocity: Limits = None,
    acceleration: Limits = None,
    jerk: Limits = None,
    payload: Payload | None = None,
    mounting: Mounting | None = None,
    joints: Sequence[str] | None = None,
    exclude: Sequence[str] | None = None,
    duty: Motion | Mix | str | Path | None = None,
    moves: int | None = None,
    seed: int | None = None,
    catalog: Catalog | None = (),
    settings: SearchSettings | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    options: Options | None = None,
    units: Sequence[Unit] | None = None,
    **values: Unpack[OptionValues],
) -> EnvelopeResult:
    """The unit per joint that holds for any motion within a spec, and the worst states.

    Args:
        robot: Robot file or loaded robot; None takes the envelope file's ``robot``. An
            envelope file (``.toml``) here, with no `spec`, is the spec.
        spec: An envelope file (TOML): limits, payload, mounting, duty, options.
        velocity: Speed limits [rad/s or m/s]: one number, one per joint, or a mapping of
            joint names (the rest from the file, else the robot file).
        acceleration: Acceleration limits [rad/s^2 or m/s^2], as `velocity` (no default).
        jerk: Jerk limits of the default duty's moves [rad/s^3 or m/s^3], as `velocity`;
            like `moves` and `seed`, refused where the duty is a motion file.
        payload: Payload, overriding the file's (and the duty's; a mix's tasks keep theirs).
        mounting: Mounting, overriding the file's (and the duty's).
        joints: Joints to size (default: the file's, the duty's, else every rotary joint).
        exclude: Joints not to size; they still move and load the others.
        duty: A motion or mix file (or Motion, Mix) for the averaged rules (a mix's tasks
            pooled by share, as `size` pools them); None: the file's, else random moves.
        moves: Moves of the default duty (default: the file's, else `DUTY_MOVES`).
        seed: Seed of the default duty's poses (default: the file's, else 0).
        catalog: Extra catalog files (the built-in PSA-G catalog is always loaded), or the
            units already loaded.
        settings: How hard the search looks (default `SearchSettings()`).
        workers: Compute the search's quasi-random states in this many worker processes
            (with `scheduler`, Dask workers; default there: the cores here); None computes
            them in this process, on every core.
        scheduler: ``"local"`` for a Dask LocalCluster here, ``"tcp://HOST:PORT"`` for a
            running Dask scheduler (checked before any work, and asked for Dask's greeting
            before it is used); None for none.
        timeout: The time limit of connecting to the scheduler [s], at most a day.
        options: The assumptions as a whole (the files' are not read); not with `values`.
        units: Deprecated: the loaded catalog, now given as `catalog`.
        **values: Fields of `hdselect.sizing.options.Options` (``stop_time``,
            ``efficiency``, ``rotor_inertia``, ``motor_mass``, ``mass_coupling``, ``prefer``,
            ``life_hours``, ``life_basis``, ``margin``, ``bearing_offset``,
            ``bearing_loads``, ``threads``, ``max_samples``); what is not given comes from
            the envelope file, the duty's motion file, else the defaults. The output
            bearings' largest loads are over the duty and the worst states, their means
            over the duty (`hdselect.envelope.torques.BEARING_NOTE`).

    Returns:
        The envelope.

    Raises:
        InputError: A file or argument is invalid, no acceleration limit is given, an
            argument of the default duty is given beside a motion duty, or the duty leaves
            the spec.
        PlanningError: The duty cannot be planned.
    """
    started = time.perf_counter()
    timeout = timeout_seconds(timeout, "timeout")
    spread = (None if workers is None and scheduler is None else
              Spread(workers if workers is not None else default_workers(), scheduler, timeout))
    expect_type(robot, (Robot, str, Path, type(None)), "robot", "a Robot, a robot file or None")
    options_argument(options, values)
    expect_type(spec, (str, Path, type(None)), "spec", "an envelope file or None")
    expect_type(duty, (Motion, Mix, str, Path, type(None)), "duty", "a Motion, Mix, file or None")
    expect_type(settings, (SearchSettings, type(None)), "settings", "a SearchSettings or None")
    for name, value, low, high in (("moves", moves, 1, MAX_DUTY_MOVES),
                                   ("seed", seed, 0, 2**63 - 1)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                                  or not low <= value <= high):
            raise InputError(f"must be a whole number in [{low}, {high}], got {value!r}",
                             field=name)
    if units is not None:
        catalog = units_as_catalog(units, catalog, "envelope")
    catalog = catalog_argument(catalog)  # checked before any file is read
    if spec is None and isinstance(robot, str | Path) and Path(robot).suffix.lower() == ".toml":
        robot, spec = None, robot  # an envelope file alone: it names its robot
    if robot is None and spec is None:
        raise InputError("give a robot file, or an envelope file that names one", field="robot")
    base = robot if isinstance(robot, Robot) else load_robot(
        robot if robot is not None else envelope_robot_file(str(spec)))
    file = load_envelope_file(spec, base) if spec is not None else None
    source = duty_source(duty, file, base)
    if source is not None:
        refuse_default_duty(duty, file, moves=moves, seed=seed, jerk=jerk)
    filed = mounting is None and file is not None and file.mounting is not None
    mounting = mounting if mounting is not None else (file.mounting if file else None)
    with mounting_named(file if filed else None):
        robot, source = _robot_state(base, source, file, payload, mounting, joints, exclude)
    limits = resolve_spec(robot, velocity=velocity, acceleration=acceleration, jerk=jerk,
                          file=file)
    resolved = options if options is not None else _options(file, source, values)
    refuse_arm_targets(resolved, values if options is None else vars(options), file, source)
    if source is None:
        problem = Problem(robot, None, catalog_units(catalog), resolved, {})
        chosen_duty = default_duty(
            robot, limits, _first(moves, file.moves if file else None, DUTY_MOVES),
            _first(seed, file.seed if file else None, 0), max_samples=resolved.max_samples)
        problem = replace(problem, tasks=chosen_duty.tasks)
    else:  # the one resolver: the duty's units, options, motors and tasks
        problem = problem_of(robot, source, catalog=catalog, options=resolved, plan=False,
                             mounting=mounting)
        with mounting_named(file if filed else None):
            problem = plan_tasks(problem)
        chosen_duty = problem_duty(problem)
    check_within(chosen_duty, limits)
    duty_sizing = size_problem(problem)
    settings = settings or SearchSettings()
    if spread is None:
        return _envelope(problem, limits, chosen_duty, duty_sizing, settings, None, started)
    with spread:
        result = _envelope(problem, limits, chosen_duty, duty_sizing, settings, spread,
                           started)
        return replace(result, executor=spread.where)


def _envelope(problem: Problem, spec: Spec, duty: Duty, duty_sizing: SizingResult,
              settings: SearchSettings, evaluate: Evaluate | None,
              started: float) -> EnvelopeResult:
    """The rounds of search and selection until the carried masses settle; the result."""
    units, options = problem.units, problem.options
    robot = carrying_every_part(problem.robot, duty.tasks)  # the worst states carry every part
    options = options if options.prefer is not None else replace(options, prefer=DEFAULT_PREFER)
    box, stop_time, threads = spec.box, options.stop_time, options.threads
    masses = ({joint.name: added_mass(joint, options) for joint in duty_sizing.joints}
              if options.mass_coupling else {})
    carriers = {j: tuple(k for k in robot.sized_joints
                         if robot.carried_mass(name, {k: 1.0}) > 0.0)
                for j, name in enumerate(robot.joint_names)}
    found: dict[tuple[int, str], Worst] = {}
    searched: dict[int, tuple[float, ...]] = {}
    rows: dict[int, StateRows] = {}
    states = rounds = 0
    settled = False
    per_joint = {name: units for name in robot.sized_joints}
    if options.mass_coupling:
        masses, states = _guessed_masses(robot, spec, duty, masses, per_joint, options,
                                         settings, evaluate)
    while True:
        key = {j: tuple(masses.get(k, 0.0) for k in carriers[j]) for j in carriers}
        stale = [j for j in carriers if searched.get(j) != key[j]]
        if not stale:
            settled = True
            break
        if rounds == MAX_ROUNDS:
            break
        carrying = robot.with_gearheads(masses) if masses else robot
        new, count = search(carrying, box, stop_time, stale, settings, threads=threads,
                            evaluate=evaluate)
        states, rounds = states + count, rounds + 1
        found.update(new)
        for j in stale:
            searched[j] = key[j]
            rows[j] = state_rows(carrying, box, {(j, k): new[(j, k)] for k in KINDS},
                                 stop_time, threads=threads)
        model = EnvelopeTorques(duty.tasks, _stacked([rows[j] for j in sorted(rows)]),
                                stop_time, threads=threads, guess=masses, idle=duty.idle,
                                wrenches=options.bearing_loads, states=robot)
        sized, chosen = select_units(model, per_joint, options, {}, slowdowns=False)
        masses = chosen if options.mass_coupling else {}
    sizing = SizingResult(problem.robot, duty.tasks[0].trajectory, tuple(sized), options, units,
                          duty.motion, loads=model.loads(masses), tasks=duty.tasks,
                          idle=duty.idle, mix=duty.mix, precision=duty_precision(
                              model, sized, masses, options))
    joints = tuple(_joint(model, joint, found, options, settings,
                          duty_sizing.joints[i].selected, masses)
                   for i, joint in enumerate(sized))
    sizing = replace(sizing, diagnoses=envelope_diagnoses(sizing, joints, duty))
    return EnvelopeResult(problem.robot, spec, duty, joints, sizing, duty_sizing, masses, settings,
                          states, rounds, settled, time.perf_counter() - started)


def _guessed_masses(robot: Robot, spec: Spec, duty: Duty, masses: dict[str, float],
                    per_joint: Mapping[str, tuple[Unit, ...]], options: Options,
                    settings: SearchSettings, evaluate: Evaluate | None
                    ) -> tuple[dict[str, float], int]:
    """The masses of a quick selection: a coarse search (`GUESS`) on a decimated duty.

    Starting the full search from them, it usually runs once: the duty alone tends to
    choose weaker (lighter) units than the envelope.
    """
    carrying = robot.with_gearheads(masses) if masses else robot
    quick, count = search(carrying, spec.box, options.stop_time, range(robot.dof),
                          replace(GUESS, seed=settings.seed), threads=options.threads,
                          evaluate=evaluate)
    rows = state_rows(carrying, spec.box, quick, options.stop_time, threads=options.threads)
    coarse = [decimated_task(task, GUESS_SAMPLES) for task in duty.tasks]
    model = EnvelopeTorques(coarse, rows, options.stop_time, threads=options.threads,
                            guess=masses, idle=duty.idle, states=robot,
                            wrenches=any(unit.bearing is not None
                                         for units in per_joint.values() for unit in units))
    _, chosen = select_units(model, per_joint, options, {}, detail=False, slowdowns=False)
    return chosen, count


def _joint(model: EnvelopeTorques, joint: JointSizing, found: Mapping[tuple[int, str], Worst],
           options: Options, settings: SearchSettings, duty_choice, masses) -> JointEnvelope:
    """One joint's worst states, gravity pose and convergence, from the final selection."""
    samples, robot = model.samples, model.states
    j = robot.joint_index(joint.name)
    rest = samples.rest[:, j]
    tau, stop = np.asarray(joint.torque), np.asarray(joint.stop_torque)
    duty_count = len(samples) - len(model.rows)
    worst: dict[str, WorstState] = {}
    notes: list[str] = []
    for figure, values, mask, kind in (("peak", tau, ~rest, "peak"), ("static", tau, rest, "held"),
                                       ("stop", stop, np.ones_like(rest), "stop")):
        where = np.flatnonzero(mask)
        i = int(where[np.argmax(np.abs(values[where]))])
        own = duty_count + model.rows.row(j, kind)
        if abs(values[own]) >= abs(values[i]) * (1.0 - 1e-12):  # ties: the search's own
            i = own
        source = ("search" if i >= duty_count
                  else f"duty {duty_time(samples, i)}")
        worst[figure] = WorstState(figure, model.q[i], samples.qd[i], samples.qdd[i],
                                   float(values[i]), source)
        if i != own and not agree(abs(values[own]), abs(values[i]), settings.tolerance):
            notes.append(f"{figure}: a state of {_origin(model, i, duty_count)} carries "
                         f"{abs(values[i]):.4g} N m, above the search's worst "
                         f"{abs(values[own]):.4g} N m")
    posed = model.rows.row(j, "gravity")
    carrying = robot.with_gearheads(masses) if masses else robot
    held = gravity_torques(carrying, model.rows.q[posed][None], threads=options.threads)[0, j]
    gravity = WorstState("gravity", model.rows.q[posed], np.zeros(robot.dof),
                         np.zeros(robot.dof), float(held), "search")
    demands = {kind: found[(j, kind)] for kind in KINDS}
    unsettled = [kind for kind, w in demands.items() if not w.converged]
    if unsettled:
        notes.insert(0, f"{', '.join(unsettled)}: the worst values from the last starts "
                        f"differ by more than {settings.tolerance:.1%}")
    return JointEnvelope(joint.name, joint, worst, gravity,
                         Convergence(demands, not notes, "; ".join(notes)), duty_choice)


def _origin(model: EnvelopeTorques, i: int, duty_count: int) -> str:
    """Where sample i comes from, in words."""
    if i < duty_count:
        return f"the duty ({duty_time(model.samples, i)})"
    r = i - duty_count
    return (f"the search for {model.robot.joint_names[model.rows.joint[r]]}'s "
            f"{model.rows.kind[r]}")


def _stacked(parts: Sequence[StateRows]) -> StateRows:
    """The rows of several joints, one after the other."""
    return StateRows(np.concatenate([p.q for p in parts]), np.concatenate([p.qd for p in parts]),
                     np.concatenate([p.qdd for p in parts]),
                     np.concatenate([p.joint for p in parts]),
                     tuple(k for p in parts for k in p.kind))


def _first(*values):
    """The first value that is not None."""
    return next(value for value in values if value is not None)


def _robot_state(base: Robot, source: Motion | Mix | None, file: EnvelopeFile | None,
                 payload: Payload | None, mounting: Mounting | None,
                 joints: Sequence[str] | None, exclude: Sequence[str] | None
                 ) -> tuple[Robot, Motion | Mix | None]:
    """The robot as the envelope sizes it, and the duty: argument, else envelope file, else duty's.

    A motion duty is set up as `hdselect.load_case` sets it up (its tool poses solved);
    a mix duty's tasks keep theirs, and the search runs the one payload and mounting
    they share (`hdselect.envelope.dutycycle.mix_robot`).

    Raises:
        InputError: As `hdselect.load_case`; a payload frame or a joint that the envelope
            file names and the robot lacks is blamed on the file's key.
    """
    expect_type(payload, (Payload, type(None)), "payload", "a Payload or None")
    from_file: dict[str, str] = {}  # what the envelope file gives -> its key there
    if file is not None:
        if payload is None and file.payload is not None:
            payload, from_file["payload"] = file.payload, "payload"
        for name, given, filed in (("joints", joints, file.joints),
                                   ("exclude", exclude, file.exclude or None)):
            if given is None and filed is not None:
                from_file[name] = f"sizing.{name}"
        joints = joints if joints is not None else file.joints
        exclude = exclude if exclude is not None else (file.exclude or None)
    try:
        if isinstance(source, Mix):  # the search's one payload and mounting (the envelope's)
            return mix_robot(base, source, payload=payload, mounting=mounting, joints=joints,
                             exclude=exclude), source
        if source is not None:
            return load_case(source, base, payload=payload, mounting=mounting, joints=joints,
                             exclude=exclude)
        robot = base.with_payload(payload) if payload is not None else base
        robot = robot.with_mounting(mounting) if mounting is not None else robot
        if joints is not None or exclude:
            robot = robot.with_sized_joints(joints, exclude or ())
        return robot, None
    except InputError as err:  # the robot lacks what an argument or the file names
        field = str(err.field)
        owner = next((k for k in ("payload", "joints", "exclude")
                      if field == k or field.startswith(f"{k}.")), None)
        if owner is None or err.path != base.path:
            raise
        where = ({"path": file.path, "field": from_file[owner] + field[len(owner):]}
                 if file is not None and owner in from_file else {"field": field})
        raise InputError(f"{err.reason} (robot file {base.path.name})", **where) from err


def _options(file: EnvelopeFile | None, motion: Motion | Mix | None,
             given: Mapping[str, Any]) -> Options:
    """The options: given, else the envelope file's, else the duty's motion file's."""
    values = dict(given)
    values.setdefault("max_samples", DEFAULT_MAX_SAMPLES)
    for name, value in (given_by(file, "envelope") if file is not None else {}).items():
        if values.get(name) is None:
            values[name] = value
    return source_options(motion, **values)
