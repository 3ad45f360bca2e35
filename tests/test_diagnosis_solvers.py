"""A joint no unit holds, as fastest, max-payload, envelope and studies say it: a result.

The oracle is a one-link pendulum on a horizontal axis, a point-like bob of mass m at
l from the axis: gravity holds it with m g l cos q, the largest (m g l) where the link is
horizontal, and its inertia about the axis is m l^2 + I_yy. With m g l over every PSA-G
unit's repeated peak (20.3 N m) nothing can help but another unit or leaving the joint
out; with a light bob only the acceleration fails, and lower limits do help.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import re
from pathlib import Path

import pytest

from helpers import run

G = 9.80665
"""Standard gravity, the mounting's default [m/s^2]."""

STRONGEST_PEAK = 20.3
"""PSA-14-100's repeated peak torque, the largest of the PSA-G page [N m]."""

PYBULLET_DATA = (Path(importlib.util.find_spec("pybullet_data").origin).parent
                 if importlib.util.find_spec("pybullet_data") else None)

ENVELOPE_QUICK = ("--starts", "64", "--moves", "2")


def pendulum(folder: Path, mass: float, length: float, inertia: float = 1e-4) -> Path:
    """A bob of `mass` [kg] at `length` [m] on a horizontal axis (y), range +-60 deg."""
    path = folder / "pendulum.urdf"
    path.write_text(
        '<robot name="pendulum"><link name="base"/><link name="bob"><inertial>'
        f'<origin xyz="{length} 0 0"/><mass value="{mass}"/><inertia ixx="{inertia}" '
        f'ixy="0" ixz="0" iyy="{inertia}" iyz="0" izz="{inertia}"/></inertial></link>'
        '<joint name="swing" type="revolute"><parent link="base"/><child link="bob"/>'
        '<axis xyz="0 1 0"/><limit lower="-1.0472" upper="1.0472" effort="100" '
        'velocity="3"/></joint></robot>')
    return path


def swing_motion(folder: Path, payload: bool = False) -> Path:
    """From -30 to 30 deg and back: it passes the horizontal (the most gravity) moving."""
    path = folder / "swing.toml"
    path.write_text(
        'robot = "pendulum.urdf"\nplanner = "ruckig"\nangle_unit = "deg"\ndt = 0.002\n'
        + ('[payload]\nmass = 0.2\ncom = [0.0, 0.0, 0.0]\n' if payload else "")
        + "[limits]\nvelocity = 60\nacceleration = 120\njerk = 2000\n"
        "[[waypoint]]\nq = [-30]\ndwell = 0.2\n[[waypoint]]\nq = [30]\ndwell = 0.2\n"
        "[[waypoint]]\nq = [-30]\n")
    return path


def flat(text: str) -> str:
    """Printed text as one line (the terminal wraps it)."""
    return " ".join(text.split())


def gravity_said(text: str, joint: str) -> float:
    """The gravity-alone torque a diagnosis states for a joint [N m]."""
    found = re.search(rf"{joint}: gravity alone needs ([\d.,]+) N m, over every unit's limit",
                      flat(text))
    assert found, text
    return float(found.group(1).replace(",", ""))


def assert_no_wrong_advice(text: str) -> None:
    """Neither of the old advices that fail where gravity alone is too much."""
    assert "lower the limits" not in text and "give one with --units" not in text
    assert "lower the velocity and acceleration limits" not in flat(text)


@pytest.fixture
def heavy(tmp_path):
    """m g l = 5 kg x 9.80665 x 0.5 m = 24.5 N m: over PSA-14-100's 20.3 N m."""
    pendulum(tmp_path, 5.0, 0.5)
    return tmp_path, 5.0 * G * 0.5


def test_fastest_says_gravity_alone_and_exits_1(capsys, heavy):
    folder, weight = heavy
    assert weight > STRONGEST_PEAK
    status, out, err = run(capsys, "fastest", swing_motion(folder), "--json",
                           folder / "fastest.json")
    assert status == 1 and err == ""
    assert "joint 'swing' on this motion at any speed" in flat(out)
    assert gravity_said(out, "swing") == pytest.approx(weight, rel=5e-3)
    assert "PSA-14-100: 20.3 N m" in flat(out)
    assert "no slow-down or lower speed/acceleration limit helps" in flat(out)
    assert_no_wrong_advice(out)
    document = json.loads((folder / "fastest.json").read_text())
    assert document["feasible"] is False and document["cycle_time_s"] is None
    (row,) = document["no_unit"]
    assert row["joint"] == "swing" and row["diagnosis"]["gravity"]["exceeds"] is True
    assert row["diagnosis"]["gravity"]["torque_nm"] == pytest.approx(weight, rel=5e-3)


def test_fastest_with_a_unit_given_that_cannot_hold_gravity_is_a_result(capsys, heavy):
    folder, weight = heavy
    status, out, err = run(capsys, "fastest", swing_motion(folder), "--units",
                           "swing=PSA-14-100", "--out", folder / "never.csv")
    assert status == 1 and err == ""
    text = flat(out)
    assert "joint 'swing' cannot hold its gravity load at any speed" in text
    found = re.search(r"([\d.]+) N m between .* beyond its repeated-peak limit 20\.3 N m", text)
    assert found and float(found.group(1)) == pytest.approx(weight, rel=5e-3)
    assert not (folder / "never.csv").exists()


def test_max_payload_names_the_joint_and_gravity(capsys, heavy):
    folder, weight = heavy
    status, out, _ = run(capsys, "max-payload", swing_motion(folder, payload=True), "--json",
                         folder / "payload.json")
    assert status == 1
    assert "no payload mass, not even none" in flat(out)
    assert "Even without the payload no unit fits swing" in flat(out)
    assert gravity_said(out, "swing") == pytest.approx(weight, rel=5e-3)
    assert_no_wrong_advice(out)
    document = json.loads((folder / "payload.json").read_text())
    assert document["max_payload_kg"] is None
    assert [row["joint"] for row in document["no_unit"]] == ["swing"]


def test_envelope_says_gravity_alone_over_the_range_and_no_lower_limit(capsys, heavy):
    folder, weight = heavy
    status, out, _ = run(capsys, "envelope", folder / "pendulum.urdf", "--velocity", "30",
                         "--acceleration", "60", "--json", folder / "envelope.json",
                         *ENVELOPE_QUICK)
    assert status == 1
    assert gravity_said(out, "swing") == pytest.approx(weight, rel=5e-3)
    assert "no slow-down or lower speed/acceleration limit helps" in flat(out)
    assert "--exclude" not in out  # the only joint: nothing would be left to size
    assert_no_wrong_advice(out)
    (joint,) = json.loads((folder / "envelope.json").read_text())["joints"]
    assert joint["selected"] is None and joint["diagnosis"]["gravity"]["exceeds"] is True
    # the range -60..60 deg holds the horizontal: gravity over it is m g l, to the search
    assert joint["diagnosis"]["gravity"]["torque_nm"] == pytest.approx(weight, rel=1e-4)
    assert joint["diagnosis"]["next_steps"] == []


def test_envelope_suggests_lower_limits_only_where_dynamics_fail_and_they_work(capsys,
                                                                              tmp_path):
    # 1 kg at 0.5 m: m g l = 4.9 N m; at 6000 deg/s^2 (104.7 rad/s^2) the inertia
    # m l^2 = 0.25 kg m^2 adds 26.2 N m: peak 31.1 N m, over every unit's 20.3 N m
    robot = pendulum(tmp_path, 1.0, 0.5)
    inertia, accel = 1.0 * 0.5**2 + 1e-4, 6000.0 / 57.29577951308232
    status, out, _ = run(capsys, "envelope", robot, "--velocity", "60", "--acceleration",
                         "6000", "--json", tmp_path / "fast.json", *ENVELOPE_QUICK)
    assert status == 1
    (joint,) = json.loads((tmp_path / "fast.json").read_text())["joints"]
    peak = abs(joint["worst"]["peak"]["torque"])
    assert peak == pytest.approx(1.0 * G * 0.5 + inertia * accel, rel=1e-3)
    text = flat(out)
    assert "swing: no unit holds it: repeated peak torque" in text
    assert "swing: lower the velocity and acceleration limits" in text
    assert "gravity alone needs at most 4.9 N m" in text
    assert "gravity alone needs 4.9" not in text  # not over any limit
    # following it: 1000 deg/s^2 gives 4.9 + 4.4 = 9.3 N m, within PSA-14-100
    status, out, _ = run(capsys, "envelope", robot, "--velocity", "60", "--acceleration",
                         "1000", *ENVELOPE_QUICK)
    assert status == 0, out


def test_a_study_records_the_shortfall_as_a_result(capsys, heavy):
    folder, weight = heavy
    swing_motion(folder, payload=True)
    study = folder / "study.toml"
    study.write_text('compute = ["size", "fastest", "max-payload"]\n[base]\n'
                     'motion = "swing.toml"\n[grid]\ntime_scale = [1.0, 2.0]\n')
    status, out, _ = run(capsys, "study", study, "--out", folder / "rows.csv",
                         "--workers", "0")
    assert status == 0, out  # every case ran: no unit for a joint is a result
    with (folder / "rows.csv").open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert {row["status"] for row in rows} == {"ok"}
    for compute in ("size", "fastest", "max-payload"):
        mine = [row for row in rows if row["compute"] == compute]
        assert len(mine) == 2 and all(row["feasible"] == "false" for row in mine), compute
        for row in mine:
            said = re.search(r"gravity alone needs ([\d.]+) N m", row["shortfall"])
            assert said and float(said.group(1)) == pytest.approx(weight, rel=5e-3)


@pytest.mark.skipif(PYBULLET_DATA is None, reason="pybullet_data is not installed")
def test_the_kuka_iiwa_outgrows_psa_g_at_joint_2(capsys, tmp_path):
    motion = tmp_path / "iiwa.toml"
    assert run(capsys, "init", PYBULLET_DATA / "kuka_iiwa" / "model.urdf", "--out",
               motion)[0] == 0
    status, out, _ = run(capsys, "fastest", motion)
    assert status == 1
    assert "joint 'lbr_iiwa_joint_2' on this motion at any speed" in flat(out)
    assert gravity_said(out, "lbr_iiwa_joint_2") > STRONGEST_PEAK
    assert_no_wrong_advice(out)
    # the next step is this command with the joints no unit holds as sized left out (joint
    # 4 only by a slow-down), and it runs
    step = re.search(r"size the other joints without the 2 that no unit holds: "
                     r"(hdselect fastest \S+ --exclude (\S+))", flat(out))
    assert step and step.group(2) == "lbr_iiwa_joint_2,lbr_iiwa_joint_4"
    assert run(capsys, "fastest", motion, "--exclude", step.group(2))[0] == 0
    status, out, _ = run(capsys, "max-payload", motion)
    assert status == 1 and "no unit fits lbr_iiwa_joint_2" in flat(out)


@pytest.mark.skipif(PYBULLET_DATA is None, reason="pybullet_data is not installed")
def test_the_xarm6_envelope_says_gravity_alone_at_joint_2(capsys):
    status, out, _ = run(capsys, "envelope", PYBULLET_DATA / "xarm" / "xarm6_robot.urdf",
                         "--velocity", "90", "--acceleration", "180", *ENVELOPE_QUICK)
    assert status == 1
    assert gravity_said(out, "joint2") > STRONGEST_PEAK
    text = flat(out)
    assert "joint2: lower the velocity" not in text and "lower the limits" not in text
    assert "joint1: lower the velocity and acceleration limits" in text  # dynamics only


def test_fastest_on_a_mix_names_it(capsys, heavy):
    folder, weight = heavy
    swing_motion(folder)
    mix = folder / "day.toml"
    mix.write_text('robot = "pendulum.urdf"\n[[task]]\nname = "swing"\nmotion = "swing.toml"\n'
                   "share = 1.0\n")
    status, out, _ = run(capsys, "fastest", mix, "--json", folder / "mix.json")
    assert status == 1 and "joint 'swing' on this mix at any speed" in flat(out)
    assert gravity_said(out, "swing") == pytest.approx(weight, rel=5e-3)
    document = json.loads((folder / "mix.json").read_text())
    assert document["mix"] == str(mix) and document["motion"] is None
