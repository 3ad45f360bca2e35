"""Lives beyond what the formulas can say, reported one way everywhere.

A joint that nothing loads carries the noise of the inverse dynamics (2e-10 N m gave a
life of 9.2e37 h in the JSON and the parts list while the terminal wrote "> 1e6 h"):
torques below `NOISE_FLOOR` of the robot's scale count as zero, so its life is
unlimited. A real but tiny load gives a life beyond `LIFE_CAP`: the terminal, the parts
list and the JSON all report the cap, the JSON flagging it.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.catalog.checks import LIFE_CAP
from hdselect.cli.main import main
from hdselect.robot.dynamics import NOISE_FLOOR, torque_floor
from hdselect.robot.mounting import STANDARD_GRAVITY
from helpers import REPO
from helpers.options import ONE_MOVE

PLANAR2 = REPO / "robots" / "planar2.urdf"


def _arm(tmp_path: Path, elbow_mass: str) -> Path:
    """planar2 with the elbow's link this light (its inertia 1e-13 kg m^2), no payload."""
    text = PLANAR2.read_text(encoding="utf-8").replace('<mass value="0.16875"/>',
                                                       f'<mass value="{elbow_mass}"/>')
    for element in ('ixx="1.01953e-05"', 'iyy="0.000887695"', 'izz="0.000880313"'):
        text = text.replace(element, element.split("=")[0] + '="1e-13"')
    (tmp_path / "arm.urdf").write_text(text, encoding="utf-8")
    motion = ONE_MOVE.replace("../robots/planar2.urdf", "arm.urdf")
    motion = motion[:motion.index("[payload]")] + motion[motion.index("[limits]"):]
    path = tmp_path / "move.toml"
    path.write_text(motion, encoding="utf-8")
    return path


def _outputs(capsys, motion: Path) -> tuple[str, dict, list[dict]]:
    """The terminal table, the JSON and the parts list of `size`."""
    out_json = motion.parent / "out.json"
    assert main(["size", str(motion), "--json", str(out_json)]) in (0, 1)
    table = capsys.readouterr().out
    assert main(["size", str(motion), "--bom", "-"]) in (0, 1)
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    return table, json.loads(out_json.read_text()), rows


def _elbow(document: dict) -> dict:
    joint = next(j for j in document["joints"] if j["name"] == "elbow")
    return next(c for c in joint["candidates"] if c["unit"] == joint["selected"])


def test_the_floor_is_the_robots_weight_at_its_whole_length_by_hand():
    robot = hdselect.load_robot(PLANAR2)
    mass = 0.243 + 0.16875  # the two links (the file's header)
    length = 0.30 + 0.30 + 0.15 + 0.125  # joint offsets, then the centres of mass
    assert torque_floor(robot) == pytest.approx(
        [NOISE_FLOOR * STANDARD_GRAVITY * mass * length] * 2, rel=1e-12)


def test_a_torque_at_noise_level_counts_as_zero_and_its_life_is_unlimited(capsys, tmp_path):
    motion = _arm(tmp_path, "1e-10")
    robot, loaded = hdselect.load_case(motion)
    trajectory = hdselect.plan(robot, loaded)
    data = robot.model.createData()
    raw = np.array([pin.rnea(robot.model, data, robot.configuration(trajectory.q[i][None])[:, 0],
                             trajectory.qd[i], trajectory.qdd[i])[1]
                    for i in range(len(trajectory.t))])  # Pinocchio itself, one state a call
    assert 1e-11 < np.abs(raw).max() < torque_floor(robot)[1]  # ~1e-10 N m: under the floor
    result = hdselect.size_trajectory(robot, trajectory, hdselect.load_catalog())
    shoulder, elbow = result.joints
    assert np.all(elbow.torque == 0.0) and elbow.selected.life_hours is None
    assert np.abs(shoulder.torque).max() > 1.0  # carried on as computed
    table, document, rows = _outputs(capsys, motion)
    elbow = _elbow(document)
    assert elbow["life_hours"] is None and elbow["l10_hours"] is None
    assert elbow["life_capped"] is False
    assert "unlimited" in next(r for r in table.splitlines() if r.startswith("elbow"))
    row = next(r for r in rows if r["joint"] == "elbow")
    assert row["life_l50_h"] == row["life_l10_h"] == "unlimited"
    assert next(r for r in rows if r["joint"] == "total")["life_l50_h"] == ""


def test_a_life_beyond_the_cap_reads_the_same_everywhere(capsys, tmp_path):
    motion = _arm(tmp_path, "1e-4")
    result = hdselect.size(None, motion)
    elbow = next(j for j in result.joints if j.name == "elbow")
    assert elbow.selected.life_hours > 1e9 * LIFE_CAP  # the cube law, far past the cap
    table, document, rows = _outputs(capsys, motion)
    assert "> 1e6 h" in next(r for r in table.splitlines() if r.startswith("elbow"))
    candidate = _elbow(document)
    assert candidate["life_hours"] == candidate["l10_hours"] == LIFE_CAP
    assert candidate["life_capped"] is candidate["l10_capped"] is True
    assert candidate["checks"]["life"]["value"] == LIFE_CAP
    assert candidate["checks"]["life"]["capped"] is True and candidate["checks"]["life"]["ok"]
    row = next(r for r in rows if r["joint"] == "elbow")
    assert row["life_l50_h"] == row["life_l10_h"] == "> 1e6"
    summary = next(j for j in hdselect.summarize(result).joints if j.name == "elbow")
    assert summary.life_l50_hours == LIFE_CAP and summary.life_capped
    shoulder = _elbow({"joints": [{**j, "name": "elbow"} for j in document["joints"]
                                  if j["name"] == "shoulder"]})
    assert shoulder["life_capped"] is False and 1e4 < shoulder["life_hours"] < LIFE_CAP
