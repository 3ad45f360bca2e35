"""Tests of hdselect.robot.mjcf against MuJoCo itself (the oracle) and closed forms.

Every MJCF document shipped by the installed packages (pybullet_data, gymnasium,
dm_control, mujoco) is read; a file MuJoCo compiles is either loaded and its
kinematics and mass compared with MuJoCo's (its torques: test_mujoco_oracle), or
refused for a reason checked against MuJoCo's own model. Synthetic files cover
what the real ones may not: default classes, includes, visual-only geoms, several
joints in one body, angle units, joint ``ref``, couplings, several trees,
fusestatic; their inverse dynamics are compared with MuJoCo's here.
"""

from __future__ import annotations

import importlib.util
import math
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.mjcf import UNLIMITED, MjcfRead, model_from_mjcf
from mujoco_oracle import compare as oracle_compare
from mujoco_oracle import compile_quietly as mj_compile

SAMPLES = 20
"""Random states per synthetic file."""
REAL_SAMPLES = 2
"""Random states per real file (their torques are compared end to end in test_mujoco_oracle)."""
RTOL = 1e-9
"""Torque agreement, relative to the largest MuJoCo torque of the file's samples."""
PACKAGES = ("pybullet_data", "gymnasium", "dm_control", "mujoco")
_DISABLED = (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
             | mujoco.mjtDisableBit.mjDSBL_EQUALITY | mujoco.mjtDisableBit.mjDSBL_LIMIT
             | mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS | mujoco.mjtDisableBit.mjDSBL_ACTUATION
             | mujoco.mjtDisableBit.mjDSBL_SPRING | mujoco.mjtDisableBit.mjDSBL_DAMPER)
_JOINT, _BODY, _SITE = mujoco.mjtObj.mjOBJ_JOINT, mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_SITE


# ---------------------------------------------------------------- helpers (the oracle)

def _root_tag(path: Path) -> str | None:
    try:
        for _, element in ET.iterparse(path, events=("start",)):
            return element.tag
    except ET.ParseError:
        return None
    return None


def mjcf_files() -> list[Path]:
    """Every XML document with a ``<mujoco>`` root shipped by the installed PACKAGES."""
    files = []
    for package in PACKAGES:
        spec = importlib.util.find_spec(package)
        for root in (spec.submodule_search_locations or []) if spec else []:
            files += [p for p in sorted(Path(root).rglob("*.xml")) if _root_tag(p) == "mujoco"]
    return files


def oracle(path: Path) -> mujoco.MjModel:
    """MuJoCo's model of `path` with everything but rigid-body dynamics switched off."""
    mj = mj_compile(path)
    for field in ("dof_armature", "dof_damping", "dof_frictionloss", "jnt_stiffness",
                  "tendon_armature", "actuator_armature", "body_gravcomp"):
        getattr(mj, field)[:] = 0.0
    mj.opt.density = mj.opt.viscosity = 0.0
    mj.opt.disableflags |= _DISABLED
    mujoco.mj_setConst(mj, mujoco.MjData(mj))  # dof_M0 of simple bodies holds the armature
    return mj


def _mj_id(mj: mujoco.MjModel, kind: mujoco.mjtObj, name: str, unnamed: str) -> int:
    """MuJoCo's id of a Pinocchio name: by name, or from ``unnamed_<kind>_<id>``."""
    index = mujoco.mj_name2id(mj, kind, name)
    if index < 0 and name.startswith(unnamed):
        index = int(name.removeprefix(unnamed))
    assert index >= 0, name
    return index


def addresses(read: MjcfRead, mj: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo qpos and dof address of each Pinocchio q and v entry, found by joint name."""
    model = read.model
    qpos, dof = np.zeros(model.nq, dtype=int), np.zeros(model.nv, dtype=int)
    for j in range(1, model.njoints):
        jid = _mj_id(mj, _JOINT, model.names[j], "unnamed_joint_")
        qpos[model.joints[j].idx_q] = mj.jnt_qposadr[jid]
        dof[model.joints[j].idx_v] = mj.jnt_dofadr[jid]
    return qpos, dof


def random_q(model: pin.Model, rng: np.random.Generator) -> np.ndarray:
    """A configuration within the limits: uniform in a range, else within +-pi rad or +-1 m."""
    low, high = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    free = ~np.isfinite(low)
    low[free], high[free] = -math.pi, math.pi
    return rng.uniform(low, high)


def compare(path: Path, samples: int = SAMPLES, seed: int = 0) -> tuple[MjcfRead, float, float]:
    """Load `path` and check torques, kinematics and mass against MuJoCo.

    Returns:
        The read, the worst torque difference [N m or N] and the torque scale [N m or N].
    """
    read = model_from_mjcf(path)
    mj = oracle(path)
    model, data, d = read.model, read.model.createData(), mujoco.MjData(mj)
    qpos, dof = addresses(read, mj)
    np.testing.assert_array_equal(qpos, read.qpos_index)
    np.testing.assert_array_equal(dof, read.dof_index)
    rng = np.random.default_rng(seed)
    worst = scale = 0.0
    for k in range(samples):
        q = random_q(model, rng)
        v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
        d.qpos[:], d.qvel[:], d.qacc[:] = mj.qpos0, 0.0, 0.0
        d.qpos[qpos], d.qvel[dof], d.qacc[dof] = q, v, a
        mujoco.mj_inverse(mj, d)
        assert not d.qfrc_passive.any() and not d.qfrc_constraint.any()
        tau = pin.rnea(model, data, q, v, a)
        worst = max(worst, float(np.abs(tau - d.qfrc_inverse[dof]).max()))
        scale = max(scale, float(np.abs(d.qfrc_inverse[dof]).max()))
        if k < 3:
            check_kinematics(read, mj, d, data, q)
    assert worst <= RTOL * max(scale, 1e-12), (worst, scale)
    check_mass(read, mj)
    return read, worst, scale


def check_kinematics(read: MjcfRead, mj: mujoco.MjModel, d: mujoco.MjData, data: pin.Data,
                     q: np.ndarray) -> None:
    """Every body, site and joint of the model where MuJoCo puts it (d holds q already)."""
    model = read.model
    mujoco.mj_kinematics(mj, d)
    pin.framesForwardKinematics(model, data, q)
    tol = 1e-9 * max(1.0, mj.stat.extent)
    for f, frame in enumerate(model.frames):
        if frame.type == pin.FrameType.BODY:
            b = _mj_id(mj, _BODY, frame.name, "unnamed_body_")
            pos, rot = d.xpos[b], d.xmat[b].reshape(3, 3)
        elif frame.type == pin.FrameType.OP_FRAME:
            s = mujoco.mj_name2id(mj, _SITE, frame.name)
            pos, rot = d.site_xpos[s], d.site_xmat[s].reshape(3, 3)
        elif frame.type == pin.FrameType.JOINT:
            jid = _mj_id(mj, _JOINT, frame.name, "unnamed_joint_")
            placement = data.oMi[frame.parentJoint]
            anchor = d.xanchor[jid].copy()  # MuJoCo's anchor is where the joint starts:
            if mj.jnt_type[jid] == mujoco.mjtJoint.mjJNT_SLIDE:  # a slide moves it on
                adr = mj.jnt_qposadr[jid]
                anchor += (d.qpos[adr] - mj.qpos0[adr]) * d.xaxis[jid]
            np.testing.assert_allclose(placement.translation, anchor, atol=tol)
            np.testing.assert_allclose(placement.rotation @ mj.jnt_axis[jid], d.xaxis[jid],
                                       atol=1e-9)
            continue
        else:
            continue
        np.testing.assert_allclose(data.oMf[f].translation, pos, atol=tol, err_msg=frame.name)
        np.testing.assert_allclose(data.oMf[f].rotation, rot, atol=1e-9, err_msg=frame.name)


def check_mass(read: MjcfRead, mj: mujoco.MjModel) -> None:
    """The model carries exactly MuJoCo's mass of the bodies it holds [kg]."""
    bodies = [_mj_id(mj, _BODY, f.name, "unnamed_body_") for f in read.model.frames
              if f.type == pin.FrameType.BODY]
    mass = sum(float(inertia.mass) for inertia in read.model.inertias)
    assert mass == pytest.approx(float(mj.body_mass[bodies].sum()), rel=1e-12, abs=1e-15)


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text))
    return path


# ---------------------------------------------------------------- every MJCF file on the machine

FILES = mjcf_files()


def test_the_machine_has_mjcf_files() -> None:
    assert len(FILES) >= 26  # pybullet_data/mjcf alone ships 26


@pytest.mark.parametrize("path", FILES, ids=lambda p: "/".join(p.parts[-3:]))
def test_real_file_is_read_as_mujoco_reads_it(path: Path) -> None:
    try:
        mj_compile(path)
    except ValueError:
        with pytest.raises(InputError, match="not a valid MJCF robot \\(MuJoCo's compiler\\)") \
                as err:
            model_from_mjcf(path)
        assert str(path) in str(err.value) and "\n" not in str(err.value)
        return
    try:
        compare(path, samples=REAL_SAMPLES)
    except InputError as err:
        check_refusal(path, err)


def check_refusal(path: Path, err: InputError) -> None:
    """A refusal of a file MuJoCo compiles names a reason that MuJoCo's model confirms."""
    mj = mj_compile(path)
    assert err.path == path and "\n" not in str(err)
    kinds = set(int(t) for t in mj.jnt_type)
    if err.reason.startswith("no hinge or slide joint to size"):
        assert not kinds & {mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE}
    else:
        body, joint = err.reason.split("'")[1], err.reason.split("'")[3]
        assert err.reason.endswith("hdselect sizes hinge and slide joints only")
        jid = _mj_id(mj, _JOINT, joint, "unnamed_joint_")
        assert mj.jnt_type[jid] == mujoco.mjtJoint.mjJNT_BALL
        assert mj.jnt_bodyid[jid] == _mj_id(mj, _BODY, body, "unnamed_body_")


# ---------------------------------------------------------------- closed forms

PENDULUM = """
<mujoco>
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="link" pos="0 0 1">
      <joint name="swing" type="hinge" axis="0 1 0"/>
      {inertia}
      <site name="tip" pos="0 0 -0.5"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(("inertia", "moment"), [
    ('<inertial pos="0 0 -0.5" mass="2" diaginertia="0.01 0.03 0.02"/>', 0.03),
    ('<geom type="sphere" pos="0 0 -0.5" size="0.1" mass="2"/>', 2 / 5 * 2 * 0.1 ** 2),
])
def test_pendulum_closed_form(tmp_path: Path, inertia: str, moment: float) -> None:
    path = write(tmp_path, "pendulum.xml", PENDULUM.format(inertia=inertia))
    read = model_from_mjcf(path)
    model, data = read.model, read.model.createData()
    mass, arm, g = 2.0, 0.5, 9.81
    assert pin.computeTotalMass(model) == pytest.approx(mass)
    rng = np.random.default_rng(1)
    for q, v, a in rng.normal(size=(SAMPLES, 3)):
        tau = pin.rnea(model, data, np.array([q]), np.array([v]), np.array([a]))[0]
        assert tau == pytest.approx((moment + mass * arm ** 2) * a + mass * g * arm * math.sin(q),
                                    rel=1e-12, abs=1e-12)
    compare(path)


# ---------------------------------------------------------------- synthetic files vs MuJoCo

SEVERAL_JOINTS = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0.1 0.2 0.3" quat="0.9 0.1 0.3 0.2">
      <geom type="box" size="0.05 0.05 0.05" mass="3"/>
      <body name="knot" pos="0 0 0.2" euler="0.3 -0.2 0.5">
        <joint name="first" type="hinge" pos="0.02 0.01 -0.03" axis="1 2 3" ref="0.4"
               range="-1 2"/>
        <joint name="second" type="slide" pos="-0.01 0.05 0" axis="0 1 1" ref="0.05"/>
        <joint name="third" type="hinge" pos="0.03 -0.02 0.04" axis="0 0 1" ref="-0.3"/>
        <geom type="capsule" fromto="0 0 0 0.3 0.1 0" size="0.03" mass="1.5"/>
        <site name="knot_site" pos="0.3 0.1 0" euler="0.1 0.2 0.3"/>
        <body name="tip" pos="0.3 0.1 0">
          <joint name="fourth" type="hinge" pos="0 0 0.01" axis="0 -1 0"/>
          <geom type="box" size="0.02 0.1 0.03" pos="0 0.1 0" mass="0.7"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_several_joints_in_one_body_are_exact(tmp_path: Path) -> None:
    path = write(tmp_path, "several.xml", SEVERAL_JOINTS)
    read, worst, scale = compare(path)
    model = read.model
    assert [model.names[j] for j in range(1, model.njoints)] == ["first", "second", "third",
                                                                 "fourth"]
    # the body "knot" sits on its last joint; the joints before it carry no mass
    knot = model.frames[model.getFrameId("knot", pin.FrameType.BODY)]
    assert knot.parentJoint == model.getJointId("third")
    assert model.inertias[model.getJointId("first")].mass == 0.0
    assert model.inertias[model.getJointId("second")].mass == 0.0
    # hinge/slide axes as MuJoCo normalises them; the unit axis 0 0 1 is Pinocchio's RZ
    first = model.joints[model.getJointId("first")].extract()
    np.testing.assert_allclose(first.axis, np.array([1, 2, 3]) / math.sqrt(14), atol=1e-15)
    assert model.joints[model.getJointId("third")].shortname() == "JointModelRZ"
    assert model.joints[model.getJointId("second")].shortname() == "JointModelPrismaticUnaligned"


def test_joint_ref_keeps_mujoco_qpos_and_limits(tmp_path: Path) -> None:
    """A joint's ``ref`` shifts MuJoCo's zero; the Pinocchio q is qpos, limits as in the file."""
    path = write(tmp_path, "several.xml", SEVERAL_JOINTS)
    read = model_from_mjcf(path)
    mj = mj_compile(path)
    model = read.model
    np.testing.assert_array_equal(model.referenceConfigurations["qpos0"], mj.qpos0)
    assert list(model.lowerPositionLimit) == [-1.0, -UNLIMITED, -UNLIMITED, -UNLIMITED]
    assert list(model.upperPositionLimit) == [2.0, UNLIMITED, UNLIMITED, UNLIMITED]
    assert np.all(model.upperEffortLimit == UNLIMITED)
    assert np.all(model.upperVelocityLimit == UNLIMITED)
    # at q = qpos0 (the refs) the bodies are where the file draws them
    data, d = model.createData(), mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, d)
    pin.framesForwardKinematics(model, data, mj.qpos0)
    tip = model.getFrameId("tip", pin.FrameType.BODY)
    np.testing.assert_allclose(data.oMf[tip].translation, d.xpos[mj.body("tip").id], atol=1e-12)


DEGREES = """
<mujoco>
  <compiler angle="{unit}"/>
  <worldbody>
    <body name="upper" pos="0 0 0.5" euler="{e1} 0 {e2}">
      <joint name="shoulder" type="hinge" axis="0 1 0" range="{lo} {hi}" ref="{ref}"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04" density="2700"/>
      <body name="lower" pos="0 0 -0.4" axisangle="1 0 0 {e1}">
        <joint name="elbow" type="hinge" axis="1 0 0" range="{lo} {hi}"/>
        <geom type="cylinder" fromto="0 0 0 0.3 0 -0.1" size="0.03" density="2700"/>
        <site name="wrist" pos="0.3 0 -0.1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_compiler_angle_units_and_fromto_geoms(tmp_path: Path) -> None:
    degrees = write(tmp_path, "degrees.xml", DEGREES.format(unit="degree", e1=30, e2=-45, lo=-90,
                                                            hi=120, ref=20))
    radians = write(tmp_path, "radians.xml", DEGREES.format(
        unit="radian", e1=math.radians(30), e2=math.radians(-45), lo=math.radians(-90),
        hi=math.radians(120), ref=math.radians(20)))
    for path in (degrees, radians):
        compare(path)
    a, b = model_from_mjcf(degrees).model, model_from_mjcf(radians).model
    np.testing.assert_allclose(a.lowerPositionLimit, [math.radians(-90)] * 2, rtol=1e-15)
    np.testing.assert_allclose(a.upperPositionLimit, b.upperPositionLimit, rtol=1e-15)
    for j in range(1, a.njoints):
        assert a.jointPlacements[j].isApprox(b.jointPlacements[j], 1e-12)
        assert a.inertias[j].isApprox(b.inertias[j], 1e-12)


def test_welded_base_and_sites_are_frames(tmp_path: Path) -> None:
    path = write(tmp_path, "welded.xml", """
        <mujoco>
          <worldbody>
            <body name="pedestal" pos="1 2 0" euler="0 0 90">
              <geom type="cylinder" size="0.1 0.2" mass="20"/>
              <site name="pedestal_top" pos="0 0 0.2"/>
              <body name="link1" pos="0 0 0.2">
                <joint name="j1" type="hinge" axis="0 0 1"/>
                <geom type="box" size="0.2 0.03 0.03" pos="0.2 0 0" mass="2"/>
                <body name="flange" pos="0.4 0 0" euler="0 90 0">
                  <site name="tcp" pos="0 0 0.1"/>
                </body>
              </body>
            </body>
          </worldbody>
        </mujoco>""")
    read, _, _ = compare(path)
    model = read.model
    assert read.root_body == "pedestal"
    kinds = {f.name: f.type for f in model.frames}
    assert kinds["tcp"] == kinds["pedestal_top"] == pin.FrameType.OP_FRAME
    assert kinds["flange"] == kinds["pedestal"] == pin.FrameType.BODY
    tcp = model.frames[model.getFrameId("tcp")]
    assert tcp.parentJoint == model.getJointId("j1")
    assert model.frames[model.getFrameId("pedestal")].parentJoint == 0


def test_fusestatic_moves_mass_and_sites_as_mujoco_does(tmp_path: Path) -> None:
    path = write(tmp_path, "fused.xml", """
        <mujoco>
          <compiler fusestatic="true"/>
          <worldbody>
            <body name="link" pos="0 0 1">
              <joint name="j" type="hinge" axis="0 1 0"/>
              <geom type="sphere" size="0.05" mass="1"/>
              <body name="bracket" pos="0.3 0 0" euler="0 0 45">
                <geom type="box" size="0.05 0.05 0.05" mass="4"/>
                <site name="mount" pos="0.1 0 0"/>
              </body>
            </body>
          </worldbody>
        </mujoco>""")
    read, _, _ = compare(path)
    names = {f.name for f in read.model.frames}
    assert "bracket" not in names and "mount" in names  # MuJoCo fused the body, kept its site
    assert pin.computeTotalMass(read.model) == pytest.approx(5.0)


def test_armature_left_out_where_mujoco_precomputes_it(tmp_path: Path) -> None:
    """A one-body tree is 'simple' in MuJoCo: its inertia, armature included, is compiled."""
    path = write(tmp_path, "rotor.xml", """
        <mujoco>
          <worldbody>
            <body name="disc">
              <joint name="spin" type="hinge" axis="0 0 1" armature="0.2"/>
              <geom type="sphere" size="0.1" mass="1"/>
            </body>
          </worldbody>
          <actuator><motor name="drive" joint="spin" gear="50" armature="0.001"/></actuator>
          <keyframe><key name="home" qpos="0.5"/></keyframe>
        </mujoco>""")
    read, _, _ = compare(path)
    raw = mj_compile(path)
    d = mujoco.MjData(raw)
    d.qacc[:] = 1.0
    mujoco.mj_inverse(raw, d)
    disc = 2 / 5 * 1.0 * 0.1 ** 2  # [kg m^2]
    assert d.qfrc_inverse[0] == pytest.approx(disc + 0.2 + 50 ** 2 * 0.001)  # MuJoCo's own
    model = read.model
    tau = pin.rnea(model, model.createData(), np.zeros(1), np.zeros(1), np.ones(1))
    assert tau[0] == pytest.approx(disc, rel=1e-12)
    assert "armature on 1 joint (up to 0.2 kg m^2 or kg): the motor's reflected inertia, not " \
        "load on the gear output; left out" in read.set_aside
    assert any("drive on joint spin, gear 50, armature 0.001" in note for note in read.set_aside)
    assert model.referenceConfigurations["home"][0] == 0.5


# ---------------------------------------------------------------- Pinocchio's reader vs MuJoCo's

def test_visual_geoms_have_mass_as_in_mujoco(tmp_path: Path) -> None:
    path = write(tmp_path, "visual.xml", """
        <mujoco>
          <worldbody>
            <body name="link">
              <joint name="j" type="hinge" axis="0 0 1"/>
              <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" density="1000"
                    contype="0" conaffinity="0"/>
            </body>
          </worldbody>
        </mujoco>""")
    mass = float(mj_compile(path).body_mass[1])
    assert mass > 0.4
    assert sum(i.mass for i in pin.buildModelFromMJCF(str(path)).inertias) == 0.0  # Pinocchio
    assert pin.computeTotalMass(model_from_mjcf(path).model) == pytest.approx(mass, rel=1e-12)
    compare(path)


def test_gym_pusher_arm_mass_as_in_mujoco() -> None:
    spec = importlib.util.find_spec("gymnasium")
    if spec is None:
        pytest.skip("gymnasium is not installed")
    path = Path(spec.submodule_search_locations[0]) / "envs/mujoco/assets/pusher.xml"
    mj = mj_compile(path)
    arm = float(mj.body_subtreemass[mj.body("r_shoulder_pan_link").id])
    assert arm == pytest.approx(13.7, abs=0.05)
    assert sum(i.mass for i in pin.buildModelFromMJCF(str(path)).inertias) < 0.2  # Pinocchio
    read = model_from_mjcf(path)
    assert pin.computeTotalMass(read.model) == pytest.approx(arm, rel=1e-12)
    assert any(note.startswith("trees with hinge or slide joints but no actuator are left out: "
                               "object, goal") for note in read.notes)


def test_joint_pos_from_a_default_class_as_in_mujoco(tmp_path: Path) -> None:
    path = write(tmp_path, "defaults.xml", """
        <mujoco>
          <default>
            <default class="finger">
              <joint type="hinge" pos="0 0 0.05" axis="0 1 0" range="-1 1"/>
            </default>
          </default>
          <worldbody>
            <body name="link" pos="0 0 0.1" childclass="finger">
              <joint name="j"/>
              <geom type="box" size=".01 .01 .05" pos="0 0 -0.05" mass="1"/>
            </body>
          </worldbody>
        </mujoco>""")
    anchor = np.array([0.0, 0.0, 0.15])  # MuJoCo: body pos + the class's joint pos
    mj = mj_compile(path)
    d = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, d)
    np.testing.assert_allclose(d.xanchor[0], anchor)
    theirs = pin.buildModelFromMJCF(str(path))
    assert not np.allclose(theirs.jointPlacements[1].translation, anchor)  # Pinocchio
    ours = model_from_mjcf(path).model
    np.testing.assert_allclose(ours.jointPlacements[1].translation, anchor, atol=1e-15)
    assert ours.upperPositionLimit[0] == math.radians(1)  # MJCF angles are degrees by default
    compare(path)


INCLUDING = """
<mujoco>
  <worldbody>
    <body name="link">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <geom type="sphere" size="0.01" mass="0.1"/>
      <include file="{file}"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_include_is_read_as_in_mujoco(tmp_path: Path) -> None:
    write(tmp_path, "parts.xml", """
        <mujocoinclude>
          <geom type="sphere" size="0.05" pos="0.3 0 0" mass="2"/>
        </mujocoinclude>""")
    path = write(tmp_path, "including.xml", INCLUDING.format(file="parts.xml"))
    assert sum(i.mass for i in pin.buildModelFromMJCF(str(path)).inertias) == 0.1  # Pinocchio
    assert pin.computeTotalMass(model_from_mjcf(path).model) == pytest.approx(2.1)
    compare(path)


def test_missing_include_is_one_line_naming_the_file(tmp_path: Path) -> None:
    path = write(tmp_path, "including.xml", INCLUDING.format(file="missing_parts.xml"))
    pin.buildModelFromMJCF(str(path))  # Pinocchio loads it without a word
    with pytest.raises(InputError) as err:
        model_from_mjcf(path)
    assert str(err.value) == (f"{path}: not a valid MJCF robot (MuJoCo's compiler): Error opening "
                              "file 'missing_parts.xml' (element 'include', line 7)")


def test_bad_attribute_is_one_line_naming_the_file(tmp_path: Path) -> None:
    path = write(tmp_path, "bad.xml", PENDULUM.format(inertia='<geom size="0.1" mas="2"/>'))
    with pytest.raises(InputError) as err:
        model_from_mjcf(path)
    assert err.value.path == path
    assert str(err.value) == (f"{path}: not a valid MJCF robot (MuJoCo's compiler): Schema "
                              "violation: unrecognized attribute: 'mas' (element 'geom', line 7)")


# ---------------------------------------------------------------- trees, free and ball joints

ARM = """
<body name="{name}" pos="{x} 0 0.5">
  <joint name="{name}_shoulder" type="hinge" axis="0 1 0" armature="0.1" damping="2"
         frictionloss="0.3" stiffness="5" springref="10"/>
  <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="1"/>
  <body name="{name}_forearm" pos="0.4 0 0">
    <joint name="{name}_elbow" type="hinge" axis="0 1 0" ref="15"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
    <site name="{name}_tcp" pos="0.3 0 0"/>
  </body>
</body>
"""


def scene(arms: str, actuators: str = "", extra: str = "") -> str:
    return f"""
    <mujoco>
      <worldbody>
        <geom name="floor" type="plane" size="2 2 0.1"/>
        {arms}
        <body name="ball" pos="1 1 0.1"><freejoint/><geom type="sphere" size="0.05" mass="0.2"/>
        </body>
      </worldbody>
      <actuator>{actuators}</actuator>
      {extra}
    </mujoco>"""


def test_one_arm_among_loose_objects(tmp_path: Path) -> None:
    path = write(tmp_path, "arm.xml", scene(
        ARM.format(name="arm", x=0),
        '<motor joint="arm_shoulder" gear="100" ctrlrange="-1 1" forcerange="-50 50"/>',
        '<tendon><fixed name="sum"><joint joint="arm_shoulder" coef="1"/>'
        '<joint joint="arm_elbow" coef="1"/></fixed></tendon>'))
    read, _, _ = compare(path)
    assert read.root_body == "world"  # the top body 'arm' turns on its shoulder: the world holds
    notes = "\n".join(read.notes + read.set_aside)
    for expected in (
            "trees whose only joints are free or ball joints are left out (loose objects, not "
            "robot links): ball",
            "armature on 1 joint (up to 0.1 kg m^2 or kg)", "damping on 1 joint (up to 2 ",
            "frictionloss on 1 joint (up to 0.3 ", "springs (stiffness) on 1 joint (up to 5 ",
            "1 actuator set aside", "actuator 0 on joint arm_shoulder, gear 100, ctrlrange [-1, "
            "1], forcerange [-50, 50]", "1 tendon set aside", "contacts (2 colliding geoms"):
        assert expected in notes


def test_two_actuated_arms_are_kept_and_said_so(tmp_path: Path) -> None:
    path = write(tmp_path, "two.xml", scene(
        ARM.format(name="left", x=-1) + ARM.format(name="right", x=1),
        '<motor joint="left_shoulder"/><motor joint="right_elbow"/>'))
    read, _, _ = compare(path)
    assert read.root_body == "world"
    assert ("2 kinematic trees carry actuated joints (left, right): all are kept, each fixed to "
            "the world on its own") in read.notes


def test_unactuated_tree_left_out_beside_an_actuated_one(tmp_path: Path) -> None:
    path = write(tmp_path, "passive.xml", scene(
        ARM.format(name="left", x=-1) + ARM.format(name="right", x=1),
        '<motor joint="right_elbow"/>'))
    read, _, _ = compare(path)
    assert read.root_body == "world"  # 'right' turns on its shoulder
    assert "trees with hinge or slide joints but no actuator are left out: left" in read.notes


def test_free_root_is_held_fixed(tmp_path: Path) -> None:
    path = write(tmp_path, "floating.xml", """
        <mujoco>
          <worldbody>
            <body name="torso" pos="0.2 -0.1 1.0" quat="0.8 0.2 0.1 0.3">
              <freejoint name="root"/>
              <geom type="box" size="0.2 0.1 0.1" mass="10"/>
              <body name="leg" pos="0 0 -0.1">
                <joint name="hip" type="hinge" axis="1 0 0" range="-60 60"/>
                <joint name="hip_y" type="hinge" axis="0 1 0" pos="0 0 0.02"/>
                <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04" mass="2"/>
              </body>
            </body>
          </worldbody>
        </mujoco>""")
    read, _, _ = compare(path)
    assert read.root_body == "torso"
    assert "the free joint of body 'torso' is held fixed: hdselect sizes a fixed-base arm" \
        in read.notes
    assert read.model.nq == 2


def test_ball_joint_is_refused_naming_body_and_joint(tmp_path: Path) -> None:
    path = write(tmp_path, "ball.xml", """
        <mujoco>
          <worldbody>
            <body name="upper">
              <joint name="shoulder" type="hinge"/>
              <geom size="0.1" mass="1"/>
              <body name="lower" pos="0 0 -0.3">
                <joint name="wrist" type="ball"/>
                <geom size="0.1" mass="1"/>
              </body>
            </body>
          </worldbody>
        </mujoco>""")
    with pytest.raises(InputError) as err:
        model_from_mjcf(path)
    assert err.value.reason == ("body 'lower' holds the ball joint 'wrist': hdselect sizes hinge "
                                "and slide joints only")


def test_file_without_hinge_or_slide_is_refused(tmp_path: Path) -> None:
    path = write(tmp_path, "loose.xml", scene(""))
    with pytest.raises(InputError, match="no hinge or slide joint to size: its only joints are "
                                        "free joints"):
        model_from_mjcf(path)


# ---------------------------------------------------------------- equality constraints

def test_joint_coupling_matches_mujocos_constraint(tmp_path: Path) -> None:
    path = write(tmp_path, "coupled.xml", """
        <mujoco>
          <worldbody>
            <body name="palm">
              <joint name="leader" type="hinge" axis="0 0 1" ref="20"/>
              <geom size="0.05" mass="1"/>
              <body name="finger" pos="0.1 0 0">
                <joint name="follower" type="slide" axis="1 0 0" ref="0.01"/>
                <geom size="0.02" mass="0.1"/>
                <body name="tip" pos="0.05 0 0">
                  <joint name="tip" type="hinge" axis="0 1 0"/>
                  <geom size="0.01" mass="0.01"/>
                </body>
              </body>
            </body>
            <body name="anchor" pos="1 0 0"><geom size="0.01" mass="0.01"/></body>
          </worldbody>
          <equality>
            <joint name="mimic" joint1="follower" joint2="leader" polycoef="0.002 -0.03 0 0 0"/>
            <joint joint1="tip" joint2="leader" polycoef="0 1 0.5 0 0"/>
            <weld body1="tip" body2="anchor" active="false"/>
            <connect name="loop" body1="finger" body2="anchor" anchor="0 0 0"/>
          </equality>
        </mujoco>""")
    read = model_from_mjcf(path)
    coupling = read.couplings["follower"]
    assert coupling.leader == "leader" and coupling.equality == "mimic"
    assert coupling.multiplier == -0.03
    # MuJoCo's own constraint residual vanishes on the coupling, wherever the leader is
    mj = mj_compile(path)
    d = mujoco.MjData(mj)
    for x in (-1.0, 0.2, 2.5):
        d.qpos[:] = mj.qpos0
        d.qpos[mj.joint("leader").qposadr[0]] = x
        d.qpos[mj.joint("follower").qposadr[0]] = coupling.offset + coupling.multiplier * x
        mujoco.mj_forward(mj, d)
        rows = np.flatnonzero((d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
                              & (d.efc_id == 0))
        assert abs(d.efc_pos[rows[0]]) < 1e-15
    assert set(read.couplings) == {"follower"}
    assert ("equality 1 couples 'tip' to 'leader' by a polynomial of degree 2: not a linear "
            "coupling, both joints move independently here") in read.notes
    assert any(note.startswith("equality constraints that are not joint couplings are set aside:"
                               " 1 connect (loop); 1 weld (equality 2)") for note in read.notes)


# ---------------------------------------------------------------- compiler warnings

def test_compiler_warnings_become_notes(tmp_path: Path) -> None:
    path = write(tmp_path, "total.xml", PENDULUM.format(
        inertia='<geom type="sphere" pos="0 0 -0.5" size="0.1" mass="2"/>').replace(
        "<option", '<compiler settotalmass="3"/><option'))
    hook = mujoco.get_mju_user_warning()
    read = model_from_mjcf(path)
    assert mujoco.get_mju_user_warning() is hook
    assert any(n.startswith("MuJoCo's compiler warns: compiler attribute 'settotalmass' is "
                            "deprecated") for n in read.notes)
    assert pin.computeTotalMass(read.model) == pytest.approx(3.0)


# ---------------------------------------------------------------- through load_robot, end to end

def test_a_joint_coupling_becomes_a_mimic_follower_with_its_own_range(tmp_path: Path) -> None:
    path = write(tmp_path, "gripper.xml", """
        <mujoco>
          <compiler angle="radian"/>
          <worldbody>
            <body name="arm" pos="0 0 0.5">
              <joint name="shoulder" type="hinge" axis="0 1 0" range="-2 2"/>
              <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="2"/>
              <body name="finger" pos="0.4 0 0">
                <joint name="finger" type="hinge" axis="0 1 0" range="-0.5 0.8"/>
                <geom type="box" size="0.04 0.01 0.01" pos="0.04 0 0" mass="0.1"/>
                <body name="pad" pos="0.08 0 0">
                  <joint name="pad" type="hinge" axis="0 1 0" range="-1 1"/>
                  <geom type="box" size="0.02 0.01 0.01" pos="0.02 0 0" mass="0.05"/>
                </body>
              </body>
            </body>
          </worldbody>
          <equality><joint joint1="pad" joint2="finger" polycoef="0.1 -2 0 0 0"/></equality>
          <actuator><motor joint="shoulder"/><motor joint="finger"/></actuator>
        </mujoco>""")
    robot = hdselect.load_robot(path)
    assert robot.joint_names == ("shoulder", "finger")
    assert robot.mimic["pad"] == hdselect.robot.model.Mimic("finger", -2.0, 0.1, -1.0, 1.0)
    assert any(note.startswith("joint equalities made mimic followers") for note in robot.notes)
    worst, scale = oracle_compare(robot, count=10)
    assert worst <= 1e-12 * scale


def test_several_joints_in_one_body_are_built_and_said_so(tmp_path: Path) -> None:
    """The decision: a body's joints are sized as a chain through massless frames (exact)."""
    path = write(tmp_path, "several.xml", SEVERAL_JOINTS)
    robot = hdselect.load_robot(path)
    assert ("bodies holding several joints, built as MuJoCo composes them (a chain through "
            "massless frames; each joint sized on its own): knot (first, second, third)"
            in robot.notes)
    worst, scale = oracle_compare(robot, count=10)
    assert worst <= 1e-12 * scale


PLANAR = """<mujoco model="planar2_mj">
  {compiler}
  <default><geom density="2700" {geom_default}/></default>
  <worldbody>
    <body name="base_link" pos="0 0 0.3" {base}>
      {lift}
      <body name="link1">
        <joint name="shoulder" type="hinge" axis="0 -1 0" range="{r1}"/>
        <geom type="box" size="0.15 0.005 0.015" pos="0.15 0 0"/>
        <body name="link2" pos="0.3 0 0">
          <joint name="elbow" type="hinge" axis="0 -1 0" range="{r2}" {elbow}/>
          <geom type="box" size="0.125 0.005 0.0125" pos="0.125 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def planar(**changes: str) -> str:
    fields = dict(compiler='<compiler angle="radian"/>', geom_default="", base="", lift="",
                  r1="-1.5707963 2.0943951", r2="-2.6179939 2.6179939", elbow="")
    fields.update(changes)
    return PLANAR.format(**fields)


@pytest.mark.parametrize("text", [
    planar(base='quat="0.7071068 0.7071068 0 0"'),
    planar(compiler="", r1="-90 120", r2="-150 150",
           lift='<joint name="lift" type="slide" axis="0 0 1" range="0 0.2"/>'
                '<geom type="box" size="0.03 0.03 0.03" mass="1"/>'),
    planar(elbow='limited="false"'),
    planar(geom_default='mass="0.5"'),
    planar(elbow='ref="0.5"'),
], ids=["root-body-rotated", "slide-range-in-metres", "limited-false", "default-geom-mass",
        "joint-ref"])
def test_what_pinocchios_reader_got_wrong_is_read_as_mujoco_reads_it(tmp_path: Path,
                                                                     text: str) -> None:
    path = write(tmp_path, "planar.xml", text)
    robot = hdselect.load_robot(path)
    mj = mj_compile(path)
    for j, name in enumerate(robot.joint_names):
        joint = mj.joint(name)
        lower, upper = joint.range if joint.limited[0] else (-math.inf, math.inf)
        assert (robot.lower[j], robot.upper[j]) == (lower, upper), name
    worst, scale = oracle_compare(robot, count=10)
    assert worst <= 1e-12 * scale


def test_the_robot_carries_no_armature_damping_or_springs(tmp_path: Path) -> None:
    path = write(tmp_path, "lossy.xml", scene(ARM.format(name="arm", x=0),
                                              '<motor joint="arm_shoulder" gear="100"/>'))
    robot = hdselect.load_robot(path)
    rng = np.random.default_rng(5)
    q, qd, qdd = rng.normal(size=(3, 4, robot.dof))
    model = model_from_mjcf(path).model  # the reader's model: no armature either
    model.gravity.linear = np.array(robot.gravity)
    expected = np.array([pin.rnea(model, model.createData(), *state)
                         for state in zip(q, qd, qdd, strict=True)])
    np.testing.assert_allclose(inverse_dynamics(robot, q, qd, qdd), expected, rtol=1e-13,
                               atol=1e-13)
    worst, scale = oracle_compare(robot, count=5)
    assert worst <= 1e-12 * scale
