"""Gearhead masses carried by the arm.

A gearhead (and its motor) is bolted to the link before its joint, centred on
the joint axis: a point mass at the joint origin, carried by every joint nearer
the base and by none further out. Its rotor inertia spinning on a moving link is
neglected.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
import pinocchio as pin

from hdselect.robot import Robot


def with_gearheads(robot: Robot, masses: Mapping[str, float]) -> Robot:
    """A copy of the robot carrying a point mass at the origin of each named joint.

    Args:
        robot: The robot.
        masses: Mass mounted at each joint, on the link before it [kg].

    Returns:
        The robot with the masses added to its model; the original is unchanged.
    """
    model = pin.Model(robot.model)
    for name, mass in masses.items():
        joint_id = model.getJointId(name)
        parent = model.parents[joint_id]
        if mass > 0.0 and parent > 0:
            point = pin.Inertia(mass, np.zeros(3), np.zeros((3, 3)))
            model.appendBodyToJoint(parent, point, model.jointPlacements[joint_id])
    return replace(robot, model=model)


def carried_mass(robot: Robot, masses: Mapping[str, float], joint: str) -> float:
    """Total of the masses mounted on links that `joint` moves [kg]."""
    model = robot.model
    joint_id = model.getJointId(joint)
    total = 0.0
    for name, mass in masses.items():
        ancestor = model.parents[model.getJointId(name)]
        while ancestor > joint_id:
            ancestor = model.parents[ancestor]
        if ancestor == joint_id:
            total += mass
    return total
