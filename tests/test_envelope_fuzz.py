"""Fuzzing ``hdselect envelope``: envelope files and command lines with hostile values.

The promise of `test_fuzz` holds here too: exit 0, 1 or 2, never a traceback; on 2 one
line and no file touched; on 0 or 1 strict JSON with finite numbers. Each run is kept
small (the planar arm, 64 starts, a short default duty).
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.fuzz import (
    anything,
    check_run,
    extreme,
    option_value,
    output_path,
    toml_value,
    workdir,
)

SMALL = ["--starts", "64", "--moves", "2", "--max-samples", "20000"]
FEW = settings(max_examples=min(settings.default.max_examples, 30))


@st.composite
def envelope_files(draw) -> str:
    entries: list[tuple[str, object]] = [
        ("robot", draw(st.sampled_from(["../robots/planar2.urdf", "../robots/planar2.urdf",
                                        "../robots/index_table.urdf", "nowhere.urdf", 3]))),
        ("angle_unit", draw(st.sampled_from(["deg", "deg", "rad", "grad"])))]
    if draw(st.booleans()):
        entries.append(("mounting", draw(st.sampled_from(["floor", "wall", "roof"]))))
    limits = {"velocity": draw(st.sampled_from([180, 90.0, [180, 90], {"elbow": 45}])),
              "acceleration": draw(st.sampled_from([900, 600.0, [900, 300],
                                                    {"shoulder": 500, "elbow": 500}]))}
    for key in list(limits):
        if draw(st.integers(0, 4)) == 0:
            limits[key] = draw(st.one_of(extreme, anything))
    if draw(st.booleans()):
        limits["jerk"] = draw(st.one_of(st.just(9000), extreme))
    if draw(st.integers(0, 6)) == 0:
        limits["torque"] = 3  # not an envelope key
    lines = [f"{key} = {toml_value(value)}" for key, value in entries]
    lines.append("[limits]")
    lines += [f"{key} = {_toml(value)}" for key, value in limits.items()]
    if draw(st.booleans()):
        lines += ["[safety]", f"stop_time = {toml_value(draw(st.one_of(st.just(0.1), extreme)))}"]
    if draw(st.booleans()):
        lines += ["[payload]", f"mass = {toml_value(draw(st.one_of(st.just(0.3), extreme)))}",
                  'frame = "tool"']
    duty = draw(st.sampled_from(["", "moves = 2", "moves = 0", "seed = -1",
                                 'motion = "planar2_pick_place.toml"', "moves = 2\nseed = 3"]))
    if duty:
        lines += ["[duty]", duty]
    return "\n".join(lines) + "\n"


def _toml(value: object) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"
    return toml_value(value)


@pytest.mark.slow
@FEW
@given(envelope_files(), output_path)
def test_fuzz_envelope_files(text, out):
    with workdir() as work:
        spec = work / "tr" / "spec.toml"
        spec.write_text(text)
        check_run(work, ["envelope", str(spec), *SMALL, "--json", out],
                  stdout_json=out == "-", json_files=(out,) if out.endswith(".json") else ())


@st.composite
def command_lines(draw) -> list[str]:
    argv = ["envelope", draw(st.sampled_from(["robots/planar2.urdf", "robots/planar2.urdf",
                                              "robots/pan_tilt.urdf", "none.urdf",
                                              "tr/planar2_pick_place.toml"]))]
    options = {
        "--velocity": lambda: draw(st.one_of(option_value, st.sampled_from(
            ["shoulder=90", "elbow=nan", "knee=3", "shoulder=90,elbow=45", "=3"]))),
        "--acceleration": lambda: draw(st.one_of(option_value, st.just("900"))),
        "--jerk": lambda: draw(option_value),
        "--angle-unit": lambda: draw(st.sampled_from(["deg", "rad"])),
        "--stop-time": lambda: draw(option_value),
        "--payload": lambda: draw(option_value),
        "--duty": lambda: draw(st.sampled_from(["tr/planar2_pick_place.toml", "none.toml",
                                                "robots/planar2.urdf"])),
        "--moves": lambda: draw(st.sampled_from(["0", "-1", "1", "2", "x", "100000"])),
        "--starts": lambda: draw(st.sampled_from(["0", "63", "64", "100", "-64", "1e3"])),
        "--life-hours": lambda: draw(option_value),
        "--joints": lambda: draw(st.sampled_from(["shoulder", "elbow,pan", ""])),
    }
    argv += ["--acceleration", "900"] if draw(st.booleans()) else []
    for option in draw(st.lists(st.sampled_from(list(options)), max_size=4, unique=True)):
        argv += [option, options[option]()]
    argv += ["--starts", "64"] if "--starts" not in argv else []
    argv += ["--moves", "2"] if "--moves" not in argv else []
    return argv + ["--max-samples", "20000"]


@pytest.mark.slow
@FEW
@given(command_lines(), output_path)
def test_fuzz_envelope_command_lines(argv, out):
    with workdir() as work:
        check_run(work, [*argv, "--json", out], stdout_json=out == "-",
                  json_files=(out,) if out.endswith(".json") else ())
