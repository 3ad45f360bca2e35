"""Every option is validated once, whichever way it comes in, and reaches the computation.

Each option is checked by the number it changes, computed independently: on the
index table (one vertical axis, tau = J qdd, no gravity) the motor torque and
the stop torque have closed forms; on planar2 the payload and its centre of
mass change the gravity torque by m g r.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hdselect import Options, Payload, load_case, plan, size, size_trajectory
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.select import PREFERENCES
from hdselect.cli.main import main
from hdselect.sizing.core import size_tasks
from hdselect.sizing.options import options_for
from hdselect.sizing.tasks import task_of
from helpers import REPO
from helpers.dynamics import J_TABLE, G

INDEX = REPO / "trajectories" / "index_table_indexing.toml"
PLANAR2 = REPO / "trajectories" / "planar2_pick_place.toml"
BENCHTOP = REPO / "trajectories" / "benchtop6_pick_place.toml"
RPM = 60 / (2 * math.pi)


def index_case():
    robot, motion = load_case(INDEX)
    return robot, motion, plan(robot, motion)


def candidate(result, unit_id, joint=0):
    return next(c for c in result.joints[joint].candidates if c.unit.id == unit_id)


# --- one validation ---------------------------------------------------------------------------

BAD = [
    ("stop_time", 0.0), ("stop_time", -1.0), ("stop_time", math.nan), ("stop_time", math.inf),
    ("stop_time", "0.1"), ("efficiency", 0.0), ("efficiency", 1.2), ("efficiency", math.nan),
    ("rotor_inertia", -1e-6), ("rotor_inertia", math.inf), ("motor_mass", -0.1),
    ("mass_coupling", "yes"), ("prefer", "cheapest"), ("life_hours", 0.0),
    ("life_hours", -1.0), ("life_hours", math.inf), ("life_basis", "L90"), ("threads", 0),
    ("threads", 1.5), ("threads", True),
]


@pytest.mark.parametrize(("name", "value"), BAD, ids=lambda v: repr(v))
def test_options_refuse_bad_values_naming_the_field(name, value):
    with pytest.raises(InputError) as caught:
        Options(**{name: value})
    assert caught.value.field == name


@pytest.mark.parametrize(("name", "value"), BAD[:6], ids=lambda v: repr(v))
def test_size_refuses_the_same_values(name, value):
    with pytest.raises(InputError) as caught:
        size(None, INDEX, **{name: value})
    assert caught.value.field == name


FLAGS = [("--stop-time", "0"), ("--stop-time", "nan"), ("--efficiency", "1.5"),
         ("--motor-inertia", "-1"), ("--motor-mass", "inf"), ("--life-hours", "-1"),
         ("--life-hours", "nan"), ("--life-hours", "0")]


@pytest.mark.parametrize(("flag", "value"), FLAGS)
def test_the_command_line_refuses_the_same_values(flag, value, capsys):
    assert main(["size", str(INDEX), flag, value]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and flag in err


def test_an_unknown_option_is_an_error_not_ignored():
    with pytest.raises(InputError, match="unknown option 'stoptime'"):
        size(None, INDEX, stoptime=0.2)


def test_the_motion_file_fills_what_is_not_given():
    _, motion = load_case(INDEX)
    assert options_for(motion) == Options(stop_time=0.1, life_hours=20000.0)
    assert options_for(motion, stop_time=0.3).stop_time == 0.3
    assert options_for(None) == Options()


# --- every option reaches the numbers ---------------------------------------------------------

def test_stop_time_reaches_the_momentary_check():
    """Index table, no gravity: an emergency stop from speed w takes J w / T_stop; a crash
    adds J_in N^2 w / T_stop to the torque carried. Both scale as 1 / T_stop."""
    robot, _, traj = index_case()
    w = np.abs(traj.qd[:, 0])
    units = load_catalog()
    for stop_time in (0.05, 0.2):
        result = size_trajectory(robot, traj, units, Options(stop_time=stop_time))
        for c in result.joints[0].candidates:
            unit = c.unit
            stop = J_TABLE * w.max() / stop_time
            crash = (np.abs(J_TABLE * traj.qdd[:, 0])
                     + unit.input_inertia * unit.ratio**2 * w / stop_time).max()
            assert c.checks["momentary"].value == pytest.approx(max(stop, crash), rel=1e-9)


@pytest.mark.parametrize("efficiency", [0.5, 0.9])
def test_efficiency_and_rotor_inertia_reach_the_motor_torque(efficiency):
    """T_motor = tau / (N eta) while driving, tau eta / N while braking, + (J_in + J_m) N qdd."""
    robot, _, traj = index_case()
    rotor = 2e-6
    result = size_trajectory(robot, traj, load_catalog(),
                             Options(efficiency=efficiency, rotor_inertia=rotor))
    qd, qdd = traj.qd[:, 0], traj.qdd[:, 0]
    tau = J_TABLE * qdd
    for c in result.joints[0].candidates:
        n = c.unit.ratio
        driving = tau * qd >= 0
        motor = (np.where(driving, tau / (n * efficiency), tau * efficiency / n)
                 + (c.unit.input_inertia + rotor) * n * qdd)
        assert c.motor.peak_torque == pytest.approx(np.abs(motor).max(), rel=1e-9)
        assert c.motor.rms_torque == pytest.approx(np.sqrt(np.mean(motor**2)), rel=1e-9)
        assert c.motor.max_speed == pytest.approx(np.abs(qd).max() * n * RPM, rel=1e-12)


def test_motor_mass_and_mass_coupling_reach_the_carried_mass():
    base = size(None, BENCHTOP)
    heavier = size(None, BENCHTOP, motor_mass=0.2)
    bare = size(None, BENCHTOP, mass_coupling=False)
    for result, motor in ((base, 0.0), (heavier, 0.2)):
        # shoulder_pan carries every other joint's unit and motor
        beyond = sum((j.selected or j.strongest).unit.mass + motor for j in result.joints[1:])
        assert result.joints[0].carried_mass == pytest.approx(beyond, rel=1e-12)
    assert all(j.carried_mass == 0.0 for j in bare.joints)
    lift = [j for j in (base, heavier) for j in j.joints if j.name == "shoulder_lift"]
    assert lift[1].load.peak_torque > lift[0].load.peak_torque


@pytest.mark.parametrize("prefer", list(PREFERENCES))
def test_prefer_chooses_by_its_own_order(prefer):
    result = size(None, BENCHTOP, prefer=prefer)
    key = PREFERENCES[prefer][1]
    for joint in result.joints:
        feasible = [c for c in joint.candidates if c.feasible]
        assert joint.selected is min(feasible, key=key)
        if prefer == "motor-rms":
            assert joint.selected.motor.rms_torque == min(c.motor.rms_torque for c in feasible)
        if prefer == "motor-peak":
            assert joint.selected.motor.peak_torque == min(c.motor.peak_torque
                                                           for c in feasible)


def test_life_hours_and_basis_reach_the_life_check():
    """A required L10 of H hours is an L50 of 5 H: the utilizations differ by five."""
    l50 = size(None, INDEX, life_hours=30000.0, life_basis="L50")
    l10 = size(None, INDEX, life_hours=30000.0, life_basis="L10")
    for a, b in zip(l50.joints[0].candidates, l10.joints[0].candidates, strict=True):
        if a.life_hours is not None:
            assert a.checks["life"].utilization == pytest.approx(30000.0 / a.life_hours)
            assert b.checks["life"].utilization == pytest.approx(5 * 30000.0 / a.life_hours)


def test_threads_do_not_change_the_answer():
    robot, motion = load_case(BENCHTOP)
    traj = plan(robot, motion)
    one = size_trajectory(robot, traj, load_catalog(), Options(threads=1))
    two = size_trajectory(robot, traj, load_catalog(), Options(threads=2))
    for a, b in zip(one.joints, two.joints, strict=True):
        np.testing.assert_array_equal(a.torque, b.torque)


def test_payload_and_its_centre_of_mass_reach_the_gravity_torque():
    """planar2 at rest in its start pose: moving the payload's centre of mass 0.1 m along
    the tool's x axis (along link 2, stretched horizontally) adds m g 0.1 to both joints."""
    robot, motion = load_case(PLANAR2)
    m = 0.4
    near = robot.with_payload(Payload(m, (0.0, 0.0, 0.0), frame="tool"))
    far = robot.with_payload(Payload(m, (0.1, 0.0, 0.0), frame="tool"))
    from hdselect.robot.dynamics import gravity_torques

    q = np.zeros((1, 2))  # both links along +x, horizontal
    diff = gravity_torques(far, q) - gravity_torques(near, q)
    np.testing.assert_allclose(np.abs(diff[0]), [m * G * 0.1, m * G * 0.1], rtol=1e-9)
    # and through the whole sizing: the same payload given three ways gives the same numbers
    api = size(None, PLANAR2, payload=Payload(m, (0.1, 0.0, 0.0), frame="tool"))
    core = size_tasks((task_of(far, plan(far, motion), motion),), load_catalog(),
                      options_for(motion))  # the file's part between its events
    for a, b in zip(api.joints, core.joints, strict=True):
        np.testing.assert_array_equal(a.torque, b.torque)


def test_payload_com_on_the_command_line_reaches_the_json(capsys, tmp_path):
    def peak(*extra):
        out = tmp_path / "result.json"
        main(["size", str(PLANAR2), "--json", str(out), "--payload", "0.4", *extra])
        capsys.readouterr()
        return {j["name"]: j["peak_torque_nm"] for j in json.loads(out.read_text())["joints"]}

    plain, shifted = peak(), peak("--payload-com", "0.1", "0", "0")
    assert shifted["shoulder"] > plain["shoulder"] and shifted["elbow"] > plain["elbow"]
    api = size(None, PLANAR2, payload=Payload(0.4, (0.1, 0.0, 0.0)))
    assert {j.name: j.load.peak_torque for j in api.joints} == pytest.approx(shifted, rel=1e-12)


def test_joints_sizes_only_those_named_and_others_still_load_them():
    only = size(None, BENCHTOP, joints=["elbow"])
    every = size(None, BENCHTOP, mass_coupling=False)
    assert [j.name for j in only.joints] == ["elbow"]
    elbow = next(j for j in every.joints if j.name == "elbow")
    np.testing.assert_array_equal(only.joints[0].torque, elbow.torque)  # nothing beyond it
    with pytest.raises(InputError, match="expected a list"):
        size(None, BENCHTOP, joints="elbow")


def test_mounting_reaches_the_gravity_torque():
    wall = size(None, PLANAR2, mounting="wall", mass_coupling=False)
    floor = size(None, PLANAR2, mass_coupling=False)
    assert not np.allclose(wall.joints[0].torque, floor.joints[0].torque)


def test_a_loaded_motion_does_not_drop_the_arguments():
    """The arguments apply whether the motion is a file or already loaded."""
    robot, motion = load_case(PLANAR2)
    from_file = size(None, PLANAR2, payload=Payload(1.0), mounting="ceiling", stop_time=0.3)
    loaded = size(robot, motion, payload=Payload(1.0), mounting="ceiling", stop_time=0.3)
    assert loaded.robot.payload.mass == 1.0 and loaded.options.stop_time == 0.3
    np.testing.assert_allclose(loaded.robot.gravity, [0, 0, 9.80665])
    for a, b in zip(from_file.joints, loaded.joints, strict=True):
        np.testing.assert_array_equal(a.torque, b.torque)
