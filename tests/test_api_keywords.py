"""One meaning per keyword in the public Python API, and every type it names is public.

- ``catalog`` is the units to choose from (files or loaded units), ``units`` a fixed unit
  per joint, ``options`` an `Options`: the old spellings of a loaded catalog (``units=``,
  ``load_catalog(extra=...)``) warn once, at the caller's line, and give the same result.
- Every class a public function's annotations name (its parameters, option keywords and
  return value) is exported from ``hdselect``.
"""

from __future__ import annotations

import collections.abc
import inspect
import types
import typing
from pathlib import Path

import pytest
import typing_extensions

import hdselect
from hdselect import InputError, Task
from hdselect.sizing.result import JointSizing
from hdselect.sizing.summary import summarize

REPO = Path(__file__).resolve().parents[1]
PLANAR = REPO / "trajectories" / "planar2_pick_place.toml"
CONVEYOR = REPO / "trajectories" / "duty" / "conveyor_index.toml"
RATED = REPO / "catalogs" / "example_rated_bearing.toml"


@pytest.fixture(scope="module")
def case():
    robot, motion = hdselect.load_case(PLANAR)
    return robot, hdselect.plan(robot, motion), hdselect.load_catalog()[-4:]


def _ids(result):
    return [joint.selected.unit.id if joint.selected else None for joint in result.joints]


def _old_spelling(call, match, *args, **kwargs):
    """Call with a deprecated spelling: exactly one warning, naming the new one, at this line."""
    with pytest.warns(DeprecationWarning, match=match) as caught:
        result = call(*args, **kwargs)
    assert len(caught) == 1 and caught[0].filename == __file__
    assert len(str(caught[0].message).splitlines()) == 1
    return result


# ------------------------------------------------------------------ deprecated spellings

def test_size_trajectory_units_is_the_old_spelling_of_catalog(case):
    robot, trajectory, units = case
    old = _old_spelling(hdselect.size_trajectory, r"size_trajectory\(units=\.\.\.\) is "
                        r"deprecated; use size_trajectory\(catalog=\.\.\.\)",
                        robot, trajectory, units=units)
    new = hdselect.size_trajectory(robot, trajectory, catalog=units)
    positional = hdselect.size_trajectory(robot, trajectory, units)  # no warning
    assert old.units == new.units == positional.units == tuple(units)
    assert summarize(old).to_dict() == summarize(new).to_dict() == summarize(
        positional).to_dict()


def test_size_tasks_units_is_the_old_spelling_of_catalog(case):
    robot, trajectory, units = case
    tasks = [Task(robot, trajectory, 0.5, name="a"), Task(robot, trajectory, 0.5, name="b")]
    old = _old_spelling(hdselect.size_tasks, r"size_tasks\(units=\.\.\.\) is deprecated; "
                        r"use size_tasks\(catalog=\.\.\.\)", tasks, units=units)
    new = hdselect.size_tasks(tasks, catalog=units)
    assert old.units == new.units == tuple(units)
    assert summarize(old).to_dict() == summarize(new).to_dict()


def test_size_duty_units_is_the_old_spelling_of_catalog():
    cycle = hdselect.load_duty(CONVEYOR)
    units = hdselect.load_catalog()[2:]
    old = _old_spelling(hdselect.size_duty, r"size_duty\(units=\.\.\.\) is deprecated; use "
                        r"size_duty\(catalog=\.\.\.\)", cycle, units=units, margin=0.1)
    new = hdselect.size_duty(cycle, catalog=units, margin=0.1)
    assert old == new and [c.unit for c in new.candidates] == list(units)


def test_load_catalog_extra_is_the_old_spelling_of_catalog():
    old = _old_spelling(hdselect.load_catalog, r"load_catalog\(extra=\.\.\.\) is deprecated; "
                        r"use load_catalog\(catalog=\.\.\.\)", extra=[RATED])
    new = hdselect.load_catalog(catalog=[RATED])
    assert old == new == hdselect.load_catalog([RATED])
    assert len(new) > len(hdselect.load_catalog())


def test_the_old_co_design_names_warn_at_the_callers_line():
    import hdselect.codesign as codesign

    found = _old_spelling(getattr, r"hdselect\.codesign\.mix_fastest is deprecated; use "
                          r"hdselect\.codesign\.fastest", codesign, "mix_fastest")
    assert found is hdselect.fastest


@pytest.mark.parametrize("call", ["size_trajectory", "size_tasks", "size_duty", "load_catalog"])
def test_both_spellings_together_are_refused_without_a_warning(case, call, recwarn):
    robot, trajectory, units = case
    first = {"size_trajectory": (robot, trajectory), "size_tasks": ((Task(robot, trajectory),),),
             "size_duty": (hdselect.load_duty(CONVEYOR),), "load_catalog": ()}[call]
    old, new = (("extra", [RATED]), ("catalog", [RATED])) if call == "load_catalog" else (
        ("units", units), ("catalog", units))
    with pytest.raises(InputError, match="not both") as caught:
        getattr(hdselect, call)(*first, **{old[0]: old[1], new[0]: new[1]})
    assert caught.value.field == old[0] and not recwarn.list


@pytest.mark.parametrize("call", ["size_trajectory", "size_tasks", "size_duty"])
@pytest.mark.parametrize("keyword", ["catalog", "units"])
@pytest.mark.parametrize("wrong", [42, "PSA-14-80", ("PSA-14-80",), ()])
def test_a_wrong_catalog_names_the_keyword_given(case, call, keyword, wrong, recwarn):
    robot, trajectory, _ = case
    first = {"size_trajectory": (robot, trajectory), "size_tasks": ((Task(robot, trajectory),),),
             "size_duty": (hdselect.load_duty(CONVEYOR),)}[call]
    with pytest.raises(InputError) as caught:
        getattr(hdselect, call)(*first, **{keyword: wrong})
    assert caught.value.field == keyword and not recwarn.list


def test_the_catalog_left_out_is_the_built_in_one(case):
    robot, trajectory, _ = case
    everything = hdselect.load_catalog()
    assert (summarize(hdselect.size_trajectory(robot, trajectory)).to_dict()
            == summarize(hdselect.size_trajectory(robot, trajectory, everything)).to_dict())
    cycle = hdselect.load_duty(CONVEYOR)
    assert hdselect.size_duty(cycle) == hdselect.size_duty(cycle, everything)


# ------------------------------------------------------------------ the keywords' meanings

def _functions():
    return [name for name in hdselect.__all__ if name[0].islower() and name != "__version__"]


def _function(name: str):
    """The public function of a name (the callable modules' own function)."""
    value = getattr(hdselect, name)
    return type(value).__call__ if isinstance(value, types.ModuleType) else value


def _hints(function) -> dict[str, object]:
    return typing.get_type_hints(function, localns={"Unpack": typing_extensions.Unpack},
                                 include_extras=True)


def _deprecated(function, parameter: str) -> bool:
    """Whether the docstring calls the parameter deprecated (``name: Deprecated: ...``)."""
    return f"{parameter}: Deprecated:" in " ".join((function.__doc__ or "").split())


@pytest.mark.parametrize("name", _functions())
def test_a_keyword_means_one_thing(name):
    function = _function(name)
    parameters = inspect.signature(function).parameters
    hints = _hints(function)
    for parameter in parameters.values():
        leaves = set(_classes(hints[parameter.name]))
        if parameter.name == "catalog":  # the units to choose from: files or loaded units
            assert leaves & {hdselect.Unit, str}, (name, leaves)
            assert collections.abc.Mapping not in leaves, name
        elif parameter.name == "units" and not _deprecated(function, "units"):
            assert collections.abc.Mapping in leaves and hdselect.Unit in leaves, name
        elif parameter.name == "units":  # the old spelling of a loaded catalog
            assert parameter.default is None and parameter.kind is parameter.KEYWORD_ONLY
        elif parameter.name == "options":
            assert leaves == {hdselect.Options, type(None)}, (name, leaves)
        elif parameter.kind is parameter.VAR_KEYWORD:  # Options' fields, typed
            assert typing.get_origin(hints[parameter.name]) is typing_extensions.Unpack
    first = list(parameters)[:1]
    if {"robot", "motion"} & set(parameters):
        assert first in (["robot"], ["motion"], ["path"]), (name, first)


# ------------------------------------------------------------------ every type public

_LIBRARIES = ("builtins", "collections", "typing", "typing_extensions", "pathlib", "types")


def _classes(annotation):
    """The classes an annotation names: unions and generics taken apart, option keywords
    (``**values: Unpack[OptionValues]``) as their fields' types."""
    origin = typing.get_origin(annotation)
    if origin is typing_extensions.Unpack:
        (fields,) = typing.get_args(annotation)
        for field in typing.get_type_hints(fields).values():
            yield from _classes(field)
        return
    if origin is typing.Literal:
        return
    if origin is not None:
        if origin not in (typing.Union, types.UnionType):
            yield origin
        for argument in typing.get_args(annotation):
            for part in argument if isinstance(argument, list) else [argument]:
                if part is not Ellipsis:
                    yield from _classes(part)
        return
    if isinstance(annotation, type):
        yield annotation


def _not_exported(function) -> list[str]:
    """The hdselect classes in a function's annotations that ``hdselect`` does not export."""
    out = []
    for parameter, annotation in _hints(function).items():
        for cls in _classes(annotation):
            if cls.__module__.split(".")[0] in _LIBRARIES + ("numpy",):
                continue
            if getattr(hdselect, cls.__name__, None) is not cls:
                out.append(f"{parameter}: {cls.__module__}.{cls.__qualname__}")
    return out


def test_every_type_a_public_function_takes_or_returns_is_exported():
    missing = {name: _not_exported(_function(name)) for name in _functions()}
    assert {name: found for name, found in missing.items() if found} == {}
    for name in ("DutyCycle", "DutyResult", "JointInfo", "Planned", "SearchSettings"):
        assert name in hdselect.__all__ and getattr(hdselect, name).__name__ == name


class _Shape(typing.TypedDict, total=False):
    joint: JointSizing


def test_the_walk_finds_a_type_that_is_not_exported():
    def takes(joint: JointSizing | None, *, robots: tuple[hdselect.Robot, ...] = (),
              **values: typing_extensions.Unpack[_Shape]) -> dict[str, JointSizing]:
        """A function naming a class hdselect does not export."""
        raise NotImplementedError

    assert _not_exported(takes) == [
        "joint: hdselect.sizing.result.JointSizing",
        "values: hdselect.sizing.result.JointSizing",
        "return: hdselect.sizing.result.JointSizing"]
