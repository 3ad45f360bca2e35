"""The whole-arm targets (sizing/stiffening.py) against a brute force over every choice.

The oracle: planar3 (a three-link arm in the vertical plane, tests/data) holding 1 kg,
sized with the invented ZS series (tests/data/invented_stiff_catalog.toml, five units
whose torque, mass and stiffness grow together). Every combination of three units is
checked with `check_units` (the units' masses carried); for each that passes every
joint's rules, the tool's holding deflection and the arm's lowest mode are computed here
by hand from the arm's geometry (`oracle_figures`: no Pinocchio, no hdselect but the
catalog's three-segment twist, tested on Harmonic Drive's example in
test_stiffness_curve.py). The smallest total mass that meets a target is what the
raising step must find.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.stiffness import torsion
from hdselect.motion.loading import load_case
from hdselect.motion.planning import plan
from hdselect.sizing.core import check_units, select_units, size, size_trajectory
from hdselect.sizing.options import Options
from hdselect.sizing.stiffening import stiffened
from hdselect.sizing.tasks import Task, pooled
from hdselect.sizing.torques import DirectTorques
from helpers import REPO
from helpers.motions import planar2_motion

DATA = REPO / "tests" / "data"

MOTION = """\
robot = "{robot}"
planner = "ruckig"
angle_unit = "deg"
dt = 0.005
[payload]
mass = 1.0
frame = "tool"
[limits]
velocity = 60
acceleration = 200
jerk = 2000
[[waypoint]]
q = [10, -20, -10]
dwell = 0.3
[[waypoint]]
q = [40, -70, 20]
dwell = 0.3
[[waypoint]]
q = [-10, 30, -40]
"""


def zs_units():
    """The invented ZS units alone (the built-in PSA-G units rate no stiffness)."""
    return tuple(u for u in load_catalog([DATA / "invented_stiff_catalog.toml"])
                 if u.series == "ZS")


def planar3_motion(folder: Path) -> Path:
    path = folder / "planar3.toml"
    path.write_text(MOTION.format(robot=(DATA / "planar3.urdf").as_posix()))
    return path


# planar3's geometry as its file states it (tests/data/planar3.urdf): shoulder height,
# link lengths, link masses, their centres from the joint and inertias about y
SHOULDER_Z = 0.30
LENGTH = (0.40, 0.35, 0.15)
LINK_MASS = (1.2, 0.8, 0.4)
CENTRE = (0.20, 0.175, 0.075)
LINK_INERTIA = (0.016, 0.0081667, 0.00075)
PAYLOAD = 1.0  # [kg], a point at the tool frame (the motion's [payload])
G = 9.80665  # [m/s^2]


def oracle_figures(q: np.ndarray, units: tuple, carried: bool = True) -> tuple[float, float]:
    """(largest holding tool translation [m], lowest arm mode [Hz]) over the poses `q`.

    planar3 by hand, every pose at once: the joint origins o_i, link directions u_i at
    the summed angles; each unit a point mass at its joint's origin, carried by the joints
    nearer the base. Holding torque tau_i = g sum over the bodies beyond i of m (x - x_i);
    each joint turns by -phi(tau_i); a turn d about o_i moves a point p by d perp(p - o_i)
    (perp(x, z) = (-z, x): a positive angle raises the arm). Modes: M = sum of m J^T J +
    I j^T j over the bodies, K = diag(K1): the lowest w^2 is 1 / the largest eigenvalue
    of K^-1/2 M K^-1/2.
    """
    n = len(q)
    angle = np.cumsum(q, axis=1)
    direction = np.stack([np.cos(angle), np.sin(angle)], axis=2)  # (n, 3, 2): x, z
    origin = np.zeros((n, 4, 2))
    origin[:, 0, 1] = SHOULDER_Z
    for i in range(3):
        origin[:, i + 1] = origin[:, i] + LENGTH[i] * direction[:, i]
    tool = origin[:, 3]
    # bodies: (mass, inertia, position (n, 2), how many joints move it)
    bodies = [(LINK_MASS[i], LINK_INERTIA[i], origin[:, i] + CENTRE[i] * direction[:, i], i + 1)
              for i in range(3)]
    bodies.append((PAYLOAD, 0.0, tool, 3))
    if carried:  # the units' masses (the shoulder's sits on the fixed base)
        bodies += [(units[k].mass, 0.0, origin[:, k], k) for k in (1, 2)]
    tau = np.zeros((n, 3))
    mass = np.zeros((n, 3, 3))
    for m, inertia, at, moved in bodies:
        jacobian = np.zeros((n, 2, 3))
        for i in range(moved):
            tau[:, i] += G * m * (at[:, 0] - origin[:, i, 0])
            arm = at - origin[:, i]
            jacobian[:, 0, i], jacobian[:, 1, i] = -arm[:, 1], arm[:, 0]
        spin = np.zeros(3)
        spin[:moved] = 1.0
        mass += m * np.einsum("nki,nkj->nij", jacobian, jacobian) + inertia * np.outer(spin, spin)
    turn = -np.stack([torsion(units[i].stiffness, tau[:, i]) for i in range(3)], axis=1)
    moved_tool = np.zeros((n, 2))
    for i in range(3):
        arm = tool - origin[:, i]
        moved_tool += turn[:, [i]] * np.stack([-arm[:, 1], arm[:, 0]], axis=1)
    scale = np.array([1.0 / math.sqrt(unit.stiffness.k1) for unit in units])
    largest = np.linalg.eigvalsh(mass * np.outer(scale, scale))[:, -1]
    lowest = np.sqrt(1.0 / largest) / (2.0 * math.pi)
    return float(np.linalg.norm(moved_tool, axis=1).max()), float(lowest.min())


def brute_force(robot, trajectory, units, options=None):
    """Every combination whose units pass every joint's rules: (ids, mass, deflection, Hz)."""
    carried = options is None or options.mass_coupling
    rows = []
    for combo in itertools.product(units, repeat=len(robot.sized_joints)):
        chosen = dict(zip(robot.sized_joints, combo, strict=True))
        if check_units(robot, trajectory, chosen, options).feasible:
            rows.append((tuple(u.id for u in combo), sum(u.mass for u in combo),
                         *oracle_figures(trajectory.q, combo, carried)))
    return rows


@pytest.fixture(scope="module")
def arm(tmp_path_factory):
    robot, motion = load_case(planar3_motion(tmp_path_factory.mktemp("planar3")))
    trajectory = plan(robot, motion)
    units = zs_units()
    return robot, trajectory, units, brute_force(robot, trajectory, units)


def lightest(table, deflection=None, frequency=None):
    """The brute force's answer: the lightest rows meeting the targets (ties all kept)."""
    meeting = [row for row in table if (deflection is None or row[2] <= deflection)
               and (frequency is None or row[3] >= frequency)]
    if not meeting:
        return []
    least = min(row[1] for row in meeting)
    return [row for row in meeting if row[1] <= least + 1e-9]


def between(values, rank):
    """A limit halfway between the rank-th and the next distinct figure: no tie at the edge."""
    ordered = sorted(set(values))
    return 0.5 * (ordered[rank] + ordered[rank + 1])


def sized(arm, **targets):
    robot, trajectory, units, _ = arm
    return size_trajectory(robot, trajectory, units, Options(**targets))


def chosen(result):
    return tuple(joint.selected.unit.id for joint in result.joints)


def assert_the_lightest(result, table, deflection=None, frequency=None):
    answers = lightest(table, deflection, frequency)
    assert answers, "the brute force finds a choice"
    ids = chosen(result)
    mass = sum(joint.selected.unit.mass for joint in result.joints)
    assert mass == pytest.approx(answers[0][1], abs=1e-9)
    assert ids in [row[0] for row in answers]
    row = next(row for row in answers if row[0] == ids)
    checks = {check.name: check for check in result.precision.targets}
    if deflection is not None:
        check = checks["tool_deflection"]
        assert check.ok and check.shortfall is None and check.limit == deflection
        assert check.value == pytest.approx(row[2], rel=1e-6)
    if frequency is not None:
        check = checks["arm_frequency"]
        assert check.ok and check.shortfall is None and check.limit == frequency
        assert check.value == pytest.approx(row[3], rel=1e-6)


@pytest.mark.parametrize("rank", [0, 3, 9, 16, 25, 34, 41])
def test_a_tool_deflection_target_takes_the_lightest_choice_that_meets_it(arm, rank):
    table = arm[3]
    limit = between([row[2] for row in table], rank)
    assert_the_lightest(sized(arm, max_tool_deflection=limit), table, deflection=limit)


@pytest.mark.parametrize("rank", [1, 6, 13, 22, 31, 40])
def test_an_arm_frequency_target_takes_the_lightest_choice_that_meets_it(arm, rank):
    table = arm[3]
    limit = between([row[3] for row in table], rank)
    assert_the_lightest(sized(arm, min_arm_frequency=limit), table, frequency=limit)


def test_both_targets_together_take_the_lightest_choice_that_meets_both(arm):
    table = arm[3]
    deflection = between([row[2] for row in table], 30)
    frequency = between([row[3] for row in table], 12)
    result = sized(arm, max_tool_deflection=deflection, min_arm_frequency=frequency)
    assert_the_lightest(result, table, deflection, frequency)


def test_the_raises_name_every_changed_unit_and_its_own_added_mass(arm):
    robot, _, units, table = arm
    plain = sized(arm)
    limit = between([row[2] for row in table], 9)
    result = sized(arm, max_tool_deflection=limit)
    mass = {unit.id: unit.mass for unit in units}
    expected = tuple((before.name, before.selected.unit.id, after.selected.unit.id)
                     for before, after in zip(plain.joints, result.joints, strict=True)
                     if before.selected.unit.id != after.selected.unit.id)
    raised = result.precision.raised
    assert expected and tuple((r.joint, r.chosen, r.raised_to) for r in raised) == expected
    for r in raised:
        assert r.reason == "tool deflection"
        assert r.added_mass == pytest.approx(mass[r.raised_to] - mass[r.chosen])
    # the units carried are the raised ones: every joint's figures as check_units gives them
    again = check_units(robot, arm[1], {j.name: j.selected.unit for j in result.joints})
    for joint, checked in zip(result.joints, again.joints, strict=True):
        assert joint.carried_mass == pytest.approx(checked.carried_mass)
        assert joint.load.peak_torque == pytest.approx(checked.load.peak_torque)


def test_a_target_the_per_joint_choice_meets_raises_nothing(arm):
    table = arm[3]
    plain = sized(arm)
    own = next(row for row in table if row[0] == chosen(plain))
    result = sized(arm, max_tool_deflection=own[2] * 1.01, min_arm_frequency=own[3] * 0.99)
    assert chosen(result) == chosen(plain) and result.precision.raised == ()
    assert all(check.ok for check in result.precision.targets)


@pytest.mark.parametrize(("target", "column", "words"), [
    ("max_tool_deflection", 2, "best reached {best:.3g} mm against {limit:.3g} mm"),
    ("min_arm_frequency", 3, "best reached {best:.3g} Hz against {limit:.3g} Hz")])
def test_a_target_no_choice_meets_states_the_best_reached(arm, target, column, words):
    table = arm[3]
    values = [row[column] for row in table]
    best = min(values) if column == 2 else max(values)
    limit = best * (0.8 if column == 2 else 1.2)
    result = sized(arm, **{target: limit})
    (check,) = result.precision.targets
    assert not check.ok and check.limit == limit
    assert check.value == pytest.approx(best, rel=1e-6)  # the brute force's best
    scale = 1e3 if column == 2 else 1.0
    assert check.shortfall.startswith("cannot be met by this catalog: ")
    assert words.format(best=best * scale, limit=limit * scale) in check.shortfall
    assert result.precision.raised  # the units that reach it
    assert result.feasible


def test_given_units_are_judged_and_never_raised(arm):
    robot, trajectory, units, table = arm
    row = next(row for row in table if row[0] == ("ZS-17-100", "ZS-14-100", "ZS-11-100"))
    given = dict(zip(robot.sized_joints, (next(u for u in units if u.id == i) for i in row[0]),
                     strict=True))
    result = check_units(robot, trajectory, given, Options(max_tool_deflection=row[2] / 2))
    (check,) = result.precision.targets
    assert not check.ok and check.value == pytest.approx(row[2], rel=1e-6)
    assert check.shortfall.startswith("not met by the units given")
    assert result.precision.raised == ()


def test_a_target_on_units_that_rate_no_stiffness_is_not_judged(tmp_path):
    # the built-in PSA-G units rate no K1: the figure is unknown, never a number
    motion = planar2_motion(tmp_path / "m.toml", (0, 0, 0.5), (30, -20, 0.5), payload=0.2,
                            frame="tool")
    result = size(None, motion, max_tool_deflection=1e-3)
    assert result.feasible and result.precision.raised == ()
    (check,) = result.precision.targets
    assert check.value is None and not check.ok
    assert check.shortfall == ("cannot be judged: no unit that fits joints 'shoulder', "
                               "'elbow' rates K1")


def test_units_without_stiffness_are_raised_to_rated_ones_first(tmp_path):
    # PSA-G and ZS together: the per-joint choice takes PSA-G units (no K1); the target
    # raises each to a ZS unit, and then as far as it needs
    motion = planar2_motion(tmp_path / "m.toml", (0, 0, 0.5), (30, -20, 0.5), payload=0.2,
                            frame="tool")
    units = load_catalog([DATA / "invented_stiff_catalog.toml"])
    plain = size(None, motion, catalog=units)
    assert all(joint.selected.unit.series == "PSA" for joint in plain.joints)
    zs = [u for u in units if u.series == "ZS"]
    loose = size(None, motion, catalog=zs)
    limit = 0.9 * loose.precision.tool.max_holding
    result = size(None, motion, catalog=units, max_tool_deflection=limit)
    assert all(joint.selected.unit.series == "ZS" for joint in result.joints)
    assert [r.joint for r in result.precision.raised] == ["shoulder", "elbow"]
    (check,) = result.precision.targets
    assert check.ok and check.value <= limit
    assert check.value == pytest.approx(result.precision.tool.max_holding)
    # the same search on the ZS units alone reaches the same units
    again = size(None, motion, catalog=zs, max_tool_deflection=limit)
    assert chosen(again) == chosen(result)


def test_a_joint_without_a_unit_leaves_the_targets_unraised(tmp_path):
    # the built-in PSA-G units cannot hold planar3's shoulder: nothing is raised, and
    # the target says why
    result = size(None, planar3_motion(tmp_path), max_tool_deflection=1e-3,
                  min_arm_frequency=10.0)
    assert not result.feasible and result.precision.raised == ()
    for check in result.precision.targets:
        assert not check.ok and check.value is None
        assert check.shortfall == "not raised: no unit fits joint 'shoulder' by its own rules"


def test_the_same_problem_gives_the_same_raises(arm):
    table = arm[3]
    limit = between([row[3] for row in table], 22)
    first, again = (sized(arm, min_arm_frequency=limit) for _ in range(2))
    assert first.precision.raised == again.precision.raised
    assert first.precision.targets == again.precision.targets


def test_without_mass_coupling_the_raise_is_the_lightest_choice_too(arm):
    # no unit loads another: the search runs on the full samples (no coarse guess)
    robot, trajectory, units, _ = arm
    options = Options(mass_coupling=False)
    table = brute_force(robot, trajectory, units, options)
    for rank in (5, 20):
        limit = between([row[2] for row in table], rank)
        result = size_trajectory(robot, trajectory, units,
                                 Options(mass_coupling=False, max_tool_deflection=limit))
        assert_the_lightest(result, table, deflection=limit)


def test_stiffened_raises_from_a_selection_that_kept_only_the_chosen_units(arm):
    # a study's front end selects with detail=False and calls `stiffened` itself
    robot, trajectory, units, table = arm
    limit = between([row[2] for row in table], 16)
    options = Options(max_tool_deflection=limit, prefer="size")
    tasks = (Task(robot, trajectory),)
    samples = pooled(tasks)
    model = DirectTorques(tasks, samples, options.stop_time)
    per_joint = dict.fromkeys(robot.sized_joints, units)
    joints, masses = select_units(model, per_joint, options, {}, detail=False)
    found = stiffened(model, per_joint, joints, masses, options, {}, select=select_units)
    ids = tuple(joint.selected.unit.id for joint in found.joints)
    assert ids in [row[0] for row in lightest(table, deflection=limit)]
    assert found.masses == {joint.name: joint.selected.unit.mass for joint in found.joints}
    assert found.precision.targets[0].ok and found.precision.raised
