"""The README's first screen and its "Your own robot" steps, run as a user would.

Its other examples, and those of docs/*.md, are run by test_docs.
"""

from __future__ import annotations

import re

from docs_examples import OWN_ROBOT, ROOT, examples, matches, run, scratch

README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_first_screen_has_the_two_setup_commands_and_ci_runs_the_test_one():
    (setup,) = re.findall(r"## Set up\n.*?```sh\n(.*?)```", README, flags=re.S)
    install_and_run, install_and_test = setup.strip().split("\n")
    assert "pip install -e ." in install_and_run and "hdselect size" in install_and_run
    assert "pytest" in install_and_test
    assert install_and_test in (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert README.index("## Set up") < 1500


def test_the_readme_fits_on_a_few_screens():
    assert len(README.splitlines()) <= 250


def test_your_own_robot_steps_run_in_order(tmp_path):
    """joints -> init -> edit (the toml block replaces the commented [payload]) -> size."""
    work = scratch(tmp_path)
    start = README.index(OWN_ROBOT)
    section = README[start:README.index("\n## ", start + 1)]
    assert [kind for kind in re.findall(r"```(\w+)\n", section)] == [
        "console", "console", "toml", "console"]
    (edit,) = re.findall(r"```toml\n(.*?)```", section, flags=re.S)
    steps = examples(ROOT / "README.md", section)
    assert [step.kind for step in steps] == ["console"] * 3
    for step in steps:
        if step.source.startswith("hdselect size"):
            motion = work / "out" / "my_scara.toml"
            text = motion.read_text()
            commented = re.search(r"^# \[payload\].*?\n\n", text, flags=re.S | re.M)
            assert commented is not None
            motion.write_text(text.replace(commented.group(0), edit + "\n"))
        printed = run(step, work)
        assert matches(printed, step.shown), f"{step.source}\n{printed}"
    assert "payload: 0.053 kg on 'end_effector'" in printed
