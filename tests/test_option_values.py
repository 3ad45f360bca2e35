"""Every option's value is read as given or refused in one line naming the option.

An empty value never means "not given" (``--velocity ''`` once fell back to the robot
file's limit), and a number that is not finite or far beyond any physical range
(``nan``, ``inf``, ``1e308``) is refused naming the option, on every command. The
options are found in the parser, so a new option is covered without a new row.
"""

from __future__ import annotations

import argparse

import pytest

from hdselect.cli.main import _parser, main
from helpers import REPO

MOTION = str(REPO / "trajectories" / "planar2_pick_place.toml")
PLANAR2 = str(REPO / "robots" / "planar2.urdf")
BASE = {
    "catalog": [],
    "duty": [str(REPO / "trajectories" / "duty" / "conveyor_index.toml")],
    "plan": [MOTION, "--out", "OUT/t.csv"],
    "size": [MOTION], "compare": [MOTION], "fastest": [MOTION], "max-payload": [MOTION],
    "envelope": [PLANAR2, "--acceleration", "900", "--starts", "64", "--moves", "2"],
    "joints": [PLANAR2], "init": [PLANAR2],
    "study": [str(REPO / "trajectories" / "studies" / "scara_ratio_speed.toml"),
              "--out", "OUT/s.csv"],
}
"""Per command, a valid command line the option under test is added to."""
NUMBERS_AS_TEXT = {("envelope", "--velocity"), ("envelope", "--acceleration"),
                   ("envelope", "--jerk")}
"""Options that take numbers written as text (``V`` or ``JOINT=V``)."""


def _actions() -> dict[str, list[argparse.Action]]:
    commands = next(a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction))
    return {name: [a for a in sub._actions if a.option_strings and a.nargs != 0
                   and "--help" not in a.option_strings]
            for name, sub in commands.choices.items()}


def _argv(command: str, flag: str, value: str, nargs, tmp_path) -> list[str]:
    base = [arg.replace("OUT", str(tmp_path)) for arg in BASE[command]]
    return [command, *base, flag, *[value] * (nargs if isinstance(nargs, int) else 1)]


def _refused(capsys, argv: list[str], flag: str) -> None:
    try:
        status = main(argv)
    except SystemExit as exit_:  # the parser's own refusal: one line too
        status = exit_.code
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and flag in lines[0], (argv, status, err)


def test_every_command_has_a_base_line():
    assert set(BASE) == set(_actions())


@pytest.mark.parametrize(("command", "flag", "nargs"), [
    (command, max(a.option_strings, key=len), a.nargs)
    for command, actions in _actions().items() for a in actions])
def test_an_empty_value_is_refused_naming_the_option(capsys, tmp_path, command, flag, nargs):
    for empty in ("", " "):
        _refused(capsys, _argv(command, flag, empty, nargs, tmp_path), flag)
    assert not any(tmp_path.iterdir())  # nothing written


@pytest.mark.parametrize(("command", "flag", "nargs"), [
    (command, max(a.option_strings, key=len), a.nargs)
    for command, actions in _actions().items() for a in actions
    if a.type in (int, float) or (command, max(a.option_strings, key=len)) in NUMBERS_AS_TEXT])
@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e308", "-1e308"])
def test_a_number_beyond_any_range_is_refused_naming_the_option(capsys, tmp_path, command,
                                                                flag, nargs, value):
    _refused(capsys, _argv(command, flag, value, nargs, tmp_path), flag)
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(("command", "flag"), [
    ("envelope", "--velocity"), ("envelope", "--acceleration"), ("envelope", "--jerk"),
    ("envelope", "--joints"), ("envelope", "--exclude"), ("size", "--joints"),
    ("size", "--exclude"), ("plan", "--exclude")])
def test_a_list_of_nothing_is_refused_naming_the_option(capsys, tmp_path, command, flag):
    """Only commas: no name or number given, so refused, not read as not given."""
    _refused(capsys, _argv(command, flag, ", ,", 1, tmp_path), flag)
