"""The real arms of the test suite get a unit for every revolute joint from the shipped series.

Each arm's starter motion (`hdselect init`, unedited) is sized with PSA-G alone and with
every built-in catalog loaded together; the unit each joint gets from each is stated here
(`EXPECTED`) and in docs/catalogs.md ("Real arms", with each joint's peak torque and its
unit's repeated-peak limit), and the two are checked against each other, so a change of
the data or the selection shows as a diff of both. The torques the sizing judges are
checked against MuJoCo's inverse dynamics of the same trajectory (`mujoco_oracle`), with
each chosen unit's mass added to the robot file as a point mass at its joint's origin on
the link before it (what mass coupling carries), written into the URDF MuJoCo reads.
"""

from __future__ import annotations

import importlib.util
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.catalog import load_catalog
from hdselect.catalog.builtin import builtin_catalogs
from helpers import REPO, run_redirected
from helpers.robots import ARMS as EXAMPLE_ARMS
from helpers.robots import example_robots
from mujoco_oracle import mujoco_of, mujoco_torques

RTOL = 1e-9
"""Agreement asked of the torques, relative to the joint's largest MuJoCo torque."""

ARMS = {
    **{arm: ("example-robot-data", EXAMPLE_ARMS[arm])
       for arm in ("UR3", "UR5", "UR10", "Panda", "Kinova", "TALOS left arm", "Z1")},
    "KUKA iiwa": ("pybullet", "kuka_iiwa/model.urdf"),
    "xArm6": ("pybullet", "xarm/xarm6_robot.urdf"),
}
"""Each arm: the package that ships it (pip's name) and its file in the package's robots
folder (example-robot-data, a test dependency) or in ``pybullet_data`` (optional)."""

EXPECTED: dict[str, dict[str, tuple[str, str, str]]] = {
    "UR3": {
        "shoulder_pan_joint": ("PSA-14-80", "CSF-14-80-2UH", "SHG-14-80-2UH"),
        "shoulder_lift_joint": ("none", "CSG-17-100-2UH", "CSG-17-100-2UH"),
        "elbow_joint": ("PSA-14-80", "CSG-14-80-2UH", "CSG-14-80-2UH"),
        "wrist_1_joint": ("PSA-08-100", "PSA-08-100", "CSG-14-50-2UH"),
        "wrist_2_joint": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
        "wrist_3_joint": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "UR5": {
        "shoulder_pan_joint": ("none", "CSF-17-100-2UH", "SHG-17-80-2UH"),
        "shoulder_lift_joint": ("none", "CSG-25-100-2UH", "CSG-25-100-2UH"),
        "elbow_joint": ("none", "SHG-17-100-2UH", "SHG-17-100-2UH"),
        "wrist_1_joint": ("PSA-14-80", "CSG-14-80-2UH", "CSG-14-80-2UH"),
        "wrist_2_joint": ("PSA-08-100", "PSA-08-100", "CSG-14-50-2UH"),
        "wrist_3_joint": ("PSA-08-100", "PSA-08-100", "HFUS-14-30-2UH"),
    },
    "UR10": {
        "shoulder_pan_joint": ("none", "CSF-25-160-2UH", "SHG-25-50-2UH"),
        "shoulder_lift_joint": ("none", "CSG-25-100-2UH", "CSG-32-100-2UH"),
        "elbow_joint": ("none", "SHG-17-100-2UH", "SHG-17-100-2UH"),
        "wrist_1_joint": ("PSA-08-100", "PSA-08-100", "SHG-14-80-2UH"),
        "wrist_2_joint": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
        "wrist_3_joint": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "Panda": {
        "panda_joint1": ("none", "CSF-14-80-2UH", "SHG-17-50-2UH"),
        "panda_joint2": ("none", "CSG-17-100-2UH", "CSG-20-100-2UH"),
        "panda_joint3": ("none", "SHG-14-80-2UH", "SHG-14-80-2UH"),
        "panda_joint4": ("none", "CSG-17-100-2UH", "SHG-17-100-2UH"),
        "panda_joint5": ("PSA-10-80", "PSA-10-80", "CSG-14-80-2UH"),
        "panda_joint6": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "panda_joint7": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "Kinova": {
        "j2s6s200_joint_1": ("PSA-10-80", "PSA-10-80", "SHG-14-50-2UH"),
        "j2s6s200_joint_2": ("PSA-14-100", "PSA-14-100", "CSG-17-100-2UH"),
        "j2s6s200_joint_3": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "j2s6s200_joint_4": ("PSA-08-100", "PSA-08-100", "CSG-14-50-2UH"),
        "j2s6s200_joint_5": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "j2s6s200_joint_6": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "TALOS left arm": {
        "arm_left_2_joint": ("none", "CSG-17-100-2UH", "CSG-17-100-2UH"),
        "arm_left_3_joint": ("PSA-14-80", "CSF-14-80-2UH", "SHG-14-50-2UH"),
        "arm_left_4_joint": ("PSA-14-80", "CSG-14-80-2UH", "CSG-14-80-2UH"),
        "arm_left_5_joint": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "arm_left_6_joint": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "arm_left_7_joint": ("PSA-08-100", "PSA-08-100", "CSG-14-80-2UH"),
        "gripper_left_joint": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "Z1": {
        "joint1": ("PSA-08-100", "PSA-08-100", "SHG-14-50-2UH"),
        "joint2": ("PSA-14-100", "CSG-14-80-2UH", "CSG-14-80-2UH"),
        "joint3": ("PSA-14-100", "PSA-14-100", "CSG-17-100-2UH"),
        "joint4": ("PSA-10-80", "PSA-10-80", "CSG-14-80-2UH"),
        "joint5": ("PSA-08-100", "PSA-08-100", "HFUS-14-30-2UH"),
        "joint6": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
        "jointGripper": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "KUKA iiwa": {
        "lbr_iiwa_joint_1": ("PSA-14-80", "CSF-14-80-2UH", "HFUS-20-30-2UH"),
        "lbr_iiwa_joint_2": ("none", "CSG-20-120-2UH", "CSG-20-120-2UH"),
        "lbr_iiwa_joint_3": ("PSA-14-100", "CSF-14-80-2UH", "SHG-14-50-2UH"),
        "lbr_iiwa_joint_4": ("none", "CSG-14-80-2UH", "CSG-14-80-2UH"),
        "lbr_iiwa_joint_5": ("PSA-08-100", "PSA-08-100", "HFUS-14-30-2UH"),
        "lbr_iiwa_joint_6": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
        "lbr_iiwa_joint_7": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
    "xArm6": {
        "joint1": ("PSA-10-80", "PSA-10-80", "SHG-14-50-2UH"),
        "joint2": ("none", "CSG-17-100-2UH", "CSG-17-100-2UH"),
        "joint3": ("PSA-14-100", "PSA-14-100", "CSG-14-80-2UH"),
        "joint4": ("PSA-08-100", "PSA-08-100", "HFUS-14-30-2UH"),
        "joint5": ("PSA-08-100", "PSA-08-100", "CSG-14-50-2UH"),
        "joint6": ("PSA-08-80", "PSA-08-80", "HFUS-14-30-2UH"),
    },
}
"""Per arm and revolute joint, the unit its starter motion gets from PSA-G alone (``none``:
no unit holds it), with every built-in catalog loaded, and from the series that rate
their output bearing (`BEARING_RATED`)."""


BEARING_RATED = ("csg-2uh", "hfus-2uh", "shg-2uh")
"""The shipped series that rate their output bearing (`hdselect catalog --list`)."""


def shipped_units(series: tuple[str, ...] = ()) -> tuple[hdselect.Unit, ...]:
    """Every unit of every built-in catalog (`hdselect catalog --list`), or of `series`."""
    return load_catalog([catalog.name for catalog in builtin_catalogs()], series=series)


def arm_file(arm: str) -> Path:
    """The arm's robot file; the test is skipped where its package is not installed."""
    package, relative = ARMS[arm]
    if package == "example-robot-data":
        return example_robots() / relative
    spec = importlib.util.find_spec("pybullet_data")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip(f"{package} is not installed (pip install {package} to size {arm})")
    return Path(list(spec.submodule_search_locations)[0]) / relative


def carrying(text: bytes, masses: dict[str, float]) -> bytes:
    """A URDF document with a point mass [kg] fixed at each named joint's origin on its parent."""
    root = ET.fromstring(text.lstrip())
    joints = {joint.get("name"): joint for joint in root.findall("joint")}
    for name, mass in masses.items():
        joint = joints[name]
        link = ET.SubElement(root, "link", name=f"{name}_gearhead")
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "mass", value=repr(mass))
        ET.SubElement(inertial, "inertia", ixx="0", iyy="0", izz="0", ixy="0", ixz="0",
                      iyz="0")
        mount = ET.SubElement(root, "joint", name=f"{name}_gearhead_mount", type="fixed")
        ET.SubElement(mount, "parent", link=joint.find("parent").get("link"))
        ET.SubElement(mount, "child", link=f"{name}_gearhead")
        origin = joint.find("origin")
        if origin is not None:
            ET.SubElement(mount, "origin", origin.attrib)
    return ET.tostring(root)


def documented() -> dict[str, dict[str, tuple[str, ...]]]:
    """The "Real arms" table of docs/catalogs.md: arm -> joint -> (PSA-G alone, every
    series, bearing rated, peak, repeated peak), as printed."""
    text = (REPO / "docs" / "catalogs.md").read_text(encoding="utf-8")
    (section,) = re.findall(r"^#+ Real arms\n(.*?)(?=^#|\Z)", text, flags=re.S | re.M)
    table: dict[str, dict[str, tuple[str, ...]]] = {}
    for arm, joint, *cells in re.findall(r"^\| ([^|`]+?) \| `([^`]+)`" + r" \| ([^|]+?)" * 5
                                         + r" \|$", section, flags=re.M):
        table.setdefault(arm, {})[joint] = tuple(cells)
    return table


def chosen(result: hdselect.SizingResult) -> dict[str, str]:
    """The unit each sized joint gets (``none`` where no unit holds it)."""
    return {joint.name: joint.selected.unit.id if joint.selected else "none"
            for joint in result.joints}


def sized(arm: str, folder: Path) -> tuple[dict[str, str], hdselect.SizingResult,
                                           dict[str, str]]:
    """An arm's starter motion, written in `folder`, sized with PSA-G alone, with every
    series and with the bearing-rated ones: (units alone, the result, units rated)."""
    motion = folder / "m.toml"
    status, _, err = run_redirected(["init", arm_file(arm), "--out", motion])
    assert status == 0, err
    alone = chosen(hdselect.size(None, motion))
    rated = hdselect.size(None, motion, catalog=shipped_units(BEARING_RATED))
    assert rated.feasible
    return alone, hdselect.size(None, motion, catalog=shipped_units()), chosen(rated)


@pytest.mark.slow
@pytest.mark.parametrize("arm", list(ARMS))
def test_every_revolute_joint_gets_a_shipped_unit(arm: str, tmp_path: Path) -> None:
    alone, result, rated = sized(arm, tmp_path)
    robot = result.robot
    assert list(chosen(result)) == [name for name in robot.joint_names
                                    if robot.joint_type(name) in ("revolute", "continuous")]
    assert result.feasible
    assert {name: (alone[name], unit, rated[name])
            for name, unit in chosen(result).items()} == EXPECTED[arm]
    masses = {joint.name: joint.selected.unit.mass for joint in result.joints}
    trajectory = result.trajectory
    theirs = mujoco_torques(mujoco_of(robot, carrying(arm_file(arm).read_bytes(), masses)),
                            robot, trajectory.q, trajectory.qd, trajectory.qdd)
    rows = documented()[arm]
    for joint in result.joints:
        tau = theirs[:, robot.joint_index(joint.name)]
        assert np.abs(joint.torque - tau).max() <= RTOL * np.abs(tau).max(), joint.name
        unit = joint.selected.unit
        assert np.abs(tau).max() <= unit.repeated_torque, joint.name
        assert rows[joint.name][3:] == (f"{np.abs(tau).max():.3g}", f"{unit.repeated_torque:g}")


def test_the_bearing_rated_series_are_those_whose_every_unit_rates_its_bearing() -> None:
    units = shipped_units()
    rating = {unit.series: True for unit in units}
    for unit in units:
        rating[unit.series] &= unit.bearing is not None
    assert {series.lower() for series, rated in rating.items() if rated} \
        == set(BEARING_RATED)


def test_the_documented_table_is_the_tested_one() -> None:
    assert {arm: {joint: cells[:3] for joint, cells in rows.items()}
            for arm, rows in documented().items()} == EXPECTED


if __name__ == "__main__":
    # `python tests/test_real_arms.py` prints `EXPECTED` and the docs' table as the data
    # now gives them, to paste (and review as a diff) after a catalog changes.
    import tempfile
    expected, table = [], []
    for arm in ARMS:
        with tempfile.TemporaryDirectory() as folder:
            alone, result, rated = sized(arm, Path(folder))
        expected.append(f"    {arm!r}: {{")
        for joint in result.joints:
            unit = joint.selected.unit if joint.selected else None
            uid = unit.id if unit else "none"
            expected.append(f"        {joint.name!r}: "
                            f"({alone[joint.name]!r}, {uid!r}, {rated[joint.name]!r}),")
            table.append(f"| {arm} | `{joint.name}` | {alone[joint.name]} | {uid} | "
                         f"{rated[joint.name]} | {np.abs(joint.torque).max():.3g} | "
                         f"{unit.repeated_torque if unit else float('nan'):g} |")
        expected.append("    },")
    print("\n".join(["EXPECTED = {", *expected, "}", "", *table]).replace("'", '"'))
