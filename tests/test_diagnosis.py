"""The one diagnosis of a joint no unit holds (`hdselect.sizing.diagnosis`): by hand, real arms.

Oracles: a one-link pendulum (gravity m g l; a vertical axis, where the peak is I a and
the smallest slow-down sqrt(I a / T_R)); Pinocchio's RNEA with the carried units written
into the model as point masses (the real arms); every next step re-run through the
command line it prints.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import shlex
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.catalog.catalogfile import load_catalog
from hdselect.codesign.payloadbounds import duty_bounds
from hdselect.report.parts import parts_csv
from hdselect.report.report_files import report_page
from hdselect.sizing.diagnosis import diagnose, with_diagnoses
from hdselect.sizing.tasks import pooled
from helpers import REPO, run
from helpers.dynamics import rnea_loop, with_point_masses
from helpers.motions import gravity_overload_motion
from helpers.robots import BOX, revolute, urdf

BIG = REPO / "tests" / "data" / "invented_big_units.toml"
"""Invented units larger than PSA-G (not vendor data): a shipped series stands in."""


def big_units() -> dict[str, tuple]:
    """The invented catalog by its ``--catalog`` argument, as `diagnose` takes catalogs."""
    return {str(BIG): tuple(u for u in load_catalog([BIG]) if u.series == "BIG")}


def pendulum(folder: Path, *, axis: str, mass: float, length: float, limits: tuple,
             swing: float, stop_time: float = 0.1) -> Path:
    """One link of `mass` [kg] at `length` [m] on one joint about `axis`; a motion 0 -> swing.

    `limits`: velocity, acceleration, jerk [deg/s, deg/s^2, deg/s^3]. Its inertia about its
    centre is 1e-6 kg m^2 about every axis.
    """
    body = ('<link name="base"/>' + revolute("swing", "base", "arm", axis=axis)
            + f'<link name="arm">{BOX.format(x=length, m=mass, i=1e-6)}</link>')
    robot = urdf(folder, body, "pendulum.urdf")
    velocity, acceleration, jerk = limits
    motion = folder / "pendulum.toml"
    motion.write_text(f"""\
robot = "{robot.as_posix()}"
planner = "ruckig"
angle_unit = "deg"
[safety]
stop_time = {stop_time}
[limits]
velocity = {velocity}
acceleration = {acceleration}
jerk = {jerk}
[[waypoint]]
q = [0]
dwell = 0.5
[[waypoint]]
q = [{swing}]
dwell = 0.5
[[waypoint]]
q = [0]
""")
    return motion


def step_of(diagnosis, kind):
    return next((step for step in diagnosis.steps if step.kind == kind), None)


def rerun(capsys, command: str) -> tuple[int, str]:
    """Run a next step's command line as printed (``hdselect`` dropped)."""
    argv = shlex.split(command)
    assert argv[0] == "hdselect"
    status, out, _ = run(capsys, *argv[1:])
    return status, out


def test_gravity_alone_over_every_unit_by_hand(tmp_path, capsys):
    """m g l over every PSA-G unit's repeated peak: "gravity alone", no slow-down offered."""
    mass, length = 10.0, 0.5
    motion = pendulum(tmp_path, axis="0 1 0", mass=mass, length=length,
                      limits=(10, 50, 500), swing=2)
    result = hdselect.size(None, motion)
    g = float(np.linalg.norm(result.robot.gravity))
    (found,) = diagnose(result, catalogs=big_units()).values()
    assert found.joint == "swing"
    assert found.gravity.exceeds
    assert found.gravity.torque == pytest.approx(mass * g * length, rel=1e-6)
    strongest = max(u.repeated_torque for u in result.units)
    assert found.gravity.limit == pytest.approx(strongest)
    assert found.headline.rule == "peak" and found.headline.usable == pytest.approx(strongest)
    assert found.headline.value >= mass * g * length * math.cos(math.radians(2))
    assert step_of(found, "slowdown") is None  # the time scales agree: none fits
    text = " ".join(found.lines())
    assert f"gravity alone needs {mass * g * length:.3g} N m" in text
    assert "no slow-down or lower speed/acceleration limit helps" in text
    catalog = step_of(found, "catalog")
    assert catalog is not None and catalog.unit == "BIG-20-100"
    status, out = rerun(capsys, catalog.command)  # the step works as printed
    assert status == 0 and "BIG-20-100" in out
    assert step_of(found, "exclude") is None  # its only joint: nothing would be left


def test_dynamics_only_and_the_slowdown_by_hand(tmp_path, capsys):
    """A vertical axis: no gravity torque; the peak is I a, and s = sqrt(I a / T_R) fits."""
    mass, length, accel = 2.0, 0.5, 100.0  # [kg], [m], [rad/s^2]
    inertia = mass * length**2 + 1e-6
    motion = pendulum(tmp_path, axis="0 0 1", mass=mass, length=length,
                      limits=(math.degrees(2.0), math.degrees(accel), 1e8), swing=60,
                      stop_time=1.0)
    result = hdselect.size(None, motion)
    (found,) = diagnose(result).values()
    assert not found.gravity.exceeds and found.gravity.torque == pytest.approx(0.0, abs=1e-9)
    assert found.headline.rule == "peak"
    assert found.headline.value == pytest.approx(inertia * accel, rel=1e-6)
    strongest = max(result.units, key=lambda u: u.repeated_torque)
    exact = math.sqrt(inertia * accel / strongest.repeated_torque)
    step = step_of(found, "slowdown")
    assert step is not None and step.unit == strongest.id
    assert step.value == pytest.approx(math.ceil(exact * 1000) / 1000)
    assert "gravity alone" not in " ".join(found.lines())
    s = step.value  # run the motion s times slower (limits v/s, a/s^2, j/s^3, dwells x s)
    slower = motion.read_text().replace("dwell = 0.5", f"dwell = {0.5 * s!r}")
    slower = re.sub(r"(velocity|acceleration|jerk) = (\S+)", lambda m: f"{m[1]} = " + repr(
        float(m[2]) / s ** {"velocity": 1, "acceleration": 2, "jerk": 3}[m[1]]), slower)
    motion.write_text(slower)
    status, out, _ = run(capsys, "size", motion)
    assert status == 0 and strongest.id in out


def test_less_payload_is_the_solvers_and_works(tmp_path, capsys):
    """8 kg on planar2's tool: the payload step names a mass that `--payload` then holds."""
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = hdselect.size(None, motion)
    found = diagnose(result, payload_bounds=duty_bounds)["shoulder"]
    step = step_of(found, "payload")
    assert step is not None and 0.0 < step.value < 8.0
    status, out = rerun(capsys, step.command)
    assert status == 0, out
    heavier = f"{step.value + 0.05:.2f}"  # a little more and no unit holds it
    status, _, _ = run(capsys, "size", motion, "--payload", heavier)
    assert status == 1


def test_the_life_is_never_the_headline(tmp_path):
    """Life goes with the cube of torque; it is stated last, in hours, never as a percentage."""
    catalog = tmp_path / "weak.toml"  # invented: strong limits, a tiny rated torque
    catalog.write_text("""\
series = "LOW"
source = "INVENTED FOR TESTS ONLY, NOT VENDOR DATA"
[rules]
rated_input_speed_rpm = 2000
rated_life_hours = 50000
life_basis = "L50"
mean_torque_limit = "tabulated"
mean_speed = "moving"
max_momentary_events = 10000
[[unit]]
size = 20
ratio = 100
rated_torque_nm = 0.5
repeated_torque_nm = 300
average_torque_nm = 300
momentary_torque_nm = 600
static_torque_nm = 600
max_input_speed_rpm = 6500
input_inertia_kg_cm2 = 0.2
mass_kg = 1.5
""")
    units = tuple(u for u in load_catalog([catalog]) if u.series == "LOW")
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = hdselect.size(None, motion, catalog=units, life_hours=20000)
    shoulder = with_diagnoses(result).diagnoses["shoulder"]
    assert [s.rule for s in shoulder.shortfalls] == ["life"]  # holds all but its life
    assert shoulder.headline.short().startswith("life ") and "%" not in shoulder.headline.short()
    assert shoulder.headline.short().endswith("< 20,000 h")
    order = ["peak", "momentary", "static", "mean", "speed", "average_speed", "life"]
    heavy = hdselect.size(None, motion, life_hours=20000)  # PSA-G: torque and life fail
    found = with_diagnoses(heavy).diagnoses["shoulder"]
    rules = [s.rule for s in found.shortfalls]
    assert found.headline.rule == "peak" and rules[-1] == "life"
    assert rules == sorted(rules, key=order.index)  # torque, then speed rules, life last


def test_json_carries_the_diagnosis_beside_every_key(tmp_path, capsys):
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    status, out, err = run(capsys, "size", motion, "--json", "-")
    assert status == 1, err
    document = json.loads(out)
    shoulder, elbow = document["joints"]
    assert elbow["diagnosis"] is None and elbow["selected"] is not None
    for key in ("selected", "binding", "slowdown", "time_scales", "candidates",
                "max_gravity_torque_nm", "peak_torque_nm"):
        assert key in shoulder  # never renamed or dropped
    found = shoulder["diagnosis"]
    assert set(found) == {"headline", "combined", "candidates", "shortfalls", "gravity",
                          "next_steps"}
    first = found["shortfalls"][0]
    assert set(first) == {"rule", "unit", "value", "limit", "usable_limit", "si_unit",
                          "utilization", "text"}
    assert first["rule"] == "peak" and first["si_unit"] == "N m"
    assert found["headline"] == f"peak {first['value']:.3g} > {first['usable_limit']:.3g} N m"
    assert found["gravity"]["exceeds"] is True
    assert {s["kind"] for s in found["next_steps"]} >= {"payload", "exclude"}


class _Rows(HTMLParser):
    """Every table row (its cells' text) and every figure caption of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.rows: list[list[str]] = []
        self.captions: list[str] = []
        self._cell: list[str] | None = None
        self._caption: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = []
        elif tag == "figcaption":
            self._caption = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None and self.rows:
            self.rows[-1].append("".join(self._cell).strip())
            self._cell = None
        elif tag == "figcaption" and self._caption is not None:
            self.captions.append("".join(self._caption))
            self._caption = None

    def handle_data(self, data):
        for part in (self._cell, self._caption):
            if part is not None:
                part.append(data)


def test_report_and_parts_list_name_no_unit_for_the_joint(tmp_path):
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = with_diagnoses(hdselect.size(None, motion), payload_bounds=duty_bounds)
    headline = result.diagnoses["shoulder"].headline.short()
    ids = [unit.id for unit in result.units]
    parsed = _Rows()
    parsed.feed(report_page(result))
    rows = [row for row in parsed.rows if row and row[0] == "shoulder"]
    assert len(rows) >= 4  # selection (twice), parts list, bearing, loads...
    for row in rows:
        assert not any(unit in cell for cell in row for unit in ids), row
    assert any(headline in cell for row in rows for cell in row)
    captions = [c for c in parsed.captions if "shoulder" in c]
    assert captions and not any(unit in c for c in captions for unit in ids)
    (row,) = [r for r in csv.DictReader(io.StringIO(parts_csv(result)))
              if r["joint"] == "shoulder"]
    assert row["gearhead"] == "" and row["mass_kg"] == ""
    assert row["status"] == f"no unit fits: {headline}" and row["binding"] == "peak"


# --- real arms: pybullet's KUKA iiwa and xArm6 -----------------------------------------------

pybullet_data = pytest.importorskip("pybullet_data")


@pytest.mark.parametrize(("robot", "stuck"), [
    ("kuka_iiwa/model.urdf", {"lbr_iiwa_joint_2", "lbr_iiwa_joint_4"}),
    ("xarm/xarm6_robot.urdf", {"joint2"}),
])
def test_real_arms_against_pinocchio(tmp_path, capsys, robot, stuck):
    """The starter motion: the joints without a unit, their N m against Pinocchio's RNEA."""
    path = Path(pybullet_data.getDataPath()) / robot
    motion = tmp_path / "m.toml"
    assert run(capsys, "init", path, "--out", motion)[0] == 0
    status, out, err = run(capsys, "size", motion)
    assert status == 1, err
    result = hdselect.size(None, motion)
    found = diagnose(result)
    assert set(found) == stuck
    model = pin.buildModelFromUrdf(str(path))
    model.gravity.linear = np.asarray(result.robot.gravity, dtype=float)
    masses = {j.name: (j.selected or j.strongest).unit.mass for j in result.joints}
    model = with_point_masses(model, masses)
    traj = result.trajectory
    tau = rnea_loop(model, traj.q, traj.qd, traj.qdd)
    still = rnea_loop(model, traj.q, np.zeros_like(traj.qd), np.zeros_like(traj.qdd))
    rest = pooled(result.tasks).rest
    for name, diagnosis in found.items():
        j = result.robot.joint_index(name)
        moving = ~rest[:, j]
        assert diagnosis.headline.rule != "life"
        assert diagnosis.headline.short() in " ".join(out.split())  # the table's cell
        peak = next((s for s in diagnosis.shortfalls if s.rule == "peak"), None)
        if peak is not None:
            assert peak.value == pytest.approx(np.abs(tau[moving, j]).max(), rel=1e-6)
        if diagnosis.gravity.exceeds:
            assert diagnosis.gravity.torque == pytest.approx(np.abs(still[moving, j]).max(),
                                                             rel=1e-6)


def test_a_step_keeps_the_runs_own_options(tmp_path, capsys, monkeypatch):
    """The command is the run's, one option set and the output files left out."""
    monkeypatch.chdir(tmp_path)
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    status, _, err = run(capsys, "size", "heavy.toml", "--margin", "0.1", "--json", "a.json",
                         "--exclude", "elbow")
    assert status == 1, err
    (shoulder,) = json.loads((tmp_path / "a.json").read_text())["joints"]
    steps = {s["kind"]: s["command"] for s in shoulder["diagnosis"]["next_steps"]}
    assert steps["payload"].startswith("hdselect size heavy.toml --margin 0.1 --exclude elbow")
    assert "--json" not in steps["payload"] and "exclude" not in steps  # its only joint left
    status, out = rerun(capsys, steps["payload"])
    assert status == 0 and "design margin: 10 %" in " ".join(out.split()) and motion.exists()


def test_each_rule_held_by_some_unit_but_none_holds_all(tmp_path):
    """A strong slow unit and a weak fast one: the closest unit's shortfalls, said so."""
    catalog = tmp_path / "split.toml"  # invented
    unit = """\
[[unit]]
size = {size}
ratio = 100
rated_torque_nm = {torque}
repeated_torque_nm = {torque}
momentary_torque_nm = {torque}
static_torque_nm = {torque}
max_input_speed_rpm = {speed}
input_inertia_kg_cm2 = 0.01
mass_kg = 0.5
"""
    catalog.write_text(BIG.read_text().split("[[unit]]")[0].replace('"BIG"', '"SPLIT"')
                       + unit.format(size=20, torque=300, speed=100)
                       + unit.format(size=21, torque=1, speed=9000))
    units = tuple(u for u in load_catalog([catalog]) if u.series == "SPLIT")
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = hdselect.size(None, motion, catalog=units)
    found = diagnose(result)["shoulder"]
    strong = result.joints[0].candidates[0]
    speed = strong.checks["speed"]
    assert found.combined and [s.rule for s in found.shortfalls] == ["speed"]
    assert found.headline.unit == strong.unit.id == "SPLIT-20-100"
    assert found.headline.value == pytest.approx(speed.value) and found.headline.limit == 100
    assert found.headline.short() == f"speed {speed.value:.3g} > 100 rpm"
    assert found.lines()[0].startswith("shoulder: no unit holds every rule; the closest: ")


def test_figures_name_no_unit_as_the_joints(tmp_path):
    """The torque figure's title gives the shortfall; the bearing figure draws no rating."""
    from hdselect.report.bearing_figures import bearing_figure
    from hdselect.report.joint_figures import joint_figure

    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = with_diagnoses(hdselect.size(None, motion))
    shoulder = result.joints[0]
    title = joint_figure(result, shoulder).get_suptitle()
    assert title.startswith(f"shoulder: {result.diagnoses['shoulder'].summary()}; the limits "
                            "drawn: the strongest candidate, ")
    bearing = bearing_figure(result, shoulder)
    assert bearing is not None
    assert not any(unit.id in bearing.get_suptitle() for unit in result.units)


def test_no_step_checked_on_less_than_the_joint_was_sized_on(tmp_path):
    """An envelope sizes a joint on its tasks' samples and worst states of no duration:
    a step checked on the tasks alone could fail there, so none is offered from them."""
    from dataclasses import replace

    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = hdselect.size(None, motion)
    worse = replace(result, joints=tuple(
        replace(j, torque=np.append(j.torque, 0.0), stop_torque=np.append(j.stop_torque, 0.0))
        for j in result.joints))
    plain = diagnose(result, catalogs=big_units(), payload_bounds=duty_bounds)["shoulder"]
    found = diagnose(worse, catalogs=big_units(), payload_bounds=duty_bounds)["shoulder"]
    assert {s.kind for s in plain.steps} == {"catalog", "payload", "exclude"}
    assert {s.kind for s in found.steps} == {"exclude"}
    assert found.shortfalls == plain.shortfalls


def test_the_design_margin_lowers_every_limit_stated(tmp_path):
    motion = gravity_overload_motion(tmp_path / "heavy.toml")
    result = hdselect.size(None, motion, margin=0.2)
    found = diagnose(result)["shoulder"]
    strongest = max(u.repeated_torque for u in result.units)
    assert found.headline.limit == pytest.approx(strongest)
    assert found.headline.usable == pytest.approx(0.8 * strongest)
    assert found.gravity.limit == pytest.approx(0.8 * strongest)
    assert found.headline.short().endswith(f"> {0.8 * strongest:.3g} N m")
