"""Every number of a catalog file and of a motor file, pushed to the edges of a float.

Each field of the example files (catalogs/example_rated_bearing.toml, with its rated
output bearings, and motors/example_motors.toml) in turn gets 1e-300, 1e308, 0 and -1.
The promise: the file is refused in one line naming it and the field (exit 2), or the
sizing runs (exit 0 or 1) and its JSON holds only finite numbers, none huge: no quotient
of a rating that underflows to 0 (a bearing's C = 1e-300 N once gave ZeroDivisionError,
exit 70; its C0 a static safety utilization of 3e301).
"""

from __future__ import annotations

import json
import re

import pytest

from hdselect.cli.main import main
from helpers import REPO
from helpers.options import ONE_MOVE

CATALOG = (REPO / "catalogs" / "example_rated_bearing.toml").read_text(encoding="utf-8")
MOTORS = (REPO / "motors" / "example_motors.toml").read_text(encoding="utf-8")
EDGES = ("1e-300", "1e308", "0", "-1")
HUGE = 1e100
"""No number a sizing writes is this large: it would be a quotient of a vanishing rating."""


def _fields(text: str) -> list[tuple[int, str]]:
    """(line number, key) of every number the first entry of each table gives."""
    found, seen = [], set()
    section = ""
    for number, line in enumerate(text.splitlines()):
        if line.startswith("["):
            section = line
        match = re.match(r"^(\w+) = (\[[-\d., e]+\]|[-\d.e]+)\s*(#.*)?$", line)
        if match and (section, match.group(1)) not in seen:
            seen.add((section, match.group(1)))
            found.append((number, match.group(1)))
    return found


def _edited(text: str, line: int, value: str) -> str:
    lines = text.splitlines()
    key, _, given = lines[line].partition(" = ")
    if given.startswith("["):  # a curve: its second point
        points = given.strip("[]").split(",")
        points[min(1, len(points) - 1)] = f" {value}"
        value = "[" + ",".join(points).strip() + "]"
    lines[line] = f"{key} = {value}"
    return "\n".join(lines) + "\n"


CASES = ([("catalog", line, key) for line, key in _fields(CATALOG)]
         + [("motors", line, key) for line, key in _fields(MOTORS)]
         + [("motors", -1, "max_inertia_ratio")])


def test_every_field_is_pushed():
    keys = {key for _, _, key in CASES}
    assert {"pitch_diameter_m", "dynamic_rating_n", "static_rating_n", "max_moment_nm",
            "max_radial_n", "max_axial_n", "offset_m", "rated_life_hours", "mass_kg",
            "bearing_load_factor", "resistance_ohm", "peak_torque_nm", "speed_rpm",
            "rotor_inertia_kg_cm2", "torque_constant_nm_per_a"} <= keys


@pytest.mark.parametrize("value", EDGES)
@pytest.mark.parametrize(("kind", "line", "key"), CASES,
                         ids=[f"{kind}-{line}-{key}" for kind, line, key in CASES])
def test_a_number_at_the_edge_is_refused_or_gives_finite_answers(capsys, tmp_path,
                                                                 monkeypatch, kind, line,
                                                                 key, value):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "move.toml").write_text(ONE_MOVE.replace("../robots", str(REPO / "robots")))
    if kind == "catalog":
        text, flag, name = _edited(CATALOG, line, value), "--catalog", "cat.toml"
    elif line < 0:
        text, flag, name = f"{key} = {value}\n" + MOTORS, "--motor-catalog", "mot.toml"
    else:
        text, flag, name = _edited(MOTORS, line, value), "--motor-catalog", "mot.toml"
    (tmp_path / name).write_text(text)
    status = main(["size", "move.toml", flag, name, "--json", "out.json"])
    out, err = capsys.readouterr()
    if status == 2:
        lines = err.strip().splitlines()
        in_curve = kind == "motors" and line >= 0 and "[" in MOTORS.splitlines()[line]
        assert len(lines) == 1 and name in lines[0], err
        assert key in lines[0] or (in_curve and "curve" in lines[0]), err
        assert not (tmp_path / "out.json").exists()
        return
    assert status in (0, 1), err

    def strict(constant: str) -> float:
        raise AssertionError(f"{key} = {value}: {constant} in the JSON")

    document = json.loads((tmp_path / "out.json").read_text(), parse_constant=strict)
    huge = [(where, number) for where, number in _numbers(document) if abs(number) > HUGE]
    assert not huge, (key, value, huge[:5])


def _numbers(document, where: str = ""):
    if isinstance(document, dict):
        for k, v in document.items():
            yield from _numbers(v, f"{where}.{k}")
    elif isinstance(document, list):
        for i, v in enumerate(document):
            yield from _numbers(v, f"{where}[{i}]")
    elif isinstance(document, float | int) and not isinstance(document, bool):
        yield where, float(document)
