"""Checks of a built robot model: bodies physical, every number finite and in range.

Pinocchio's URDF and MJCF readers accept NaN and 1e308 where a length or a mass
goes. These checks run on the model Pinocchio built, after it merged every link
on a fixed joint into its moving body, so bodies are checked as the dynamics will
see them (`hdselect.robot.reading` calls them; it also catches the parser's output).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from hdselect.base import bounds
from hdselect.base.errors import InputError


def model_limit(model: pin.Model, name: str, old_name: str) -> np.ndarray:
    """A per-degree-of-freedom limit of the file; Pinocchio 3 and 4 name them differently."""
    return np.array(getattr(model, name) if hasattr(model, name) else getattr(model, old_name),
                    dtype=float)


def body_links(model: pin.Model, joint_id: int) -> list[str]:
    """The links a joint moves rigidly: its own first, then those merged on fixed joints."""
    return [f.name for f in model.frames
            if f.type == pin.FrameType.BODY and f.parentJoint == joint_id]


def check_bodies(model: pin.Model, path: Path) -> list[str]:
    """Reject a moving body whose inertia is not physical; note one that is barely so.

    An empty body (frame links such as ``tool0``) is skipped. A body's mass is in
    `bounds.MASS`, its centre of mass within `bounds.LENGTH` and each element of its
    inertia within `bounds.INERTIA`.

    Returns:
        A note for each body whose principal moments violate the triangle inequality.

    Raises:
        InputError: A body has a non-finite or out-of-range mass, centre of mass or
            inertia, rotational inertia without mass, or a negative principal moment.
    """
    notes = []
    for joint_id in range(1, model.njoints):
        body = model.inertias[joint_id]
        mass, com, inertia = float(body.mass), np.array(body.lever), np.array(body.inertia)
        if mass == 0.0 and not np.any(inertia):
            continue  # an empty body: frames only
        links = body_links(model, joint_id)
        link = links[0] if links else model.names[joint_id]
        merged = f" (with {', '.join(links[1:])} merged)" if len(links) > 1 else ""
        field = f"link[{link}].inertial"
        where = f"link '{link}'{merged}"
        if not (np.isfinite(mass) and np.all(np.isfinite(com)) and np.all(np.isfinite(inertia))):
            raise InputError(f"{where} has a non-finite mass, centre of mass or inertia",
                             path=path, field=field)
        if mass <= 0.0:
            raise InputError(f"{where} has mass {mass:g} kg; a moving body with rotational "
                             "inertia must have positive mass", path=path, field=field)
        bounds.MASS.check(mass, path=path, field=field + ".mass")
        for x in com:
            bounds.LENGTH.check(float(x), path=path, field=field + ".origin")
        for value in inertia.flat:
            bounds.INERTIA.check(float(value), path=path, field=field + ".inertia")
        moments = np.linalg.eigvalsh(inertia)
        scale = max(float(np.abs(moments).max()), mass * 1e-6)  # 1e-6: a point mass at 1 mm
        text = ", ".join(f"{m:.3g}" for m in moments)
        if moments[0] < -1e-9 * scale:
            raise InputError(f"{where} inertia is not positive semi-definite (principal moments "
                             f"{text} kg m^2)", path=path, field=field)
        if moments[0] + moments[1] < moments[2] * (1.0 - 1e-6) - 1e-9 * scale:
            notes.append(f"{where}: principal moments {text} kg m^2 violate the triangle "
                         "inequality (no rigid body has them); used as written")
    return notes


def check_geometry(model: pin.Model, path: Path) -> None:
    """Every joint origin and frame is finite and within `bounds.LENGTH`; so is the dynamics.

    Also: velocity and effort limits are zero (not given) or positive.

    Raises:
        InputError: One is not (the field names the joint or frame).
    """
    placements = [(f"joint[{model.names[j]}].origin", model.jointPlacements[j])
                  for j in range(1, model.njoints)]
    placements += [(f"frame[{frame.name}].origin", frame.placement) for frame in model.frames]
    for where, placement in placements:
        if not np.all(np.isfinite(placement.rotation)):
            raise InputError("the rotation is not finite", path=path, field=where)
        for x in placement.translation:
            bounds.LENGTH.check(float(x), path=path, field=where)
    data = model.createData()
    probe = pin.rnea(model, data, pin.neutral(model), np.ones(model.nv), np.ones(model.nv))
    if not np.all(np.isfinite(probe)):
        raise InputError("the dynamics are not finite (a joint axis or an origin is not a "
                         "number?)", path=path)
    for name, values in (("velocity", model_limit(model, "upperVelocityLimit", "velocityLimit")),
                         ("effort", model_limit(model, "upperEffortLimit", "effortLimit"))):
        bad = np.flatnonzero(np.isnan(values) | (values < 0.0))
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
