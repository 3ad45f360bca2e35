"""Fuzzing the newer inputs: mix files, catalogs that rate output bearings, xacro arguments.

The promise of `test_fuzz` holds here too: exit 0, 1 or 2 (3 for a study), never a
traceback; on 2 one line, nothing on standard output and no file touched; on 0 or 1
strict JSON with finite numbers. Each run is small (the planar arm, a few thousand
samples).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.fuzz import (
    EXTREMES,
    MAX_SAMPLES,
    anything,
    check_run,
    extreme,
    output_path,
    shuffled_entries,
    toml_text,
    toml_value,
    workdir,
)

FEW = settings(max_examples=min(settings.default.max_examples, 30))

SECOND_MOTION = """robot = "../robots/planar2.urdf"
planner = "ruckig"
angle_unit = "deg"
[payload]
mass = 0.2
frame = "tool"
[limits]
velocity = 120
acceleration = 600
jerk = 6000
[safety]
stop_time = 0.1
[[waypoint]]
q = {shoulder = 0, elbow = 0}
dwell = 0.2
[[waypoint]]
q = {shoulder = 60, elbow = -90}
"""
"""A second task for the planar arm, beside tr/planar2_pick_place.toml."""


def _inline(value: object) -> str:
    """A value as TOML text, tables and lists included."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{key} = {_inline(item)}" for key, item in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_inline(item) for item in value) + "]"
    return toml_value(value)


# --- mixes --------------------------------------------------------------------------------------

@st.composite
def mix_files(draw) -> str:
    lines: list[str] = []
    if draw(st.booleans()):
        robot = draw(st.sampled_from(["../robots/planar2.urdf", "../robots/pan_tilt.urdf",
                                      "nowhere.urdf", 3]))
        lines.append(f"robot = {_inline(robot)}")
    if draw(st.booleans()):
        lines += ["[requirements]",
                  f"life_hours = {_inline(draw(st.one_of(st.floats(100, 1e6), extreme)))}"]
    if draw(st.integers(0, 3)) == 0:
        lines += ["[safety]", f"stop_time = {_inline(draw(st.one_of(st.just(0.1), extreme)))}"]
    by_rate = draw(st.booleans())
    names = draw(st.sampled_from([["pick", "move"], ["pick", "pick"], ["pick"], ["a", ""]]))
    motions = ["planar2_pick_place.toml", "second.toml"]
    for index, name in enumerate(names):
        motion = draw(st.sampled_from([motions[index % 2], motions[index % 2], "missing.toml"]))
        lines += ["[[task]]", f"name = {_inline(name)}", f"motion = {_inline(motion)}"]
        if by_rate:
            rate = draw(st.one_of(st.floats(1, 300), extreme, anything))
            lines.append(f"cycles_per_hour = {_inline(rate)}")
        else:
            share = draw(st.one_of(st.just(1 / len(names)), extreme, anything))
            lines.append(f"share = {_inline(share)}")
        if draw(st.integers(0, 2)) == 0:
            payload = {"mass": draw(st.one_of(st.floats(0.01, 2.0), extreme)),
                       "frame": draw(st.sampled_from(["tool", "tool", "link9", ""]))}
            if draw(st.booleans()):
                payload["com"] = draw(st.sampled_from([[0.0, 0.0, 0.02], [EXTREMES[0], 0, 0],
                                                       [0.0, 0.0]]))
            lines.append(f"payload = {_inline(payload)}")
        if draw(st.integers(0, 5)) == 0:
            mounting = draw(st.sampled_from(["wall", "roof", 3]))
            lines.append(f"mounting = {_inline(mounting)}")
        if draw(st.integers(0, 8)) == 0:
            lines.append("colour = 1")  # not a task key
    return "\n".join(lines) + "\n"


@pytest.mark.slow
@FEW
@given(mix_files(), st.sampled_from(["size", "size", "compare"]))
def test_fuzz_mix_files(text, command):
    with workdir() as work:
        Path("tr/second.toml").write_text(SECOND_MOTION)
        Path("tr/mix.toml").write_text(text)
        check_run(work, [command, "tr/mix.toml", "--json", "-", "--max-samples", MAX_SAMPLES],
                  stdout_json=True)


@settings(max_examples=min(settings.default.max_examples, 12))
@given(st.sampled_from([[[1.0]], [[0.5, 0.5]], [[1.0, 0.0], [0.3, 0.7]], [[0.5, 0.6]],
                        [[2.0, -1.0]]]),
       st.sampled_from([None, {"pick": 0.3}, {"nosuch": 0.3}, {"pick": -1.0}]),
       st.sampled_from(["out.csv", os.devnull, "existing_dir", "none/out.csv"]))
def test_fuzz_mix_studies(shares, payloads, out):
    with workdir() as work:
        Path("tr/second.toml").write_text(SECOND_MOTION)
        Path("tr/mix.toml").write_text(
            '[[task]]\nname = "pick"\nmotion = "planar2_pick_place.toml"\nshare = 0.5\n'
            '[[task]]\nname = "move"\nmotion = "second.toml"\nshare = 0.5\n')
        lines = ['title = "mix"', 'compute = "size"', "[base]", 'motion = "tr/mix.toml"',
                 f"max_samples = {MAX_SAMPLES}", "[grid]", f"shares = {_inline(shares)}"]
        if payloads is not None:
            lines.append(f"payloads = [{_inline(payloads)}]")
        Path("study.toml").write_text("\n".join(lines) + "\n")
        status = check_run(work, ["study", "study.toml", "--out", out, "--workers", "0"],
                           statuses=(0, 2, 3))
        valid = all(abs(sum(row) - 1) < 1e-9 and len(row) == 2 and min(row) >= 0
                    for row in shares)
        if not valid or payloads is not None and ("nosuch" in payloads
                                                  or min(payloads.values()) < 0):
            assert status == 2, (shares, payloads)


# --- catalogs that rate the output bearing ------------------------------------------------------

BEARING_KEYS = {"pitch_diameter_m": 0.025, "dynamic_rating_n": 1800, "static_rating_n": 2400,
                "max_moment_nm": 6.0, "max_radial_n": 300, "max_axial_n": 500,
                "offset_m": 0.005}
"""The example catalog's bearing of the smaller unit."""


@st.composite
def bearing_catalogs(draw) -> str:
    entries: list[tuple[str, object]] = [
        ("series", "XB"), ("[rules]", None),
        ("rated_input_speed_rpm", 1750), ("rated_life_hours", 35000), ("life_basis", "L50"),
        ("mean_torque_limit", "speed-adjusted"), ("mean_speed", "moving"),
        ("max_momentary_events", 10000)]
    if draw(st.booleans()):
        entries.append(("bearing_load_factor", draw(st.one_of(st.just(1.2), extreme))))
    if draw(st.booleans()):
        entries.append(("bearing_static_safety", draw(st.one_of(st.just(1.5), extreme))))
    text = toml_text(draw(shuffled_entries(entries)))
    for size, torque in ((14, 12.0), (20, 40.0)):
        unit = [("size", size), ("ratio", 100), ("rated_torque_nm", torque / 2),
                ("repeated_torque_nm", torque), ("momentary_torque_nm", torque * 2),
                ("static_torque_nm", torque * 2), ("max_input_speed_rpm", 7000),
                ("input_inertia_kg_cm2", 0.01), ("mass_kg", 0.5)]
        bearing = [(key, value * size / 14) for key, value in BEARING_KEYS.items()
                   if draw(st.integers(0, 6)) > 0]
        for index in draw(st.lists(st.integers(0, len(bearing) - 1), max_size=2)) \
                if bearing else []:
            bearing[index] = (bearing[index][0], draw(st.one_of(extreme, anything)))
        text += "\n[[unit]]\n" + toml_text(unit) + "\n[unit.bearing]\n" + toml_text(bearing)
    return text


@pytest.mark.slow
@FEW
@given(bearing_catalogs(), st.sampled_from(["size", "compare", "max-payload"]))
def test_fuzz_bearing_catalogs(text, command):
    with workdir() as work:
        Path("bearing.toml").write_text(text)
        check_run(work, [command, "tr/planar2_pick_place.toml", "--catalog", "bearing.toml",
                         "--json", "-", "--max-samples", MAX_SAMPLES], stdout_json=True)


# --- xacro arguments ----------------------------------------------------------------------------

xacro_value = st.one_of(st.sampled_from(["0.5", "2.0", "nan", "inf", "-1", "1e308", "1e-300",
                                         "abc", "", "0"]), extreme.map(repr))
xacro_name = st.sampled_from(["gripper_mass", "gripper_mass", "gripper_mas", "nosuch", ""])


@pytest.mark.slow
@FEW
@given(st.lists(st.tuples(xacro_name, xacro_value), min_size=1, max_size=2),
       st.sampled_from(["joints", "size", "plan", "motion-file"]), output_path)
def test_fuzz_xacro_arguments(arguments, command, out):
    with workdir() as work:
        motion = (Path("tr/planar2_pick_place.toml").read_text()
                  .replace("../robots/planar2.urdf", "../robots/planar2_gripper.urdf.xacro")
                  .replace('frame = "tool"', 'frame = "gripper"'))
        if command == "motion-file":
            table = ", ".join(f"{name or 'x'} = {toml_value(value)}" for name, value in arguments)
            motion = motion.replace('planner = "ruckig"',
                                    f'planner = "ruckig"\nxacro_args = {{{table}}}')
        Path("tr/xacro.toml").write_text(motion)
        options = [] if command == "motion-file" else [
            item for name, value in arguments for item in ("--xacro-arg", f"{name}:={value}")]
        if command == "joints":
            argv = ["joints", "robots/planar2_gripper.urdf.xacro", *options, "--json", out]
        elif command == "plan":
            argv = ["plan", "tr/xacro.toml", *options, "--out", out]
        else:
            argv = ["size", "tr/xacro.toml", *options, "--json", out]
        status = check_run(work, [*argv, "--max-samples", MAX_SAMPLES] if command != "joints"
                           else argv, json_files=(out,) if out.endswith(".json") else (),
                           csv_files=(out,) if command == "plan" and out in ("-", "out.csv")
                           else ())
        declared = all(name == "gripper_mass" for name, _ in arguments)
        if not declared:
            assert status == 2, arguments
