"""Motor files: the example catalog, the torque-speed curve, and every kind of bad input.

A bad motor file is refused with one message naming the file and the field, through
`load_motors` and through the command line (one line on stderr, exit status 2).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.catalog.motors import Motor, load_motors
from hdselect.cli.main import main
from hdselect.sizing.core import size
from helpers import REPO

EXAMPLE = REPO / "motors" / "example_motors.toml"
INDEX = REPO / "trajectories" / "index_table_indexing.toml"

GOOD = """\
[[motor]]
id = "M1"
rated_torque_nm = 0.1
peak_torque_nm = 0.3
max_speed_rpm = 6000
rated_speed_rpm = 4000
rotor_inertia_kg_cm2 = 0.05
mass_kg = 0.3
[motor.curve]
speed_rpm = [0, 3000, 6000]
peak_torque_nm = [0.3, 0.3, 0.15]
"""


def write(tmp_path: Path, text: str, name: str = "motors.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def motor(**changes) -> Motor:
    values = dict(id="M", rated_torque=0.1, peak_torque=0.3, max_speed=6000.0,
                  rated_speed=4000.0, rotor_inertia=5e-6, mass=0.3)
    values.update(changes)
    return Motor(**values)


# --- the example catalog ---------------------------------------------------------------------

def test_example_catalog_is_labelled_and_in_the_psa_g_range():
    text = EXAMPLE.read_text()
    assert "EXAMPLE" in text and "NOT vendor data" in text
    motors = load_motors(EXAMPLE)
    assert len(motors) >= 4
    assert len({m.id for m in motors}) == len(motors)
    # PSA-G input speeds (6000/7000 rpm), motor torques from a few mN m to about 0.5 N m
    assert all(6000 <= m.max_speed <= 7000 for m in motors)
    assert min(m.rated_torque for m in motors) < 0.01
    assert max(m.peak_torque for m in motors) == pytest.approx(0.5)
    for m in motors:
        assert m.rated_torque < m.peak_torque and m.rated_speed <= m.max_speed
        assert 0.0 < m.rotor_inertia < 1e-4 and 0.0 < m.mass < 1.0
        assert m.source == EXAMPLE


def test_file_values_are_converted_to_si(tmp_path):
    (m,) = load_motors(write(tmp_path, GOOD))
    assert (m.id, m.rated_torque, m.peak_torque, m.max_speed, m.rated_speed) == (
        "M1", 0.1, 0.3, 6000.0, 4000.0)
    assert m.rotor_inertia == pytest.approx(0.05e-4)  # 1 kg cm^2 = 1e-4 kg m^2
    assert m.curve == ((0.0, 0.3), (3000.0, 0.3), (6000.0, 0.15))
    assert m.torque_constant is None and m.resistance is None
    text = GOOD.replace("rotor_inertia_kg_cm2 = 0.05", "rotor_inertia_kg_m2 = 5e-6")
    (si,) = load_motors(write(tmp_path, text + "", "si.toml"))
    assert si.rotor_inertia == 5e-6


def test_curve_is_interpolated_linearly_by_hand():
    m = motor(curve=[(0, 0.3), (3000, 0.3), (6000, 0.15)])
    # 4500 rpm: halfway down the falling segment, (0.3 + 0.15) / 2
    np.testing.assert_allclose(m.peak_torque_at(np.array([0, 1500, 3000, 4500, -4500, 6000])),
                               [0.3, 0.3, 0.3, 0.225, 0.225, 0.15], rtol=0, atol=1e-15)
    flat = motor()
    np.testing.assert_array_equal(flat.peak_torque_at(np.array([0.0, 5999.0])), [0.3, 0.3])


# --- bad input -------------------------------------------------------------------------------

BAD_FILES = [
    (GOOD.replace('id = "M1"\n', ""), "motor[0].id", "required"),
    (GOOD.replace("rated_torque_nm = 0.1\n", ""), "motor[M1].rated_torque_nm", "required"),
    (GOOD.replace("mass_kg = 0.3\n", ""), "motor[M1].mass_kg", "required"),
    (GOOD.replace("rotor_inertia_kg_cm2 = 0.05\n", ""), "rotor_inertia", "exactly one"),
    (GOOD.replace("rotor_inertia_kg_cm2 = 0.05\n",
                  "rotor_inertia_kg_cm2 = 0.05\nrotor_inertia_kg_m2 = 5e-6\n"),
     "rotor_inertia", "exactly one"),
    (GOOD.replace("rated_torque_nm = 0.1", "rated_torque_nm = nan"),
     "motor[M1].rated_torque_nm", "finite"),
    (GOOD.replace("peak_torque_nm = 0.3\n", "peak_torque_nm = inf\n", 1),
     "motor[M1].peak_torque_nm", "finite"),
    (GOOD.replace("rated_torque_nm = 0.1", "rated_torque_nm = -0.1"),
     "motor[M1].rated_torque_nm", "a torque between 0.0001 and 1e+07 N m"),
    (GOOD.replace("max_speed_rpm = 6000", "max_speed_rpm = 0"),
     "motor[M1].max_speed_rpm", "a speed between 1 and 1e+06 rpm"),
    (GOOD.replace("mass_kg = 0.3", "mass_kg = -0.3"), "motor[M1].mass_kg", "at least 0"),
    (GOOD.replace("rotor_inertia_kg_cm2 = 0.05", "rotor_inertia_kg_cm2 = -0.05"),
     "motor[M1].rotor_inertia_kg_cm2", "at least 0"),
    # finite but out of any physical range: refused, never an overflow further on
    (GOOD.replace("rated_torque_nm = 0.1", "rated_torque_nm = 1e308"),
     "motor[M1].rated_torque_nm", "between 0.0001 and 1e+07"),
    (GOOD.replace("mass_kg = 0.3", "mass_kg = 1e300"), "motor[M1].mass_kg", "at most 100000 kg"),
    (GOOD.replace("max_speed_rpm = 6000", "max_speed_rpm = 1e300"),
     "motor[M1].max_speed_rpm", "between 1 and 1e+06"),
    (GOOD.replace("rotor_inertia_kg_cm2 = 0.05", "rotor_inertia_kg_cm2 = 1e308"),
     "motor[M1].rotor_inertia_kg_cm2", "at most 1e+07 kg cm^2"),
    # found by fuzzing: a subnormal rotor inertia made the load/rotor ratio infinite
    (GOOD.replace("rotor_inertia_kg_cm2 = 0.05", "rotor_inertia_kg_cm2 = 2.2e-311"),
     "motor[M1].rotor_inertia_kg_cm2", "must be 0 or at least 1e-08 kg cm^2"),
    (GOOD.replace("mass_kg = 0.3", 'mass_kg = "0.3"'), "motor[M1].mass_kg", "number"),
    (GOOD.replace("peak_torque_nm = 0.3\n", "peak_torque_nm = 0.05\n", 1),
     "motor[M1].peak_torque_nm", "below the rated torque"),
    (GOOD.replace("rated_speed_rpm = 4000", "rated_speed_rpm = 7000"),
     "motor[M1].rated_speed_rpm", "above the maximum speed"),
    (GOOD.replace("mass_kg = 0.3", "mass_kg = 0.3\nresistance_ohm = 0"),
     "motor[M1].resistance_ohm", "a resistance between 1e-06"),
    (GOOD.replace("mass_kg = 0.3", "mass_kg = 0.3\ncolour = 'red'"), "motor[M1].colour",
     "unknown key"),
    # curves that are not a function of speed, or do not cover the speed range
    (GOOD.replace("speed_rpm = [0, 3000, 6000]", "speed_rpm = [0, 3000, 3000]"),
     "motor[M1].curve", "not a function of speed"),
    (GOOD.replace("speed_rpm = [0, 3000, 6000]", "speed_rpm = [0, 4000, 3000]"),
     "motor[M1].curve", "not a function of speed"),
    (GOOD.replace("speed_rpm = [0, 3000, 6000]", "speed_rpm = [500, 3000, 6000]"),
     "motor[M1].curve", "start at 0 rpm"),
    (GOOD.replace("speed_rpm = [0, 3000, 6000]", "speed_rpm = [0, 3000, 5000]"),
     "motor[M1].curve", "below the maximum speed"),
    (GOOD.replace("peak_torque_nm = [0.3, 0.3, 0.15]", "peak_torque_nm = [0.3, 0.15]"),
     "motor[M1].curve.peak_torque_nm", "one peak torque per speed"),
    (GOOD.replace("peak_torque_nm = [0.3, 0.3, 0.15]", "peak_torque_nm = [0.4, 0.3, 0.15]"),
     "motor[M1].curve", "above the peak torque"),
    (GOOD.replace("peak_torque_nm = [0.3, 0.3, 0.15]", "peak_torque_nm = [0.3, 0.05, 0.05]"),
     "motor[M1].curve", "below the rated torque"),
    (GOOD.replace("peak_torque_nm = [0.3, 0.3, 0.15]", "peak_torque_nm = [0.3, -0.3, 0.15]"),
     "motor[M1].curve.peak_torque_nm[1]", "at least 0"),
    (GOOD.replace("speed_rpm = [0, 3000, 6000]", "speed_rpm = [0, nan, 6000]"),
     "motor[M1].curve.speed_rpm[1]", "finite"),
    (GOOD + GOOD.replace("[[motor]]\n", "[[motor]]\n", 1), "motor[M1].id", "more than once"),
    ("source = 'x'\n", "motor", "no [[motor]]"),
    ("[[motor]\n", None, "not valid TOML"),
]


@pytest.mark.parametrize(("text", "field", "fragment"), BAD_FILES,
                         ids=[f"{i}-{case[2]}" for i, case in enumerate(BAD_FILES)])
def test_bad_motor_file_names_the_file_and_the_field(tmp_path, text, field, fragment):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as info:
        load_motors(path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    assert fragment in message, message
    if field is not None:
        assert field in message, message


def test_missing_motor_file(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        load_motors(tmp_path / "none.toml")


@pytest.mark.parametrize(("changes", "field"), [
    ({"rated_torque": math.nan}, "rated_torque"), ({"mass": -1.0}, "mass"),
    ({"rotor_inertia": math.inf}, "rotor_inertia"), ({"id": ""}, "id"),
    ({"peak_torque": True}, "peak_torque"), ({"curve": [(0, 0.3)]}, "curve"),
    ({"curve": [(0, 0.3), (0, 0.2), (6000, 0.1)]}, "curve"),
    ({"curve": [(0, 0.3), (6000,)]}, "curve"), ({"torque_constant": 0.0}, "torque_constant"),
])
def test_python_motors_are_validated_the_same_way(changes, field):
    with pytest.raises(InputError) as info:
        motor(**changes)
    assert info.value.field == field


def test_zero_rotor_inertia_and_mass_are_allowed():
    m = motor(rotor_inertia=0.0, mass=0.0)
    assert (m.rotor_inertia, m.mass) == (0.0, 0.0)


def test_bad_motor_catalog_on_the_command_line_is_one_line(capsys, tmp_path):
    path = write(tmp_path, GOOD.replace("speed_rpm = [0, 3000, 6000]",
                                        "speed_rpm = [0, 3000, 2000]"))
    status = main(["size", str(INDEX), "--motor-catalog", str(path)])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith("hdselect: error: ")
    assert str(path) in lines[0] and "motor[M1].curve" in lines[0]
    assert "not a function of speed" in lines[0]


def test_a_motor_for_a_joint_that_is_not_sized_is_an_error(tmp_path):
    """Nothing given is ignored: a [motor.JOINT] block for an excluded joint cannot apply."""
    motion = tmp_path / "motion.toml"
    source = (REPO / "trajectories" / "benchtop6_pick_place.toml").read_text()
    source = source.replace('robot = "../robots/benchtop6.urdf"',
                            f'robot = "{(REPO / "robots" / "benchtop6.urdf").as_posix()}"')
    motion.write_text(source + '\n[sizing]\nexclude = ["wrist_3"]\n\n[motor.wrist_3]\n'
                      'id = "EX-16"\ncatalog = "'
                      + (REPO / "motors" / "example_motors.toml").as_posix() + '"\n')
    with pytest.raises(InputError, match="wrist_3") as caught:
        size(None, motion)
    assert caught.value.field == "motor.wrist_3"
