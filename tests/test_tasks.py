"""Tests of hdselect.sizing.tasks and .torques: a robot's tasks pooled, torques on demand.

Oracles: the pooled weights by hand (each task's samples stand for its share of the
operating time), per-sample `pinocchio.rnea` on the robot with the masses written in
independently, and the single-task sizing itself (a task of share 0 changes nothing).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

import hdselect.sizing.torques as torques_module
from hdselect import InputError, load_case, load_catalog, plan, size_trajectory
from hdselect.sizing.core import size_tasks
from hdselect.sizing.tasks import Task, pooled
from hdselect.sizing.torques import DirectTorques
from helpers import REPO
from helpers.dynamics import pin_config, with_point_masses
from helpers.studies import differences

PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
CONTOUR = REPO / "trajectories" / "benchtop6_contour.toml"


@pytest.fixture(scope="module")
def two_tasks():
    """benchtop6 with the pick-and-place's payload, its plan, and the contour motion."""
    robot, pick = load_case(PICK)
    _, contour = load_case(CONTOUR)
    return robot, plan(robot, pick), None, contour


def test_pooled_samples_stand_for_each_tasks_share_of_the_time(two_tasks):
    robot, pick, other, contour = two_tasks
    second = plan(robot, contour)
    shares = (0.7, 0.3)
    samples = pooled((Task(robot, pick, shares[0]), Task(robot, second, shares[1])))
    n = len(pick.t)
    time = [float(np.sum(samples.dt[:n])), float(np.sum(samples.dt[n:]))]
    # a task's n_k samples of dt_k stand for one cycle, and it runs share_k / (n_k dt_k)
    # cycles per unit time: the pooled durations are in the ratio of the shares
    assert time[1] / time[0] == pytest.approx(shares[1] / shares[0], rel=1e-12)
    assert time[0] == pytest.approx(len(pick.t) * pick.dt, rel=1e-12)
    assert list(samples.task[:n]) == [0] * n and set(samples.task[n:]) == {1}
    assert samples.weight is not None and samples.weight[0] == 1.0


def test_a_task_of_share_zero_counts_in_no_rule(two_tasks):
    robot, pick, _, contour = two_tasks
    units = load_catalog()
    alone = size_trajectory(robot, pick, units)
    mixed = size_tasks((Task(robot, pick, 1.0), Task(robot, plan(robot, contour), 0.0)), units)
    assert differences(_plain(mixed), _plain(alone)) == 0.0  # to the last bit
    assert len(mixed.tasks) == 2 and mixed.trajectory is pick


def test_a_task_twice_at_half_the_time_each_is_the_task(two_tasks):
    robot, pick, _, _ = two_tasks
    units = load_catalog()
    alone = size_trajectory(robot, pick, units)
    twice = size_tasks((Task(robot, pick, 0.5), Task(robot, pick, 0.5)), units)
    for a, b in zip(alone.joints, twice.joints, strict=True):
        assert a.selected.unit.id == b.selected.unit.id
        for check in a.selected.checks:
            assert (b.selected.checks[check].utilization
                    == pytest.approx(a.selected.checks[check].utilization, rel=1e-12, abs=1e-15))
        if a.selected.life_hours is not None:
            assert b.selected.life_hours == pytest.approx(a.selected.life_hours, rel=1e-12)


def test_shares_must_be_fractions_summing_to_one(two_tasks):
    robot, pick, _, _ = two_tasks
    units = load_catalog()
    with pytest.raises(InputError, match="sum to 0.9;"):
        size_tasks((Task(robot, pick, 0.6), Task(robot, pick, 0.3)), units)
    with pytest.raises(InputError, match=">= 0"):
        size_tasks((Task(robot, pick, 1.5), Task(robot, pick, -0.5)), units)
    with pytest.raises(InputError, match="same robot file"):
        size_tasks((Task(robot, pick, 0.5),
                    Task(robot.with_sized_joints(["elbow"]), pick, 0.5)), units)


def test_direct_torques_equal_rnea_with_the_masses_written_in(two_tasks):
    robot, pick, _, _ = two_tasks
    masses = {"elbow": 0.5, "wrist_1": 0.4, "wrist_2": 0.3, "wrist_3": 0.3}
    samples = pooled((Task(robot, pick),))
    model = DirectTorques(samples.tasks, samples, 0.1, guess={"elbow": 9.0})
    oracle = with_point_masses(robot.model, masses)
    data = oracle.createData()
    rows = np.linspace(0, len(pick.t) - 1, 25).astype(int)
    for name in robot.sized_joints:
        tau, stop = model.torques(name, masses)
        j = robot.joint_index(name)
        for i in rows:
            q = pin_config(oracle, pick.q[i])
            expected = pin.rnea(oracle, data, q, pick.qd[i], pick.qdd[i])[j]
            braking = pin.rnea(oracle, data, q, pick.qd[i], -pick.qd[i] / 0.1)[j]
            assert tau[i] == pytest.approx(expected, rel=1e-9, abs=1e-9)
            assert stop[i] == pytest.approx(braking, rel=1e-9, abs=1e-9)


def test_a_right_guess_costs_one_pair_of_passes(two_tasks, monkeypatch):
    robot, pick, _, _ = two_tasks
    units = load_catalog()
    calls = []
    original = torques_module.cycle_torques

    def counted(*args, **kwargs):
        calls.append(len(args[1]))
        return original(*args, **kwargs)

    monkeypatch.setattr(torques_module, "cycle_torques", counted)
    result = size_trajectory(robot, pick, units)
    full = [n for n in calls if n == len(pick.t)]
    assert len(full) == 1, "the coarse guess should make the full trajectory one pass"
    assert result.feasible


def _plain(result):
    """A result as nested plain values, for `differences` (the summary's record)."""
    from hdselect import summarize

    return replace(summarize(result), warnings=(), tasks=()).to_dict()  # tasks: listed apart


def test_the_pooled_mean_torque_weights_each_task_by_its_rate():
    """Two index-table tasks by hand: constant torque T_k at speed w_k, cycles T_k long.

    With shares s_k, task k runs s_k / T_k cycles per unit time; per unit time its
    samples carry |n| |T|^3 dt summed to s_k w_k T_k^3 (all moving), so
    T_av^3 = sum s_k w_k tau_k^3 / sum s_k w_k and N_av = sum s_k w_k / sum s_k.
    """
    from hdselect.catalog.rules import cycle_load

    w, tau, shares = (1.0, 3.0), (2.0, 5.0), (0.25, 0.75)
    durations = (2.0, 0.5)
    t, dt, speed, torque = [], [], [], []
    reference = shares[0] / durations[0]
    for k in range(2):
        n = 100
        step = durations[k] / n
        rate = shares[k] / durations[k] / reference
        dt += [step * rate] * n
        speed += [w[k]] * n
        torque += [tau[k]] * n
        t += list(np.arange(n) * step)
    load = cycle_load(np.array(torque), np.array(speed), np.array(dt), np.zeros(200, bool))
    cubes = sum(s * v * x**3 for s, v, x in zip(shares, w, tau, strict=True))
    travel = sum(s * v for s, v in zip(shares, w, strict=True))
    assert load.mean_torque == pytest.approx(math.cbrt(cubes / travel), rel=1e-12)
    assert load.mean_speed == pytest.approx(travel / sum(shares), rel=1e-12)
