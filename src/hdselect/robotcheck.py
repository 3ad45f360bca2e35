"""Checks of a robot file beyond what its parser checks: every number finite and in range.

Pinocchio's URDF and MJCF readers accept NaN and 1e308 where a length or a mass
goes, and the URDF reader writes its complaints straight to file descriptor 2.
These checks run on the built model, so merged fixed links are checked as the
dynamics will see them; `c_stderr` turns the reader's complaints into one line.
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect import bounds
from hdselect.errors import InputError


def check_geometry(model: pin.Model, path: Path) -> None:
    """Every joint origin, frame and centre of mass is finite and within `bounds.LENGTH`.

    Raises:
        InputError: One is not (the field names the joint, frame or body).
    """
    placements = [(f"joint[{model.names[j]}].origin", model.jointPlacements[j])
                  for j in range(1, model.njoints)]
    placements += [(f"frame[{frame.name}].origin", frame.placement) for frame in model.frames]
    for where, placement in placements:
        if not np.all(np.isfinite(placement.rotation)):
            raise InputError("the rotation is not finite", path=path, field=where)
        for x in placement.translation:
            bounds.LENGTH.check(float(x), path=path, field=where)
    for j in range(1, model.njoints):
        body = model.inertias[j]
        where = f"joint[{model.names[j]}].inertial"
        bounds.ADDED_MASS.check(float(body.mass), path=path, field=where + ".mass")
        for x in body.lever:
            bounds.LENGTH.check(float(x), path=path, field=where + ".origin")
        if not np.all(np.isfinite(body.inertia)):
            raise InputError("the inertia is not finite", path=path, field=where)
    data = model.createData()
    probe = pin.rnea(model, data, pin.neutral(model), np.ones(model.nv), np.ones(model.nv))
    if not np.all(np.isfinite(probe)):
        raise InputError("the dynamics are not finite (a joint axis or an origin is not a "
                         "number?)", path=path)
    for name, values in (("velocity", model.velocityLimit), ("effort", model.effortLimit)):
        bad = np.flatnonzero(np.isnan(values) | (np.asarray(values) < 0.0))
        if bad.size:
            joint = joint_of_v(model, int(bad[0]))
            raise InputError(f"the {name} limit must be zero or positive, got "
                             f"{values[bad[0]]:g}", path=path, field=f"joint[{joint}].limit")


def joint_of_v(model: pin.Model, index: int) -> str:
    """The name of the joint owning velocity coordinate `index`."""
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.idx_v <= index < joint.idx_v + joint.nv:
            return model.names[j]
    return "?"


@contextmanager
def c_stderr() -> Iterator[list[str]]:
    """Catch what C++ code (the URDF parser) writes straight to file descriptor 2.

    Yields the list the lines are put in when the block ends, so that a malformed
    file is one line of ours, not the parser's dump. Where descriptor 2 cannot be
    redirected the lines go where they always went.
    """
    lines: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield lines
        return
    with tempfile.TemporaryFile() as capture:
        os.dup2(capture.fileno(), 2)
        try:
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            capture.seek(0)
            lines += capture.read().decode("utf-8", errors="replace").splitlines()
