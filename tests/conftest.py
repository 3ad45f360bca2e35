"""Fixtures the test modules share; shared factories and oracles are in tests/helpers/.

Run the fast subset (every test but those marked ``slow``) with
``python -m pytest -m "not slow"`` (docs/architecture.md, "How it is tested").

Hypothesis runs the "ci" profile (60 cases per test, a fixed seed, no deadline: a test
must not depend on the machine's speed) unless ``HDSELECT_FUZZ=long`` asks for 2,000
fresh cases per test. It is loaded here, before any test module sets its own settings
from ``settings.default``.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

from helpers import REPO

settings.register_profile(
    "ci", max_examples=60, derandomize=True, deadline=None, database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
settings.register_profile(
    "long", max_examples=2000, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
settings.load_profile(os.environ.get("HDSELECT_FUZZ", "ci"))


@pytest.fixture
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The working directory: the shipped robots (robots/) and a copy of the motions (tr/)."""
    (tmp_path / "robots").symlink_to(REPO / "robots")
    shutil.copytree(REPO / "trajectories", tmp_path / "tr")
    monkeypatch.chdir(tmp_path)
    return tmp_path
