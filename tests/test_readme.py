"""The README's examples, run as a user would, so they cannot drift."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from hdselect.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


OWN_ROBOT = README[README.index("## Your own robot"):README.index("\n## ", README.index(
    "## Your own robot") + 1)]
"""The section whose steps build on each other: run in order by its own test."""


def console_examples() -> list[tuple[str, str]]:
    """Each ``$ hdselect ...`` line of a console block, with the output shown under it.

    The blocks of "Your own robot" are left to `test_your_own_robot_steps_run_in_order`.
    """
    examples = []
    for block in re.findall(r"```console\n(.*?)```", README.replace(OWN_ROBOT, ""), flags=re.S):
        lines = block.rstrip("\n").split("\n")
        command = lines[0].removeprefix("$ ")
        examples.append((command, "\n".join(lines[1:])))
    return examples


def workdir(tmp_path: Path) -> Path:
    """A directory where the README's relative paths resolve and outputs land."""
    for name in ("robots", "trajectories", "motors"):
        (tmp_path / name).symlink_to(ROOT / name)
    return tmp_path


@pytest.mark.parametrize(("command", "shown"), console_examples(), ids=lambda x: x[:40])
def test_console_example_prints_what_the_readme_shows(command, shown, tmp_path, monkeypatch,
                                                      capsys):
    monkeypatch.chdir(workdir(tmp_path))
    monkeypatch.setenv("COLUMNS", "80")  # the README shows piped output at 80 columns
    args = shlex.split(command)
    assert args[0] == "hdselect"
    assert main(args[1:]) == 0
    printed = "\n".join(line.rstrip() for line in capsys.readouterr().out.rstrip().split("\n"))
    assert printed == shown.rstrip()
    for option in ("--out", "--plot"):
        if option in args:
            assert (tmp_path / args[args.index(option) + 1]).stat().st_size > 0


def test_python_examples_run(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(workdir(tmp_path))
    blocks = re.findall(r"```python\n(.*?)```", README, flags=re.S)
    (motor_example,) = [block for block in blocks if "load_motors" in block]
    size_example, core_example, codesign_example = [
        block for block in blocks if block is not motor_example]
    exec(compile(size_example, "README.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == JOINTS
    exec(compile(core_example, "README.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":")[0] for line in lines] == ["0.5 kg", "1.0 kg", "2.0 kg"]
    for line in lines:
        assert [pair.split()[0] for pair in line.split(": ")[1].split(", ")] == JOINTS
    exec(compile(motor_example, "README.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == JOINTS
    for line in lines:  # joint, gearhead + motor, the motor's binding rule, the inertia ratio
        name, unit, plus, motor, rule, ratio = line.split()
        assert unit.startswith("PSA-") and plus == "+" and motor.startswith("EX-")
        assert rule.startswith("motor_") and float(ratio) > 0
    exec(compile(codesign_example, "README.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 9
    assert lines[0].endswith("lengthened by None") or "lengthened by ('shoulder_pan'" in lines[0]
    assert [line.split()[0] for line in lines[1:8]] == [
        "PSA-08-80", "PSA-08-100", "PSA-10-50", "PSA-10-80", "PSA-14-50", "PSA-14-80", "PSA-14-100"]
    assert lines[8].endswith("kg: shoulder PSA-14-100 momentary")


JOINTS = ["shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"]


def test_first_screen_has_the_two_setup_commands_and_ci_runs_the_test_one():
    (setup,) = re.findall(r"## Set up\n.*?```sh\n(.*?)```", README, flags=re.S)
    install_and_run, install_and_test = setup.strip().split("\n")
    assert "pip install -e ." in install_and_run and "hdselect size" in install_and_run
    assert "pytest" in install_and_test
    assert install_and_test in (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert README.index("## Set up") < 1500


def test_your_own_robot_steps_run_in_order(tmp_path, monkeypatch, capsys):
    """joints -> init -> edit (the toml block replaces the commented [payload]) -> size."""
    monkeypatch.chdir(workdir(tmp_path))
    monkeypatch.setenv("COLUMNS", "80")
    blocks = re.findall(r"```(console|toml)\n(.*?)```", OWN_ROBOT, flags=re.S)
    assert [kind for kind, _ in blocks] == ["console", "console", "toml", "console"]
    motion = None
    for kind, block in blocks:
        if kind == "toml":
            text = motion.read_text()
            commented = re.search(r"^# \[payload\].*?\n\n", text, flags=re.S | re.M)
            assert commented is not None
            motion.write_text(text.replace(commented.group(0), block + "\n"))
            continue
        command, *shown = block.rstrip("\n").split("\n")
        args = shlex.split(command.removeprefix("$ "))
        assert main(args[1:]) == 0
        printed = "\n".join(line.rstrip() for line in capsys.readouterr().out.rstrip().split("\n"))
        assert printed == "\n".join(shown).rstrip()
        if "--out" in args:
            motion = tmp_path / args[args.index("--out") + 1]
    assert "payload: 0.053 kg on 'end_effector'" in printed
