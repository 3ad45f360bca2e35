"""Co-design and the per-joint precision targets: `fastest`, `max-payload` honour them.

Oracles from outside the code under test: the index table's load inertia by hand
(`J_TABLE`, its disk and four blocks, as in tests/test_envelope.py), a point payload's
m r^2 on it, and the catalog's stiffness curve inverted (`torque_at_torsion`, checked
against Harmonic Drive's published example in tests/test_stiffness_curve.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hdselect
from hdselect import load_catalog
from hdselect.catalog.stiffness import torque_at_torsion
from hdselect.catalog.units import RAD_PER_ARCMIN
from hdselect.cli.main import main
from hdselect.codesign.choice import NoUnit
from hdselect.codesign.fastest_cycle import fastest
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.pathbounds import PathInfeasible
from hdselect.codesign.records import fastest_json
from helpers import REPO

SHG = load_catalog(["shg-2uh"], series=["SHG-2UH"])
PLANAR = REPO / "trajectories" / "planar2_pick_place.toml"
TABLE = REPO / "trajectories" / "index_table_indexing.toml"
J_TABLE = 0.0429416 + 4 * (0.00010048 + 0.3768 * 0.11**2)
"""The index table's inertia about its axis [kg m^2]: disk, and four blocks at 0.11 m."""
R = 0.2
"""The payload's distance from the table axis [m]: a point mass adds m R^2."""


@pytest.mark.slow
def test_fastest_says_no_unit_meets_a_frequency_instead_of_searching(capsys):
    problem = hdselect.resolve(None, PLANAR, catalog=SHG,
                               min_natural_frequency={"elbow": 5000.0})
    with pytest.raises(NoUnit) as caught:
        fastest(problem)
    assert caught.value.joints == ("elbow",)
    assert "natural frequency" in caught.value.diagnoses()["elbow"].lines()[0]
    with pytest.raises(PathInfeasible) as fixed:  # given units: no speed helps either
        fastest(problem, units={"shoulder": "SHG-14-50-2UH", "elbow": "SHG-14-50-2UH"})
    assert fixed.value.joint == "elbow" and fixed.value.limit == "natural_frequency"
    assert "at every speed" in str(fixed.value)
    status = main(["fastest", str(PLANAR), "--series", "SHG-2UH",
                   "--min-natural-frequency", "elbow=5000"])
    out = " ".join(capsys.readouterr().out.split())
    assert status == 1 and "no unit of the catalog can run joint 'elbow'" in out


@pytest.mark.slow
def test_fastest_holds_a_torsion_target_on_its_cycle():
    free = fastest(hdselect.resolve(None, PLANAR, catalog=SHG))
    units = {joint.name: joint.selected.unit for joint in free.check.joints}
    peak = {joint.name: float(np.max(np.abs(joint.torque))) for joint in free.check.joints}
    # a target the free cycle breaks on the shoulder, above what holding its poses takes
    figures = free.check.precision.joints[0]
    twist = 0.5 * (figures.holding_torsion + figures.max_torsion)
    bound = hdselect.resolve(None, PLANAR, catalog=SHG, max_torsion={"shoulder": twist})
    found = fastest(bound, units=units)
    shoulder = found.check.joints[0]
    limit = torque_at_torsion(units["shoulder"].stiffness, twist)
    assert limit < peak["shoulder"]
    assert shoulder.selected is not None and shoulder.selected.checks["torsion"].ok
    assert float(np.max(np.abs(shoulder.torque))) <= limit * (1.0 + 1e-9)
    assert found.cycle_time > free.cycle_time
    assert found.tasks[0].limits["shoulder"].torque_by == "torsion"
    assert fastest_json(found)["joints"][0]["torque_limit_rule"] == "torsion"
    # below what holding a pose takes, no speed helps: the message names the target
    held = hdselect.resolve(None, PLANAR, catalog=SHG,
                            max_torsion={"shoulder": 0.5 * figures.holding_torsion})
    with pytest.raises(PathInfeasible) as caught:
        fastest(held, units=units)
    assert caught.value.gravity and caught.value.joint == "shoulder"
    assert "torque limit of its largest torsion target" in str(caught.value)


@pytest.mark.slow
@pytest.mark.parametrize("target", [0.5, 2.0])
def test_max_payload_stops_where_the_torsion_target_binds(target):
    problem = hdselect.resolve(None, TABLE, catalog=SHG,
                               max_torsion={"*": target * RAD_PER_ARCMIN})
    found = max_payload(problem, com=(R, 0.0, 0.0))
    assert found.rule == "torsion" and found.joint == "table"
    limit = torque_at_torsion(found.unit.stiffness, target * RAD_PER_ARCMIN)
    joint = found.selection.joints[0]
    assert joint.selected.unit is found.unit
    assert math.isclose(joint.load.peak_torque, limit, rel_tol=1e-8)
    # by hand: the table turns alone about a vertical axis, tau = (J_TABLE + m R^2) qdd
    accel = float(np.max(np.abs(found.trajectory.qdd)))
    assert math.isclose(found.mass, (limit / accel - J_TABLE) / R**2, rel_tol=1e-6)


@pytest.mark.slow
def test_max_payload_stops_where_the_natural_frequency_binds():
    problem = hdselect.resolve(None, TABLE, catalog=SHG, min_natural_frequency=30.0)
    found = max_payload(problem, com=(R, 0.0, 0.0))
    assert found.rule == "natural_frequency" and found.joint == "table"
    # by hand: sqrt(K1 / (J_TABLE + m R^2)) / 2 pi = 30 Hz
    k1 = found.unit.stiffness.k1
    assert math.isclose(found.mass, (k1 / (2 * math.pi * 30.0) ** 2 - J_TABLE) / R**2,
                        rel_tol=1e-6)
    check = found.selection.joints[0].selected.checks["natural_frequency"]
    assert check.ok and math.isclose(check.value, 30.0, rel_tol=1e-6)
