"""What many test modules share: the repository's root and the command-line runners.

Test modules import their shared factories and oracles from the modules of this
package (never from one another); fixtures live in tests/conftest.py.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from hdselect.cli.main import main

REPO = Path(__file__).resolve().parents[2]
"""The repository's root (robots/, trajectories/, motors/, docs/ below it)."""


def run(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    """Run the command line on `argv` (each item str()-ed); (status, stdout, stderr)."""
    status = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return status, out, err


def run_redirected(argv: Sequence[object]) -> tuple[int, str, str]:
    """`run` without capsys: the output caught by redirecting sys.stdout and sys.stderr."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main([str(arg) for arg in argv])
    return status, out.getvalue(), err.getvalue()
