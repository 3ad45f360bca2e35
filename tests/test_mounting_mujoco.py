"""The same physical task on the floor and hung from a ceiling (``--base``), against MuJoCo.

The oracle does not come from the code under test: MuJoCo's own model of the robot file,
its base placed where ``--base`` says (origin and roll, pitch, yaw about fixed axes, as
URDF's ``<origin>``) in a z-up world with gravity (0, 0, -9.80665) m/s^2, and the poses
read from the motion file here with ``tomllib`` and scipy's rotations. hdselect keeps the
robot in its base frame and turns gravity into it; MuJoCo turns the robot instead. A
joint torque is a scalar, the same in any frame, so along the same joint trajectory
the two agree; and the floor's and the ceiling's joint paths, each placed in MuJoCo's
world, put the tool on the same poses and lines: the same task.
"""

from __future__ import annotations

import csv
import json
import re
import tomllib
from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import hdselect
from hdselect.cli.main import main
from hdselect.motion.planning import plan_motion
from hdselect.robot.dynamics import inverse_dynamics
from helpers import REPO
from helpers.motions import whole_cycle
from mujoco_oracle import rigid

EXAMPLE = REPO / "trajectories" / "benchtop6_pick_place_poses.toml"
PLANAR2 = REPO / "trajectories" / "planar2_pick_place.toml"
WORLD_GRAVITY = np.array([0.0, 0.0, -9.80665])

CEILING = ((0.0, 0.0, 0.5), (180.0, 0.0, 0.0))
"""benchtop6 hung from a ceiling 0.5 m above the floor's base, turned over about world x:
the file's poses (the work 0.08 to 0.30 m above the floor) lie within the arm's 0.64 m
reach of it. 2 m up they are out of reach."""


@pytest.fixture(scope="module")
def example(tmp_path_factory) -> Path:
    """The shipped pick-and-place of tool poses with its ``[payload]`` carried all cycle: any
    payload events (``[payloads.*]``, ``attach``, ``release``) left out, so that one MuJoCo
    model holds the whole cycle (tests/test_payload_events.py checks the events)."""
    kept, skipping = [], False
    for line in EXAMPLE.read_text().splitlines():
        if line.startswith("["):
            skipping = line.startswith("[payloads.")
        if not skipping and not re.match(r"\s*(attach|release)\s*=", line):
            kept.append(line.replace('"../robots/', f'"{EXAMPLE.parent}/../robots/'))
    path = tmp_path_factory.mktemp("example") / EXAMPLE.name
    path.write_text("\n".join(kept) + "\n")
    doc = tomllib.loads(path.read_text())
    assert "payloads" not in doc and not any({"attach", "release"} & set(w)
                                             for w in doc["waypoint"])
    return path


def read_csv(path) -> dict[str, np.ndarray]:
    """A CSV's columns by header, as floats."""
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(rows[0])}


def placed(robot_file, xyz, rpy_deg, payloads: tuple[dict, ...] = ()) -> mujoco.MjModel:
    """MuJoCo's model of `robot_file`, its base at `xyz` [m] turned by `rpy_deg`, rigid-body
    dynamics only; with a body for each payload (a motion file's ``[payload]`` or
    ``[payloads.*]`` table, its ``frame`` a body, ``at`` its place there [m])."""
    spec = mujoco.MjSpec.from_file(str(robot_file))
    spec.compiler.fusestatic = False  # keep tool0 as a body
    root = spec.worldbody.bodies[0]
    assert np.allclose(root.pos, 0.0) and np.allclose(root.quat, [1, 0, 0, 0])
    root.pos = list(xyz)
    root.quat = list(Rotation.from_euler("xyz", rpy_deg, degrees=True).as_quat(
        scalar_first=True))
    for i, payload in enumerate(payloads):
        load = spec.body(payload["frame"]).add_body(name=f"payload{i}",
                                                    pos=payload.get("at", [0, 0, 0]))
        load.mass, load.ipos, load.explicitinertial = payload["mass"], payload["com"], True
        inertia = np.array(payload.get("inertia", np.zeros((3, 3))))
        load.fullinertia = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1],
                            inertia[0, 2], inertia[1, 2]]
    return rigid(spec.compile(), WORLD_GRAVITY)


def planned(tmp_path, name: str, *argv) -> tuple[dict, dict, dict]:
    """``hdselect plan`` with `argv`: the trajectory, and where a motion has tool poses the
    solved path (--waypoints) and the line samples (--line-errors); empty otherwise."""
    out = [tmp_path / f"{name}_{kind}.csv" for kind in ("trajectory", "solved", "lines")]
    poses = any(str(arg).endswith(EXAMPLE.name) for arg in argv)
    extra = ["--waypoints", str(out[1]), "--line-errors", str(out[2])] if poses else []
    assert main(["plan", *map(str, argv), "--out", str(out[0]), *extra]) == 0
    return tuple(read_csv(path) if path.exists() else {} for path in out)  # type: ignore[return-value]


def base_flag(base) -> list[str]:
    """``--base X,Y,Z,ROLL,PITCH,YAW`` of a base ((x, y, z), (roll, pitch, yaw))."""
    return ["--base", ",".join(f"{v:g}" for v in (*base[0], *base[1]))]


def mujoco_torques(model: mujoco.MjModel, q, qd, qdd) -> np.ndarray:
    """MuJoCo's inverse dynamics at every sample of a trajectory [N m]."""
    data = mujoco.MjData(model)
    tau = np.empty_like(q)
    for k in range(len(q)):
        data.qpos[:], data.qvel[:], data.qacc[:] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(model, data)
        tau[k] = data.qfrc_inverse
    return tau


def tool_pose(model: mujoco.MjModel, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where MuJoCo puts tool0 in its world at joints `q`: position [m] and rotation."""
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    return data.body("tool0").xpos.copy(), data.body("tool0").xmat.reshape(3, 3).copy()


def exact(motion, base, robot=None):
    """The trajectory and bare torques [N m] as the library plans them with the base pose
    ``--base`` gives (metres, degrees turned to radians here), unrounded."""
    pose = hdselect.BasePose.from_xyz_rpy(base[0], np.radians(base[1]))
    loaded, solved = hdselect.load_case(motion, robot, mounting=pose)
    trajectory = plan_motion(loaded, solved).trajectory
    return trajectory, inverse_dynamics(loaded, trajectory.q, trajectory.qd, trajectory.qdd)


def same_as_written(columns: dict, trajectory, tau, joints) -> None:
    """The CSV ``hdselect plan --base`` wrote is the library's plan, to its 10 digits."""
    for kind, values in (("q", trajectory.q), ("qd", trajectory.qd), ("qdd", trajectory.qdd),
                         ("tau", tau)):
        written = np.column_stack([columns[f"{kind}_{j}"] for j in joints])
        np.testing.assert_allclose(written, values, rtol=1e-9,
                                   atol=1e-9 * np.abs(values).max(), err_msg=kind)


@pytest.mark.slow
def test_floor_and_ceiling_plan_the_same_task_and_torques_that_mujoco_gives(tmp_path, example):
    doc = tomllib.loads(example.read_text())
    assert doc["mounting"] == "floor" and doc["angle_unit"] == "deg"
    joints = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")
    written = [(np.array(w["pose"]["xyz"]),
                Rotation.from_euler("xyz", w["pose"]["rpy"], degrees=True).as_matrix())
               for w in doc["waypoint"]]
    paths = {}
    for name, base in (("floor", ((0, 0, 0), (0, 0, 0))), ("ceiling", CEILING)):
        flags = [] if name == "floor" else base_flag(base)
        columns, solved, lines = planned(tmp_path, name, example, *flags)
        trajectory, tau = exact(example, base)
        same_as_written(columns, trajectory, tau, joints)
        model = placed(REPO / "robots" / "benchtop6.urdf", *base, payloads=(doc["payload"],))
        peak = np.abs(tau).max()
        assert peak > 1.0
        np.testing.assert_allclose(mujoco_torques(model, trajectory.q, trajectory.qd,
                                                  trajectory.qdd), tau, rtol=0, atol=1e-9 * peak)
        # the task in the world: every waypoint on its pose, every line sample on its line
        at = solved["fraction"] == 1.0
        q_solved = np.column_stack([solved[f"q_{j}"] for j in joints])
        assert at.sum() == len(written)
        for (xyz, rotation), q in zip(written, q_solved[at], strict=True):
            position, turned = tool_pose(model, q)
            assert np.linalg.norm(position - xyz) < 1e-4
            assert Rotation.from_matrix(rotation.T @ turned).magnitude() < np.radians(0.01)
        on_line = np.searchsorted(trajectory.t, lines["t"] - 1e-9)
        assert np.allclose(trajectory.t[on_line], lines["t"], atol=1e-9) and len(on_line) > 100
        for k, last in zip(on_line, lines["line"].astype(int), strict=True):
            start, end = written[last - 1][0], written[last][0]
            position, _ = tool_pose(model, trajectory.q[k])
            along = np.clip((position - start) @ (end - start) / np.sum((end - start) ** 2), 0, 1)
            assert np.linalg.norm(position - start - along * (end - start)) < 1e-4
        paths[name] = q_solved[at], tau
    # other joint motions for the one task, and other torques: the mounting mattered
    assert np.abs(paths["floor"][0] - paths["ceiling"][0]).max() > 0.5
    assert abs(np.abs(paths["floor"][1]).max() - np.abs(paths["ceiling"][1]).max()) > 0.1


@pytest.mark.slow
def test_sized_peaks_on_the_ceiling_are_mujocos(tmp_path, example):
    """size's peak torques with no unit masses carried (--no-mass-coupling) are the largest
    of MuJoCo's inverse dynamics along the same planned trajectory."""
    doc = tomllib.loads(example.read_text())
    report = tmp_path / "size.json"
    assert main(["size", str(example), *base_flag(CEILING), "--no-mass-coupling",
                 "--json", str(report)]) in (0, 1)
    sized = json.loads(report.read_text())
    trajectory, _ = exact(example, CEILING)
    model = placed(REPO / "robots" / "benchtop6.urdf", *CEILING, payloads=(doc["payload"],))
    tau = mujoco_torques(model, trajectory.q, trajectory.qd, trajectory.qdd)
    assert sized["samples"] == len(tau) and [j["name"] for j in sized["joints"]] == list(
        trajectory.joint_names)
    for j, joint in enumerate(sized["joints"]):
        assert joint["peak_torque_nm"] == pytest.approx(np.abs(tau[:, j]).max(), rel=0,
                                                        abs=1e-9 * np.abs(tau).max())


@pytest.mark.parametrize("base", [((0, 0, 2), (180, 0, 0)), ((0.1, -0.2, 0.3), (30, -45, 60))])
def test_an_mjcf_robot_placed_by_the_base_flag_has_mujocos_torques(tmp_path, base):
    """planar2.xml (MuJoCo's own file) hung 2 m up, and tilted anyhow: its joint
    waypoints move with the robot, and the torques are those of MuJoCo's world. The
    shipped pick-and-place with its part carried the whole cycle (no payload events), so
    that one MuJoCo model holds the whole cycle (tests/test_payload_events.py checks the
    events)."""
    robot = REPO / "robots" / "planar2.xml"
    motion = whole_cycle(PLANAR2, tmp_path)
    columns, _, _ = planned(tmp_path, "mjcf", robot, motion, *base_flag(base))
    trajectory, tau = exact(motion, base, robot)
    same_as_written(columns, trajectory, tau, ("shoulder", "elbow"))
    doc = tomllib.loads(motion.read_text())
    assert doc["payload"]["frame"] == "tool"  # the site at the end of link2
    loads = (doc["payload"], *({"frame": "tool", **part} for part in doc["payloads"].values()))
    assert len(loads) == 2  # the gripper and the part
    # point masses: MuJoCo wants an inertia; 1e-12 kg m^2 adds at most 1e-12 max|qdd| N m
    point = 1e-12 * np.eye(3)
    model = placed(robot, *base, payloads=tuple(
        {**load, "frame": "link2", "at": [0.25, 0, 0], "inertia": point} for load in loads))
    np.testing.assert_allclose(mujoco_torques(model, trajectory.q, trajectory.qd,
                                              trajectory.qdd), tau, rtol=0,
                               atol=1e-9 * np.abs(tau).max())
