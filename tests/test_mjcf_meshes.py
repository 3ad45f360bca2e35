"""An MJCF robot read without its mesh files, and joint ranges MuJoCo would quietly drop.

A file copied alone (MuJoCo Menagerie's UR5e XML without ``assets/``) is compiled
without the geoms whose mesh files are missing when every body gives its own
``<inertial>``: the oracle is MuJoCo's inverse dynamics of the same file with the
meshes in place. Where a body's mass comes from a missing mesh, the refusal names
the body and the mesh.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.base.errors import InputError
from hdselect.robot.mjcf import model_from_mjcf
from mujoco_oracle import compile_quietly, rigid

ARM = """\
<mujoco model="arm">
  <compiler angle="radian" meshdir="assets" {compiler}/>
  <asset>
    <mesh name="base" file="base_0.obj"/>
    <mesh name="bar" file="bar.obj" scale="0.3 0.02 0.02"/>
  </asset>
  <worldbody>
    <geom type="mesh" mesh="base"/>
    <body name="link1" pos="0 0 0.3">
      <joint name="shoulder" axis="0 1 0" range="-1 1"/>
      <inertial pos="0.15 0 0" mass="0.243" diaginertia="2e-5 0.0018 0.0018"/>
      <geom type="mesh" mesh="bar" pos="0.15 0 0"/>
      <body name="link2" pos="0.3 0 0">
        <joint name="elbow" axis="0 1 0" range="{elbow}"/>
        {link2}
        <geom type="mesh" mesh="bar" pos="0.125 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
INERTIAL = '<inertial pos="0.125 0 0" mass="0.16875" diaginertia="1e-5 0.00089 0.00088"/>'
CUBE = """\
v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5
v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5
f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8
"""


def arm(folder: Path, *, meshes: bool, link2: str = INERTIAL, compiler: str = "",
        elbow: str = "-2 2") -> Path:
    """The two-link arm, its mesh files in ``assets/`` or not."""
    if meshes:
        (folder / "assets").mkdir(exist_ok=True)
        for name in ("base_0.obj", "bar.obj"):
            (folder / "assets" / name).write_text(CUBE)
    path = folder / "arm.xml"
    path.write_text(ARM.format(link2=link2, compiler=compiler, elbow=elbow))
    return path


def mujoco_torques(path: Path, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """MuJoCo's inverse dynamics of the file, its meshes in place [N m]."""
    mj = rigid(compile_quietly(path), np.array([0.0, 0.0, -9.81]))
    d = mujoco.MjData(mj)
    torques = []
    for qk, vk, ak in zip(q, v, a, strict=True):
        d.qpos[:], d.qvel[:], d.qacc[:] = qk, vk, ak
        mujoco.mj_inverse(mj, d)
        torques.append(d.qfrc_inverse.copy())
    return np.array(torques)


def test_a_file_without_its_meshes_is_read_when_every_body_gives_its_inertia(tmp_path):
    (tmp_path / "with").mkdir()
    with_meshes = arm(tmp_path / "with", meshes=True)
    alone = arm(tmp_path, meshes=False)
    with pytest.raises(ValueError, match="Error opening file"):
        mujoco.MjModel.from_xml_path(str(alone))  # what MuJoCo itself says
    read = model_from_mjcf(alone)
    assert read.notes[0] == (
        "mesh files not found (assets/bar.obj, assets/base_0.obj): the 3 geoms drawing them "
        "are left out; no body takes its mass from them (each gives its <inertial>), so the "
        "dynamics do not need them")
    rng = np.random.default_rng(5)
    q, v, a = rng.uniform(-1.0, 1.0, (3, 6, 2))
    data = read.model.createData()
    ours = np.array([pin.rnea(read.model, data, *state) for state in zip(q, v, a, strict=True)])
    np.testing.assert_allclose(ours, mujoco_torques(with_meshes, q, v, a), rtol=1e-10,
                               atol=1e-12)
    robot = hdselect.load_robot(alone)
    assert robot.notes[-1].startswith("mesh files not found")
    assert robot.moved_mass("shoulder") == pytest.approx(0.243 + 0.16875)


@pytest.mark.parametrize(("link2", "compiler"), [
    ("", ""),  # no <inertial>: MuJoCo derives the body's mass from its geoms
    (INERTIAL, 'inertiafromgeom="true"'),  # the geoms override every <inertial>
])
def test_a_body_whose_mass_comes_from_a_missing_mesh_is_refused_naming_it(
        tmp_path, link2, compiler):
    path = arm(tmp_path, meshes=False, link2=link2, compiler=compiler)
    body = "link2" if not compiler else "link1"
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    fix = (" give the body an <inertial>" if not compiler else  # it has one: the compiler
           ", to use the bodies' own <inertial>, drop the compiler's inertiafromgeom=\"true\" "
           "(it takes every body's inertia from its geoms)")
    assert str(info.value) == (
        f"{path}: body '{body}' takes its mass and inertia from mesh 'bar', whose file "
        f"assets/bar.obj is not found: put the mesh files where the file names them, or{fix}")
    model_from_mjcf(arm(tmp_path, meshes=True, link2=link2, compiler=compiler))  # with them


def test_another_error_of_a_file_without_meshes_is_mujocos_own(tmp_path):
    """Compiled without its meshes, the file's next error is the message."""
    path = arm(tmp_path, meshes=False, elbow='2 -2" limited="true')
    with pytest.raises(InputError) as info:
        model_from_mjcf(path)
    assert info.value.reason.startswith("not a valid MJCF robot (MuJoCo's compiler): range[0] "
                                        "should be smaller than range[1] in joint")


def test_a_range_upside_down_is_refused_naming_the_joint(tmp_path):
    """MuJoCo leaves such a joint unlimited without a word (autolimits)."""
    path = arm(tmp_path, meshes=True, elbow="2 -2")
    assert not compile_quietly(path).jnt_limited[1]
    with pytest.raises(InputError) as info:
        hdselect.load_robot(path)
    assert str(info.value) == (f"{path}: joint[elbow].range: its range's lower end is above "
                               "its upper end (2 > -2): MuJoCo would leave it unlimited")
    hdselect.load_robot(arm(tmp_path, meshes=True, elbow="0 0"))  # no range: unlimited


def test_the_menagerie_layout_reads_the_meshdir(tmp_path):
    """The mesh files are looked for where MuJoCo looks: meshdir, beside the file."""
    path = arm(tmp_path, meshes=True)
    (tmp_path / "assets" / "bar.obj").unlink()
    read = model_from_mjcf(path)
    assert read.notes[0].startswith("mesh files not found (assets/bar.obj): the 2 geoms ")
