"""Mix files written for the tests: tasks on different mountings, a task of tool poses."""

from __future__ import annotations

from pathlib import Path

from helpers import REPO

PLANAR2 = REPO / "robots" / "planar2.urdf"
PLANAR2_MOTION = REPO / "trajectories" / "planar2_pick_place.toml"
POSES = REPO / "trajectories" / "benchtop6_pick_place_poses.toml"
INSPECT = REPO / "trajectories" / "benchtop6_inspect.toml"


def two_mountings(folder: Path) -> Path:
    """Planar2's motion twice, shares 0.5: on its file's floor, and on the mix file's ceiling."""
    path = folder / "mounted.toml"
    path.write_text(f'robot = "{PLANAR2}"\n'
                    f'[[task]]\nname = "floor"\nmotion = "{PLANAR2_MOTION}"\nshare = 0.5\n'
                    f'[[task]]\nname = "ceiling"\nmotion = "{PLANAR2_MOTION}"\nshare = 0.5\n'
                    'mounting = "ceiling"\n')
    return path


def poses_mix(folder: Path) -> Path:
    """The benchtop arm's tool-pose motion (its file: the floor) and its inspection, 0.5 each."""
    path = folder / "poses.toml"
    path.write_text(f'[[task]]\nname = "poses"\nmotion = "{POSES}"\nshare = 0.5\n'
                    f'[[task]]\nname = "inspect"\nmotion = "{INSPECT}"\nshare = 0.5\n')
    return path
