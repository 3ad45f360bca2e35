"""The output bearing through the sizing: selection, time scales, studies, every output.

Oracles: a spinning mass whose radial force is m r sqrt(qd^4 + qdd^2) by hand, so the
slow-down at which a radial limit is met follows in closed form; the same case sized
directly and from a study's basis; the docs page's examples as a user runs them.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

import hdselect
from hdselect import Options, load_case, load_catalog, plan, size_trajectory, summarize
from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.motion.motionfile import load_motion
from hdselect.robot.wrenches import bearing_loads
from hdselect.study.compute import size_rows
from hdselect.study.group import build_basis
from hdselect.study.pooled import size_case
from helpers import REPO
from helpers.bearings import BEARING_BOUND, SPIN_RULES
from helpers.studies import differences, separate

PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
EXAMPLE = REPO / "catalogs" / "example_rated_bearing.toml"
DOC = (REPO / "docs" / "bearing.md").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def rated():
    """The benchtop pick-and-place sized with the example catalog that rates bearings."""
    return hdselect.size(None, PICK, catalog=[EXAMPLE])


def test_a_rated_bearing_changes_the_selection_and_binds_it(rated):
    """The shoulder's pan axis carries the arm off-centre: a moment above the XB-07-100's
    6 N m, so the XB-08-100 is chosen, bound by its bearing moment."""
    pan = rated.joints[0]
    assert pan.selected.unit.id == "XB-08-100" and pan.selected.binding == "bearing_moment"
    small = next(c for c in pan.candidates if c.unit.id == "XB-07-100")
    assert not small.feasible and small.binding == "bearing_moment"
    assert small.checks["bearing_moment"].value > 6.0 > 0.0
    # the unit's centre is its catalog offset from the flange, the worse side per sample
    axial, radial, tilting = bearing_loads(pan.wrench.full(), 0.0, 0.006)
    assert pan.selected.bearing.load.max_moment == pytest.approx(tilting.max(), rel=1e-12)
    assert pan.selected.bearing.load.max_moment >= pan.bearing.max_moment
    assert pan.selected.checks["bearing_moment"].value == pytest.approx(tilting.max())
    lift = rated.joints[1]
    assert lift.selected.unit.bearing is None and lift.selected.bearing is None
    assert not any(name.startswith("bearing_") for name in lift.selected.checks)


def test_loads_are_reported_and_flagged_not_rated_on_every_result(tmp_path):
    """The PSA-G page rates no bearing: loads everywhere, the flag everywhere, no check."""
    out = tmp_path / "out.json"
    assert main(["size", str(PICK), "--json", str(out)]) == 0
    document = json.loads(out.read_text())
    for joint in document["joints"]:
        bearing = joint["bearing"]
        assert bearing["rated"] is False and "not rated by the source" in bearing["note"]
        assert bearing["max_moment_nm"] > 0.0 and bearing["max_radial_n"] > 0.0
        for candidate in joint["candidates"]:
            assert candidate["bearing"] == {"rated": False, "note": bearing["note"]}
            assert not any(name.startswith("bearing_") for name in candidate["checks"])
    summary = summarize(hdselect.size(None, PICK))
    assert all(j.bearing_rated is False and j.bearing_max_moment > 0 for j in summary.joints)
    rows = size_rows(summary.to_dict())
    assert {row["bearing"] for row in rows} == {"not rated"}
    assert all(row["bearing_max_radial_n"] > 0 for row in rows)


def test_the_terminal_groups_the_bearing_columns_and_says_not_rated(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    assert main(["size", str(PICK)]) == 0
    printed = capsys.readouterr().out
    table = printed[printed.index("tilt M N m"):]
    assert "max / mean" in table and table.count("not rated") >= 6
    assert "bearing not rated by the source" in " ".join(printed.split())
    monkeypatch.setenv("COLUMNS", "250")  # wide: one table holds every column
    assert main(["size", str(PICK)]) == 0
    wide = capsys.readouterr().out
    header = next(line for line in wide.splitlines() if line.startswith("joint "))
    assert "L50 life" in header and "bearing" in header


def test_json_gives_a_rated_units_figures(rated, tmp_path):
    from hdselect.sizing.records import size_json

    document = size_json(rated)
    pan = document["joints"][0]
    entry = next(c for c in pan["candidates"] if c["unit"] == "XB-08-100")
    assert entry["bearing"]["rated"] and entry["bearing"]["dynamic_rating_n"] == 3200.0
    figures = rated.joints[0].selected.bearing
    # its L10 life as every output reports it: the cap, flagged, beyond 1e6 h
    assert figures.life_hours > 1e6 and entry["bearing"]["life_capped"] is True
    assert entry["bearing"]["life_l10_hours"] == 1e6
    assert entry["bearing"]["loads"]["spread_m"] == 0.006
    assert entry["checks"]["bearing_static"]["value"] == figures.static_safety
    assert entry["rules"]["bearing_load_factor"] == 1.2
    assert document["assumptions"]["bearing_loads"] is True
    assert "10/3" in document["assumptions"]["bearing_rule"]


def test_bearing_loads_off_is_refused_with_rated_units_and_leaves_them_out_otherwise():
    units = load_catalog([EXAMPLE])
    robot, motion = load_case(PICK)
    trajectory = plan(robot, motion)
    with pytest.raises(InputError, match="XB-07-100, XB-08-100 rate their output bearing"):
        size_trajectory(robot, trajectory, units, Options(bearing_loads=False))
    plain = size_trajectory(robot, trajectory, load_catalog(), Options(bearing_loads=False))
    loaded = size_trajectory(robot, trajectory, load_catalog(), Options())
    assert all(joint.bearing is None and joint.wrench is None for joint in plain.joints)
    for a, b in zip(plain.joints, loaded.joints, strict=True):  # the torques, bit for bit
        assert np.array_equal(a.torque, b.torque) and a.selected.unit == b.selected.unit


def test_the_motion_files_offset_moves_the_flange(tmp_path):
    text = PICK.read_text().replace('robot = "../robots/', f'robot = "{REPO}/robots/')
    motion = tmp_path / "offset.toml"
    motion.write_text(text + '\n[sizing]\nbearing_offset_m = { shoulder_lift = 0.04 }\n')
    result = hdselect.size(None, motion)
    lift = result.joints[1]
    assert result.options.bearing_offset == {"shoulder_lift": 0.04}
    assert lift.bearing.offset == 0.04
    _, _, tilting = bearing_loads(lift.wrench.full(), 0.04)
    assert lift.bearing.max_moment == pytest.approx(tilting.max(), rel=1e-12)
    for bad, message in (('{ wrist = 0.1 }', "unknown joint 'wrist'"),
                         ('{ elbow = 500 }', "must be a position along the axis")):
        motion.write_text(text + f"\n[sizing]\nbearing_offset_m = {bad}\n")
        with pytest.raises(InputError, match=message) as caught:
            load_motion(motion)
        assert caught.value.field.startswith("sizing.bearing_offset_m.")
    motion.write_text(text + '\n[sizing]\nexclude = ["elbow"]\n'
                      'bearing_offset_m = { elbow = 0.01 }\n')
    with pytest.raises(InputError, match="'elbow' is not a sized joint"):
        hdselect.size(None, motion)


# --- a spinning mass: the slow-down a radial limit needs, by hand ----------------------------

SPIN = """<?xml version="1.0"?>
<robot name="spin"><link name="base"/>
  <joint name="spin" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-4" upper="4" effort="100" velocity="10"/></joint>
  <link name="arm"><inertial><origin xyz="0.3 0 0"/><mass value="2.0"/>
    <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
</robot>
"""
SPIN_MOTION = """robot = "spin.urdf"
planner = "ruckig"
angle_unit = "deg"
dt = 0.001
[limits]
velocity = [300]
acceleration = [1500]
jerk = [20000]
[[waypoint]]
q = [-180]
[[waypoint]]
q = [180]
"""
SPIN_CATALOG = """series = "SPIN"
source = "made up for a test"
""" + SPIN_RULES + """[[unit]]
size = 20
ratio = 10
rated_torque_nm = 500
repeated_torque_nm = 500
momentary_torque_nm = 500
static_torque_nm = 500
max_input_speed_rpm = 100000
input_inertia_kg_cm2 = 0.0001
mass_kg = 1
[unit.bearing]
max_radial_n = 8
"""


def test_the_slow_down_a_radial_limit_needs_is_the_hand_value(tmp_path):
    """A 2 kg mass at r = 0.3 m about a vertical axis: F_r = m r sqrt(qd^4 + qdd^2)
    (centripetal and tangential). Run s times slower, F_r / s^2: the radial limit of
    8 N holds from s* = sqrt(m r max sqrt(qd^4 + qdd^2) / 8)."""
    (tmp_path / "spin.urdf").write_text(SPIN)
    (tmp_path / "spin.toml").write_text(SPIN_MOTION)
    (tmp_path / "spin_units.toml").write_text(SPIN_CATALOG)
    units = [u for u in load_catalog([tmp_path / "spin_units.toml"]) if u.series == "SPIN"]
    robot, motion = load_case(tmp_path / "spin.toml")
    trajectory = plan(robot, motion)
    qd, qdd = trajectory.qd[:, 0], trajectory.qdd[:, 0]
    radial = 2.0 * 0.3 * np.sqrt(qd**4 + qdd**2)
    result = size_trajectory(robot, trajectory, units, Options())
    (joint,) = result.joints
    np.testing.assert_allclose(bearing_loads(joint.wrench.full())[1], radial, rtol=1e-9, atol=1e-9)
    assert joint.selected is None and joint.strongest.binding == "bearing_radial"
    exact = math.sqrt(radial.max() / 8.0)
    assert exact > 1.1
    (fits,) = joint.scales.fits["SPIN-20-10"]
    assert fits[0] == pytest.approx(exact, rel=1e-5) and fits[1] == math.inf
    assert exact <= joint.slowdown.factor <= exact + 0.001 + 1e-9


# --- studies --------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def rated_basis():
    """The pick-and-place basis with load inertias, the example rated catalog, its motors."""
    robot, motion = load_case(PICK)
    bare = robot.with_payload(None)
    basis = build_basis(bare, motion, motion.payload, inertias=True)
    motors = hdselect.load_motors(REPO / "motors" / "example_motors.toml")
    return bare, motion, basis, load_catalog([EXAMPLE]), motors


@pytest.mark.parametrize(("mass", "time_scale", "given"), [
    (0.5, 1.0, {}),
    (2.0, 0.8, {}),
    (1.0, 1.0, {"margin": 0.2}),
    (1.5, 0.9, {"margin": 0.1, "stop_time": 0.2}),
])
def test_a_grouped_case_with_rated_bearings_equals_the_direct_sizing(rated_basis, mass,
                                                                      time_scale, given):
    """The basis of wrenches gives the loads and checks `size_trajectory` gives, under a
    design margin too."""
    bare, motion, basis, units, _ = rated_basis
    options = Options(**{"life_hours": 20_000.0, "threads": 1, **given})
    grouped = size_case(basis, mass, time_scale, units, options)
    direct = separate(bare, motion, mass, time_scale, units, options)
    assert differences(grouped.to_dict(), direct.to_dict()) < 1e-9
    assert any(joint.bearing_rated for joint in grouped.joints)
    assert any(name.startswith("bearing_") for j in grouped.joints for name in j.utilization)


@pytest.mark.parametrize(("mass", "time_scale", "given"), [
    (0.5, 1.0, {"margin": 0.15, "max_inertia_ratio": 10.0}),
    (1.0, 0.9, {"prefer": "inertia", "inertia_target": 5.0, "max_inertia_ratio": 30.0}),
])
def test_grouped_pairs_with_rated_bearings_equal_the_direct_sizing(rated_basis, mass,
                                                                   time_scale, given):
    """Gearhead and motor pairs on rated bearings with a margin and a largest inertia ratio:
    the grouped case's bearing, motor and inertia-ratio checks are the core's."""
    bare, motion, basis, units, motors = rated_basis
    per_joint = {name: motors for name in bare.sized_joints}
    options = Options(**{"life_hours": 20_000.0, "threads": 1, **given})
    grouped = size_case(basis, mass, time_scale, units, options, per_joint)
    direct = separate(bare, motion, mass, time_scale, units, options, per_joint)
    assert differences(grouped.to_dict(), direct.to_dict()) < 1e-9
    checked = {name for j in grouped.joints for name in j.utilization}
    assert {"bearing_moment", "motor_rms", "inertia_ratio"} <= checked
    assert all(joint.inertia_ratio > 0.0 for joint in grouped.joints)


# --- the example catalog (its page's examples run in test_docs) ----------------------------

def test_the_example_catalog_says_it_is_not_vendor_data():
    text = EXAMPLE.read_text()
    assert text.startswith("# EXAMPLE ONLY, NOT VENDOR DATA.")
    assert all(unit.source == EXAMPLE for unit in load_catalog([EXAMPLE])
               if unit.series == "XB")
    assert "**It is an example, not vendor\ndata**" in DOC


# --- the HTML report ----------------------------------------------------------------------------

@pytest.mark.slow
def test_the_report_has_a_bearing_section_with_a_figure_per_joint(rated, tmp_path):
    from hdselect.report.report_files import write_report

    write_report(tmp_path / "report", rated)
    page = (tmp_path / "report" / "index.html").read_text()
    section = page[page.index("<section id=bearing>"):]
    section = section[:section.index("</section>")]
    assert "bearing not rated by the source" in section  # the shoulder_lift's PSA-14-100
    assert section.count("rated: checked") == 5
    for joint in rated.joints:
        assert (tmp_path / "report" / f"bearing_{joint.name}.png").stat().st_size > 10_000
        assert f"alt='output bearing loads of {joint.name}" in section
    assert "data-check='bearing_moment'" in page




@pytest.mark.slow
def test_max_payload_stops_where_a_rated_bearing_does(tmp_path):
    """A unit whose gear carries 60 N m but whose bearing only 15 N m of tilting moment:
    the largest payload is where the first bearing runs out (not where the torques do, 9.9
    kg), and the sizing there holds while 0.2 % more fails on that bearing."""
    from hdselect.codesign import max_payload

    (tmp_path / "xb.toml").write_text(BEARING_BOUND)
    units = [u for u in load_catalog([tmp_path / "xb.toml"]) if u.series == "XB"]
    robot, motion = load_case(PICK)
    found = max_payload(robot, motion, catalog=units)
    assert found.rule == "bearing_moment" and 0.5 < found.mass < 5.0
    assert found.selection.feasible
    mass = found.mass * 1.002  # the payload's inertia is per kg: the same body, denser
    heavier = replace(found.payload, mass=mass,
                      inertia=tuple(tuple(v * mass for v in row) for row in found.payload.inertia))
    above = size_trajectory(robot.with_payload(heavier), found.trajectory, units)
    assert not above.feasible
    failing = [joint for joint in above.joints if joint.selected is None]
    assert failing and all(joint.strongest.binding.startswith("bearing_") for joint in failing)
