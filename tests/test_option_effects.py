"""Every option of every command takes effect or is refused; every public function refuses a
wrong type with an `InputError` naming the parameter.

Each option is run against the same command without it: what it writes must differ (or the
command refuses it in one line). `test_every_option_is_in_the_table` keeps the table whole:
a new option without a row here fails. The commands that take a mix file (several motions
sized as one duty) run the same table on one too: a mix honours every option a motion does.
"""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import pytest

import hdselect
from hdselect import InputError
from hdselect.cli.main import _parser, main
from hdselect.sizing.tasks import Task
from helpers import REPO
from helpers.options import ONE_MOVE, OTHER, effect_options

ACME = ('series = "ACME"\n[[unit]]\nsize = 20\nratio = 30\nrated_torque_nm = 40\n'
        "repeated_torque_nm = 50\nmax_input_speed_rpm = 4000\ninput_inertia_kg_cm2 = 0.2\n"
        "mass_kg = 1.5\n")

SIZING = [
    ("--catalog", ["acme.toml"]), ("--stop-time", ["0.3"]), ("--efficiency", ["0.5"]),
    ("--motor-inertia", ["1e-5"]), ("--motor-mass", ["1.0"]),
    ("--motor-catalog", ["motors/example_motors.toml"]), ("--no-mass-coupling", []),
    ("--prefer", ["margin"]), ("--life-hours", ["1e5"]), ("--life-basis", ["L10"]),
    ("--payload-com", ["0", "0", "0.1"]), ("--payload-frame", ["link2"]),
    ("--mounting", ["wall"]), ("--base", ["0,0,0.5,90,0,0"]), ("--joints", ["shoulder"]),
    ("--exclude", ["elbow"]), ("--max-samples", ["100"]), ("--margin", ["0.3"]),
    ("--max-inertia-ratio", ["3"], ["--motor-catalog", "motors/example_motors.toml"]),
    ("--inertia-target", ["50"], ["--motor-catalog", "motors/example_motors.toml",
                                  "--prefer", "inertia"]),
    ("--series", ["ACME"], ["--catalog", "acme.toml"]),  # PSA-G left out
    ("--max-torsion", ["0.5"], ["--series", "shg-2uh"]),  # PSA-G rates no stiffness
    ("--min-natural-frequency", ["hand-axes"], ["--series", "shg-2uh"]),
    ("--max-tool-deflection", ["0.005"], ["--series", "shg-2uh"]),  # refused: fastest, ...
    ("--min-arm-frequency", ["laser-welding-hand-axes"], ["--series", "shg-2uh"]),
    ("--allow-flip", []),  # refused: the motion has no tool pose (test_underdetermined_poses)
]
"""Options every sizing command takes, with a value that must change its answer."""

EFFECTS = {
    "size": [*SIZING, ("--payload", ["0.9"]), ("--report", ["rep"]),
             ("--no-precision", [], ["--series", "shg-2uh"])],
    "compare": [*SIZING, ("--payload", ["0.9"]), ("--report", ["rep"]),
                ("--no-precision", [], ["--series", "shg-2uh"]),
                ("--joint", ["elbow"])],
    "fastest": [*[row for row in SIZING if row[0] != "--catalog"], ("--payload", ["0.9"]),
                ("--catalog", ["acme.toml"], ["--compare-ratios"]),  # more units compared
                ("--units", ["shoulder=PSA-14-80"]),
                ("--compare-ratios", []), ("--joint", ["elbow"]), ("--out", ["f.csv"]),
                ("--plot", ["f.png"])],
    "max-payload": [*[row for row in SIZING if row[0] != "--prefer"],
                    ("--units", ["shoulder=PSA-14-100", "--units", "elbow=PSA-14-100"]),
                    ("--task", ["pick"])],  # a mix's: refused for a motion file
    "plan": [("--payload", ["0.9"]), ("--payload-com", ["0", "0", "0.1"]),
             ("--payload-frame", ["link2"]), ("--mounting", ["wall"]),
             ("--base", ["0,0,0.5,90,0,0"]),  # turned over on its side: gravity along base y
             ("--task", ["pick"]),  # a mix's: refused for a motion file
             ("--joints", ["shoulder"]), ("--exclude", ["elbow"]),  # refused without --plot
             ("--joints", ["shoulder"], ["--plot", "p.png"]),  # the joints plotted
             ("--max-samples", ["100"]), ("--plot", ["p.png"]),
             ("--waypoints", ["w.csv"]),  # the joint path as solved (here the file's)
             ("--line-errors", ["l.csv"]),  # refused: the motion has no straight line
             ("--units", ["shoulder=PSA-14-100"]),  # the units' masses in tau_
             ("--motor-catalog", ["motors/example_motors.toml"]),  # and the motors'
             ("--catalog", ["acme.toml"]),  # refused without --units; test_size_cli: its id
             ("--motor-mass", ["1.0"], ["--units", "shoulder=PSA-14-100"]),
             ("--no-mass-coupling", [], ["--units", "shoulder=PSA-14-100"]),
             ("--allow-flip", [])],  # refused: no tool pose (test_underdetermined_poses)
}
"""Per command, each option and its value."""

DAY = """\
[[task]]
name = "pick"
motion = "move.toml"
share = 0.7
[[task]]
name = "heavy"
motion = "move.toml"
share = 0.3
payload = {mass = 0.8, com = [0.03, 0.0, 0.0], frame = "tool"}
"""
"""A mix of the move twice, the second with twice the payload: one duty of two tasks."""

MIX_EFFECTS = {command: EFFECTS[command] for command in ("size", "compare", "fastest",
                                                        "max-payload")}
"""The commands that take a mix, each with every option of its motion table: on a mix the
payload options are refused (each task gives its own) and max-payload's --task chooses the
tasks whose payload scales."""

MIX_NOT_YET: dict[str, tuple[str, ...]] = {}
"""What co-design on a mix refuses for now: nothing of the tables above but fastest's
--out, and --plot without --compare-ratios (one trajectory each; refused in one line
naming the option like any refusal). A motion is a mix of one task: motors, units fixed
and ratios compared act on a mix as on a motion."""


@pytest.fixture
def work(tmp_path, monkeypatch):
    (tmp_path / "robots").symlink_to(REPO / "robots")
    (tmp_path / "motors").symlink_to(REPO / "motors")
    (tmp_path / "tr").mkdir()
    (tmp_path / "tr" / "move.toml").write_text(ONE_MOVE)
    (tmp_path / "tr" / "day.toml").write_text(DAY)
    (tmp_path / "acme.toml").write_text(ACME)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def outcome(capsys, command: str, extra: list[str], tag: str,
            motion: str = "tr/move.toml") -> tuple[int, str, bytes]:
    """Exit status, standard error, and every byte the command wrote (files, JSON, stdout)."""
    out_dir = Path(tag)
    out_dir.mkdir()
    argv = [command, motion]
    argv += ["--out", str(out_dir / "t.csv")] if command == "plan" else [
        "--json", str(out_dir / "r.json")]
    extra = [str(out_dir / x) if x in ("rep", "f.csv", "f.png", "p.png", "w.csv", "l.csv") else x
             for x in extra]
    status = main([*argv, *extra])
    out, err = capsys.readouterr()
    written = []
    for path in sorted(out_dir.rglob("*")):
        if path.suffix == ".json":  # the options echoed back are not an effect
            written.append(json.dumps(_without(json.loads(path.read_text()), "assumptions"),
                                      sort_keys=True).encode())
        elif path.is_file() and path.suffix != ".html":  # the page echoes the command
            written.append(path.read_bytes())
    return status, err, b"".join(written)


def _without(document, key):
    """The JSON document with every `key` left out, at any depth."""
    if isinstance(document, dict):
        return {k: _without(v, key) for k, v in document.items() if k != key}
    if isinstance(document, list):
        return [_without(v, key) for v in document]
    return document


@pytest.mark.slow
@pytest.mark.parametrize(("command", "option", "values", "base_args"), [
    (command, row[0], row[1], row[2] if len(row) > 2 else [])
    for command, rows in EFFECTS.items() for row in rows])
def test_an_option_changes_the_answer_or_is_refused(work, capsys, command, option, values,
                                                    base_args):
    base = outcome(capsys, command, base_args, "base")
    assert base[0] in (0, 1), base[1]
    status, err, written = outcome(capsys, command, [*base_args, option, *values], "with")
    if status == 2:
        assert len(err.strip().splitlines()) == 1 and option in err, err
        return
    assert status in (0, 1), err
    assert written != base[2], f"{command} {option} took no effect"


@pytest.mark.slow
@pytest.mark.parametrize(("command", "option", "values", "base_args"), [
    (command, row[0], row[1], row[2] if len(row) > 2 else [])
    for command, rows in MIX_EFFECTS.items() for row in rows])
def test_an_option_changes_the_answer_of_a_mix_or_is_refused(work, capsys, command, option,
                                                             values, base_args):
    refused = [arg for arg in [*base_args, option] if arg in MIX_NOT_YET.get(command, ())]
    if refused:
        status, err, _ = outcome(capsys, command, [*base_args, option, *values], "with",
                                 "tr/day.toml")
        assert status == 2 and len(err.strip().splitlines()) == 1 and refused[0] in err, err
        return
    base = outcome(capsys, command, base_args, "base", "tr/day.toml")
    assert base[0] in (0, 1), base[1]
    status, err, written = outcome(capsys, command, [*base_args, option, *values], "with",
                                   "tr/day.toml")
    if status == 2:
        assert len(err.strip().splitlines()) == 1 and option in err, err
        assert not option.startswith("--payload") or "each task's `payload`" in err, err
        return
    assert not option.startswith("--payload"), f"{command} {option} taken for a mix"
    assert status in (0, 1), err
    assert written != base[2], f"{command} {option} took no effect on a mix"


ALONE_IN_VAIN = [
    (["--max-inertia-ratio", "3"], ["--max-inertia-ratio", "--motor-catalog"]),
    (["--inertia-target", "3"], ["--inertia-target", "--prefer inertia"]),
    (["--inertia-target", "3", "--prefer", "margin"], ["--inertia-target", "--prefer inertia"]),
    (["--inertia-target", "3", "--prefer", "inertia"], ["--inertia-target", "--motor-catalog"]),
    (["--prefer", "inertia"], ["--prefer", "--motor-catalog"]),
    (["--prefer", "motor-rms"], ["--prefer", "--motor-catalog"]),
    (["--inertia-target", "3", "--motor-catalog", "motors/example_motors.toml"],
     ["--inertia-target", "--prefer inertia"]),
]
"""Options that act on gearhead and motor pairs, given where they cannot act (no motors, or
no ``--prefer inertia`` for its target): each once accepted without effect, now refused in
one line naming the option and the one it needs."""


@pytest.mark.parametrize("command", ["size", "compare", "fastest", "max-payload"])
@pytest.mark.parametrize(("extra", "named"), ALONE_IN_VAIN, ids=lambda x: " ".join(x)[:40])
def test_an_option_that_cannot_act_is_refused_naming_what_it_needs(work, capsys, command,
                                                                   extra, named):
    status, err, written = outcome(capsys, command, extra, "with")
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert all(flag in err for flag in named) and not written, err


def test_the_envelope_help_lists_no_option_it_refuses(capsys):
    with pytest.raises(SystemExit):
        main(["envelope", "--help"])
    shown = capsys.readouterr().out
    for flag in ("--motor-catalog", "--max-inertia-ratio", "--inertia-target"):
        assert flag not in shown
        assert main(["envelope", str(REPO / "robots" / "planar2.urdf"), flag, "3"]) == 2
    assert "refused beside --duty" in " ".join(shown.split())  # --moves, --seed, --jerk
    assert "--prefer {size,margin,mass}" in shown  # the orders of pairs need motors


def test_max_payload_selects_in_the_order_preferred(work):
    robot, motion = hdselect.load_case("tr/move.toml")
    options = hdselect.Options(prefer="margin")
    result = hdselect.max_payload(robot, motion, options)
    assert result.selection is not None and result.selection.options.prefer == "margin"


def test_every_option_is_in_the_table():
    for command, options in effect_options(_parser()).items():
        covered = {row[0] for row in EFFECTS.get(command, [])} | set(OTHER.get(command, []))
        assert options <= covered, (command, options - covered)


# --- Python ----------------------------------------------------------------------------------

def _public_functions():
    return [name for name in hdselect.__all__
            if name[0].islower() and name not in ("study",) and inspect.isfunction(
                getattr(hdselect, name))]


@pytest.fixture(scope="module")
def case():
    robot, motion = hdselect.load_case(REPO / "trajectories" / "planar2_pick_place.toml")
    return robot, motion, hdselect.plan(robot, motion), hdselect.load_catalog()


WRONG = [42, object()]


@pytest.mark.parametrize("name", _public_functions())
def test_a_public_function_names_the_parameter_of_a_wrong_type(case, name):
    """Each parameter in turn gets a value of no type it takes; the others valid ones."""
    robot, motion, trajectory, units = case
    valid = {"robot": robot, "motion": motion, "trajectory": trajectory, "units": units,
             "path": REPO / "robots" / "planar2.urdf", "robot_file": "planar2.urdf",
             "result": None, "tasks": (Task(robot, trajectory),)}
    if name == "check_units":
        valid["units"] = {j: units[-1] for j in robot.sized_joints}
    if name in ("load_catalog",):
        valid["path"] = None
    function = getattr(hdselect, name)
    parameters = [p for p in inspect.signature(function).parameters.values()
                  if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]
    if name in ("summarize", "size_duty", "load_duty", "load_motors", "load_catalog"):
        pytest.skip("covered with its own inputs in test_summary, test_duty, test_motors, "
                    "test_catalog")
    for parameter in parameters:
        for wrong in WRONG:
            args = {p.name: valid.get(p.name) for p in parameters
                    if p.default is inspect.Parameter.empty}
            args[parameter.name] = wrong
            with pytest.raises(InputError) as info:
                function(**args)
            message = f"{info.value.field} {info.value.reason}"
            assert parameter.name.rstrip("s") in message or parameter.name in message, (
                name, parameter.name, message)
