"""Design margin, largest load-to-rotor inertia ratio and inertia matching, by hand.

The margin m: every rule must hold at (1 - m) of its limit; utilization stays demand /
limit. The inertia ratio of a (gearhead, motor) pair is (J_load / N^2 + J_in) / J_m.
The numbers below are worked out in each test's docstring from the catalog's
figures and the index table's closed form (tests/test_sizing_motors.py), not taken
from `hdselect.catalog.rules`.
"""

from __future__ import annotations

import json
import math

import pytest

from hdselect import size
from hdselect.base.errors import InputError
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.duty import load_duty, size_duty
from hdselect.catalog.motors import Motor, load_motors
from hdselect.catalog.rules import check_unit
from hdselect.cli.main import main
from hdselect.sizing.options import Options
from test_dynamics import J_TABLE, REPO
from test_rules import make_load, make_unit
from test_sizing_motors import CYCLE, ETA, T_A, A, index_motion

PSA_14_100 = next(u for u in load_catalog() if u.id == "PSA-14-100")
J_IN = 3.3e-6  # PSA-14-100 input inertia: 0.033 kg cm^2 [kg m^2]


# --- the margin on one unit ----------------------------------------------------------------

def test_a_unit_at_85_percent_passes_without_margin_and_fails_at_20_percent():
    """Unit: repeated peak 20 N m. Peak 17 N m: 17 / 20 = 85 %, within 100 % but above
    the 80 % a 0.2 margin allows. The utilization is 0.85 either way."""
    load = make_load(peak=17.0, mean=5.0)
    plain = check_unit(load, make_unit())
    kept = check_unit(load, make_unit(), margin=0.2)
    assert plain.checks["peak"].utilization == kept.checks["peak"].utilization == 17.0 / 20.0
    assert plain.feasible and plain.checks["peak"].ok
    assert not kept.feasible and not kept.checks["peak"].ok
    assert kept.binding == "peak" and kept.required_margin == 0.2


def test_the_margin_holds_on_life_and_exactly_at_its_edge():
    """T_N 10 N m, ratio 50, output 35 rpm: N_av = 1750 rpm, T_allow = 10 N m.
    T_av 8 N m: mean 8 / 10 = 80 %, exactly at the edge of a 0.2 margin: it holds.
    L50 = 35000 x (1750 / 1750) x (10 / 8)^3 = 68,359 h; 60,000 h required: 87.8 %,
    which fails at 0.2 and passes without."""
    load = make_load(peak=8.0, mean=8.0)
    life = 35000 * (10 / 8) ** 3
    plain = check_unit(load, make_unit(), life_hours=60000.0)
    kept = check_unit(load, make_unit(), life_hours=60000.0, margin=0.2)
    assert kept.checks["mean"].utilization == pytest.approx(0.8, abs=1e-12)
    assert kept.checks["mean"].ok  # <= 80 % holds
    assert plain.checks["life"].utilization == pytest.approx(60000 / life, rel=1e-12)
    assert plain.feasible and not kept.feasible and not kept.checks["life"].ok


def test_duty_honours_the_margin_and_rejects_one_out_of_range(capsys):
    """The shipped duty example: a unit passes at margin 0.2 exactly when its worst
    utilization is at most 80 % (at margin 0: at most 100 %)."""
    profile = REPO / "trajectories" / "duty" / "conveyor_index.toml"
    units = load_catalog()
    plain = size_duty(load_duty(profile), units)
    kept = size_duty(load_duty(profile), units, margin=0.2)
    for a, b in zip(plain.candidates, kept.candidates, strict=True):
        worst = max(c.utilization for c in a.checks.values())
        assert b.feasible == (worst <= 0.8)
        assert a.feasible == (worst <= 1.0)
    assert any(a.feasible and not b.feasible for a, b in zip(plain.candidates, kept.candidates,
                                                             strict=True))
    assert main(["duty", str(profile), "--margin", "1.5"]) == 2
    assert "--margin" in capsys.readouterr().err


# --- the margin through the whole sizing -------------------------------------------------

def rms_by_hand(j_m: float) -> float:
    """Motor RMS torque behind PSA-14-100 on the index table [N m].

    T_acc = J a / (N eta) + (J_in + J_m) N a, T_dec = J a eta / N + (J_in + J_m) N a,
    each for T_A = 0.25 s of the 2.25 s cycle. With J_m = 5e-6 kg m^2: T_acc = 0.021485,
    T_dec = 0.015847, RMS = sqrt((T_acc^2 + T_dec^2) 0.25 / 2.25) = 0.008899 N m.
    """
    t_acc = J_TABLE * A / (100 * ETA) + (J_IN + j_m) * 100 * A
    t_dec = J_TABLE * A * ETA / 100 + (J_IN + j_m) * 100 * A
    return math.sqrt((t_acc**2 + t_dec**2) * T_A / CYCLE)


MOTOR_M10 = """\
id = "M10"
rated_torque_nm = 0.0100
peak_torque_nm = 0.1
max_speed_rpm = 6000
rated_speed_rpm = 3000
rotor_inertia_kg_m2 = 5e-6
mass_kg = 0.2
"""


def test_a_pair_at_89_percent_rms_is_chosen_without_margin_and_refused_at_20_percent(tmp_path):
    """PSA-14-100 behind a motor rated 0.0100 N m: RMS 0.008899 N m is 89 % of rated.
    Its other rules stay far below 80 % (repeated peak 0.774 / 20.3 N m = 4 %, motor peak
    0.0215 / 0.1 = 21 %, input speed 3000 / 6000 rpm = 50 %), so the margin alone
    decides."""
    motion = index_motion(tmp_path, MOTOR_M10)
    rms = rms_by_hand(5e-6)
    assert rms == pytest.approx(0.008899, abs=1e-6)
    plain = size(None, motion, catalog=[PSA_14_100])
    kept = size(None, motion, catalog=[PSA_14_100], margin=0.2)
    (joint,), (held,) = plain.joints, kept.joints
    assert joint.selected is not None and joint.selected.binding == "motor_rms"
    assert joint.selected.checks["motor_rms"].utilization == pytest.approx(rms / 0.01, rel=3e-3)
    assert held.selected is None and not kept.feasible
    (pair,) = held.candidates
    assert pair.checks["motor_rms"].utilization == joint.selected.checks["motor_rms"].utilization
    assert [name for name, c in pair.checks.items() if not c.ok] == ["motor_rms"]
    assert kept.options.margin == 0.2
    # the slow-down search keeps the margin too: at s the RMS falls as 1/s^2 (all of it
    # inertial), so the pair fits from 89 % / s^2 <= 80 %, s >= sqrt(0.89 / 0.8)
    assert held.slowdown is not None and held.slowdown.factor is not None
    need = math.sqrt(pair.checks["motor_rms"].utilization / 0.8)
    assert held.slowdown.factor == pytest.approx(need, abs=2e-3)


def test_a_motion_files_margin_and_the_flag(tmp_path, capsys):
    """``[requirements] margin`` applies unless ``--margin`` overrides it; out of range is
    one line naming the field and exit status 2."""
    motion = index_motion(tmp_path, MOTOR_M10)
    text = motion.read_text().replace("[safety]", "[requirements]\nmargin = 0.2\n[safety]")
    motion.write_text(text)
    assert size(None, motion, catalog=[PSA_14_100]).options.margin == 0.2
    assert not size(None, motion, catalog=[PSA_14_100]).feasible
    assert size(None, motion, catalog=[PSA_14_100], margin=0.0).feasible
    out = tmp_path / "out.json"
    assert main(["size", str(motion), "--json", str(out)]) == 0  # another pair keeps 20 %
    document = json.loads(out.read_text())
    assert document["assumptions"]["margin"] == 0.2
    (joint,) = document["joints"]
    chosen = next(c for c in joint["candidates"] if c["unit"] == joint["selected"]
                  and c["motor"]["id"] == joint["selected_motor"])
    assert chosen["margin_required"] == 0.2
    assert max(c["utilization"] for c in chosen["checks"].values()) <= 0.8
    capsys.readouterr()
    motion.write_text(text.replace("margin = 0.2", "margin = 1.2"))
    assert main(["size", str(motion)]) == 2
    err = capsys.readouterr().err
    assert "requirements.margin" in err and len(err.strip().splitlines()) == 1
    assert main(["size", str(index_motion(tmp_path, MOTOR_M10, name="b.toml")),
                 "--margin", "-0.1"]) == 2
    assert "--margin" in capsys.readouterr().err


# --- the inertia ratio ---------------------------------------------------------------------

LIGHT = Motor("LIGHT", rated_torque=0.03, peak_torque=0.1, max_speed=6000, rated_speed=3000,
              rotor_inertia=5e-7, mass=0.1)
HEAVY = Motor("HEAVY", rated_torque=0.03, peak_torque=0.1, max_speed=6000, rated_speed=3000,
              rotor_inertia=5e-6, mass=0.3)


def ratio_by_hand(j_m: float) -> float:
    """(J / N^2 + J_in) / J_m: J = 0.061581 kg m^2, N = 100, J_in = 3.3e-6 kg m^2.
    J / N^2 = 6.1581e-6; + J_in = 9.4581e-6 kg m^2 at the motor shaft: over 5e-7 it is
    18.916, over 5e-6 it is 1.8916."""
    return (J_TABLE / 100**2 + J_IN) / j_m


def test_a_light_motor_is_rejected_for_its_inertia_ratio(tmp_path):
    """Without a limit the lightest pair wins: LIGHT (0.1 kg), ratio 18.9. With at most
    10 it is not feasible and HEAVY (ratio 1.89) is chosen. Both motors pass every
    other rule (LIGHT's T_acc = 0.0111 + 3.8e-6 x 100 x 12.57 = 0.0158 N m)."""
    motion = index_motion(tmp_path, "", header="")
    motors = {"table": (LIGHT, HEAVY)}
    assert ratio_by_hand(5e-7) == pytest.approx(18.916, abs=1e-3)
    free = size(None, motion, catalog=[PSA_14_100], motors=motors)
    (joint,) = free.joints
    assert joint.selected.motor_unit is LIGHT
    assert joint.selected.inertia_ratio == pytest.approx(ratio_by_hand(5e-7), rel=1e-9)
    assert "inertia_ratio" not in joint.selected.checks  # no limit given: reported only
    limited = size(None, motion, catalog=[PSA_14_100], motors=motors, max_inertia_ratio=10.0)
    (joint,) = limited.joints
    assert joint.selected.motor_unit is HEAVY
    light = next(c for c in joint.candidates if c.motor_unit is LIGHT)
    check = light.checks["inertia_ratio"]
    assert not light.feasible and not check.ok and light.binding == "inertia_ratio"
    assert check.value == pytest.approx(ratio_by_hand(5e-7), rel=1e-9) and check.limit == 10.0
    assert joint.selected.checks["inertia_ratio"].value == pytest.approx(
        ratio_by_hand(5e-6), rel=1e-9)
    # the margin does not apply to the ratio (a design choice, not a rating): 1.89 of 2
    # is 95 % and still holds at margin 0.2
    tight = size(None, motion, catalog=[PSA_14_100], motors={"table": (HEAVY,)},
                 max_inertia_ratio=2.0, margin=0.2)
    assert tight.joints[0].selected is not None


def test_a_motor_files_largest_ratio_and_the_flag_override(tmp_path, capsys):
    """The file's top-level max_inertia_ratio = 10 applies to every motor of it;
    ``--max-inertia-ratio 20`` overrides it (18.9 then passes)."""
    file = tmp_path / "motors.toml"
    file.write_text("max_inertia_ratio = 10\n" + "".join(
        f"""[[motor]]
id = "{m.id}"
rated_torque_nm = {m.rated_torque}
peak_torque_nm = {m.peak_torque}
max_speed_rpm = {m.max_speed}
rated_speed_rpm = {m.rated_speed}
rotor_inertia_kg_m2 = {m.rotor_inertia}
mass_kg = {m.mass}
""" for m in (LIGHT, HEAVY)))
    motors = load_motors(file)
    assert [m.max_inertia_ratio for m in motors] == [10.0, 10.0]
    motion = index_motion(tmp_path, "", header="")
    result = size(None, motion, catalog=[PSA_14_100], motors={"table": motors})
    assert result.joints[0].selected.motor_unit.id == "HEAVY"
    override = size(None, motion, catalog=[PSA_14_100], motors={"table": motors},
                    max_inertia_ratio=20.0)
    assert override.joints[0].selected.motor_unit.id == "LIGHT"
    out = tmp_path / "size.json"
    assert main(["size", str(motion), "--motor-catalog", str(file), "--json", str(out)]) == 0
    (joint,) = json.loads(out.read_text())["joints"]
    assert joint["selected_motor"] == "HEAVY"
    file.write_text(file.read_text().replace("max_inertia_ratio = 10", "max_inertia_ratio = 0"))
    capsys.readouterr()
    assert main(["size", str(motion), "--motor-catalog", str(file)]) == 2
    assert "max_inertia_ratio" in capsys.readouterr().err


@pytest.mark.parametrize(("target", "chosen"), [(1.0, "HEAVY"), (20.0, "LIGHT"),
                                                (5.9, "HEAVY"), (6.1, "LIGHT")])
def test_prefer_inertia_takes_the_pair_closest_to_the_target_by_factor(tmp_path, target,
                                                                       chosen):
    """Ratios 1.8916 (HEAVY) and 18.916 (LIGHT). Distance by factor, |ln(r / target)|:
    the two are equally far from their geometric middle sqrt(1.8916 x 18.916) = 5.9817,
    so a target of 5.9 goes to HEAVY and 6.1 to LIGHT."""
    middle = math.sqrt(ratio_by_hand(5e-6) * ratio_by_hand(5e-7))
    assert middle == pytest.approx(5.9817, abs=1e-3)
    motion = index_motion(tmp_path, "", header="")
    result = size(None, motion, catalog=[PSA_14_100], motors={"table": (LIGHT, HEAVY)},
                  prefer="inertia", inertia_target=target)
    assert result.joints[0].selected.motor_unit.id == chosen
    assert result.options.prefer == "inertia" and result.options.inertia_target == target


def test_inertia_options_are_checked():
    for field, value in (("margin", 0.95), ("margin", -0.1), ("max_inertia_ratio", 0.0),
                         ("inertia_target", -1.0), ("margin", float("nan"))):
        with pytest.raises(InputError) as info:
            Options(**{field: value})
        assert getattr(info.value, "field", None) == field
