"""Read a study file (TOML): the cases of a design study, each resolved and keyed.

A study is a grid (every combination of the lists in ``[grid]``), an explicit list
(``[[case]]``), or both (each listed case crossed with the grid), over the values in
``[base]``. Paths are relative to the study file. Each case gets a stable key: a hash
of everything its result depends on, the contents of its files included, so a study
re-run skips what it already has and re-runs exactly what changed.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from hdselect.base import bounds
from hdselect.base.errors import InputError
from hdselect.base.inputfiles import MAX_LOG_BYTES, read_input
from hdselect.base.tomlfile import as_number, check_keys, read_toml, table_of
from hdselect.catalog.builtin import catalog_file, series_catalogs
from hdselect.catalog.catalogfile import BUILTIN
from hdselect.motion.bagfile import log_files
from hdselect.motion.mixfile import task_names
from hdselect.motion.option_specs import OPTION, OPTIONS, from_edge
from hdselect.robot.mounting import MOUNTINGS
from hdselect.robot.payload import Payload
from hdselect.sizing.options import Options
from hdselect.sizing.tasks import check_shares
from hdselect.study.case import Case
from hdselect.study.casetasks import check_task_keys
from hdselect.study.compute import COMPUTATIONS

OPTION_KEYS = tuple(option.name for option in OPTIONS if option.study)
"""Sizing options a study may set or vary (`hdselect.motion.option_specs.Option.study`;
workers use one thread, the bearing offsets come from each case's motion file), in the
units of flags and files (a torsion in arcmin, a deflection in mm, a frequency in Hz or an
application class's name); a per-joint target is one value, for every sized joint."""


CASE_KEYS = ("motion", "robot", "payload", "shares", "payloads", "time_scale", "mounting",
             "catalog", "series", "ratio", "motor_catalog", *OPTION_KEYS)
"""Every key of ``[base]``, ``[grid]`` and ``[[case]]``, in the order of the CSV columns."""


_TOP_KEYS = ("title", "compute", "base", "grid", "case")


_PAYLOAD_KEYS = ("mass", "com", "inertia", "frame")


@dataclass(frozen=True)
class Study:
    """A study file, read.

    Attributes:
        path: The study file.
        title: Its title (default: the file name).
        compute: What is computed for every case, in order.
        cases: Every case (each computation of each combination), in study order.
        keys: The keys the study sets anywhere, in `CASE_KEYS` order: the CSV's parameter columns.
        varied: The keys whose value differs between cases, in the order the file gives
            them: the pivot and the plot use the first two.
    """

    path: Path
    title: str
    compute: tuple[str, ...]
    cases: tuple[Case, ...]
    keys: tuple[str, ...]
    varied: tuple[str, ...]


def load_study(path: str | Path, computations: Sequence[str] | None = None) -> Study:
    """Read and validate a study file; resolve and key every case.

    Args:
        path: The study file (TOML).
        computations: The computations this version knows (default: every registered one).

    Returns:
        The study.

    Raises:
        InputError: The study file is missing, malformed, or gives a value that is not
            valid (a missing robot or motion file is not an error here: that case fails
            when it runs, and says so in its row).
    """
    if computations is None:
        computations = tuple(COMPUTATIONS)
    path = bounds.file_argument(path, "path")
    doc = read_toml(path)
    check_keys(doc, _TOP_KEYS, path, "")
    title = doc.get("title", path.stem)
    if not isinstance(title, str):
        raise InputError("expected a string", path=path, field="title")
    compute = _compute(doc.get("compute", "size"), computations, path)
    base = _values(table_of(doc.get("base", {}), path, "base"), path, "base")
    grid_table = table_of(doc.get("grid", {}), path, "grid")
    check_keys(grid_table, CASE_KEYS, path, "grid")
    grid: dict[str, list[Any]] = {}
    for key, values in grid_table.items():
        if not isinstance(values, list) or not values:
            raise InputError("expected a non-empty list of values", path=path,
                             field=f"grid.{key}")
        grid[key] = [_value(key, value, path, f"grid.{key}[{i}]")
                     for i, value in enumerate(values)]
    listed = doc.get("case", [{}])
    if not isinstance(listed, list) or not listed:
        raise InputError("expected [[case]] tables", path=path, field="case")
    count = len(listed) * len(compute) * math.prod(len(values) for values in grid.values())
    if count > bounds.MAX_STUDY_CASES:
        raise InputError(f"makes {count:,} cases, more than {bounds.MAX_STUDY_CASES:,}; split "
                         "the study", path=path, field="grid" if grid else "case")
    rows = []
    mixes: dict[Path, tuple[str, ...] | None] = {}
    for i, item in enumerate(listed):
        given = _values(table_of(item, path, f"case[{i}]"), path, f"case[{i}]")
        where = {**{key: f"base.{key}" for key in base},
                 **{key: f"case[{i}].{key}" for key in given},
                 **{key: f"grid.{key}" for key in grid}}
        for combination in itertools.product(*grid.values()):
            rows.append({**base, **given, **dict(zip(grid, combination, strict=True))})
            _check_tasks(rows[-1], where, path, mixes)
    order = [*base, *(k for item in listed for k in item), *grid]
    keys = tuple(k for k in CASE_KEYS if k in order)
    varied = tuple(dict.fromkeys(k for k in order if len({_canonical(r.get(k))
                                                          for r in rows}) > 1))
    cases: list[Case] = []
    for values in rows:
        if "motion" not in values:
            raise InputError("every case needs a motion file: set it in [base], [grid] or "
                             "[[case]]", path=path, field="base.motion")
        for name in compute:
            cases.append(_case(len(cases), name, values, path))
    return Study(path, title, compute, tuple(cases), keys, varied)


def _check_tasks(values: dict[str, Any], where: dict[str, str], path: Path,
                 mixes: dict[Path, tuple[str, ...] | None]) -> None:
    """Refuse a case's ``shares``, ``payloads`` and ``payload`` that its motion file cannot take.

    ``shares`` and ``payloads`` are a mix file's, one share per task and payloads by task
    name; ``payload`` is a single motion's. A motion file that cannot be read is left to
    its case, which fails and says why.

    Args:
        values: The case's values.
        where: Where the study file gives each key (``grid.shares``, ``case[1].payloads``).
        path: The study file.
        mixes: Each motion file's task names (None: a single motion), filled as read.

    Raises:
        InputError: A key the case's motion file cannot take, naming it.
    """
    if "motion" not in values or not {"shares", "payloads", "payload"} & set(values):
        return
    motion = path.parent / values["motion"]
    if motion not in mixes:
        try:
            doc = read_toml(motion)
        except InputError:
            return
        names = task_names(motion) if "task" in doc else None
        if "task" in doc and names is None:
            return  # a broken mix file: its case says what is wrong
        mixes[motion] = names
    names = mixes[motion]
    if names is None:
        for key in ("shares", "payloads"):
            if key in values:
                raise InputError(f"gives the tasks of a mix file, and {values['motion']} is a "
                                 "single motion; vary `payload` or `time_scale` instead",
                                 path=path, field=where[key])
        return
    if "payload" in values:
        raise InputError(f"{values['motion']} is a mix file, whose tasks carry their own "
                         "payloads: vary `payloads` (task name -> mass [kg]) instead",
                         path=path, field=where["payload"])
    try:
        check_task_keys(values.get("shares"), values.get("payloads"), names, motion.name)
    except InputError as err:
        raise InputError(err.reason, path=path, field=where[str(err.field)]) from err


def _compute(value: Any, known: Sequence[str], path: Path) -> tuple[str, ...]:
    names = [value] if isinstance(value, str) else value
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputError("expected a computation name or a list of them", path=path,
                         field="compute")
    for name in names:
        if name not in known:
            raise InputError(f"'{name}' is not in this version of hdselect; it computes: "
                             f"{', '.join(known)}", path=path, field="compute")
    return tuple(dict.fromkeys(names))


def _values(table: dict[str, Any], path: Path, where: str) -> dict[str, Any]:
    check_keys(table, CASE_KEYS, path, where)
    return {key: _value(key, value, path, f"{where}.{key}") for key, value in table.items()}


def _value(key: str, value: Any, path: Path, field: str) -> Any:
    """One parameter, validated; paths stay as written (strings), relative to the study."""
    if key in ("motion", "robot", "motor_catalog"):
        if not isinstance(value, str) or not value or "\0" in value:
            raise InputError("expected a file name, relative to the study file", path=path,
                             field=field)
        return value
    if key == "catalog":
        files = [value] if isinstance(value, str) else value
        if not isinstance(files, list) or not all(isinstance(f, str) and f and "\0" not in f
                                                  for f in files):
            raise InputError("expected a catalog file or a list of them", path=path,
                             field=field)
        return tuple(files)
    if key == "series":  # as --series: only these series' units, a built-in one loaded
        names = [value] if isinstance(value, str) else value
        if not isinstance(names, list) or not names or not all(
                isinstance(name, str) and name and "\0" not in name for name in names):
            raise InputError("expected a series name (e.g. SHG-2UH) or a list of them",
                             path=path, field=field)
        return tuple(names)
    if key == "payload":
        if isinstance(value, dict):
            check_keys(value, _PAYLOAD_KEYS, path, field)
            if "mass" not in value:
                raise InputError("required key is missing", path=path, field=f"{field}.mass")
            payload = _payload(value, path, field)
            return {"mass": payload.mass, "com": list(payload.com),
                    "inertia": [list(row) for row in payload.inertia], "frame": payload.frame}
        return _payload({"mass": value}, path, field, mass_only=True).mass
    if key == "shares":  # a mix file's tasks, in its order; they must sum to 1
        if not isinstance(value, list) or not value:
            raise InputError("expected a list of shares, one per task of the mix file",
                             path=path, field=field)
        shares = [as_number(v, path, f"{field}[{i}]", minimum=0.0) for i, v in enumerate(value)]
        try:
            check_shares(shares, field=field)
        except InputError as err:
            raise InputError(err.reason, path=path, field=err.field) from err
        return shares
    if key == "payloads":  # a mix file's tasks by name: payload mass [kg]
        table = table_of(value, path, field)
        return {name: _payload({"mass": mass}, path, f"{field}.{name}", mass_only=True).mass
                for name, mass in table.items()}
    if key == "time_scale":
        return as_number(value, path, field, bound=bounds.TIME_SCALE)
    if key == "mounting":
        if isinstance(value, str):
            if value not in MOUNTINGS:
                raise InputError(f"unknown mounting {value!r}; choose one of: "
                                 f"{', '.join(MOUNTINGS)} or a gravity vector [gx, gy, gz] in "
                                 "m/s^2", path=path, field=field)
            return value
        if not isinstance(value, list) or len(value) != 3:
            raise InputError("expected floor, wall, ceiling or [gx, gy, gz] in m/s^2",
                             path=path, field=field)
        return tuple(as_number(v, path, f"{field}[{i}]", bound=bounds.GRAVITY)
                     for i, v in enumerate(value))
    if key == "ratio":
        if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
            raise InputError(f"expected a positive whole ratio, got {value!r}", path=path,
                             field=field)
        bounds.RATIO.check(value, path=path, field=field)
        return value
    if OPTION[key].kind == "joints" and isinstance(value, dict):
        raise InputError("a study gives one value for every sized joint, not a table by "
                         "joint (name joints in the motion file's [precision] table)",
                         path=path, field=field)
    try:
        Options(**from_edge({key: value}))  # in the units of the files: arcmin, mm
    except InputError as err:
        raise InputError(err.reason, path=path, field=field) from err
    return value


def _payload(table: dict[str, Any], path: Path, field: str, mass_only: bool = False) -> Payload:
    try:
        return Payload(table["mass"], table.get("com", (0.0, 0.0, 0.0)),
                       table.get("inertia", ((0.0,) * 3,) * 3), table.get("frame"))
    except InputError as err:
        where = field if mass_only else field + str(err.field).removeprefix("payload")
        raise InputError(err.reason, path=path, field=where) from err


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True)


def _case(index: int, compute: str, values: dict[str, Any], path: Path) -> Case:
    """Resolve one combination's paths and payload and key it."""
    from hdselect import __version__  # the package is still loading when this module is

    folder = path.parent
    motion = folder / values["motion"]
    robot = folder / values["robot"] if "robot" in values else None
    payload = values.get("payload")
    shape = None
    if isinstance(payload, dict):
        shape = (tuple(payload["com"]), tuple(tuple(r) for r in payload["inertia"]),
                 payload["frame"])
        payload = payload["mass"]
    series = tuple(values.get("series", ()))
    named = tuple(values.get("catalog", ()))
    named += tuple(name for name in series_catalogs(series) if name not in named)
    catalog = tuple(catalog_file(f, base=folder, path=path, field="catalog", missing_ok=True)
                    for f in named)
    options = {k: values[k] for k in OPTION_KEYS if k in values}
    motor_catalog = folder / values["motor_catalog"] if "motor_catalog" in values else None
    files = _inputs(motion, robot, (*catalog, *([motor_catalog] if motor_catalog else [])))
    resolved = {
        "version": __version__, "compute": compute, "payload": payload, "payload_shape": shape,
        "time_scale": values.get("time_scale", 1.0), "mounting": values.get("mounting"),
        "ratio": values.get("ratio"), "options": options,
        "shares": values.get("shares"), "payloads": values.get("payloads"),
        "motion": _digest(motion), "robot": None if robot is None else _digest(robot),
        "catalog": [_digest(f) for f in catalog], "builtin": _builtin_digest(),
        "inputs": [_digest(f) for f in files],
    }
    if motor_catalog is not None:
        resolved["motor_catalog"] = _digest(motor_catalog)
    if series:  # only where given: the other cases keep their keys
        resolved["series"] = [name.lower() for name in series]
    key = hashlib.sha256(_canonical(resolved).encode()).hexdigest()[:20]
    shown = {k: (payload if k == "payload" else values[k]) for k in CASE_KEYS if k in values}
    shares = values.get("shares")
    payloads = values.get("payloads")
    return Case(index, compute, shown, motion, robot, payload, shape,
                float(values.get("time_scale", 1.0)), values.get("mounting"), catalog,
                values.get("ratio"), options, key, files, motor_catalog,
                None if shares is None else tuple(shares),
                None if payloads is None else tuple(payloads.items()), series)


def _inputs(motion: Path, robot: Path | None, catalog: tuple[Path, ...]) -> tuple[Path, ...]:
    """Every file a case reads: the motion, its robot, log and motor files, the catalogs.

    The motion file is only skimmed here for the files it names; it is read for real,
    and any error in it reported, when the case runs.
    """
    files = [motion]
    try:
        doc = tomllib.loads(read_input(motion).decode("utf-8"))
    except (InputError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError):
        doc = {}
    if robot is not None:
        files.append(robot)
    elif isinstance(doc.get("robot"), str):
        files.append(motion.parent / doc["robot"])
    tasks = doc.get("task")
    if isinstance(tasks, list):  # a mix file: its motions' files too
        for task in tasks:
            if isinstance(task, dict) and isinstance(task.get("motion"), str):
                files += _inputs(motion.parent / task["motion"], robot, ())
    samples = doc.get("samples")
    if isinstance(samples, dict) and isinstance(samples.get("file"), str):
        files += log_files(motion.parent / samples["file"])  # a rosbag2 folder's files
    motors = doc.get("motor")
    if isinstance(motors, dict):  # [motor] and [motor.JOINT] may each name a motor file
        for block in (motors, *(v for v in motors.values() if isinstance(v, dict))):
            if isinstance(block.get("catalog"), str):
                files.append(motion.parent / block["catalog"])
    # a name holding a NUL is no file: left to the case, whose reader refuses it
    return tuple(dict.fromkeys(f for f in [*files, *catalog] if "\0" not in str(f)))


def _digest(path: Path) -> str:
    """SHA-256 of a file's bytes, or a marker when it cannot be read."""
    try:
        return hashlib.sha256(read_input(path, MAX_LOG_BYTES)).hexdigest()
    except InputError as err:
        return f"unreadable: {err.reason}"


def _builtin_digest() -> str:
    """SHA-256 of the built-in catalog file."""
    return hashlib.sha256(resources.files("hdselect.catalog").joinpath("data", BUILTIN)
                          .read_bytes()).hexdigest()
