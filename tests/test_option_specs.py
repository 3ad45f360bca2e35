"""Every declared option reaches `Options` by each way it is declared, and is refused out of range.

The rows come from `hdselect.motion.option_specs.OPTIONS` itself: a new option is
covered as a field of `Options`, as its flag on ``size``, as its key in the motion,
mix and envelope files that declare one, and as a study parameter, without a new row.
Each value is checked by where it arrives (the `Options` the path builds), and each
out-of-range value by the one error naming the field as the user gave it.
"""

from __future__ import annotations

import math
from dataclasses import fields
from pathlib import Path
from typing import Any

import pytest

from hdselect import Options
from hdselect.base.errors import InputError
from hdselect.cli.inputs import sizing_options_of
from hdselect.cli.main import _parser
from hdselect.envelope.specfile import load_envelope_file
from hdselect.motion.mixfile import load_mix
from hdselect.motion.motionfile import load_motion
from hdselect.motion.option_specs import OPTION, OPTIONS, Option, given_by
from hdselect.robot.model import load_robot
from hdselect.sizing.mixtasks import mix_options
from hdselect.sizing.options import options_for
from hdselect.study.spec import load_study
from helpers import REPO

ROBOT = REPO / "robots" / "index_table.urdf"
JOINT = "table"
MOTION = f"""robot = "{ROBOT}"
planner = "ruckig"
angle_unit = "deg"

[limits]
velocity = 270
acceleration = 2000
jerk = 30000

[[waypoint]]
q = [0]

[[waypoint]]
q = [90]
"""
"""The index table's motion, to which a test adds the option's table."""


def good(option: Option) -> Any:
    """A valid value of the option that is not its default (not one needing motors)."""
    if option.kind == "number":
        assert option.bound is not None
        low, high = option.bound.low, option.bound.high
        value = math.sqrt(low * high) if low > 0.0 else high / 2.0
    elif option.kind == "count":
        value = 2
    elif option.kind == "samples":
        value = 1000
    elif option.kind == "switch":
        value = not option.default
    elif option.kind == "choice":
        value = next(c for c in option.choices
                     if c != option.default and not option.needs_motors(c))
    elif option.kind == "joints":
        assert option.bound is not None
        value = {JOINT: option.bound.high / 2.0}
    else:
        value = {JOINT: 0.01}
    assert value != option.default
    return value


def bad(option: Option) -> Any:
    """A value of the right type, out of the option's range (or not of its kind)."""
    if option.kind in ("number", "joints"):
        assert option.bound is not None  # out of range in SI and in the files' unit
        high = option.bound.high / option.scale * 10.0 + 1.0
        return high if option.kind == "number" else {JOINT: high}
    return {"count": 0, "samples": 1, "switch": "yes", "choice": "nonesuch",
            "offsets": {JOINT: 1e3}}[option.kind]


def si(option: Option, value: Any) -> Any:
    """A value given in a file's or a flag's unit (arcmin, mm), in SI as `Options` holds it."""
    return option.check(value, edge=True)


def flag_value(option: Option, value: Any) -> list[str]:
    """A value as the option's flag takes it (a per-joint value as JOINT=VALUE)."""
    if isinstance(value, dict):
        return [f"{joint}={item}" for joint, item in value.items()]
    return [str(value)]


def toml(value: Any) -> str:
    """A value as TOML writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {toml(v)}" for k, v in value.items()) + " }"
    return repr(value)


def with_key(option: Option, value: Any) -> str:
    """The option's table of a file, giving `value` under its key."""
    assert option.key is not None
    table, key = option.key.split(".")
    return f"\n[{table}]\n{key} = {toml(value)}\n"


def in_files(kind: str) -> list[Option]:
    return [option for option in OPTIONS if kind in option.files]


def ids(option: Option) -> str:
    return option.name


def test_options_has_a_field_per_declared_option_with_its_default():
    assert [f.name for f in fields(Options)] == [option.name for option in OPTIONS]
    defaults = Options()
    for option in OPTIONS:
        assert getattr(defaults, option.name) == option.default, option.name


@pytest.mark.parametrize("option", OPTIONS, ids=ids)
def test_python_takes_the_value_and_refuses_it_out_of_range(option):
    value = good(option)
    assert getattr(Options(**{option.name: value}), option.name) == value
    assert getattr(options_for(None, **{option.name: value}), option.name) == value
    with pytest.raises(InputError) as caught:
        Options(**{option.name: bad(option)})
    assert str(caught.value.field).split(".")[0] == option.name and caught.value.path is None


def size_args(motion: Path, *extra: str):
    return _parser().parse_args(["size", str(motion), *extra])


@pytest.mark.parametrize("option", [o for o in OPTIONS if o.flag], ids=ids)
def test_the_flag_gives_the_value_and_refuses_it_out_of_range(option, tmp_path, capsys):
    motion_file = tmp_path / "motion.toml"
    motion_file.write_text(MOTION)
    motion = load_motion(motion_file)
    value = good(option)
    assert option.flag is not None
    given = [option.flag] if option.kind == "switch" else [option.flag,
                                                           *flag_value(option, value)]
    assert getattr(sizing_options_of(size_args(motion_file, *given), motion),
                   option.name) == si(option, value)
    if option.kind == "switch":
        return  # a flag without a value: nothing to give out of range
    if option.choices:
        with pytest.raises(SystemExit) as ended:
            size_args(motion_file, option.flag, str(bad(option)))
        assert ended.value.code == 2 and option.flag in capsys.readouterr().err
        return
    with pytest.raises(InputError) as caught:
        sizing_options_of(size_args(motion_file, option.flag, *flag_value(option, bad(option))),
                          motion)
    assert caught.value.field == option.flag and caught.value.path is None


@pytest.mark.parametrize("option", in_files("motion"), ids=ids)
def test_the_motion_file_gives_the_value_and_refuses_it_out_of_range(option, tmp_path):
    path = tmp_path / "motion.toml"
    value = good(option)
    path.write_text(MOTION + with_key(option, value))
    assert getattr(options_for(load_motion(path)), option.name) == si(option, value)
    path.write_text(MOTION + with_key(option, bad(option)))
    with pytest.raises(InputError) as caught:
        load_motion(path)
    assert caught.value.path == path and str(caught.value.field).startswith(str(option.key))


def mix(tmp_path: Path, table: str) -> Path:
    (tmp_path / "motion.toml").write_text(MOTION)
    path = tmp_path / "mix.toml"
    path.write_text(f'robot = "{ROBOT}"\n{table}\n[[task]]\nname = "index"\n'
                    'motion = "motion.toml"\nshare = 1.0\n')
    return path


@pytest.mark.parametrize("option", in_files("mix"), ids=ids)
def test_the_mix_file_gives_the_value_and_refuses_it_out_of_range(option, tmp_path):
    robot = load_robot(ROBOT)
    value = good(option)
    read = load_mix(mix(tmp_path, with_key(option, value)), robot)
    assert getattr(mix_options(read), option.name) == si(option, value)
    with pytest.raises(InputError) as caught:
        load_mix(mix(tmp_path, with_key(option, bad(option))), robot)
    assert caught.value.path == tmp_path / "mix.toml"
    assert str(caught.value.field).startswith(str(option.key))


@pytest.mark.parametrize("option", in_files("envelope"), ids=ids)
def test_the_envelope_file_gives_the_value_and_refuses_it_out_of_range(option, tmp_path):
    robot = load_robot(ROBOT)
    path = tmp_path / "envelope.toml"
    head = f'robot = "{ROBOT}"\nangle_unit = "deg"\n'
    path.write_text(head + with_key(option, good(option)))
    assert given_by(load_envelope_file(path, robot), "envelope") == {
        option.name: si(option, good(option))}
    path.write_text(head + with_key(option, bad(option)))
    with pytest.raises(InputError) as caught:
        load_envelope_file(path, robot)
    assert caught.value.path == path
    assert str(caught.value.field).startswith(str(option.key))


@pytest.mark.parametrize("option", [o for o in OPTIONS if o.study], ids=ids)
def test_a_study_gives_the_value_and_refuses_it_out_of_range(option, tmp_path):
    (tmp_path / "motion.toml").write_text(MOTION)
    path = tmp_path / "study.toml"
    value, wrong = good(option), bad(option)
    if option.kind == "joints":  # a study gives every joint's value
        value, wrong = value[JOINT], wrong[JOINT]
    path.write_text(f'[base]\nmotion = "motion.toml"\n{option.name} = {toml(value)}\n')
    assert load_study(path).cases[0].options == {option.name: value}
    path.write_text(f'[base]\nmotion = "motion.toml"\n{option.name} = {toml(wrong)}\n')
    with pytest.raises(InputError) as caught:
        load_study(path)
    assert caught.value.path == path and caught.value.field == f"base.{option.name}"


UNDECLARED = [(option, kind) for option in OPTIONS if option.key is not None
              for kind in ("motion", "mix", "envelope") if kind not in option.files]
"""Each file key in the kinds of file that do not declare it."""


@pytest.mark.parametrize(("option", "kind"), UNDECLARED,
                         ids=lambda v: v.name if isinstance(v, Option) else v)
def test_a_key_is_refused_in_a_file_that_does_not_declare_it(option, kind, tmp_path):
    """A mix file's [sizing] options are the duty's alone: a motion or envelope file
    giving one is refused, naming the key, never read as something else or ignored."""
    table = with_key(option, good(option))
    robot = load_robot(ROBOT)
    if kind == "motion":
        path = tmp_path / "motion.toml"
        path.write_text(MOTION + table)
        read = lambda: load_motion(path)  # noqa: E731
    elif kind == "mix":
        path = mix(tmp_path, table)
        read = lambda: load_mix(path, robot)  # noqa: E731
    else:
        path = tmp_path / "envelope.toml"
        path.write_text(f'robot = "{ROBOT}"\nangle_unit = "deg"\n{table}')
        read = lambda: load_envelope_file(path, robot)  # noqa: E731
    with pytest.raises(InputError) as caught:
        read()
    assert caught.value.path == path and caught.value.field == option.key
    assert "unknown key" in caught.value.reason


OFFSET = "\n[sizing]\nbearing_offset_m = { table = 0.05 }\n"
"""A motion's output flange 50 mm along the index table's axis."""


def test_a_mix_of_one_motion_keeps_its_bearing_offset(tmp_path):
    """Shares (1, 0) reproduce the motion: its flange offset too (a mix once dropped it
    and took the bearing's loads about the joint origin)."""
    from hdselect import size

    (tmp_path / "motion.toml").write_text(MOTION + OFFSET)
    alone = size(None, tmp_path / "motion.toml")
    (tmp_path / "mix.toml").write_text(f'robot = "{ROBOT}"\n\n[[task]]\nname = "index"\n'
                                       'motion = "motion.toml"\nshare = 1.0\n')
    mixed = size(None, tmp_path / "mix.toml")
    assert alone.options.bearing_offset == mixed.options.bearing_offset == {JOINT: 0.05}
    assert alone.joints[0].bearing is not None and alone.joints[0].bearing.offset == 0.05
    assert mixed.joints[0].bearing == alone.joints[0].bearing


def test_a_mix_settles_the_bearing_offset_for_the_whole_duty(tmp_path):
    """Two motions giving different offsets are refused naming both files; the mix file's
    [sizing] bearing_offset_m settles it over theirs."""
    robot = load_robot(ROBOT)
    (tmp_path / "near.toml").write_text(MOTION + OFFSET)
    (tmp_path / "far.toml").write_text(MOTION + OFFSET.replace("0.05", "0.08"))
    tasks = ('\n[[task]]\nname = "near"\nmotion = "near.toml"\nshare = 0.5\n'
             '\n[[task]]\nname = "far"\nmotion = "far.toml"\nshare = 0.5\n')
    path = tmp_path / "mix.toml"
    path.write_text(f'robot = "{ROBOT}"\n{tasks}')
    with pytest.raises(InputError, match="near.toml gives sizing.bearing_offset_m "
                                         r"\{table = 0.05\}.*far.toml gives \{table = 0.08\}"):
        mix_options(load_mix(path, robot))
    path.write_text(f'robot = "{ROBOT}"\n{OFFSET.replace("0.05", "0.02")}{tasks}')
    settled = load_mix(path, robot)
    assert mix_options(settled).bearing_offset == {JOINT: 0.02}
    assert any("bearing_offset_m" in note for note in settled.overrides)


@pytest.mark.parametrize("option", [o for o in OPTIONS if o.pairs or o.requires], ids=ids)
def test_a_flag_that_acts_on_pairs_is_refused_without_motors(option, tmp_path):
    """Each value that acts on gearhead and motor pairs only is refused without motors,
    and accepted with them; one that needs another option's value is refused without it."""
    from hdselect.cli.inputs import refuse_pair_flags

    motion = tmp_path / "motion.toml"
    motion.write_text(MOTION)
    assert option.flag is not None
    values = [c for c in option.choices if option.needs_motors(c)] or [str(good(option))]
    for value in values:
        given = [option.flag, value]
        if option.requires is not None:
            with pytest.raises(InputError) as caught:
                refuse_pair_flags(size_args(motion, *given), motors=True)
            other = OPTION[option.requires[0]]
            assert caught.value.field == option.flag and f"{other.flag} {option.requires[1]}" \
                in caught.value.reason
            given += [str(other.flag), option.requires[1]]
        refuse_pair_flags(size_args(motion, *given), motors=True)
        with pytest.raises(InputError) as caught:
            refuse_pair_flags(size_args(motion, *given), motors=False)
        assert caught.value.field == option.flag and "no motor is given" in caught.value.reason
