"""Tests of the resolved sizing problem (hdselect.sizing.problem): one resolver for files and
objects, a motion a problem of one task.

Oracles: a motion file and the same motion as a one-task mix must resolve to the same
problem and size to the same result to the last bit; files and the objects loaded from
them must resolve alike; and `size` must be `resolve` then `size_problem`.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect import InputError, Problem, Task, load_catalog, load_mix, load_motion, resolve, size
from hdselect.sizing.core import size_problem
from hdselect.sizing.summary import summarize
from test_study_group import differences

REPO = Path(__file__).resolve().parents[1]
PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
PLANAR = REPO / "trajectories" / "planar2_pick_place.toml"
PICK_INSPECT = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"


def one_task_mix(folder: Path, motion: Path) -> Path:
    """A mix file of `motion` alone, with share 1."""
    path = folder / "alone.toml"
    path.write_text(f'[[task]]\nmotion = "{motion}"\nshare = 1\n')
    return path


def same_problem(a: Problem, b: Problem) -> bool:
    """Two problems pose the same sizing: robot, units, options, motors, tasks, idle."""
    if (a.robot.path.resolve() != b.robot.path.resolve()
            or a.robot.sized_joints != b.robot.sized_joints or a.units != b.units
            or a.options != b.options or a.idle != b.idle
            or dict(a.motors) != dict(b.motors) or len(a.tasks) != len(b.tasks)):
        return False
    for x, y in zip(a.tasks, b.tasks, strict=True):
        if (x.share != y.share or x.robot.payload != y.robot.payload
                or x.robot.sized_joints != y.robot.sized_joints
                or x.trajectory.dt != y.trajectory.dt):
            return False
        for name in ("t", "q", "qd", "qdd"):
            if not np.array_equal(getattr(x.trajectory, name), getattr(y.trajectory, name)):
                return False
        if not np.array_equal(x.robot.gravity, y.robot.gravity):
            return False
    return True


def _plain(result):
    """A result as nested plain values (its summary), without warnings and task names."""
    return replace(summarize(result), warnings=(), tasks=()).to_dict()


def test_a_motion_is_a_problem_of_one_task_with_share_one():
    problem = resolve(None, PLANAR)
    assert len(problem.tasks) == 1 and problem.tasks[0].share == 1.0 and problem.idle == 0.0
    assert problem.mix is None and problem.tasks[0].motion is not None
    assert problem.tasks[0].robot is problem.robot
    assert PLANAR in problem.files and problem.robot.path in problem.files


def test_a_motion_and_its_one_task_mix_resolve_and_size_alike(tmp_path):
    mix = one_task_mix(tmp_path, PICK)
    alone, mixed = resolve(None, PICK), resolve(None, mix)
    assert same_problem(alone, mixed)
    assert mixed.mix is not None and mixed.tasks[0].name == "benchtop6_pick_place"
    assert differences(_plain(size_problem(alone)), _plain(size_problem(mixed))) == 0.0


def test_files_and_loaded_objects_resolve_alike():
    robot = hdselect.load_robot(REPO / "robots" / "planar2.urdf")
    motion = load_motion(PLANAR, robot)
    from_files = resolve(None, PLANAR)
    from_objects = resolve(robot, motion, catalog=load_catalog())
    assert same_problem(from_files, from_objects)
    mix = load_mix(PICK_INSPECT)
    assert same_problem(resolve(None, PICK_INSPECT), resolve(None, mix))


def test_size_is_resolve_then_size_problem():
    direct = size(None, PLANAR, stop_time=0.15)
    problem = resolve(None, PLANAR, stop_time=0.15)
    assert problem.options.stop_time == 0.15
    assert differences(_plain(direct), _plain(size_problem(problem))) == 0.0


def test_an_unplanned_problem_is_planned_by_size_problem():
    unplanned = resolve(None, PICK_INSPECT, plan=False)
    assert not unplanned.planned and unplanned.tasks == ()
    planned = hdselect.sizing.plan_tasks(unplanned)
    assert [task.name for task in planned.tasks] == ["pick", "inspect"]
    assert all(isinstance(task, Task) for task in planned.tasks)
    assert differences(_plain(size_problem(unplanned)), _plain(size(None, PICK_INSPECT))) == 0.0


def test_options_as_a_whole_skip_the_files_values():
    given = hdselect.Options(stop_time=0.2)
    assert resolve(None, PLANAR, options=given, plan=False).options is given


@pytest.mark.parametrize(("kwargs", "field"), [
    ({"options": hdselect.Options(), "stop_time": 0.2}, "stop_time"),
    ({"catalog": ["catalogs/example_rated_bearing.toml", *load_catalog()[:1]]}, "catalog"),
    ({"payload": hdselect.Payload(1.0)}, "payload"),
    ({"options": {"stop_time": 0.2}}, "options"),
])
def test_contradicting_or_malformed_arguments_are_refused(kwargs, field):
    motion = PICK_INSPECT if "payload" in kwargs else PLANAR
    with pytest.raises(InputError) as caught:
        resolve(None, motion, plan=False, **kwargs)
    assert caught.value.field == field


# ------------------------------------------------------------------ the Python API's spelling

QUICK = {"velocity": 2.0, "acceleration": 10.0, "moves": 2, "stop_time": 0.1}
"""A small envelope of the planar arm (a coarse search), for spellings, not numbers."""


def test_size_units_is_the_deprecated_spelling_of_a_loaded_catalog():
    units = load_catalog()[-3:]
    with pytest.warns(DeprecationWarning, match=r"size\(units=\.\.\.\) is deprecated; use "
                      r"size\(catalog=\.\.\.\)") as caught:
        old = size(None, PLANAR, units=units)
    assert len(caught) == 1 and caught[0].filename == __file__  # the caller's line
    new = size(None, PLANAR, catalog=units)
    assert old.units == new.units == tuple(units)
    assert differences(_plain(old), _plain(new)) == 0.0


def test_envelope_units_is_the_deprecated_spelling_of_a_loaded_catalog():
    from hdselect.envelope import SearchSettings

    units = load_catalog()[-2:]
    quick = SearchSettings(starts=64, refine=1, rounds=0)
    with pytest.warns(DeprecationWarning, match=r"envelope\(units=\.\.\.\) is deprecated; use "
                      r"envelope\(catalog=\.\.\.\)"):
        old = hdselect.envelope(REPO / "robots" / "planar2.urdf", units=units, settings=quick,
                                **QUICK)
    new = hdselect.envelope(REPO / "robots" / "planar2.urdf", catalog=units, settings=quick,
                            **QUICK)
    assert old.sizing.units == new.sizing.units == tuple(units)
    assert [j.selected.unit.id for j in old.joints] == [j.selected.unit.id for j in new.joints]


@pytest.mark.parametrize("call", [size, hdselect.envelope])
def test_units_and_catalog_files_together_are_refused_without_a_warning(call, recwarn):
    with pytest.raises(InputError, match="not both") as caught:
        call(None, PLANAR, units=load_catalog(), catalog=["mine.toml"])
    assert caught.value.field == "units" and not recwarn.list


@pytest.mark.parametrize(("module", "expected"), [
    ("envelope", ["robot", "spec", "velocity", "acceleration", "catalog", "options"]),
    ("study", ["path", "out", "workers", "scheduler", "timeout"]),
])
def test_the_callable_modules_show_their_functions_signatures(module, expected):
    import inspect

    package = getattr(hdselect, module)
    parameters = inspect.signature(package).parameters
    assert all(name in parameters for name in expected), list(parameters)
    assert "args" not in parameters and "kwargs" not in parameters
    function = getattr(package, module)
    assert inspect.signature(package) == inspect.signature(function)
    assert type(package).__call__ is function  # the call is the function itself


def test_every_type_a_public_function_takes_is_exported():
    for name in ("Problem", "Task", "Options", "Payload", "Motion", "Mix", "Unit", "Motor",
                 "Robot", "Trajectory"):
        assert name in hdselect.__all__ and getattr(hdselect, name).__name__ == name
    assert hdselect.Task is hdselect.sizing.tasks.Task


def test_option_keywords_are_the_fields_of_options():
    from dataclasses import fields

    from hdselect.sizing.arguments import OptionValues

    assert list(OptionValues.__annotations__) == [f.name for f in fields(hdselect.Options)]
