"""The motion file's ``[motor]`` tables, the Python ``motors=`` and ``--motor-catalog``.

``[motor]`` applies to every rotary joint, ``[motor.JOINT]`` to one (replacing
``[motor]`` there); each is a fixed motor (inline, or ``id`` from a catalog) or a
catalog to choose from. Bad input is one line naming the motion file and the field,
exit status 2.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hdselect import load_case, plan, size, size_trajectory
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import load_motors
from hdselect.cli.main import main
from hdselect.motion.motionfile import load_motion
from helpers import REPO

EXAMPLE = REPO / "motors" / "example_motors.toml"
SCARA_MOTION = REPO / "trajectories" / "scara_wafer_transfer.toml"
PLANAR2_MOTION = REPO / "trajectories" / "planar2_pick_place.toml"
EXAMPLE_IDS = [m.id for m in load_motors(EXAMPLE)]

INLINE = """\
rated_torque_nm = 0.05
peak_torque_nm = 0.2
max_speed_rpm = 7000
rated_speed_rpm = 5000
rotor_inertia_kg_cm2 = 0.02
mass_kg = 0.2
"""


def with_motor_tables(tmp_path: Path, source: Path, tables: str, name: str = "m.toml") -> Path:
    """A copy of a shipped motion file (its robot path made absolute) with motor tables."""
    text = source.read_text()
    robot = text.split('robot = "', 1)[1].split('"', 1)[0]
    text = text.replace(f'robot = "{robot}"',
                        f'robot = "{(source.parent / robot).resolve().as_posix()}"')
    motors = tmp_path / "motors.toml"
    if not motors.exists():
        motors.write_text(EXAMPLE.read_text())
    path = tmp_path / name
    path.write_text(text + "\n" + tables)
    return path


def motors_of(path: Path) -> dict[str, list[str]]:
    _, motion = load_case(path)
    assert motion.motors is not None
    return {name: [m.id for m in motors] for name, motors in motion.motors.items()}


# --- what the tables mean --------------------------------------------------------------------

def test_shared_catalog_applies_to_every_rotary_joint_not_the_prismatic_one(tmp_path):
    path = with_motor_tables(tmp_path, SCARA_MOTION, '[motor]\ncatalog = "motors.toml"\n')
    assert motors_of(path) == {name: EXAMPLE_IDS for name in ("shoulder", "elbow", "wrist")}


def test_joint_tables_replace_the_shared_one(tmp_path):
    path = with_motor_tables(tmp_path, SCARA_MOTION, f"""\
[motor]
catalog = "motors.toml"
[motor.elbow]
id = "EX-22"                 # fixed, from [motor]'s catalog
[motor.wrist]
id = "wrist-motor"           # fixed, inline
{INLINE}""")
    found = motors_of(path)
    assert found == {"shoulder": EXAMPLE_IDS, "elbow": ["EX-22"], "wrist": ["wrist-motor"]}
    _, motion = load_case(path)
    (wrist,) = motion.motors["wrist"]
    assert wrist.rotor_inertia == pytest.approx(0.02e-4) and wrist.source == path


def test_joint_tables_alone_leave_the_other_joints_without_motors(tmp_path):
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, """\
[motor.elbow]
catalog = "motors.toml"
id = "EX-32"
""")
    assert motors_of(path) == {"elbow": ["EX-32"]}
    result = size(None, path)
    shoulder, elbow = result.joints
    assert shoulder.selected.motor_unit is None and "motor_peak" not in shoulder.selected.checks
    assert elbow.selected.motor_unit.id == "EX-32"
    assert result.options.prefer == "mass"
    # the elbow's motor rides on link 1: the shoulder carries it with the elbow's gearhead
    assert shoulder.carried_mass == pytest.approx(elbow.selected.unit.mass + 0.18, rel=1e-12)


def test_an_inline_motor_in_the_shared_table_is_every_joints(tmp_path):
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, f"[motor]\nid = 'M'\n{INLINE}")
    assert motors_of(path) == {"shoulder": ["M"], "elbow": ["M"]}


def test_python_motors_replace_the_files_and_cli_catalog_replaces_both(tmp_path, capsys):
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, '[motor]\ncatalog = "motors.toml"\n')
    (ex40,) = [m for m in load_motors(EXAMPLE) if m.id == "EX-40"]
    result = size(None, path, motors={"elbow": [ex40]})
    assert {n: [m.id for m in ms] for n, ms in result.motors.items()} == {"elbow": ["EX-40"]}
    assert result.joints[0].selected.motor_unit is None
    one = tmp_path / "one.toml"
    one.write_text(EXAMPLE.read_text().split("[[motor]]", 2)[0] + "[[motor]]"
                   + EXAMPLE.read_text().split("[[motor]]", 2)[1])
    assert [m.id for m in load_motors(one)] == ["EX-16"]
    status = main(["size", str(path), "--motor-catalog", str(one), "--json", "-"])
    out = capsys.readouterr().out
    assert status in (0, 1)
    assert '"motors": {\n      "shoulder": [\n        "EX-16"' in out


def test_size_trajectory_checks_the_motors_it_is_given():
    robot, motion = load_case(SCARA_MOTION)
    traj = plan(robot, motion)
    units = load_catalog()
    motors = load_motors(EXAMPLE)
    for bad, fragment in [({"lift": motors}, "not a sized joint"),
                          ({"elbo": motors}, "not a sized joint"),
                          ({"elbow": []}, "one or more"),
                          ({"elbow": ["EX-16"]}, "one or more"),
                          ({"elbow": [motors[0], motors[0]]}, "given twice")]:
        with pytest.raises(InputError, match=fragment):
            size_trajectory(robot, traj, units, motors=bad)


# --- bad input: one line, the motion file and the field, exit 2 ------------------------------

BAD = [
    ('[motor]\ncatalog = "none.toml"\n', "motor.catalog", "motor file not found"),
    ("[motor]\ncatalog = 3\n", "motor.catalog", "expected a motor file name"),
    ('[motor]\ncatalog = "motors.toml"\nid = "EX-99"\n', "motor.id",
     "unknown motor id 'EX-99'; motors.toml has: EX-16, EX-22"),
    ('[motor.elbow]\nid = "EX-22"\n', "motor.elbow.id", "an id needs a catalog"),
    ("[motor.elbow]\n", "motor.elbow.catalog", "give catalog"),
    (f'[motor.elbow]\ncatalog = "motors.toml"\n{INLINE}', "motor.elbow.catalog", "not both"),
    ("[motor.elbo]\n", "motor.elbo", "unknown joint 'elbo'"),
    ('[motor]\ncatalogue = "motors.toml"\n', "motor.catalogue", "did you mean 'catalog'"),
    (f"[motor.elbow]\n{INLINE.replace('mass_kg = 0.2', '')}", "motor.elbow.mass_kg",
     "required key is missing"),
    (f"[motor.elbow]\n{INLINE.replace('mass_kg = 0.2', 'mass_kg = nan')}",
     "motor.elbow.mass_kg", "finite"),
    (f"[motor.elbow]\n{INLINE.replace('peak_torque_nm = 0.2', 'peak_torque_nm = 0.01')}",
     "motor.elbow.peak_torque_nm", "below the rated torque"),
    (f"[motor.elbow]\n{INLINE}[motor.elbow.curve]\nspeed_rpm = [0, 5000, 5000, 7000]\n"
     "peak_torque_nm = [0.2, 0.2, 0.1, 0.1]\n", "motor.elbow.curve", "not a function of speed"),
]


@pytest.mark.parametrize(("tables", "field", "fragment"), BAD,
                         ids=[f"{i}-{case[2][:20]}" for i, case in enumerate(BAD)])
def test_bad_motor_tables_are_one_line_errors(tmp_path, capsys, tables, field, fragment):
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, tables)
    with pytest.raises(InputError) as info:
        load_motion(path)
    assert info.value.path == path and info.value.field == field, str(info.value)
    status = main(["size", str(path), "--json", str(tmp_path / "out.json")])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2 and out == "" and len(lines) == 1, err
    assert lines[0].startswith(f"hdselect: error: {path}: {field}: ")
    assert fragment in lines[0]
    assert not (tmp_path / "out.json").exists()


def test_a_prismatic_joint_gets_no_motor(tmp_path):
    path = with_motor_tables(tmp_path, SCARA_MOTION, '[motor.lift]\ncatalog = "motors.toml"\n')
    with pytest.raises(InputError, match="prismatic") as info:
        load_motion(path)
    assert info.value.field == "motor.lift"


@pytest.mark.parametrize("option", [["--motor-inertia", "1e-6"], ["--motor-mass", "0.1"],
                                    ["--motor-inertia", "0"]])
def test_motor_data_and_motor_options_together_are_one_line(tmp_path, capsys, option):
    for args in (["--motor-catalog", str(EXAMPLE)],):
        status = main(["size", str(PLANAR2_MOTION), *args, *option])
        out, err = capsys.readouterr()
        assert status == 2 and out == ""
        assert err.strip() == (f"hdselect: error: {option[0]}: the motors come from "
                               "--motor-catalog, with their own rotor inertia and mass; drop "
                               "this option")
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, '[motor]\ncatalog = "motors.toml"\n')
    status = main(["size", str(path), *option])
    err = capsys.readouterr().err
    assert status == 2 and "[motor] of m.toml" in err and len(err.strip().splitlines()) == 1


def test_motor_catalog_missing_on_the_command_line(tmp_path, capsys):
    status = main(["size", str(PLANAR2_MOTION), "--motor-catalog", str(tmp_path / "x.toml")])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.strip() == f"hdselect: error: {tmp_path / 'x.toml'}: file not found"


def test_json_never_writes_over_a_motor_file(tmp_path, capsys):
    path = with_motor_tables(tmp_path, PLANAR2_MOTION, '[motor]\ncatalog = "motors.toml"\n')
    before = (tmp_path / "motors.toml").read_text()
    status = main(["size", str(path), "--json", str(tmp_path / "motors.toml")])
    err = capsys.readouterr().err
    assert status == 2 and "is an input file" in err
    assert (tmp_path / "motors.toml").read_text() == before
