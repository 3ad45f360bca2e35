"""The rule registry: every rule's solver forms against its own forward check, and a new rule.

Each registered rule (`hdselect.catalog.rules.RULES`) may give forms to the solvers; each
form is checked here, on seeded random cases, against the rule's forward check as the
sizing applies it (`check_at` on the scaled cycle, `reflect` + `check_unit` on the
samples). The tests are parametrised over the registry, so a form a rule gains later is
tested by them. Every random case carries a joint's precision targets (a largest twist,
a lowest natural frequency and the load inertia it reads), which the rules without them
ignore. A rule registered by a test (`Windup`, a rough kind of issue 30's torsion) shows
what one new file brings: its check in every table, result, JSON and report column, and
the time-scale solver honouring it with no form, through the forward check.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console

from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.motors import Motor
from hdselect.catalog.rules import (
    BEARING_CHECKS,
    CHECK_LABELS,
    CHECK_NAMES,
    CHECKS,
    MOTOR_CHECKS,
    PAIR_CHECKS,
    PER_SAMPLE_CHECKS,
    RULES,
    Check,
    Part,
    PayloadCase,
    Rule,
    RuleInput,
    Scope,
    UnitBatch,
    check_unit,
    cycle_load,
    registered,
    rule,
    rules_of,
)
from hdselect.catalog.stiffness import natural_frequency, torsion
from hdselect.catalog.units import Unit
from hdselect.codesign.payloadbounds import joint_mean
from hdselect.sizing.reflect import reflect
from hdselect.sizing.timescale import RTOL, ScalableCycle, check_at, exact_scales, feasible_scales
from helpers.rules import giving

REPO = Path(__file__).resolve().parents[1]
INDEX = REPO / "trajectories" / "index_table_indexing.toml"
RPM = 60 / (2 * math.pi)  # rpm per rad/s
UNITS = load_catalog(["shg-2uh"])  # PSA-G rates no stiffness, SHG-2UH does
SHIPPED = tuple(CHECKS)  # the registry as shipped
STOP_TIME = 0.05


# --- random cases ------------------------------------------------------------------------------

def random_unit(rng: np.random.Generator) -> Unit:
    return UNITS[int(rng.integers(len(UNITS)))]


def random_targets(rng: np.random.Generator, unit: Unit) -> dict[str, float]:
    """A joint's precision targets near what the unit reaches: the twist at a torque near
    its repeated peak [rad], and the frequency under a load inertia [Hz] (of a SHG-17-100
    where the unit rates no K1)."""
    stiffness = unit.stiffness if unit.stiffness is not None and unit.stiffness.k1 else \
        next(u for u in UNITS if u.id == "SHG-17-100-2UH").stiffness
    assert stiffness is not None and stiffness.k1 is not None
    inertia = float(rng.uniform(0.01, 1.0))
    return {"max_torsion": float(torsion(stiffness, unit.repeated_torque
                                         * rng.uniform(0.2, 1.5))),
            "min_frequency": float(natural_frequency(stiffness.k1, inertia))
            * float(rng.uniform(0.7, 1.3)),
            "load_inertia": inertia}


def random_motor(rng: np.random.Generator, unit: Unit) -> Motor:
    """A motor of the unit's scale: its limits near what the unit's limits ask of it."""
    torque = unit.repeated_torque / unit.ratio
    rated = torque * rng.uniform(0.2, 1.0)
    return Motor("random", rated_torque=rated, peak_torque=rated * rng.uniform(1.0, 3.0),
                 max_speed=unit.max_input_speed * rng.uniform(0.5, 1.5), rated_speed=1.0,
                 rotor_inertia=unit.input_inertia * rng.uniform(0.5, 5.0), mass=0.5)


def random_samples(rng: np.random.Generator, unit: Unit, n: int) -> dict[str, np.ndarray]:
    """Speeds near the unit's largest at s = 1, some samples at rest, torques near its limits."""
    rest = rng.random(n) < 0.2
    top = unit.max_input_speed / unit.ratio / RPM  # rad/s at the output
    qd = np.where(rest, 0.0, rng.uniform(-1.0, 1.0, n) * top * rng.uniform(0.3, 1.5))
    qdd = np.where(rest, 0.0, rng.uniform(-1.0, 1.0, n) * 50.0)
    scale = unit.repeated_torque * rng.uniform(0.3, 1.5)
    return {"rest": rest, "qd": qd, "qdd": qdd,
            **{key: rng.uniform(-1.0, 1.0, n) * scale * factor
               for key, factor in (("g", 0.5), ("v", 0.5), ("i", 1.0), ("e", 1.0))}}


def random_cycle(rng: np.random.Generator, unit: Unit, n: int = 60) -> ScalableCycle:
    x = random_samples(rng, unit, n)
    dt = 0.01
    return ScalableCycle(t=np.arange(n) * dt, dt=dt, duration=n * dt, qd=x["qd"], qdd=x["qdd"],
                         at_rest=x["rest"], gravity=x["g"], velocity=x["v"], inertial=x["i"],
                         stop_inertial=x["e"], stop_time=STOP_TIME)


# --- every form against the forward check ------------------------------------------------------

@pytest.mark.parametrize("name", giving("scale_rows"))
def test_time_scale_form_is_the_forward_check(name):
    """Where a rule gives rows in y = 1/s, they hold exactly where its check on the cycle
    run s times slower holds (`check_at`, as the sizing judges it), with and without a
    motor and a design margin; points within rounding of a boundary are left out."""
    found = rule(name)
    rng = np.random.default_rng(280 + SHIPPED.index(name))
    verdicts = []
    for case in range(24):
        unit = random_unit(rng)
        motor = random_motor(rng, unit) if case % 2 else None
        rotor = motor.rotor_inertia if motor else float(rng.uniform(0.0, 5.0)) * unit.input_inertia
        margin = (0.0, 0.2)[case % 4 // 2]
        cycle = random_cycle(rng, unit)
        targets = random_targets(rng, unit)
        terms = cycle.terms(rotor_inertia=rotor, motor=motor, targets=targets)
        rows = found.scale_rows(terms, unit, margin)
        assert rows is not None, f"{name} defines the form: it must give it"
        for s in np.geomspace(0.1, 10.0, 25):
            y = 1.0 / s
            values = [c2 * y * y + c1 * y + c0 for c2, c1, c0 in rows]
            slack = max((float(v.max()) for v in values if v.size), default=-math.inf)
            size = max((float(np.max(np.abs(c2) * y * y + np.abs(c1) * y + np.abs(c0)))
                        for c2, c1, c0 in rows if c0.size), default=0.0)
            if abs(slack) <= 1e-9 * size:
                continue  # on a boundary: either verdict is rounding
            pair = check_at(cycle, unit, float(s), rotor_inertia=rotor, motor=motor,
                            check_options={"margin": margin, **targets})
            check = pair.checks.get(name)
            ok = True if check is None else check.ok  # absent: rows must hold everywhere
            assert (slack <= 0.0) == ok, (case, s, slack, check)
            verdicts.append(ok)
    assert True in verdicts and False in verdicts, "the cases must cross the rule's limit"


@pytest.mark.parametrize("motor", [False, True], ids=["rotor inertia given", "pairs"])
@pytest.mark.parametrize("name", giving("prefilter"))
def test_prefilter_is_the_forward_check(name, motor):
    """A prefilter gives each unit's utilization of the rule exactly, so it rejects only
    units that fail the forward check (`reflect` + `check_unit`), and passes every one
    that holds; without a known rotor inertia (pairs) a rule that needs it gives none."""
    found = rule(name)
    rng = np.random.default_rng(2800 + SHIPPED.index(name))
    verdicts = []
    for _ in range(8):
        units = tuple(UNITS[k] for k in rng.permutation(len(UNITS)))
        x = random_samples(rng, units[0], 80)
        t, dt = np.arange(80) * 0.01, 0.01
        tau, stop = x["g"] + x["i"], x["g"] + x["e"]
        load = cycle_load(tau, x["qd"], dt, x["rest"])
        rotor = float(rng.uniform(0.0, 5.0)) * units[0].input_inertia
        margin = float(rng.choice([0.0, 0.2]))
        targets = random_targets(rng, units[0])
        batch = UnitBatch(units, load, t, tau, stop, x["qd"], STOP_TIME,
                          None if motor else rotor, **targets)
        utilization = found.prefilter(batch)
        if utilization is None:
            continue
        passes = found.passes(utilization, margin)
        for k, r in enumerate(reflect(units, t, tau, x["qd"], x["qdd"], stop,
                                      stop_time=STOP_TIME, rotor_inertia=rotor,
                                      rest=x["rest"])):
            check = check_unit(load, units[k], momentary=r.momentary, margin=margin,
                               **targets).checks[name]
            assert utilization[k] == pytest.approx(check.utilization, rel=1e-12, abs=1e-300)
            assert passes[k] == check.ok
            verdicts.append(check.ok)
    if not verdicts:
        pytest.skip(f"{name} gives no prefilter here: the forward check decides")
    assert True in verdicts and False in verdicts, "the cases must cross the rule's limit"


@pytest.mark.parametrize("name", giving("payload_masses"))
def test_payload_form_is_the_forward_check(name):
    """Where a rule gives the payload masses at which it holds (torques affine in the mass
    x), each mass is inside them exactly where the rule holds on the samples at that mass
    (`reflect` + `check_unit`); masses within rounding of an end are left out."""
    found = rule(name)
    rng = np.random.default_rng(28000 + SHIPPED.index(name))
    verdicts = []
    for case in range(8):
        unit = random_unit(rng)
        if case % 2:  # the built-in catalog limits no unit's average input speed
            unit = dataclasses.replace(unit, max_average_input_speed=unit.max_input_speed
                                       * float(rng.uniform(0.05, 0.5)))
        n = 60
        x = random_samples(rng, unit, n)
        t, dt = np.arange(n) * 0.01, np.full(n, 0.01)
        tau0, stop0 = 0.3 * (x["g"] + x["i"]), 0.3 * (x["g"] + x["e"])
        tau1 = rng.uniform(-1.0, 1.0, n) * unit.repeated_torque / 20.0  # per kg
        stop1 = rng.uniform(-1.0, 1.0, n) * unit.repeated_torque / 20.0
        rotor = float(rng.uniform(0.0, 5.0)) * unit.input_inertia
        margin = (0.0, 0.2)[case % 2]
        life = (None, 5000.0)[case % 4 // 2]
        targets = random_targets(rng, unit)
        inertia0 = rng.uniform(0.2, 1.0, 12) * targets["load_inertia"]  # M_jj of 12 poses
        inertia1 = rng.uniform(0.0, 0.1, 12) * targets["load_inertia"]  # per kg
        k1 = unit.stiffness.k1 if unit.stiffness is not None and unit.stiffness.k1 else 1e4
        frequency = math.sqrt(k1 / float(np.max(inertia0 + rng.uniform(5.0, 30.0)
                                                * inertia1))) / (2 * math.pi)
        masses = found.payload_masses(PayloadCase(
            unit, dt, x["rest"], x["qd"], tau0, tau1, stop0, stop1, margin, STOP_TIME, rotor,
            life_hours=life, mean=joint_mean(dt, x["rest"], x["qd"], tau0, tau1),
            max_torsion=targets["max_torsion"], min_frequency=frequency, inertia0=inertia0,
            inertia1=inertia1))
        assert masses is not None, f"{name} defines the form: it must give it"
        for mass in np.linspace(0.0, 40.0, 41):
            if any(abs(mass - end) <= 1e-9 * max(1.0, abs(end))
                   for span in masses for end in span if math.isfinite(end)):
                continue
            tau, stop = tau0 + mass * tau1, stop0 + mass * stop1
            (r,) = reflect([unit], t, tau, x["qd"], x["qdd"], stop, stop_time=STOP_TIME,
                           rotor_inertia=rotor, rest=x["rest"])
            check = check_unit(cycle_load(tau, x["qd"], dt, x["rest"]), unit,
                               momentary=r.momentary, life_hours=life, margin=margin,
                               max_torsion=targets["max_torsion"], min_frequency=frequency,
                               load_inertia=float(np.max(inertia0 + mass * inertia1))
                               ).checks.get(name)
            ok = True if check is None else check.ok
            assert any(lo <= mass <= hi for lo, hi in masses) == ok, (case, mass, check)
            verdicts.append(ok)
    assert True in verdicts and False in verdicts, "the cases must cross the rule's limit"


def test_every_rule_has_one_name_and_the_tables_follow_the_registry():
    names = [found.name for found in RULES]
    assert len(set(names)) == len(names) == len(CHECKS) and tuple(CHECKS) == tuple(names)
    assert all(rule(name).name == name for name in names)
    assert dict(CHECK_LABELS) == {found.name: found.label for found in RULES}
    assert dict(CHECK_NAMES) == {found.name: found.words for found in RULES}
    parts = [found.part for found in RULES]
    assert parts == sorted(parts, key=list(Part).index), "results list the parts in order"
    assert set(PER_SAMPLE_CHECKS) == {"peak", "speed", "momentary", "static", "torsion",
                                      "natural_frequency", "motor_peak", "motor_speed",
                                      "inertia_ratio", "bearing_moment", "bearing_radial",
                                      "bearing_axial"}
    assert [found.name for found in RULES if not found.margin_applies] == [
        "torsion", "natural_frequency", "inertia_ratio"]  # design targets, not ratings
    with pytest.raises(KeyError, match="no rule 'twist'"):
        rule("twist")


# --- a rule added in one file -----------------------------------------------------------------

PHI_MAX = 1e-3
"""The largest wind-up the test's rule allows [rad]."""


def stiffness(unit: Unit) -> float:
    """The test's torsional stiffness K1 of a unit [N m/rad]: 100 rad^-1 x its rated torque."""
    return 100.0 * unit.rated_torque


class Windup(Rule):
    """|T_peak| / K1 <= phi_max: the gear's wind-up at its peak torque (issue 30's kind)."""

    name = "windup"
    label = "windup"
    words = "torsional wind-up"
    part = Part.GEARHEAD
    scope = Scope.SAMPLE
    unit = "rad"

    def check(self, case: RuleInput) -> Check | None:
        if (gear := case.gear) is None:
            return None
        unit, load = gear
        return self.judge(load.peak_torque / stiffness(unit), PHI_MAX, case.margin)


@pytest.fixture
def windup():
    """The registry with `Windup` in it for one test, as shipped again after it."""
    with registered(Windup()) as added:
        yield added


def test_a_registered_rule_is_in_every_table(windup):
    gearhead = len(rules_of(Part.GEARHEAD)) - 1  # after the last of its part's
    assert tuple(CHECKS) == (*SHIPPED[:gearhead], "windup", *SHIPPED[gearhead:])
    assert CHECK_LABELS["windup"] == "windup" and CHECK_NAMES["windup"] == "torsional wind-up"
    assert "windup" in PER_SAMPLE_CHECKS
    assert "windup" not in MOTOR_CHECKS + BEARING_CHECKS + PAIR_CHECKS
    with pytest.raises(ValueError, match="registered already"):
        with registered(Windup()):
            pass


def test_the_shipped_registry_is_back_after_the_fixture():
    assert tuple(CHECKS) == SHIPPED and "windup" not in CHECK_LABELS and len(SHIPPED) == 18
    assert SHIPPED[:9] == ("peak", "mean", "speed", "average_speed", "momentary", "static",
                           "life", "torsion", "natural_frequency")  # the gearhead's


def test_a_registered_rule_is_in_every_result_json_and_report(windup):
    """`size` judges it on every candidate, its JSON carries it, its table has its column."""
    from hdselect.report.size_tables import compare_table
    from hdselect.sizing.core import size
    from hdselect.sizing.records import size_json

    result = size(None, INDEX)
    document = json.loads(json.dumps(size_json(result), allow_nan=False))
    for joint, entry in zip(result.joints, document["joints"], strict=True):
        for candidate, written in zip(joint.candidates, entry["candidates"], strict=True):
            check = candidate.checks["windup"]
            assert check.value == pytest.approx(joint.load.peak_torque
                                                / stiffness(candidate.unit), rel=1e-12)
            assert check.ok == (check.value <= PHI_MAX)
            assert written["checks"]["windup"]["value"] == pytest.approx(check.value)
        console = Console(record=True, width=300)
        console.print(compare_table(result, joint))
        assert "windup" in console.export_text()
    assert any(not c.checks["windup"].ok for j in result.joints for c in j.candidates)


def test_the_time_scale_solver_honours_a_rule_without_a_form(windup):
    """Windup gives no rows in y = 1/s: `exact_scales` leaves it out and `feasible_scales`
    finds it on its grid. With only inertial torque a, the peak is a / s^2, so the rule
    holds from s* = sqrt(a / (K1 phi_max)) on; every other rule of the unit holds there."""
    unit = dataclasses.replace(UNITS[0], rated_torque=1e4, repeated_torque=math.inf,
                               momentary_torque=math.inf, static_torque=math.inf,
                               max_input_speed=math.inf)
    a = 4.0 * stiffness(unit) * PHI_MAX  # s* = 2
    n = 40
    cycle = ScalableCycle(t=np.arange(n) * 0.01, dt=0.01, duration=n * 0.01, qd=0.1, qdd=0.0,
                          at_rest=False, gravity=0.0, velocity=0.0, inertial=a,
                          stop_inertial=0.0, stop_time=STOP_TIME)
    assert windup.scale_rows(cycle.terms(), unit, 0.0) is None
    assert exact_scales(cycle, unit)[0][0] < 1.0  # no form: the exact part allows faster
    (found,) = feasible_scales(cycle, unit)
    assert found[0] == pytest.approx(2.0, rel=4 * RTOL) and found[1] == math.inf
    assert not check_at(cycle, unit, 2.0 * (1 - 1e-3)).feasible
    assert check_at(cycle, unit, 2.0 * (1 + 1e-3)).feasible


def test_old_check_helpers_warn_and_judge_as_the_rules():
    from hdselect.catalog.checks import limit_check
    from hdselect.catalog.motor_rules import inertia_check

    with pytest.warns(DeprecationWarning, match="Rule.judge"):
        assert limit_check(8.0, 10.0, margin=0.3) == rule("peak").judge(8.0, 10.0, 0.3)
    with pytest.warns(DeprecationWarning, match="INERTIA_RATIO.of"):
        missing = inertia_check(None, 3.0)
    assert not missing.ok and missing.utilization == math.inf
    with pytest.warns(DeprecationWarning):
        assert inertia_check(3.0, 3.0).ok  # no margin: at the largest ratio it holds


def test_mean_speed_definition_is_an_enum_spelled_as_in_the_catalog():
    from hdselect.catalog.units import MEAN_SPEED_RULES, MeanSpeed

    assert MEAN_SPEED_RULES == ("whole-cycle", "moving")
    psa = UNITS[0].rules
    assert psa.mean_speed is MeanSpeed.MOVING and psa.mean_speed == "moving"  # the built-in file
    whole = dataclasses.replace(psa, mean_speed="whole-cycle")  # a spelling is taken too
    assert whole.mean_speed is MeanSpeed.WHOLE_CYCLE and whole.mean_speed.over == "the whole cycle"
    assert MeanSpeed.MOVING.of(2.0, 1.0) == 2.0 and MeanSpeed.WHOLE_CYCLE.of(2.0, 1.0) == 1.0
    load = cycle_load(np.ones(4), np.r_[1.0, 1.0, 0.0, 0.0], 1.0, np.r_[False, False, True, True])
    assert load.mean_speed_under(psa) == 1.0 and load.mean_speed_under(whole) == 0.5
    with pytest.raises(ValueError):
        dataclasses.replace(psa, mean_speed="dwell")
