"""Terminal tables at any width: every unit id, joint name, binding rule and verdict whole.

The tables are rendered as the command line prints them when piped (no colour, no
trailing spaces) at 60, 80, 100 and 160 columns, for an arm with ROS-style joint
names that no unit fits at one joint, and for the catalog and a duty cycle.
"""

from __future__ import annotations

import io
import math
import os
import re
from pathlib import Path

import pytest

import hdselect
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.duty import load_duty, size_duty
from hdselect.catalog.motors import load_motors
from hdselect.catalog.rules import MOTOR_CHECKS
from hdselect.cli.main import main
from hdselect.report.case_tables import joints_table
from hdselect.report.catalog_tables import catalog_table, duty_table
from hdselect.report.size_tables import compare_table, loads_table, size_table
from hdselect.report.tables import console_for
from hdselect.report.terminal import life_text, ratio_text, utilization_text, verdict
from hdselect.robot.joints import describe_joints
from hdselect.sizing.diagnosis import with_diagnoses
from helpers import REPO
from helpers.motions import planar2_motion
from helpers.robots import LONG, ros_arm

WIDTHS = (60, 80, 100, 160)
CONVEYOR = REPO / "trajectories" / "duty" / "conveyor_index.toml"


@pytest.fixture(scope="module")
def overloaded(tmp_path_factory):
    result = hdselect.size(None, ros_arm(tmp_path_factory.mktemp("ros")))
    assert [j.name for j in result.joints] == list(LONG.values())
    assert result.joints[0].selected is None and result.joints[1].selected is not None
    return result


def printed(renderable, width: int) -> str:
    stream = io.StringIO()
    console = console_for(stream)
    console.width = width
    console.print(renderable)
    return stream.getvalue()


def assert_fits(text: str, width: int) -> list[str]:
    """Every line within `width`, but a command of a next step: never broken, to be copied."""
    lines = text.splitlines()
    prose = [line for line in lines if not line.startswith("  hdselect ")]
    assert all(len(line) <= width for line in prose), max(prose, key=len)
    assert all(line == line.rstrip() for line in lines)  # piped: no trailing spaces
    return lines


def whole(text: str, value: str) -> bool:
    """`value` appears on one line, not cut (no ellipsis) and not split."""
    return any(value in line for line in text.splitlines())


@pytest.mark.parametrize("width", WIDTHS)
def test_size_table_keeps_every_name_and_verdict_whole(overloaded, width):
    text = printed(size_table(overloaded), width)
    assert_fits(text, width)
    assert "…" not in text
    shoulder, elbow = overloaded.joints
    for joint in overloaded.joints:
        assert whole(text, joint.name)
    # the joint no unit fits: its shortfall in N m against the strongest unit, not a life %
    headline = with_diagnoses(overloaded).diagnoses[shoulder.name].headline
    assert not headline.is_life and whole(text, headline.short())
    chosen = elbow.selected
    assert whole(text, chosen.unit.id)
    binding = chosen.checks[chosen.binding]
    assert whole(text, f"{chosen.binding} {utilization_text(binding.utilization, True)}")
    motor = f"{chosen.motor.rms_torque:.3g}"  # motor figures move, never vanish
    assert whole(text, motor)
    assert whole(text, "gravity")


@pytest.mark.parametrize("width", WIDTHS)
def test_compare_table_keeps_every_unit_and_verdict_whole(overloaded, width):
    for joint in overloaded.joints:
        text = printed(compare_table(overloaded, joint), width)
        assert_fits(text, width)
        assert "…" not in text
        for c in joint.candidates:
            assert whole(text, c.unit.id)
            row = next(line for line in text.splitlines() if c.unit.id in line)
            assert verdict(c) in row or not re.search(r"\bok\b|\+", row)  # on its row, or
            assert whole(text, verdict(c))  # below: never lost
        failing = sum(not check.ok for c in joint.candidates for check in c.checks.values())
        rows = [line for line in text.splitlines() if "PSA-" in line]
        assert sum(row.count("✗") for row in rows) == failing


@pytest.mark.parametrize("width", WIDTHS)
def test_loads_table_keeps_every_joint_and_figure_whole(overloaded, width):
    text = printed(loads_table(overloaded), width)
    assert_fits(text, width)
    over = 0
    for load in overloaded.loads:
        assert whole(text, load.name)
        high = math.degrees(load.travel[1])
        assert whole(text, f"{load.peak:.3g}") and whole(text, f"{high:.3g} deg")
        over += load.above_effort + load.above_velocity
    assert over and text.count("✗") == over + 1  # each figure above its limit, and the key
    assert whole(text, "✗ above the robot file's limit")


@pytest.mark.parametrize("width", WIDTHS)
def test_joints_table_keeps_every_joint_and_limit_whole(width):
    robot = hdselect.load_robot(REPO / "robots" / "scara.urdf")
    text = printed(joints_table(robot, describe_joints(robot)), width)
    assert_fits(text, width)
    for name, range_ in (("shoulder", "-2.62 .. 2.62"), ("lift", "0 .. 0.04")):
        assert whole(text, name) and whole(text, range_)
    assert whole(text, "0.879")  # the mass the shoulder moves: moved below, never lost
    lift = next(line for line in text.splitlines() if line.startswith("lift "))
    assert lift.split()[:4] == ["lift", "2", "prismatic", "no"]  # the key columns stay


@pytest.mark.parametrize("width", WIDTHS)
def test_catalog_and_duty_tables_fit(width):
    units = load_catalog()
    for imperial in (False, True):
        text = printed(catalog_table(units, imperial=imperial), width)
        assert_fits(text, width)
        for unit in units:
            assert whole(text, unit.id)
    result = size_duty(load_duty(CONVEYOR), units)
    text = printed(duty_table(result), width)
    assert_fits(text, width)
    for c in result.candidates:
        assert whole(text, c.unit.id) and whole(text, verdict(c))


def test_a_wide_terminal_prints_one_table(overloaded):
    text = printed(size_table(overloaded), 160)
    header = [line for line in text.splitlines() if line.startswith("joint")]
    assert len(header) == 1 and "notes" in header[0]


def test_a_narrow_terminal_moves_the_motor_figures_below(overloaded):
    """At 80 columns the motor figures, then the bearing loads, then the notes move below."""
    text = printed(size_table(overloaded), 80)
    headers = [line for line in text.splitlines() if line.startswith("joint")]
    assert "binding" in headers[0] and "notes" in headers[-1]
    assert [i for i, h in enumerate(headers) if "bearing" in h] == [len(headers) - 2]
    assert_fits(text, 80)


def test_imperial_catalog_notes_are_in_lb_in():
    text = " ".join(printed(catalog_table(load_catalog(), imperial=True), 100).split())
    # 2.6 N m / 0.1129848 = 23.01 lb-in; 0.0062 kg cm^2 / 2.9264 kg cm^2 per lb-in^2
    assert "the repeated-peak limit (23 lb-in) is used" in text
    assert "(0.00212 lb-in^2) bounds it" in text
    assert "the lower, 70 lb-in, is used" in text and "the lower, 300 lb-in, is used" in text
    assert "N m) is used" not in text


def test_utilization_next_to_the_limit_never_reads_as_its_opposite():
    assert utilization_text(0.9996, True) == "99.9%"
    assert utilization_text(1.0004, False) == "100.1%"
    assert utilization_text(1.0, True) == "100.0%"
    assert utilization_text(0.5, True) == "50%" and utilization_text(1.5, False) == "150%"


def test_columns_sets_the_width_of_piped_output(overloaded, capsys, monkeypatch):
    motion = overloaded.motion.path
    for width, tables in ((60, 2), (160, 1)):
        monkeypatch.setenv("COLUMNS", str(width))
        assert main(["compare", str(motion), "--joint", LONG["elbow"]]) == 1
        lines = assert_fits(capsys.readouterr().out, width)
        assert sum(line.startswith("unit ") for line in lines) == tables


def test_case_notes_need_no_verbose(capsys, tmp_path, monkeypatch):
    """The unsized prismatic joint, a still joint and the default payload frame are stated."""
    monkeypatch.setenv("COLUMNS", "100")
    assert main(["size", str(REPO / "trajectories" / "scara_wafer_transfer.toml")]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "not sized: lift (prismatic" in text
    still = planar2_motion(tmp_path / "still.toml", (10, 20, 0.5), (10, 20), payload=0.4)
    assert main(["size", str(still)]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "hold only: nothing moves in this cycle, so only holding the pose (static)" in text
    assert ("payload: 0.4 kg on tool, the tip of the longest chain of joints not excluded, "
            "since no frame was given") in text


# --- gearhead and motor pairs ------------------------------------------------------------

EXAMPLE_MOTORS = REPO / "motors" / "example_motors.toml"


@pytest.fixture(scope="module")
def overloaded_pairs(tmp_path_factory):
    """The ROS-named arm with every example motor: no pair fits the shoulder."""
    motors = load_motors(EXAMPLE_MOTORS)
    result = hdselect.size(None, ros_arm(tmp_path_factory.mktemp("pairs")),
                           motors={name: motors for name in LONG.values()})
    assert result.joints[0].selected is None and result.joints[1].selected is not None
    return result


@pytest.mark.parametrize("width", WIDTHS)
def test_pair_table_keeps_the_pair_and_both_bindings_whole(overloaded_pairs, width):
    text = printed(size_table(overloaded_pairs), width)
    assert_fits(text, width)
    assert "…" not in text
    shoulder, elbow = overloaded_pairs.joints
    for joint in overloaded_pairs.joints:
        assert whole(text, joint.name)
    headline = with_diagnoses(overloaded_pairs).diagnoses[shoulder.name].headline
    assert whole(text, headline.short()) and "no pair holds it" in " ".join(text.split())
    chosen = elbow.selected
    gearhead, motor = chosen.checks[chosen.gearhead_binding], chosen.checks[chosen.motor_binding]
    for value in (chosen.unit.id, chosen.motor_unit.id,
                  f"{chosen.gearhead_binding} {utilization_text(gearhead.utilization, True)}",
                  f"{chosen.motor_binding.removeprefix('motor_')} "
                  f"{utilization_text(motor.utilization, True)}",
                  # the inertia ratio, life and motor figures move below, never vanish
                  ratio_text(elbow.inertia_ratio(chosen)), life_text(chosen.life_hours),
                  f"{chosen.motor.rms_torque:.3g}", f"{chosen.motor.max_speed:,.0f}"):
        assert whole(text, value), value
    if width >= 80:  # the joint, the pair and both bindings in the first table
        header = next(line for line in text.splitlines() if line.startswith("joint"))
        assert "unit" in header and "motor" in header and "binding" in header


@pytest.mark.parametrize("width", WIDTHS)
def test_pair_compare_table_keeps_every_pair_and_verdict_whole(overloaded_pairs, width):
    for joint in overloaded_pairs.joints:
        text = printed(compare_table(overloaded_pairs, joint), width)
        assert_fits(text, width)
        assert "…" not in text
        assert len(joint.candidates) == 7 * 6
        for c in joint.candidates:
            assert whole(text, c.label) and whole(text, verdict(c))
            assert whole(text, f"{c.motor.rms_torque:.3g}")
        failing = sum(not c.checks[name].ok for c in joint.candidates
                      for name in (c.gearhead_binding, *MOTOR_CHECKS))
        assert text.count("✗") == failing + 1  # every failing rule marked, and the legend


@pytest.mark.slow
def test_a_report_names_no_absolute_path_of_the_machine(tmp_path, monkeypatch, capsys):
    """Issue 27: the shipped example named the checkout it was made in. Made in one
    directory from relative paths, the report names its files relative to it, the built-in
    catalog relative to the package."""
    import sys

    work = tmp_path / "project"
    work.mkdir()
    for name in ("robots", "trajectories"):
        (work / name).symlink_to(REPO / name)
    monkeypatch.chdir(work)
    assert main(["size", "trajectories/planar2_pick_place.toml", "--report", "out"]) == 0
    capsys.readouterr()
    page = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "",  # figures: no paths
                  (work / "out" / "index.html").read_text(encoding="utf-8"))
    machine = {str(p) for p in (tmp_path, tmp_path.resolve(), REPO, REPO.parent, Path.home(),
                                Path(sys.prefix), Path(hdselect.__file__).resolve().parent)}
    assert [place for place in machine if place in page] == []
    assert "<code>trajectories/planar2_pick_place.toml</code>" in page
    assert "<code>trajectories/../robots/planar2.urdf</code>" in page
    assert ">catalog (built in)<" in page
    assert "<code>hdselect/catalog/data/psa_g.toml</code>" in page
    assert "Re-run it in the directory it ran in (the files' paths below are relative" in page
    assert "project" not in page  # nor the directory's name


def test_a_file_given_by_an_absolute_path_is_named_relative_to_the_directory(tmp_path):
    from hdselect.report.provenance import provenance

    result = hdselect.size(None, REPO / "trajectories" / "planar2_pick_place.toml")
    origin = provenance(result, ["hdselect", "size"], cwd=tmp_path)
    motion = next(f for f in origin.files if f.role == "motion")
    assert motion.path == os.path.relpath(REPO / "trajectories" / "planar2_pick_place.toml",
                                          tmp_path)
    assert not any(Path(f.path).is_absolute() for f in origin.files)
    assert origin.cwd == tmp_path.name
