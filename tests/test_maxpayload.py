"""`hdselect.codesign.maxpayload` against the sizing itself, re-run around the answer, and against
inverse dynamics re-run with the payload written into the model."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.payloadsizing import per_kilogram, scaled
from hdselect.motion.loading import load_case
from hdselect.motion.planning import plan
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.payload import Payload
from hdselect.sizing.core import size
from hdselect.sizing.options import options_for
from helpers import REPO
from helpers.motions import make_motion

MOTIONS = REPO / "trajectories"


def sized_at(robot, motion, payload: Payload):
    """`size` with `payload` where max-payload scaled it: the part the motion's events move
    (its file's table replaced), else the payload."""
    if payload.name in motion.parts:
        return size(robot, replace(motion, parts={**motion.parts, payload.name: payload}))
    return size(robot, motion, payload=payload)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "frame", "com"), [
    ("benchtop6_pick_place", None, None), ("planar2_pick_place", None, None),
    ("index_table_indexing", "fixture_1", None),  # off the axis: the disk's origin is on it
    ("pan_tilt_logged", None, (0.1, 0.0, 0.05))])
def test_one_percent_more_fails_and_one_percent_less_passes(name, frame, com):
    robot, motion = load_case(MOTIONS / f"{name}.toml")
    result = max_payload(robot, motion, frame=frame, com=com)
    assert result.mass is not None and 0.1 < result.mass < 100.0
    below = sized_at(robot, motion, scaled(result.payload, 0.99 * result.mass))
    above = sized_at(robot, motion, scaled(result.payload, 1.01 * result.mass))
    assert below.feasible
    assert not above.feasible
    failing = [joint for joint in above.joints if joint.selected is None]
    assert [joint.name for joint in failing] == [result.joint]
    (at_limit,) = [c for c in failing[0].candidates if c.unit.id == result.unit.id]
    assert at_limit.binding == result.rule
    assert [j.selected.unit.id for j in result.selection.joints] == \
        [j.selected.unit.id for j in below.joints]


def test_torque_is_affine_in_the_payload_mass():
    robot, motion = load_case(MOTIONS / "benchtop6_pick_place.toml")
    trajectory = plan(robot, motion)
    q, qd, qdd = (x[::50] for x in (trajectory.q, trajectory.qd, trajectory.qdd))
    unit = per_kilogram(robot.payload)
    assert unit.inertia[0][0] == pytest.approx(2.1e-4 / 0.5)
    bare = robot.with_payload(None)
    zero = inverse_dynamics(bare, q, qd, qdd)
    per_kg = inverse_dynamics(bare.with_payload(unit), q, qd, qdd) - zero
    for mass in (0.25, 1.7, 4.0):  # the payload written into the model, mass and inertia
        direct = inverse_dynamics(bare.with_payload(scaled(unit, mass)), q, qd, qdd)
        np.testing.assert_allclose(direct, zero + mass * per_kg, rtol=0, atol=1e-10)


def test_exact_to_a_millionth():
    robot, motion = load_case(MOTIONS / "planar2_pick_place.toml")
    result = max_payload(robot, motion)
    for factor, feasible in ((1 - 1e-6, True), (1 + 1e-6, False)):
        assert sized_at(robot, motion, scaled(result.payload, factor * result.mass)
                        ).feasible is feasible


def test_a_farther_centre_of_mass_carries_less():
    robot, motion = load_case(MOTIONS / "planar2_pick_place.toml")
    near = max_payload(robot, motion, com=(0.0, 0.0, 0.0))
    far = max_payload(robot, motion, com=(0.15, 0.0, 0.0))
    assert far.mass < near.mass
    assert far.payload.com == (0.15, 0.0, 0.0) and far.frame == "tool"
    assert far.payload.name == "part"  # the part the shipped file's events move
    assert far.payload.inertia == ((0.0,) * 3,) * 3
    checked = sized_at(robot, motion, Payload(0.99 * far.mass, (0.15, 0.0, 0.0),
                                              frame="tool", name="part"))
    assert checked.feasible


def test_a_payload_on_the_axis_has_no_limit(capsys):
    path = MOTIONS / "index_table_indexing.toml"
    robot, motion = load_case(path)
    result = max_payload(robot, motion, frame="disk", com=(0.0, 0.0, 0.0))
    assert result.mass == math.inf and result.joint is None
    assert main(["max-payload", str(path), "--payload-frame", "disk", "--payload-com", "0", "0",
                 "0", "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["unlimited"] is True and document["max_payload_kg"] is None


def test_a_point_mass_on_the_axes_loads_nothing():
    # the index table's default payload frame is the disk, whose origin is on the axis:
    # a point mass there has no moment and no inertia about it, whatever its mass
    robot, motion = load_case(MOTIONS / "index_table_indexing.toml")
    assert robot.payload_frame == "disk"
    result = max_payload(robot, motion)
    assert result.mass == math.inf and result.frame == "disk" and result.joint is None


def test_json_and_table(capsys):
    path = MOTIONS / "index_table_indexing.toml"
    assert main(["max-payload", str(path), "--payload-frame", "fixture_1", "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert set(document) == {"robot", "motion", "max_payload_kg", "unlimited", "payload",
                             "ranges_kg", "binding", "selection", "no_unit"}
    assert document["no_unit"] == []
    assert document["binding"]["joint"] == "table"
    assert document["ranges_kg"] == [[0.0, document["max_payload_kg"]]]
    assert document["selection"]["feasible"] is True
    assert document["payload"]["frame"] == "fixture_1" and document["payload"]["frame_given"]
    assert main(["max-payload", str(path), "--payload-frame", "fixture_1"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert f"the largest payload is {document['max_payload_kg']:.4g} kg" in out


def test_bad_input(tmp_path, capsys):
    path = MOTIONS / "planar2_pick_place.toml"
    assert main(["max-payload", str(path), "--payload-frame", "nowhere"]) == 2
    err = capsys.readouterr().err
    assert err == ("hdselect: error: --payload-frame: unknown frame 'nowhere' for the part "
                   "'part'; links are: base_link, link1, link2, tool\n")
    with pytest.raises(SystemExit) as exit_info:  # the mass is what it finds
        main(["max-payload", str(path), "--payload", "2.0"])
    assert exit_info.value.code == 2
    assert capsys.readouterr().err == ("hdselect max-payload: error: unrecognized arguments: "
                                       "--payload 2.0; max-payload takes no --payload (see "
                                       "hdselect max-payload --help)\n")
    robot, motion = make_motion(tmp_path, "toppra", [[0.0, 0.0], [1.0, 0.5]], velocity=2,
                                acceleration=5, torque=50.0)
    with pytest.raises(InputError, match=r"limits\.torque: the TOPPRA torque limits make the "
                                         "trajectory depend on the payload"):
        max_payload(robot, motion, options_for(motion))


def test_the_sizing_without_slow_downs_is_the_same_sizing():
    """max-payload's rounds and bisection ask the sizing for its verdict only.

    Without slow-downs (`size_tasks(..., slowdowns=False)`) a sizing where no unit fits
    some joints has the same units, figures and verdict, and no slow-down; with them it
    is `size_trajectory`'s, which gives a slow-down to every joint no unit fits.
    """
    from hdselect.catalog.catalogfile import load_catalog
    from hdselect.sizing.core import size_tasks, size_trajectory
    from hdselect.sizing.summary import summarize
    from hdselect.sizing.tasks import Task

    robot, motion = load_case(MOTIONS / "benchtop6_pick_place.toml", payload=Payload(8.0))
    trajectory = plan(robot, motion)
    units = load_catalog()
    full = size_trajectory(robot, trajectory, units)
    bare = size_tasks((Task(robot, trajectory),), units, slowdowns=False)
    stuck = [joint for joint in full.joints if joint.selected is None]
    assert stuck and all(joint.slowdown is not None for joint in stuck)
    assert any(joint.slowdown.factor is not None for joint in stuck)
    assert all(joint.slowdown is None and joint.scales is None for joint in bare.joints)
    with_them = summarize(full).to_dict()
    for joint in with_them["joints"]:
        joint["slowdown"] = None
    assert summarize(bare).to_dict() == with_them
