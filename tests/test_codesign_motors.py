"""Co-design with motors: `fastest` and `max-payload` take them, as `size` does, or refuse them.

Oracles: the motor torque along the fastest cycle re-derived here from the gear torque
the CSV carries (docs/rules.md, "The checks", motor side), and the public `size` at the
largest payload and just above it.
"""

from __future__ import annotations

import csv
import json
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect import InputError
from hdselect.catalog.motors import load_motors
from hdselect.catalog.rules import RPM_PER_RAD_S, at_rest
from helpers import REPO, run

WEAK = """\
[[motor]]
id = "WEAK"
rated_torque_nm = 0.05
peak_torque_nm = 0.09
max_speed_rpm = 4000
rated_speed_rpm = 3000
rotor_inertia_kg_cm2 = 0.05
mass_kg = 0.2
"""
"""A motor too weak for planar2's shoulder at full speed: its RMS torque binds."""


@pytest.fixture
def work(work):
    """The shared working directory (conftest.py), with a copy of motors/ and weak.toml."""
    shutil.copytree(REPO / "motors", work / "motors")
    (work / "weak.toml").write_text(WEAK)
    return work


@pytest.mark.slow
def test_fastest_holds_the_motor_to_its_ratings_and_takes_longer(work, capsys):
    """T_motor = tau / (N eta) driving or holding, tau eta / N driven back, + (J_in + J_m) N qdd.

    Re-derived here from the CSV's gear torque: every sample within the motor's peak
    torque, its RMS at most the rated torque, and the motor binding (some rule of the
    motor at its limit to 1 %), so the cycle is longer than without it.
    """
    assert run(capsys, "fastest", "tr/planar2_pick_place.toml", "--json", "free.json")[0] == 0
    status, _, err = run(capsys, "fastest", "tr/planar2_pick_place.toml", "--motor-catalog",
                         "weak.toml", "--json", "weak.json", "--out", "weak.csv")
    assert status == 0, err
    free, weak = (json.loads(Path(name).read_text()) for name in ("free.json", "weak.json"))
    assert weak["cycle_time_s"] > free["cycle_time_s"] * 1.01
    (motor,) = load_motors("weak.toml")
    catalog = {unit.id: unit for unit in hdselect.load_catalog()}
    with open("weak.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    binding = 0.0
    for joint in weak["joints"]:
        assert joint["motor"] == "WEAK"
        unit = catalog[joint["unit"]]
        name, ratio, eta = joint["name"], unit.ratio, 0.7
        tau = np.array([float(r[f"tau_{name}"]) for r in rows])
        qd = np.array([float(r[f"qd_{name}"]) for r in rows])
        qdd = np.array([float(r[f"qdd_{name}"]) for r in rows])
        driving = (tau * qd >= 0.0) | at_rest(qd, qdd)
        torque = (np.where(driving, tau / (ratio * eta), tau * eta / ratio)
                  + (unit.input_inertia + motor.rotor_inertia) * ratio * qdd)
        peak, rms = np.abs(torque).max(), np.sqrt(np.mean(torque**2))
        speed = np.abs(qd).max() * ratio * RPM_PER_RAD_S
        assert peak <= motor.peak_torque * 1.001 and rms <= motor.rated_torque * 1.001
        assert speed <= motor.max_speed * 1.001
        binding = max(binding, peak / motor.peak_torque, rms / motor.rated_torque)
    assert binding > 0.99


def test_a_motor_with_a_peak_torque_that_is_not_a_number_is_refused(work, capsys):
    Path("nan.toml").write_text(WEAK.replace("peak_torque_nm = 0.09", "peak_torque_nm = nan"))
    for command in ("fastest", "max-payload"):
        status, out, err = run(capsys, command, "tr/planar2_pick_place.toml", "--motor-catalog",
                               "nan.toml")
        assert status == 2 and out == "" and len(err.strip().splitlines()) == 1
        assert "nan.toml: motor[WEAK].peak_torque_nm: must be finite" in err


@pytest.mark.slow
def test_the_motion_files_motor_is_the_one_fastest_runs(work):
    """[motor] in the motion file, the motor file on the command line and Python agree."""
    text = Path("tr/planar2_pick_place.toml").read_text()
    Path("tr/with_motor.toml").write_text(text + '\n[motor]\ncatalog = "../weak.toml"\n')
    robot, motion = hdselect.load_case("tr/with_motor.toml")
    from_file = hdselect.fastest(robot, motion)
    robot, motion = hdselect.load_case("tr/planar2_pick_place.toml")
    (motor,) = load_motors("weak.toml")
    given = hdselect.fastest(robot, motion, motors={name: motor for name in robot.sized_joints})
    assert from_file.cycle_time == pytest.approx(given.cycle_time, rel=1e-9)
    assert {m.id for m in from_file.motors.values()} == {"WEAK"}
    only_shoulder = hdselect.fastest(robot, motion, motors={"shoulder": motor})
    assert set(only_shoulder.motors) == {"shoulder"}
    with pytest.raises(InputError) as info:
        hdselect.fastest(robot, motion, motors={"wrist": motor})
    assert info.value.field == "motors.wrist"


@pytest.mark.slow
def test_max_payload_with_motors_is_what_size_says_at_that_payload(work, capsys):
    """The largest payload with the motors passes `size` with them; 0.1 % more does not."""
    status, _, err = run(capsys, "max-payload", "tr/planar2_pick_place.toml", "--json",
                         "free.json")
    assert status == 0, err
    status, _, err = run(capsys, "max-payload", "tr/planar2_pick_place.toml",
                         "--motor-catalog", "motors/example_motors.toml", "--json", "mot.json")
    assert status == 0, err
    free, mot = (json.loads(Path(n).read_text()) for n in ("free.json", "mot.json"))
    mass = mot["max_payload_kg"]
    assert 0.0 < mass < free["max_payload_kg"]
    motors = load_motors("motors/example_motors.toml")
    robot, motion = hdselect.load_case("tr/planar2_pick_place.toml")
    every = {name: motors for name in robot.sized_joints}
    shape = motion.parts["part"]  # what scales: the part its events move (not the gripper)

    def sized(m):
        inertia = tuple(tuple(v * m / shape.mass for v in row) for row in shape.inertia)
        part = hdselect.Payload(m, shape.com, inertia, shape.frame, shape.name)
        return hdselect.size(robot, replace(motion, parts={**motion.parts, "part": part}),
                             motors=every)

    assert sized(mass * (1 - 1e-4)).feasible
    assert not sized(mass * (1 + 1e-3)).feasible


@pytest.mark.slow
def test_max_payload_of_fixed_units_is_the_check_of_those_units(work, capsys):
    """--units: the payload the given units carry, not the catalog's best."""
    status, _, _ = run(capsys, "max-payload", "tr/planar2_pick_place.toml", "--json", "a.json")
    assert status == 0
    status, _, err = run(capsys, "max-payload", "tr/planar2_pick_place.toml", "--units",
                         "shoulder=PSA-14-80", "--units", "elbow=PSA-14-100", "--json",
                         "b.json")
    assert status == 0, err
    best, fixed = (json.loads(Path(n).read_text()) for n in ("a.json", "b.json"))
    assert fixed["max_payload_kg"] < best["max_payload_kg"]
    status, out, err = run(capsys, "max-payload", "tr/planar2_pick_place.toml", "--units",
                           "shoulder=PSA-14-80")
    assert status == 2 and "--units" in err and "no unit given for elbow" in err
