"""hdselect's torques equal MuJoCo's inverse dynamics on every real robot file both read.

The files: every URDF of example-robot-data (a test dependency: always run), and,
when the packages are installed, every URDF with a movable joint and every MJCF of
pybullet's ``pybullet_data``, gymnasium's MuJoCo assets, dm_control and MuJoCo's own
test models. Each file hdselect loads is compared at a few random states with
MuJoCo's ``mj_inverse`` (`mujoco_oracle`: rigid-body dynamics only, followers folded
into their leaders); a file hdselect refuses must be refused in one line. The
counts these tests reach are stated in docs/robot-files.md.
"""

from __future__ import annotations

import importlib.util
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import hdselect
from hdselect.base.errors import InputError
from helpers.robots import EXAMPLE_ROBOTS, KNOWN_REFUSALS
from mujoco_oracle import compare

RTOL = 1e-9
"""Agreement asked, relative to the file's largest MuJoCo torque at the states drawn."""
STATES = 3
"""Random states per file."""


def package_folder(name: str) -> Path | None:
    """Where an installed package lives (found without importing it), or None."""
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(list(spec.submodule_search_locations)[0])


def root_tag(path: Path) -> str | None:
    try:
        for _, element in ET.iterparse(path, events=("start",)):
            return element.tag
    except ET.ParseError:
        return None
    return None


def movable(path: Path) -> bool:
    """A URDF that names a revolute, continuous or prismatic joint (a quick text scan)."""
    return re.search(rb'type\s*=\s*"(revolute|continuous|prismatic)"', path.read_bytes()) \
        is not None


def optional_files() -> list[tuple[str, Path | None]]:
    """(package, file) of the optional packages; (package, None) when it is not installed."""
    found: list[tuple[str, Path | None]] = []
    for package in ("pybullet_data", "gymnasium", "dm_control", "mujoco"):
        folder = package_folder(package)
        if folder is None:
            found.append((package, None))
            continue
        if package == "pybullet_data":
            found += [(package, p) for p in sorted(folder.rglob("*.urdf")) if movable(p)]
        found += [(package, p) for p in sorted(folder.rglob("*.xml"))
                  if root_tag(p) == "mujoco"]
    return found


def check(path: Path) -> str:
    """Load `path` and compare; returns 'compared' or 'refused'."""
    try:
        robot = hdselect.load_robot(path)
    except InputError as err:
        assert "\n" not in str(err) and str(path) in str(err)
        return "refused"
    worst, scale = compare(robot, STATES)
    assert worst <= RTOL * max(scale, 1e-12), (worst, scale)
    return "compared"


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLE_ROBOTS, ids=lambda p: p.name)
def test_example_robot_data(path: Path) -> None:
    outcome = check(path)
    if outcome == "refused":
        with pytest.raises(InputError, match=re.escape(KNOWN_REFUSALS[path.name])):
            hdselect.load_robot(path)


def test_nearly_every_example_robot_is_compared() -> None:
    assert len(EXAMPLE_ROBOTS) >= 69
    assert len(EXAMPLE_ROBOTS) - len(KNOWN_REFUSALS) >= 64


@pytest.mark.parametrize(("package", "path"), optional_files(),
                         ids=lambda p: p if isinstance(p, str) else "/".join(p.parts[-3:])
                         if p is not None else "absent")
def test_installed_packages(package: str, path: Path | None) -> None:
    if path is None:
        pytest.skip(f"{package} is not installed (pip install "
                    f"{'pybullet' if package == 'pybullet_data' else package.replace('_', '-')}"
                    " to compare its robot files)")
    check(path)
