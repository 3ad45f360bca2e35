"""For a joint no unit fits: the time scales at which each unit would, and the smallest."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from hdselect.catalog.motors import Motor
from hdselect.catalog.units import Unit
from hdselect.sizing.bearing import ScalableWrench
from hdselect.sizing.joint import joint_targets
from hdselect.sizing.options import Options
from hdselect.sizing.result import JointSizing, Motors
from hdselect.sizing.timescale import JointScales, ScalableCycle, Slowdown, joint_scales
from hdselect.sizing.torques import TorqueModel


def with_slowdowns(model: TorqueModel, joints: list[JointSizing],
                   units: Mapping[str, tuple[Unit, ...]], options: Options, motors: Motors,
                   masses: Mapping[str, float]) -> list[JointSizing]:
    """Attach to each joint without a unit the time scales at which each unit would fit.

    The model splits the joint's torques (with the chosen units' `masses` [kg]) into
    the parts that scale differently with time: gravity, and gravity plus the
    velocity terms; where a unit rates its bearing, the joint's wrench too (at rest,
    and along the motion).
    """
    samples = model.samples
    out = []
    for joint in joints:
        if joint.selected is None:
            j = model.robot.joint_index(joint.name)
            gravity, coast = model.scaling_parts(joint.name, masses)
            cycle = ScalableCycle.split(
                samples.t, samples.dt, samples.duration, samples.qd[:, j], samples.qdd[:, j],
                samples.rest[:, j], torque=joint.torque, stop_torque=joint.stop_torque,
                gravity=gravity, coast=coast, stop_time=options.stop_time, idle=samples.idle)
            if joint.wrench is not None and any(u.bearing is not None for u in units[joint.name]):
                still = model.gravity_wrench(joint.name, masses)
                if still is not None:
                    cycle = replace(cycle, wrench=ScalableWrench(
                        np.asarray(still[:5]), joint.wrench.full(),
                        options.bearing_offset.get(joint.name, 0.0)))
            slowdown, scales = fitting_time_scales(cycle, units[joint.name], options,
                                                   motors=tuple(motors.get(joint.name, ())),
                                                   load_inertia=joint.load_inertia,
                                                   name=joint.name)
            joint = replace(joint, slowdown=slowdown, scales=scales)
        out.append(joint)
    return out


def fitting_time_scales(cycle: ScalableCycle, units: Sequence[Unit], options: Options, *,
                        motors: Sequence[Motor] = (), load_inertia: float | None = None,
                        name: str = "") -> tuple[Slowdown, JointScales]:
    """For a joint no unit fits: every unit's feasible time scales and the smallest slow-down.

    Args:
        cycle: The joint's cycle split by how its torques scale.
        units: The catalog.
        options: The assumptions (efficiency, rotor inertia, life requirement, margin,
            largest inertia ratio).
        motors: The joint's candidate motors: then the scales are per (gearhead, motor)
            pair, each with its motor's rotor inertia and rules.
        load_inertia: The joint's load inertia [kg m^2], for the pairs' inertia ratio and
            the joint's natural frequency.
        name: The joint, for its precision targets (`joint_targets`).

    Returns:
        The slow-down, its factor rounded to 0.001 (see `_rounded`), and the scales.
    """
    scales = joint_scales(cycle, units, efficiency=options.efficiency,
                          rotor_inertia=options.rotor_inertia,
                          check_options={"life_hours": options.life_hours,
                                         "life_basis": options.life_basis,
                                         "margin": options.margin,
                                         **joint_targets(name, options, load_inertia)},
                          motors=tuple(motors),
                          pair_options={"load_inertia": load_inertia,
                                        "max_inertia_ratio": options.max_inertia_ratio})
    return _rounded(scales.slowdown(), scales, cycle.duration), scales


def _rounded(slowdown: Slowdown, scales: JointScales, duration: float) -> Slowdown:
    """The slow-down with its factor rounded to 0.001, away from the edge of what fits.

    The exact factor is the edge of the feasible range, where a re-planned motion
    sampled on its own grid can fail by the change over one sample. Rounding up (or
    down, for a speed-up) keeps inside the range whenever the range allows it.
    """
    if slowdown.factor is None or slowdown.unit is None:
        return slowdown
    exact = slowdown.factor
    rounded = (math.ceil(exact * 1000.0) if exact >= 1.0 else math.floor(exact * 1000.0)) / 1000.0
    if not any(lo <= rounded <= hi for lo, hi in scales.fits[slowdown.unit]):
        rounded = exact
    return replace(slowdown, factor=rounded, cycle_time=rounded * duration)
