"""The tool's holding deflection against MuJoCo: the units' K1 as joint springs, settled.

The planar 2-link arm (robots/planar2.xml, compiled by MuJoCo) carries a 0.4 kg payload
at its tool. Each joint gets a spring of its unit's K1 (MJCF ``stiffness``) whose rest
angle (``springref``, MuJoCo's ``qpos_spring``) is the commanded pose: the servo holds
the input there. Under gravity and the payload the arm settles where MuJoCo's spring
torque balances its gravity torque (solved by fixed-point iteration on MuJoCo's own
``qfrc_bias``, and checked by MuJoCo's forward dynamics: no acceleration there). The
tool site's displacement is then hdselect's holding deflection, to first order.

The tolerance, derived: hdselect takes the gravity torque at the commanded pose and
the kinematics to first order. Settled, the joints have turned by dtheta (here below
2e-3 rad): the gravity torque changes by dG/dq dtheta, a fraction of order |dtheta| of
itself (its lever arms turn by dtheta), and the tool's arc differs from its tangent by
|dtheta| / 2 of itself. So the two agree within a few |dtheta| of the deflection; 5
|dtheta| is asserted, and a wrong sign, a missing payload or a wrong K1 would be off by
100 % or more.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest

import hdselect
from hdselect.catalog.builtin import catalog_file
from hdselect.catalog.units import Stiffness

ROOT = Path(__file__).resolve().parents[1]
PAYLOAD, OFFSET = 0.4, 0.03  # kg, and m beyond the tool site along link2


def springy_arm(k1: tuple[float, float], gravity: float) -> mujoco.MjModel:
    """planar2.xml with a spring of K1 on each joint and the payload at its tool."""
    text = (ROOT / "robots" / "planar2.xml").read_text()
    text = text.replace('<compiler angle="radian"/>',
                        f'<compiler angle="radian"/><option gravity="0 0 {-gravity!r}"/>')
    text = text.replace('<joint name="shoulder"', f'<joint name="shoulder" stiffness="{k1[0]!r}"')
    text = text.replace('<joint name="elbow"', f'<joint name="elbow" stiffness="{k1[1]!r}"')
    text = text.replace('<site name="tool" pos="0.25 0 0"/>',
                        '<site name="tool" pos="0.25 0 0"/><body name="payload" '
                        f'pos="{0.25 + OFFSET!r} 0 0"><inertial pos="0 0 0" mass="{PAYLOAD!r}" '
                        'diaginertia="1e-9 1e-9 1e-9"/></body>')
    return mujoco.MjModel.from_xml_string(text)


def settled(model: mujoco.MjModel, commanded: np.ndarray, k1: np.ndarray) -> np.ndarray:
    """The tool site's displacement when the springs hold `commanded` against gravity [m]."""
    data = mujoco.MjData(model)
    model.qpos_spring[:] = commanded
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "tool")
    data.qpos[:] = commanded
    mujoco.mj_forward(model, data)
    start = data.site_xpos[site].copy()
    for _ in range(100):  # -K (q - q_ref) = bias(q): q = q_ref - bias(q) / K
        previous = data.qpos.copy()
        data.qpos[:] = commanded - data.qfrc_bias / k1
        mujoco.mj_forward(model, data)
        if np.max(np.abs(data.qpos - previous)) < 1e-15:
            break
    np.testing.assert_allclose(data.qacc, 0.0, atol=1e-8)  # MuJoCo's own verdict: at rest
    return data.site_xpos[site] - start


def test_holding_deflection_equals_mujoco_springs_settled_under_gravity_and_payload() -> None:
    robot = hdselect.load_robot(ROOT / "robots" / "planar2.xml").with_payload(
        hdselect.Payload(PAYLOAD, com=(OFFSET, 0.0, 0.0), frame="tool"))
    motion = hdselect.load_motion(ROOT / "trajectories" / "planar2_pick_place.toml", robot)
    trajectory = hdselect.plan(robot, motion)
    shg = {u.id: u for u in hdselect.load_catalog([catalog_file("shg-2uh")])}
    units = {}
    for name, unit_id in (("shoulder", "SHG-17-100-2UH"), ("elbow", "SHG-14-100-2UH")):
        unit = shg[unit_id]  # K1 alone: the spring MuJoCo is given, linear at every torque
        units[name] = replace(unit, stiffness=Stiffness(k1=unit.stiffness.k1), bearing=None)
    result = hdselect.check_units(robot, trajectory, units,
                                  hdselect.Options(mass_coupling=False))
    tool = result.precision.tool
    k1 = np.array([units["shoulder"].stiffness.k1, units["elbow"].stiffness.k1])
    gravity = float(np.linalg.norm(robot.model.gravity.linear))
    model = springy_arm((float(k1[0]), float(k1[1])), gravity)
    picks = sorted({int(tool.worst_holding), 0, len(tool.samples) // 3,
                    2 * len(tool.samples) // 3, len(tool.samples) - 1})
    twist = max(j.holding_torsion for j in result.precision.joints)
    assert 1e-4 < twist < 2e-3  # a sag worth measuring, small enough for first order
    for i in picks:
        pose = trajectory.q[tool.samples[i]]
        expected = settled(model, pose, k1)
        assert np.linalg.norm(expected) > 1e-5
        np.testing.assert_allclose(tool.holding_translation[i], expected,
                                   atol=5 * twist * np.linalg.norm(expected))
    worst = settled(model, trajectory.q[tool.samples[tool.worst_holding]], k1)
    assert tool.max_holding == pytest.approx(float(np.linalg.norm(worst)), rel=5 * twist)
    assert math.isclose(worst[2], tool.holding_translation[tool.worst_holding][2],
                        rel_tol=5 * twist) and worst[2] < 0.0  # it sags
