"""``--base X,Y,Z,ROLL,PITCH,YAW`` on the command line, and ``plan MIX --task NAME``.

Oracles: the same base written in the file (``base = {xyz, rpy}``, which
tests/test_toolposes.py and tests/test_mounting_mujoco.py check against MuJoCo), whose
outputs the flag must reproduce to the byte; the motion file planned alone with the
mounting the mix gives its task; and the library's own planning of a mix's tasks
(`hdselect.sizing.mixtasks.mix_tasks`), which sizes them.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.motion.loading import load_case
from hdselect.robot.dynamics import inverse_dynamics
from hdselect.robot.mounting import BasePose, base_pose_from
from hdselect.sizing.mixtasks import mix_tasks
from helpers import REPO
from helpers.options import ONE_MOVE, PLANAR2, one_line_error

POSES = REPO / "trajectories" / "benchtop6_pick_place_poses.toml"
DAY = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
CEILING = "0,0,0.5,180,0,0"
"""benchtop6 hung 0.5 m above the floor's base, turned over about world x (in degrees)."""


def with_base(tmp_path, base: str, source=POSES, name: str = "based.toml"):
    """`source` with `base` (a TOML inline table) for its ``mounting = "floor"``."""
    path = tmp_path / name
    text = source.read_text() if hasattr(source, "read_text") else source
    path.write_text(text.replace('mounting = "floor"', f"base = {base}").replace(
        '"../robots/', f'"{REPO}/trajectories/../robots/'))  # the path the file reads
    return path


def outputs(tmp_path, tag: str, argv: list[str], *, tool_poses: bool = False) -> dict:
    """Every file ``hdselect plan`` writes for `argv`, by kind, and its standard output."""
    files = {"out": tmp_path / f"{tag}.csv"}
    if tool_poses:
        files |= {"waypoints": tmp_path / f"{tag}_w.csv", "line-errors": tmp_path / f"{tag}_l.csv"}
    flags = [arg for kind, path in files.items() for arg in (f"--{kind}", str(path))]
    assert main(["plan", *argv, *flags]) == 0
    return {kind: path.read_bytes() for kind, path in files.items()}


@pytest.mark.slow
def test_the_base_flag_places_the_robot_as_the_files_base_does(tmp_path, capsys):
    """Planned and sized with ``--base``, the tool-pose task is the file with that ``base``:
    the same CSVs, the same JSON, the same base line."""
    written = with_base(tmp_path, "{xyz = [0, 0, 0.5], rpy = [180, 0, 0]}")
    given = outputs(tmp_path, "flag", [str(POSES), "--base", CEILING], tool_poses=True)
    filed = outputs(tmp_path, "file", [str(written)], tool_poses=True)
    assert given == filed
    capsys.readouterr()
    reports = {}
    for tag, argv in (("flag", [str(POSES), "--base", CEILING]), ("file", [str(written)])):
        assert main(["size", *argv, "--json", str(tmp_path / f"{tag}.json")]) in (0, 1)
        printed = capsys.readouterr().out
        assert ("base: 'base_link' held fixed on the base at (0, 0, 0.5) m, rpy (180, 0, 0)"
                in " ".join(printed.split()))
        report = json.loads((tmp_path / f"{tag}.json").read_text())
        reports[tag] = {key: value for key, value in report.items() if key != "motion"}
    assert reports["flag"] == reports["file"]


def test_the_base_flag_overrides_the_files_mounting_and_base(tmp_path):
    """``--base`` over a file's ``base``, and over its ``mounting``, as ``--mounting`` does."""
    motion = with_base(tmp_path, "", ONE_MOVE, "move.toml")  # no mounting: the floor
    tilted = with_base(tmp_path, "{xyz = [0, 0, 0.5], rpy = [90, 0, 0]}",
                       ONE_MOVE.replace('angle_unit = "deg"', 'angle_unit = "deg"\n'
                                        'mounting = "floor"'), "tilted.toml")
    elsewhere = tilted.read_text().replace("rpy = [90, 0, 0]", "rpy = [0, 45, 0]")
    other = tmp_path / "other.toml"
    other.write_text(elsewhere)
    flag = ["--base", "0,0,0.5,90,0,0"]
    reference = outputs(tmp_path, "file", [str(tilted)])
    assert outputs(tmp_path, "over_base", [str(other), *flag]) == reference
    assert outputs(tmp_path, "over_floor", [str(motion), *flag]) == reference
    assert outputs(tmp_path, "floor", [str(motion)]) != reference  # the base mattered


def test_the_base_flags_angles_are_the_files_angle_unit(tmp_path):
    """A motion file in radians reads ``--base``'s angles in radians; a mix file its own
    ``angle_unit`` (its tasks' ``base`` keys'); envelope's ``--angle-unit``."""
    quarter = repr(math.pi / 2)
    in_rad = ONE_MOVE.replace('angle_unit = "deg"', 'angle_unit = "rad"\nmounting = "floor"')
    for old, new in (("180", repr(math.pi)), ("900", repr(5 * math.pi)),
                     ("9000", repr(50 * math.pi)), ("shoulder = 40, elbow = -80",
                                                   f"shoulder = {math.radians(40)!r}, "
                                                   f"elbow = {math.radians(-80)!r}"),
                     ("shoulder = -30, elbow = 20", f"shoulder = {math.radians(-30)!r}, "
                                                    f"elbow = {math.radians(20)!r}")):
        in_rad = in_rad.replace(old, new)
    motion = tmp_path / "rad.toml"
    motion.write_text(in_rad.replace('"../robots/', f'"{REPO}/robots/'))
    filed = with_base(tmp_path, f"{{xyz = [0, 0, 0], rpy = [{quarter}, 0, 0]}}", motion,
                      "rad_base.toml")
    flag = ["--base", f"0,0,0,{quarter},0,0"]
    assert outputs(tmp_path, "flag", [str(motion), *flag]) == outputs(tmp_path, "file",
                                                                        [str(filed)])
    for unit, angle in (("deg", "90"), ("rad", quarter)):
        mix = tmp_path / f"mix_{unit}.toml"
        mix.write_text(f'angle_unit = "{unit}"\n[[task]]\nname = "move"\nmotion = "{motion}"\n'
                       "share = 1.0\n")
        assert main(["size", str(mix), "--base", f"0,0,0,{angle},0,0", "--json",
                     str(tmp_path / f"{unit}.json")]) in (0, 1)
    documents = [{key: value for key, value in json.loads(
        (tmp_path / f"{unit}.json").read_text()).items() if key != "mix"}
        for unit in ("deg", "rad")]
    assert documents[0] == documents[1]
    assert main(["size", str(tmp_path / "mix_deg.toml"), "--json",
                 str(tmp_path / "floor.json")]) in (0, 1)
    assert json.loads((tmp_path / "floor.json").read_text())["joints"] != documents[0]["joints"]


@pytest.mark.slow
def test_envelope_reads_the_base_flags_angles_in_its_angle_unit(tmp_path):
    def answer(*argv):
        out = tmp_path / "envelope.json"
        assert main(["envelope", str(PLANAR2), "--moves", "3", *argv, "--json", str(out)]) \
            in (0, 1)
        document = json.loads(out.read_text())
        document["search"].pop("seconds")  # how long it took
        out.unlink()
        return document

    in_deg = answer("--base", "0,0,0.5,90,0,0", "--velocity", "90", "--acceleration", "600")
    in_rad = answer("--angle-unit", "rad", "--base", f"0,0,0.5,{math.pi / 2!r},0,0",
                    "--velocity", repr(math.pi / 2), "--acceleration", repr(600 * math.pi / 180))
    assert in_deg == in_rad


def refused(capsys, argv: list[str], *words: str) -> None:
    """`argv` exits with status 2 and one line naming `words` (argparse's own included)."""
    try:
        status = main(argv)
    except SystemExit as stop:  # argparse: "hdselect plan: error: argument --base: ..."
        status = stop.code
    assert status == 2
    err = capsys.readouterr().err
    one_line_error(err.replace(f"hdselect {argv[0]}: error", "hdselect: error"), *words)


HOSTILE = ["nan,0,0,0,0,0", "0,0,inf,0,0,0", "0,0,-inf,0,0,0", "1e308,0,0,0,0,0",
           "0,0,0,0,0,1e308", "0,0,0,1e9,0,0", "1,2,3,4,5", "1,2,3,4,5,6,7", "a,b,c,d,e,f",
           "0,0,0,0,0,", "0,,0,0,0,0", "0;0;0;0;0;0", "1e999,0,0,0,0,0", " ", "0,0,0,0,0,0x1"]
"""``--base`` values that are not six finite numbers in range."""


@pytest.mark.parametrize("value", HOSTILE)
@pytest.mark.parametrize("command", ["plan", "size", "max-payload", "fastest", "compare",
                                     "envelope"])
def test_a_bad_base_is_one_line_naming_it_and_writes_nothing(tmp_path, capsys, command,
                                                              value):
    out = tmp_path / "out.csv"
    target = [str(PLANAR2)] if command == "envelope" else [str(REPO / "trajectories" /
                                                               "planar2_pick_place.toml")]
    writes = ["--out", str(out)] if command == "plan" else ["--json", str(out)]
    refused(capsys, [command, *target, f"--base={value}", *writes], "--base")
    assert not out.exists()


@pytest.mark.parametrize("command", ["plan", "size", "envelope"])
def test_base_beside_mounting_is_refused_naming_both(tmp_path, capsys, command):
    target = str(PLANAR2) if command == "envelope" else str(REPO / "trajectories" /
                                                          "planar2_pick_place.toml")
    out = tmp_path / "out.csv"
    writes = ["--out", str(out)] if command == "plan" else ["--json", str(out)]
    refused(capsys, [command, target, "--mounting", "wall", "--base", "0,0,0,0,0,0", *writes],
            "--base", "--mounting")
    assert not out.exists()


def test_a_base_starting_below_zero_is_written_with_an_equals_sign(tmp_path, capsys):
    motion = str(REPO / "trajectories" / "planar2_pick_place.toml")
    refused(capsys, ["plan", motion, "--base", "-0.5,0,0,0,0,0", "--out",
                     str(tmp_path / "a.csv")], "--base")
    assert main(["plan", motion, "--base=-0.5,0,0,0,0,0", "--out",
                 str(tmp_path / "b.csv")]) == 0


def test_six_numbers_make_a_base_pose_in_metres_and_the_unit_given():
    pose = base_pose_from([0.1, -0.2, 0.3, 30.0, -45.0, 60.0], angle=math.pi / 180,
                          angle_unit="deg")
    by_hand = BasePose.from_xyz_rpy([0.1, -0.2, 0.3], np.radians([30.0, -45.0, 60.0]))
    np.testing.assert_allclose(pose.matrix, by_hand.matrix, atol=1e-15)
    assert pose.xyz == (0.1, -0.2, 0.3)
    assert base_pose_from([0, 0, 2, math.pi, 0, 0]).gravity[2] == pytest.approx(9.80665)
    for bad, words in (([0.0] * 5, "expected 6 numbers"), ([0, 0, 0, True, 0, 0], "roll"),
                       ([0, 0, float("nan"), 0, 0, 0], "z must be finite"),
                       ([0, 0, 0, 0, 2e3, 0], "pitch must be an angle")):
        with pytest.raises(InputError, match=words) as info:
            base_pose_from(bad, field="--base")
        assert info.value.field == "--base"


# --- plan MIX --task NAME -------------------------------------------------------------------

def test_plan_on_a_mix_wants_a_task_and_lists_them(tmp_path, capsys):
    out = tmp_path / "a.csv"
    for extra, words in (([], ("--task NAME", "pick, inspect")),
                         (["--task", "place"], ("no task 'place'", "pick, inspect"))):
        assert main(["plan", str(DAY), *extra, "--out", str(out)]) == 2
        one_line_error(capsys.readouterr().err, "--task", *words)
        assert not out.exists()
    assert main(["plan", str(POSES), "--task", "pick", "--out", str(out)]) == 2
    one_line_error(capsys.readouterr().err, "--task", "motion file")
    assert not out.exists()


@pytest.mark.parametrize("name", ["heavy", "own"])
def test_plan_of_a_task_is_the_task_the_mix_sizes(tmp_path, capsys, name):
    """The mix's payload for 'heavy' (0.8 kg, not its motion file's 0.4 kg), the motion
    file's own for 'own': the trajectory and torques `size` pools for the task."""
    motion = with_base(tmp_path, "", ONE_MOVE, "move.toml")
    mix = tmp_path / "day.toml"
    mix.write_text(f'[[task]]\nname = "own"\nmotion = "{motion}"\nshare = 0.7\n'
                   f'[[task]]\nname = "heavy"\nmotion = "{motion}"\nshare = 0.3\n'
                   'payload = {mass = 0.8, com = [0.03, 0.0, 0.0], frame = "tool"}\n')
    out = tmp_path / "task.csv"
    assert main(["plan", str(mix), "--task", name, "--out", str(out)]) == 0
    printed = " ".join(capsys.readouterr().out.split())
    robot, loaded = load_case(mix)
    tasks, _ = mix_tasks(robot, loaded)
    task = next(t for t in tasks if t.label == name)
    mass = {"heavy": 0.8, "own": 0.4}[name]
    assert task.robot.payload is not None and task.robot.payload.mass == mass
    assert f"task '{name}' of day.toml: base: 'base_link' held fixed; payload: {mass:g} kg" \
        in printed
    tau = inverse_dynamics(task.robot, task.trajectory.q, task.trajectory.qd,
                           task.trajectory.qdd)
    written = np.loadtxt(out, delimiter=",", skiprows=1)
    columns = [task.trajectory.t] + [array[:, j] for j in range(len(robot.joint_names))
                                     for array in (task.trajectory.q, task.trajectory.qd,
                                                   task.trajectory.qdd, tau)]
    np.testing.assert_allclose(written, np.column_stack(columns), rtol=1e-9, atol=1e-12)


@pytest.mark.slow
def test_plan_of_a_task_of_tool_poses_writes_what_its_motion_writes_as_mounted(tmp_path):
    """A task mounted by the mix (its ``mounting``, its ``base``) or by the command line
    (over the mix's) writes the same files as its motion file planned on that mounting."""
    mix = tmp_path / "mix.toml"
    inspect = REPO / "trajectories" / "benchtop6_inspect.toml"
    mix.write_text(f'[[task]]\nname = "wall"\nmotion = "{POSES}"\nmounting = "wall"\n'
                   f"share = 0.5\n[[task]]\nname = \"hung\"\nmotion = \"{POSES}\"\n"
                   f"base = {{xyz = [0, 0, 0.5], rpy = [180, 0, 0]}}\nshare = 0.3\n"
                   f'[[task]]\nname = "inspect"\nmotion = "{inspect}"\nshare = 0.2\n')
    alone = {"wall": outputs(tmp_path, "wall", [str(POSES), "--mounting", "wall"],
                             tool_poses=True),
             "hung": outputs(tmp_path, "hung", [str(POSES), "--base", CEILING],
                             tool_poses=True)}
    assert outputs(tmp_path, "mix_wall", [str(mix), "--task", "wall"],
                   tool_poses=True) == alone["wall"]
    assert outputs(tmp_path, "mix_hung", [str(mix), "--task", "hung"],
                   tool_poses=True) == alone["hung"]
    assert outputs(tmp_path, "over", [str(mix), "--task", "wall", "--base", CEILING],
                   tool_poses=True) == alone["hung"]
