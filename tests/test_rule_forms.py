"""Every rule's payload and path forms against the rule's own forward check, and the fallbacks.

Oracle: `check_unit` (the forward check every sizing runs) on the cycle itself, never
the form under test. Payload form (`Rule.payload_masses`): on seeded random joints
whose torques are affine in the payload mass, masses inside the form's intervals pass
the forward check and masses outside fail (away from the ends by 1e-7). Path form
(`Rule.path_rows`): on a random path piece and a random profile, the rows the path
solver builds from the form (`pathbounds.meets`, the emergency-stop bound, the speed cap)
never pass a profile whose samples fail the forward check; where the form is exact, they
pass every profile that passes. A rule without either form, registered for the test
only, still bounds `max_payload` and `fastest` (checked by `size` around the answer and
by the index table's textbook bang-bang time).
"""

from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motor_rules import with_motor
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    RPM_PER_RAD_S,
    RULES,
    Check,
    Part,
    Rule,
    RuleInput,
    Scope,
    check_unit,
    cycle_load,
    registered,
    rule,
)
from hdselect.catalog.rules.forms import PathCase, PayloadCase
from hdselect.catalog.stiffness import torsion
from hdselect.codesign.cyclerules import after_solve
from hdselect.codesign.fastest_cycle import fastest
from hdselect.codesign.maxpayload import max_payload
from hdselect.codesign.pathbounds import bounded, joint_limits, meets, stop_bound
from hdselect.codesign.payloadbounds import forward_check, joint_mean
from hdselect.codesign.payloadsizing import scaled
from hdselect.motion.loading import load_case
from hdselect.sizing.core import size
from hdselect.sizing.options import Options
from hdselect.sizing.reflect import reflect
from helpers import REPO
from helpers.codesign import index_table, mean_speed_allowing_peak
from helpers.motions import whole_cycle
from helpers.rules import giving

CATALOG = load_catalog()
STIFF = next(u for u in load_catalog(["shg-2uh"]) if u.id == "SHG-17-100-2UH").stiffness
"""A stiffness every random case's unit is given, for the precision targets' rules."""
CASES = 40
EXACT_PATH = ("peak", "static", "speed", "motor_speed", "torsion")
"""Path forms that are the rule itself at the gridpoints; the others (the emergency stop's
first crossing, the motor's flat peak at both efficiencies) are stricter than the rule."""


def _payload_case(rng: np.random.Generator) -> PayloadCase:
    """A random joint of 5 to 80 samples on a random catalog unit, torques affine in mass.

    Half the units get a limit on the average input speed, and half of those the series
    rule that averages it over the whole cycle (the built-in catalog has neither).
    """
    unit = CATALOG[int(rng.integers(len(CATALOG)))]
    if rng.random() < 0.5:
        rules = replace(unit.rules, mean_speed="whole-cycle") if rng.random() < 0.5 \
            else unit.rules
        unit = replace(unit, rules=rules,
                       max_average_input_speed=float(rng.uniform(0.02, 0.4)
                                                     * unit.max_input_speed))
    n = int(rng.integers(5, 80))
    rest = rng.random(n) < 0.25
    top = unit.max_input_speed / unit.ratio / RPM_PER_RAD_S  # [rad/s]
    qd = rng.normal(0.0, 1.0, n) * top * rng.uniform(0.1, 0.7) * ~rest
    dt = rng.uniform(0.002, 0.02, n)
    peak = unit.repeated_torque
    tau0 = rng.normal(0.0, 0.4, n) * peak
    tau1 = rng.normal(0.0, 0.05, n) * peak * (rng.random(n) < 0.9)
    stop0 = tau0 + rng.normal(0.0, 0.2, n) * peak
    stop1 = tau1 * rng.uniform(0.5, 1.5, n)
    life = (None, 2000.0, 20000.0)[int(rng.integers(3))]
    unit = replace(unit, stiffness=STIFF)  # the precision targets need one
    assert STIFF is not None and STIFF.k1 is not None
    inertia0, inertia1 = rng.uniform(0.05, 0.5, 8), rng.uniform(0.0, 0.02, 8)  # M_jj, per kg
    case = PayloadCase(unit, dt, rest, qd, tau0, tau1, stop0, stop1,
                       margin=float(rng.choice([0.0, 0.1, 0.3])),
                       stop_time=float(rng.uniform(0.05, 0.5)),
                       rotor_inertia=float(rng.uniform(0.0, 1e-5)),
                       idle=float(rng.uniform(0.0, 1.0) * dt.sum() * (rng.random() < 0.5)),
                       life_hours=life, life_basis="L10" if rng.random() < 0.5 else "L50",
                       efficiency=0.7, qdd=rng.normal(0.0, 10.0, n),
                       max_torsion=float(torsion(STIFF, peak * rng.uniform(0.2, 1.2))),
                       min_frequency=math.sqrt(STIFF.k1 / float(np.max(
                           inertia0 + rng.uniform(0.0, 40.0) * inertia1))) / (2 * math.pi),
                       inertia0=inertia0, inertia1=inertia1)
    return replace(case, mean=joint_mean(dt, rest, qd, tau0, tau1))


def _holds(case: PayloadCase, name: str, mass: float) -> bool:
    check = forward_check(case, mass).checks.get(name)
    return check is None or check.ok  # absent: it bounds nothing


@pytest.mark.parametrize("name", giving("payload_masses"))
def test_payload_form_agrees_with_the_forward_check(name: str) -> None:
    tested = rule(name)
    rng = np.random.default_rng(sum(map(ord, name)))
    seen = set()
    for _ in range(CASES):
        case = _payload_case(rng)
        found = tested.payload_masses(case)
        assert found is not None, f"{name} defines the form: it must give it"
        ends = [end for span in found for end in span if math.isfinite(end)]
        probes = [*rng.uniform(0.0, 60.0, 12),
                  *(end * (1.0 + k * 1e-5) + k * 1e-9 for end in ends for k in (-1, 1))]
        for mass in probes:
            if mass < 0.0 or any(abs(mass - end) <= 1e-7 * max(1.0, abs(end)) for end in ends):
                continue
            inside = any(lo <= mass <= hi for lo, hi in found)
            assert _holds(case, name, mass) is inside, (name, case.unit.id, mass, found)
            seen.add(inside)
    assert seen == {True, False}, f"{name}: every probe {'passed' if True in seen else 'failed'}"


def _path_case(rng: np.random.Generator):
    """A random unit (and motor), path piece and profile, as `pathbounds.meets` reads them."""
    unit = replace(CATALOG[int(rng.integers(len(CATALOG)))], stiffness=STIFF)
    motor = None
    if rng.random() < 0.5:
        rated = unit.repeated_torque / unit.ratio * rng.uniform(0.2, 1.0)
        motor = Motor("M", rated, rated * rng.uniform(1.0, 3.0), unit.max_input_speed
                      * rng.uniform(0.5, 1.5), 1000.0, float(rng.uniform(1e-8, 1e-5)), 0.5)
    rotor = motor.rotor_inertia if motor is not None else float(rng.uniform(0.0, 1e-5))
    m, still = 30, bool(rng.random() < 0.25)
    peak = unit.repeated_torque * rng.uniform(0.1, 1.5)
    assert STIFF is not None
    case = PathCase(unit, float(rng.choice([0.0, 0.2])), float(rng.uniform(0.05, 0.5)),
                    0.7, rotor, motor,
                    max_torsion=float(torsion(STIFF, peak * rng.uniform(0.5, 4.0))))
    dq = np.zeros((m, 1)) if still else rng.normal(0.0, 1.0, (m, 1))
    ddq = np.zeros((m, 1)) if still else rng.normal(0.0, 1.0, (m, 1))
    top = unit.max_input_speed / unit.ratio / RPM_PER_RAD_S / max(np.abs(dq).max(), 1.0)
    sd = rng.uniform(0.0, 1.0, m) * top * rng.uniform(0.05, 1.3)
    a = rng.normal(0.0, 0.3, (m, 1)) * peak
    b = rng.normal(0.0, 0.3, (m, 1)) * peak / max(top, 1e-9) ** 2
    c = rng.normal(0.0, 0.4, (m, 1)) * peak
    v = rng.normal(0.0, 0.2, (m, 1)) * peak / max(top, 1e-9) ** 2
    piece = SimpleNamespace(dq=dq, ddq=ddq)
    profile = SimpleNamespace(sd=sd, sdd=rng.normal(0.0, 1.0, m - 1) * top**2
                              * rng.uniform(0.001, 1.0))
    return case, piece, profile, (a, b, c, v), still


def _samples_pass(case: PathCase, name: str, piece, profile, coefficients, still) -> bool | None:
    """The forward check on the samples TOPPRA's rows are imposed at; None: rule absent.

    Each step's path acceleration at the gridpoint it leaves and at the one it reaches
    (as `meets`); the emergency stop from each of them.
    """
    a, b, c, v = (x[:, 0] for x in coefficients)
    m = len(profile.sd)
    at = np.r_[np.arange(m - 1), np.arange(1, m)]
    u = np.r_[profile.sdd, profile.sdd]
    speed = profile.sd[at]
    x = speed**2
    tau = a[at] * u + b[at] * x + c[at]
    qd = piece.dq[at, 0] * speed
    qdd = piece.dq[at, 0] * u + piece.ddq[at, 0] * x
    stop = c[at] + v[at] * x - a[at] * speed / case.stop_time
    rest = np.full(len(at), still)
    unit = case.unit
    (reflection,) = reflect([unit], np.arange(len(at)) * 0.01, tau, qd, qdd, stop,
                            stop_time=case.stop_time, efficiency=case.efficiency,
                            rotor_inertia=case.rotor_inertia, rest=rest)
    checked = check_unit(cycle_load(tau, qd, 0.01, rest), unit, momentary=reflection.momentary,
                         motor=reflection.motor, margin=case.margin,
                         max_torsion=case.max_torsion)
    if case.motor is not None:
        checked = with_motor(checked, case.motor, reflection.motor_torque,
                             np.abs(qd) * unit.ratio * RPM_PER_RAD_S)
    found = checked.checks.get(name)
    return None if found is None else found.ok


@pytest.mark.parametrize("name", giving("path_rows"))
def test_path_form_is_never_weaker_than_the_forward_check(name: str) -> None:
    tested = rule(name)
    rng = np.random.default_rng(1000 + sum(map(ord, name)))
    seen = set()
    for _ in range(CASES):
        case, piece, profile, coefficients, still = _path_case(rng)
        bounds = tested.path_rows(case)
        assert bounds is not None, f"{name} defines the form: it must give it"
        forward = _samples_pass(case, name, piece, profile, coefficients, still)
        if not bounds:  # no bound for this case: the rule is absent for it
            assert forward is None, name
            continue
        (lim,) = [bounded([(math.inf, "motion")], math.inf, math.inf, bounds)]
        stops = ({0: stop_bound(coefficients, 0, lim.momentary, case.stop_time)}
                 if math.isfinite(lim.momentary) else {})
        rows = (meets(profile, piece, [lim], coefficients, stops)
                and bool(np.all(np.abs(piece.dq[:, 0]) * profile.sd <= lim.velocity)))
        assert forward is not None, name
        assert forward or not rows, (name, case.unit.id)  # the rows never pass a failure
        if name in EXACT_PATH:
            assert rows is forward, (name, case.unit.id)
        seen.add((rows, forward))
    assert {rows for rows, _ in seen} == {True, False}, f"{name}: the rows never bind"


def test_every_rule_on_single_samples_is_held_on_the_path_or_after_it() -> None:
    """Each per-sample rule gives the path solver a form or is checked after the solve."""
    robot, motion = load_case(REPO / "trajectories" / "planar2_pick_place.toml")
    unit, options = CATALOG[0], Options()
    limits = joint_limits(robot, motion, dict.fromkeys(robot.sized_joints, unit), options)
    case = PathCase(unit, options.margin, options.stop_time, options.efficiency,
                    options.rotor_inertia)
    for lim in limits:
        for found in RULES:
            formed = found.path_rows(case) is not None
            assert (found.name in after_solve(lim)) is (not formed and found.scope is Scope.SAMPLE
                                                        or found.scope is Scope.CYCLE
                                                        and found.part is Part.GEARHEAD)


class HalfPeak(Rule):
    """A test rule without forms: the peak torque at most half the repeated peak."""

    name = "half_peak"
    label = "half"
    words = "half the repeated peak"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE

    def check(self, case: RuleInput) -> Check | None:
        if case.gear is None:
            return None
        unit, load = case.gear
        return self.judge(load.peak_torque, 0.5 * unit.repeated_torque, case.margin)


@pytest.fixture
def half_peak():
    with registered(HalfPeak()) as found:
        yield found


def test_a_rule_without_forms_bounds_max_payload(half_peak) -> None:
    """max-payload stops where the registered rule does: size passes 1 % below, fails above."""
    robot, motion = load_case(REPO / "trajectories" / "planar2_pick_place.toml")
    result = max_payload(robot, motion)
    assert result.mass is not None and math.isfinite(result.mass)
    assert result.rule == "half_peak"
    part = result.payload  # what scales: the part the events move (`payload=` is the gripper)
    assert part is not None and part.name == "part"

    def carrying(mass: float):
        return replace(motion, parts={**motion.parts, part.name: scaled(part, mass)})
    below, above = (size(robot, carrying(f * result.mass)) for f in (0.99, 1.01))
    assert below.feasible and not above.feasible
    (stuck,) = [joint for joint in above.joints if joint.selected is None]
    assert stuck.name == result.joint
    (at_limit,) = [c for c in stuck.candidates if c.unit.id == result.unit.id]
    assert not at_limit.checks["half_peak"].ok
    assert all(joint.selected.checks["half_peak"].ok for joint in below.joints)


def test_a_rule_without_forms_bounds_fastest(tmp_path, half_peak) -> None:
    """The index table's bang-bang move at half the repeated peak: t = 2 sqrt(theta J / (T/2)).

    The rule has no path form: TOPPRA runs the table at the full peak, and the derating
    after the solve brings it to half (`after_solve`).
    """
    unit = CATALOG[len(CATALOG) // 2]
    torque = 0.5 * unit.repeated_torque
    theta = 0.5 * mean_speed_allowing_peak(unit)  # a 1 s move, the mean torque far from binding
    inertia = torque / (4.0 * theta)
    robot, motion = index_table(tmp_path, inertia, theta)
    result = fastest(robot, motion, {"table": unit}, Options(stop_time=10.0))
    expected = 2.0 * math.sqrt(theta * inertia / torque)
    assert result.feasible
    assert result.cycle_time == pytest.approx(expected, rel=3e-3)
    assert result.cycle_time >= expected * (1.0 - 1e-4)
    (joint,) = result.check.joints
    check = joint.selected.checks["half_peak"]
    assert check.ok and check.utilization > 0.99
    assert result.reason is not None and result.reason[1] == "half_peak"


def test_a_rated_bearing_bounds_each_units_payload_masses(tmp_path) -> None:
    """The bearing's rules give no payload form: the forward fallback bounds each unit.

    Oracle: max-payload's answer, the sizing itself bisected (`PayloadSizing.largest`):
    the unit whose bearing binds there allows masses up to that mass, to its bisection's
    accuracy, and its bearing's moment is the rule that ends there.
    """
    from helpers.bearings import BEARING_BOUND, PICK

    (tmp_path / "xb.toml").write_text(BEARING_BOUND)
    units = [u for u in load_catalog([tmp_path / "xb.toml"]) if u.series == "XB"]
    robot, motion = load_case(PICK)
    found = max_payload(robot, motion, catalog=units)
    assert found.rule == "bearing_moment" and found.mass is not None
    bound = next(b for b in found.bounds[found.joint] if b.unit.id == found.unit.id)
    assert bound.ends["bearing_moment"] is not None
    assert bound.masses is not None and bound.masses[1] == pytest.approx(found.mass, rel=1e-5)
    assert bound.limiting(found.mass) == "bearing_moment"


class Never(Rule):
    """A test rule without forms that no cycle passes: twice its limit, always."""

    name = "never"
    label = "never"
    words = "never passes"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE

    def check(self, case: RuleInput) -> Check | None:
        return None if case.gear is None else self.judge(2.0, 1.0, case.margin)


def test_a_rule_without_forms_that_fails_at_every_mass_leaves_no_payload(tmp_path) -> None:
    """Through the fallback, no unit has a mass at which it passes: no payload, not a guess.

    Gripper and part lumped into one 0.4 kg payload carried the whole cycle (the file
    before payload events): every sample's torque then moves with the mass scaled, so no
    formed rule fails at every mass first and every unit's bound reaches the fallback.
    """
    robot, motion = load_case(whole_cycle(REPO / "trajectories" / "planar2_pick_place.toml",
                                          tmp_path))
    (part,) = robot.parts  # at the gripper's frame and centre of mass, no inertia
    assert robot.payload is not None and part.com == robot.payload.com and not motion.events
    robot = robot.with_parts(()).with_payload(replace(robot.payload,
                                                      mass=robot.payload.mass + part.mass))
    with registered(Never()):
        result = max_payload(robot, motion, catalog=CATALOG[:2])
    assert result.mass is None and result.ranges == ()
    assert all(bound.masses is None and bound.ends["never"] is None
               for per_unit in result.bounds.values() for bound in per_unit)
