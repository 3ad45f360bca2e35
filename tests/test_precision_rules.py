"""The precision targets: the ``torsion`` and ``natural_frequency`` rules against hand
calculations, and their options as every front end reads them (and refuses them).

Oracles that do not come from the code: the index table's load inertia from its stated
geometry and materials (an aluminium disk and four steel blocks), Harmonic Drive's
published torsion example (HFUC-32-100 at 60 N m: 7.15e-4 rad, 2.5 arcmin) and the
three-segment curve written out by hand.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from hdselect import InputError, Options, size
from hdselect.catalog.catalogfile import load_catalog
from hdselect.catalog.rules import check_unit
from hdselect.catalog.stiffness import APPLICATION_CLASSES
from hdselect.catalog.units import RAD_PER_ARCMIN, Stiffness
from hdselect.cli.inputs import sizing_options_of
from hdselect.cli.main import _parser, main
from hdselect.motion.motionfile import load_motion
from hdselect.sizing.options import options_for
from hdselect.study.spec import load_study
from helpers import REPO
from helpers.motions import make_load, make_unit

INDEX = REPO / "trajectories" / "index_table_indexing.toml"
BENCHTOP = REPO / "trajectories" / "benchtop6_pick_place.toml"
SHG = tuple(load_catalog(["shg-2uh"], series=["shg-2uh"]))
"""Every SHG-2UH unit: each rates K1 (and T1, T2, K2, K3)."""


def index_table_inertia() -> float:
    """The index table's inertia about its axis, from its geometry [kg m^2].

    An aluminium disk (2700 kg/m^3) of radius 0.15 m and 0.02 m thick, m r^2 / 2; four
    steel blocks (7850 kg/m^3) 0.04 x 0.04 x 0.03 m at 0.11 m from the axis, each
    m (a^2 + b^2) / 12 + m d^2.
    """
    disk = 2700.0 * math.pi * 0.15**2 * 0.02
    block = 7850.0 * 0.04 * 0.04 * 0.03
    return disk * 0.15**2 / 2.0 + 4.0 * (block * (0.04**2 + 0.04**2) / 12.0 + block * 0.11**2)


def twist_by_hand(t1: float, t2: float, k1: float, k2: float, k3: float, torque: float) -> float:
    """The catalog's three segments written out [rad]."""
    if torque <= t1:
        return torque / k1
    if torque <= t2:
        return t1 / k1 + (torque - t1) / k2
    return t1 / k1 + (t2 - t1) / k2 + (torque - t2) / k3


# --- the rules against hand calculations -------------------------------------------------------

def test_the_natural_frequency_of_the_index_table_is_the_hand_one():
    """f_n = sqrt(K1 / J) / 2 pi with J of the disk and blocks by hand, for every unit."""
    inertia = index_table_inertia()
    assert inertia == pytest.approx(0.061581, rel=1e-5)  # the robot file's own sum
    result = size(None, INDEX, catalog=SHG, min_natural_frequency=30.0)
    (joint,) = result.joints
    assert joint.load_inertia == pytest.approx(inertia, rel=1e-5)
    for candidate in joint.candidates:
        check = candidate.checks["natural_frequency"]
        stiffness = candidate.unit.stiffness
        assert stiffness is not None and stiffness.k1 is not None
        by_hand = math.sqrt(stiffness.k1 / inertia) / (2.0 * math.pi)
        assert check.value == pytest.approx(by_hand, rel=1e-5)
        assert check.limit == 30.0 and check.ok == (by_hand >= 30.0)
        assert check.utilization == pytest.approx(30.0 / by_hand, rel=1e-5)


def test_a_frequency_target_makes_the_joint_choose_a_stiffer_unit():
    """Without the target the table takes the smallest unit; with one above that unit's
    f_n it takes the first unit (in the order of sizes) whose K1 reaches it."""
    inertia = index_table_inertia()
    plain = size(None, INDEX, catalog=SHG).joints[0].selected
    assert plain is not None and "natural_frequency" not in plain.checks  # no target: absent
    k1 = plain.unit.stiffness.k1
    target = 1.2 * math.sqrt(k1 / inertia) / (2.0 * math.pi)
    stiff = size(None, INDEX, catalog=SHG, min_natural_frequency=target).joints[0]
    assert stiff.selected is not None and stiff.selected.unit.stiffness.k1 > k1
    assert stiff.selected.checks["natural_frequency"].ok
    needed = target**2 * (2.0 * math.pi) ** 2 * inertia  # the K1 the target asks [N m/rad]
    for candidate in stiff.candidates:
        assert candidate.checks["natural_frequency"].ok == (candidate.unit.stiffness.k1 >= needed
                                                            * (1 - 1e-9))
    assert plain.unit.size <= stiff.selected.unit.size


def test_harmonic_drives_torsion_example():
    """HFUC-32-100 at 60 N m (T1 = 29 N m, K1 = 6.7e4, K2 = 1.1e5 N m/rad): 7.15e-4 rad,
    2.5 arcmin, judged against a 2.5 and a 2.4 arcmin target; the margin does not apply."""
    unit = make_unit(stiffness=Stiffness(t1=29.0, t2=108.0, k1=6.7e4, k2=1.1e5, k3=1.2e5))
    load = make_load(peak=60.0, static=45.0)  # the largest |T| is the peak
    check = check_unit(load, unit, max_torsion=2.5 * RAD_PER_ARCMIN,
                       margin=0.3).checks["torsion"]
    assert check.value * RAD_PER_ARCMIN == pytest.approx(7.15e-4, abs=0.005e-4)
    assert check.value == pytest.approx(2.5, abs=0.05) and check.limit == pytest.approx(2.5)
    assert check.ok  # 2.457 arcmin within 2.5, the 30 % margin not applied to a target
    assert not check_unit(load, unit, max_torsion=2.4 * RAD_PER_ARCMIN).checks["torsion"].ok
    held = check_unit(make_load(peak=20.0, static=60.0), unit, max_torsion=1e-3)
    assert held.checks["torsion"].value == pytest.approx(check.value)  # held torque twists too


def test_a_unit_without_stiffness_is_not_rated_and_no_target_means_no_check():
    unit = make_unit()  # no stiffness
    candidate = check_unit(make_load(), unit, max_torsion=1e-4, min_frequency=50.0,
                           load_inertia=1.0)
    for name in ("torsion", "natural_frequency"):
        check = candidate.checks[name]
        assert check.ok and check.value is None and "not_rated" in check.detail
    assert any(flag.field == "stiffness" and "targets are not checked" in flag.note
               for flag in candidate.flags)  # the tables' footnote says so
    plain = check_unit(make_load(), unit)
    assert "torsion" not in plain.checks and "natural_frequency" not in plain.checks
    assert not any(flag.field == "stiffness" for flag in plain.flags)
    with pytest.raises(ValueError, match="load inertia"):
        check_unit(make_load(), unit, min_frequency=50.0)


def test_the_torsion_of_the_index_table_is_the_curve_at_its_largest_torque():
    """The twist at the largest |T| of the cycle (moving or held), by the hand curve; a
    target below the plain choice's twist moves the joint to a stiffer unit."""
    plain = size(None, INDEX, catalog=SHG).joints[0]
    assert plain.selected is not None and "torsion" not in plain.selected.checks
    largest = float(np.abs(plain.torque).max())
    s = plain.selected.unit.stiffness
    target = 0.8 * twist_by_hand(s.t1, s.t2, s.k1, s.k2, s.k3, largest)  # [rad]
    (joint,) = size(None, INDEX, catalog=SHG, max_torsion=target).joints
    for candidate in joint.candidates:
        s = candidate.unit.stiffness
        by_hand = twist_by_hand(s.t1, s.t2, s.k1, s.k2, s.k3, largest) / RAD_PER_ARCMIN
        check = candidate.checks["torsion"]
        assert check.value == pytest.approx(by_hand, rel=1e-9)
        assert check.limit == pytest.approx(target / RAD_PER_ARCMIN)
        assert check.ok == (by_hand <= target / RAD_PER_ARCMIN)
    assert joint.selected is not None and joint.selected.unit.id != plain.selected.unit.id
    assert joint.selected.checks["torsion"].ok


def test_the_application_classes_carry_their_numbers_and_source():
    assert {c.frequency for c in APPLICATION_CLASSES.values()} == {4.0, 8.0, 15.0, 20.0, 25.0,
                                                                    30.0}
    assert APPLICATION_CLASSES["hand-axes"].frequency == 15.0
    assert APPLICATION_CLASSES["base-axes"].frequency == 8.0
    assert APPLICATION_CLASSES["milling-hardwood"].frequency == 30.0
    for name, found in APPLICATION_CLASSES.items():
        assert name == name.lower() and " " not in name and found.words and found.source
        assert "transcription" in found.source


# --- the options -------------------------------------------------------------------------------

MOTION = INDEX.read_text()


def args(*extra: str):
    return _parser().parse_args(["size", str(INDEX), *extra])


def test_a_bare_value_applies_to_every_joint_and_a_named_one_wins():
    motion = load_motion(INDEX)
    options = sizing_options_of(args("--max-torsion", "2", "--max-torsion", "table=1.5",
                                     "--min-natural-frequency", "hand-axes"), motion)
    assert options.max_torsion == {"*": pytest.approx(2 * RAD_PER_ARCMIN),
                                   "table": pytest.approx(1.5 * RAD_PER_ARCMIN)}
    assert options.joint_value("max_torsion", "table") == pytest.approx(1.5 * RAD_PER_ARCMIN)
    assert options.joint_value("max_torsion", "other") == pytest.approx(2 * RAD_PER_ARCMIN)
    assert options.joint_value("min_natural_frequency", "table") == 15.0
    assert Options().joint_value("max_torsion", "table") is None
    assert Options(max_torsion=1e-3).max_torsion == {"*": 1e-3}  # Python: SI, bare
    assert Options(min_natural_frequency={"table": "scara"}).min_natural_frequency == {
        "table": 15.0}
    whole = sizing_options_of(args("--max-tool-deflection", "0.2", "--min-arm-frequency",
                                   "12.5"), motion)
    assert (whole.max_tool_deflection, whole.min_arm_frequency, whole.precision) == (
        pytest.approx(2e-4), 12.5, True)
    for target in ("--max-tool-deflection", "--min-arm-frequency"):
        # the whole-arm targets are judged on the figures --no-precision leaves out
        with pytest.raises(InputError, match="not both") as refused:
            sizing_options_of(args(target, "10", "--no-precision"), motion)
        assert refused.value.field == target
    with pytest.raises(InputError, match="not both"):
        Options(precision=False, max_tool_deflection=1e-3)


@pytest.mark.parametrize(("given", "words"), [
    (["--max-torsion", "nan"], "must be finite"),
    (["--max-torsion", "inf"], "must be finite"),
    (["--max-torsion", "-1"], "positive"),
    (["--max-torsion", "1e308"], "at most"),
    (["--max-torsion", "0"], "positive"),
    (["--max-torsion", "table=abc"], "expected a number"),
    (["--max-torsion", "=2"], "JOINT=VALUE"),
    (["--max-torsion", "nonesuch=2"], "'nonesuch' is not a sized joint"),
    (["--max-torsion", "2", "--max-torsion", "3"], "given twice for every joint"),
    (["--max-torsion", "table=2", "--max-torsion", "table=3"], "given twice for table"),
    (["--min-natural-frequency", "hand-axis"], "hand-axes"),  # the classes listed
    (["--min-natural-frequency", "table=-3"], "positive"),
    (["--min-arm-frequency", "nope"], "milling-hardwood"),
    (["--max-tool-deflection", "1e308"], "at most 1000 mm"),
])
def test_a_bad_flag_is_refused_in_one_line_naming_it(given, words, capsys, tmp_path):
    status = main(["size", str(INDEX), *given, "--json", str(tmp_path / "r.json")])
    err = capsys.readouterr().err.strip()
    assert status == 2 and len(err.splitlines()) == 1 and given[0] in err and words in err, err
    assert not (tmp_path / "r.json").exists()


@pytest.mark.parametrize(("table", "field", "words"), [
    ("max_torsion_arcmin = { nonesuch = 2 }", "precision.max_torsion_arcmin.nonesuch",
     "unknown joint 'nonesuch'"),
    ("max_torsion_arcmin = nan", "precision.max_torsion_arcmin", "must be finite"),
    ("max_torsion_arcmin = { table = -2 }", "precision.max_torsion_arcmin.table", "positive"),
    ("min_natural_frequency_hz = \"fast\"", "precision.min_natural_frequency_hz",
     "unknown application class 'fast'"),
    ("min_natural_frequency_hz = 1e308", "precision.min_natural_frequency_hz", "at most"),
    ("max_tool_deflection_mm = -0.1", "precision.max_tool_deflection_mm", "positive"),
    ("min_arm_frequency_hz = true", "precision.min_arm_frequency_hz", "expected a number"),
    ("max_twist = 2", "precision.max_twist", "unknown key"),
])
def test_a_bad_precision_table_is_refused_naming_the_file_and_key(table, field, words,
                                                                  tmp_path):
    path = tmp_path / "motion.toml"
    path.write_text(MOTION.replace('robot = "../robots/', f'robot = "{REPO}/robots/')
                    + f"\n[precision]\n{table}\n")
    with pytest.raises(InputError) as caught:
        load_motion(path)
    assert caught.value.path == path and caught.value.field == field
    assert words in caught.value.reason


def test_a_motion_files_precision_table_reaches_the_options(tmp_path):
    path = tmp_path / "motion.toml"
    path.write_text(MOTION.replace('robot = "../robots/', f'robot = "{REPO}/robots/')
                    + '\n[precision]\nmax_torsion_arcmin = { table = 3 }\n'
                      'min_natural_frequency_hz = "base-axes"\nmax_tool_deflection_mm = 0.05\n'
                      'min_arm_frequency_hz = 12\n')
    options = options_for(load_motion(path))
    assert options.max_torsion == {"table": pytest.approx(3 * RAD_PER_ARCMIN)}
    assert options.min_natural_frequency == {"*": 8.0}
    assert options.max_tool_deflection == pytest.approx(5e-5)
    assert options.min_arm_frequency == 12.0


def test_a_study_gives_one_value_for_every_joint_in_the_files_units(tmp_path):
    (tmp_path / "m.toml").write_text(MOTION.replace('robot = "../robots/',
                                                    f'robot = "{REPO}/robots/'))
    path = tmp_path / "study.toml"
    path.write_text('[base]\nmotion = "m.toml"\nmin_natural_frequency = "hand-axes"\n'
                    '[grid]\nmax_torsion = [1, 2.5]\n')
    study = load_study(path)
    assert [case.options for case in study.cases] == [
        {"min_natural_frequency": "hand-axes", "max_torsion": 1},
        {"min_natural_frequency": "hand-axes", "max_torsion": 2.5}]
    from hdselect.study.casetasks import case_options

    options = case_options(study.cases[1], load_motion(tmp_path / "m.toml"))
    assert options.joint_value("max_torsion", "table") == pytest.approx(2.5 * RAD_PER_ARCMIN)
    assert options.joint_value("min_natural_frequency", "table") == 15.0
    path.write_text('[base]\nmotion = "m.toml"\nmax_torsion = { table = 2 }\n')
    with pytest.raises(InputError, match="one value for every sized joint") as caught:
        load_study(path)
    assert caught.value.field == "base.max_torsion"
    path.write_text('[base]\nmotion = "m.toml"\nmax_torsion = -1\n')
    with pytest.raises(InputError, match="positive"):
        load_study(path)


def test_python_refuses_a_target_for_a_joint_not_sized():
    with pytest.raises(InputError) as caught:
        size(None, INDEX, catalog=SHG, max_torsion={"nonesuch": 1e-3})
    assert caught.value.field == "max_torsion.nonesuch"


# --- the command line --------------------------------------------------------------------------

@pytest.mark.slow
def test_size_with_targets_chooses_stiffer_units_and_says_why(capsys, tmp_path):
    """The lab arm (benchtop6) with SHG-2UH: 2 arcmin and the hand-axes class (15 Hz) move
    the choice to stiffer units; every candidate's JSON has both checks."""
    argv = ["size", str(BENCHTOP), "--series", "shg-2uh"]
    assert main([*argv, "--json", str(tmp_path / "plain.json")]) in (0, 1)
    assert main([*argv, "--max-torsion", "2", "--min-natural-frequency", "hand-axes",
                 "--json", str(tmp_path / "stiff.json")]) in (0, 1)
    out = capsys.readouterr().out
    assert "torsion" in out
    plain = json.loads((tmp_path / "plain.json").read_text())
    stiff = json.loads((tmp_path / "stiff.json").read_text())
    units = {u.id: u for u in SHG}
    changed = 0
    for before, after in zip(plain["joints"], stiff["joints"], strict=True):
        for candidate in after["candidates"]:
            assert {"torsion", "natural_frequency"} <= set(candidate["checks"])
            assert candidate["checks"]["torsion"]["limit"] == pytest.approx(2.0)
            assert candidate["checks"]["natural_frequency"]["limit"] == 15.0
        old, new = before["selected"], after["selected"]
        if old != new:
            changed += 1
            assert units[new].stiffness.k1 > units[old].stiffness.k1
    assert changed >= 1


@pytest.mark.slow
def test_the_flags_act_on_a_mix_and_an_envelope_file(tmp_path):
    """A mix file's [precision] table is the duty's; an envelope file's is read too."""
    from hdselect.envelope.specfile import load_envelope_file
    from hdselect.motion.mixfile import load_mix
    from hdselect.robot.model import load_robot
    from hdselect.sizing.mixtasks import mix_options

    robot = load_robot(REPO / "robots" / "index_table.urdf")
    (tmp_path / "m.toml").write_text(MOTION.replace('robot = "../robots/',
                                                    f'robot = "{REPO}/robots/'))
    mix = tmp_path / "mix.toml"
    mix.write_text(f'robot = "{REPO}/robots/index_table.urdf"\n[precision]\n'
                   'max_torsion_arcmin = 4\n[[task]]\nname = "a"\nmotion = "m.toml"\n'
                   'share = 1.0\n')
    assert mix_options(load_mix(mix, robot)).max_torsion == {
        "*": pytest.approx(4 * RAD_PER_ARCMIN)}
    envelope = tmp_path / "envelope.toml"
    envelope.write_text(f'robot = "{REPO}/robots/index_table.urdf"\nangle_unit = "deg"\n'
                        '[precision]\nmin_natural_frequency_hz = { table = 20 }\n')
    assert load_envelope_file(envelope, robot).min_natural_frequency == {"table": 20.0}


def test_replace_keeps_the_checks():
    """An Options changed with dataclasses.replace checks the new value too."""
    with pytest.raises(InputError):
        replace(Options(), max_torsion=-1.0)


@pytest.mark.slow
def test_a_grouped_study_case_with_targets_equals_its_separate_run():
    """A study's grouped case reads the load inertias of its basis (built with them where
    a case has a frequency target) and sizes as the core does, targets and all."""
    from hdselect import load_case
    from hdselect.study.group import build_basis
    from hdselect.study.pooled import size_case
    from helpers.studies import differences, separate

    robot, motion = load_case(BENCHTOP)
    bare = robot.with_payload(None)
    options = Options(stop_time=0.15, life_hours=20000.0, threads=1,
                      max_torsion=3 * RAD_PER_ARCMIN, min_natural_frequency=15.0)
    basis = build_basis(bare, motion, motion.payload, inertias=True)
    grouped = size_case(basis, 0.5, 1.0, SHG, options)
    reference = separate(bare, motion, 0.5, 1.0, SHG, options)
    assert differences(grouped.to_dict(), reference.to_dict()) < 1e-9
    plain = size_case(basis, 0.5, 1.0, SHG, replace(options, max_torsion={},
                                                     min_natural_frequency={}))
    assert [j.unit for j in plain.joints] != [j.unit for j in grouped.joints]
    with pytest.raises(ValueError, match="inertias=True"):
        size_case(build_basis(bare, motion, motion.payload), 0.5, 1.0, SHG, options)


@pytest.mark.slow
def test_envelope_takes_the_targets(capsys, tmp_path):
    """With SHG-2UH units, a 0.5 arcmin target moves the envelope's units (PSA-G rates no
    stiffness: there the targets are not rated, and act on nothing)."""
    base = ["envelope", str(REPO / "robots" / "planar2.urdf"), "--velocity", "180",
            "--acceleration", "900", "--starts", "64", "--moves", "2", "--series", "shg-2uh"]
    chosen = []
    for extra in ([], ["--max-torsion", "0.5"], ["--min-natural-frequency", "hand-axes"]):
        out = tmp_path / f"e{len(chosen)}.json"
        assert main([*base, *extra, "--json", str(out)]) in (0, 1)
        document = json.loads(out.read_text())
        chosen.append([joint["selected"] for joint in document["joints"]])
        for joint in document["joints"]:
            for name, flag in (("torsion", "--max-torsion"),
                               ("natural_frequency", "--min-natural-frequency")):
                assert (name in joint["candidates"][0]["checks"]) == (flag in extra)
    capsys.readouterr()
    assert chosen[1] != chosen[0]


@pytest.mark.slow
def test_max_payload_stops_where_the_frequency_target_does():
    """Units fixed, the elbow's f_n falls as the payload grows (its M_jj affine in the
    mass): the largest payload is where f_n meets the target, found again by sizing the
    robot carrying that mass (M_jj recomputed at it, not interpolated).

    What scales is the part the file's events move; the gripper stays. The elbow's M_jj
    of the planar arm does not depend on the pose, so the poses that carry the part (the
    worst state) give it whatever the poses."""
    from hdselect import load_case, max_payload, plan
    from hdselect.robot.dynamics import joint_inertias
    from hdselect.sizing.torques import inertia_poses

    robot, motion = load_case(REPO / "trajectories" / "planar2_pick_place.toml")
    units = {"shoulder": "SHG-25-100-2UH", "elbow": "SHG-17-100-2UH"}
    k1 = next(u for u in SHG if u.id == units["elbow"]).stiffness.k1
    trajectory = plan(robot, motion)
    poses = trajectory.q[inertia_poses(trajectory)]

    part = motion.parts["part"]

    def elbow_inertia(mass: float) -> float:  # the last joint: no unit is carried past it
        carrying = robot.with_parts((*robot.parts, replace(part, mass=mass)))  # and the gripper
        return float(joint_inertias(carrying, poses, ["elbow"]).max())

    target = math.sqrt(k1 / elbow_inertia(1.5)) / (2.0 * math.pi)  # reached at 1.5 kg
    found = max_payload(robot, motion, Options(min_natural_frequency={"elbow": target}),
                        catalog=SHG, units=units, trajectory=trajectory)
    assert found.rule == "natural_frequency" and found.joint == "elbow"
    assert found.mass == pytest.approx(1.5, rel=1e-6)


def test_a_mix_refuses_motions_that_disagree_on_a_target_in_their_words(tmp_path):
    from hdselect.motion.mixfile import load_mix
    from hdselect.robot.model import load_robot
    from hdselect.sizing.mixtasks import mix_options

    text = MOTION.replace('robot = "../robots/', f'robot = "{REPO}/robots/')
    (tmp_path / "a.toml").write_text(text + "\n[precision]\nmax_torsion_arcmin = 2\n")
    (tmp_path / "b.toml").write_text(text + "\n[precision]\nmax_torsion_arcmin = 3\n")
    mix = tmp_path / "mix.toml"
    mix.write_text(f'robot = "{REPO}/robots/index_table.urdf"\n'
                   '[[task]]\nmotion = "a.toml"\nshare = 0.5\n'
                   '[[task]]\nmotion = "b.toml"\nshare = 0.5\n')
    robot = load_robot(REPO / "robots" / "index_table.urdf")
    with pytest.raises(InputError, match=r"a.toml gives precision.max_torsion_arcmin 2, .*"
                                         r"b.toml gives 3;"):
        mix_options(load_mix(mix, robot))


def test_a_catalog_whose_units_rate_no_stiffness_is_no_next_step_for_a_target(capsys):
    """CSF-2UH rates no K1: its units are "not rated" for a torsion target, which is no
    proof they hold it; the next steps offer only what is checked (here the slow-down,
    the dynamic torque falling as 1/s^2)."""
    status = main(["size", str(INDEX), "--series", "shg-2uh", "--max-torsion", "0.01"])
    out = capsys.readouterr().out
    assert status == 1 and "largest torsion" in out
    assert "csf-2uh" not in out and "slower" in out


def test_the_json_of_a_frequency_check_carries_its_load_inertia():
    from hdselect.sizing.records import size_json

    result = size(None, INDEX, catalog=SHG, min_natural_frequency=20.0, max_torsion=1e-3)
    document = json.loads(json.dumps(size_json(result), allow_nan=False))
    checks = document["joints"][0]["candidates"][0]["checks"]
    assert checks["natural_frequency"]["load_inertia_kg_m2"] == pytest.approx(
        index_table_inertia(), rel=1e-5)
    assert checks["natural_frequency"]["limit"] == 20.0
    assert checks["torsion"]["limit"] == pytest.approx(1e-3 / RAD_PER_ARCMIN)


@pytest.mark.slow
def test_fastest_takes_the_targets_and_no_speed_helps_a_resonance(capsys, tmp_path):
    """A torsion target slows the index table (a torque limit); a frequency target it
    meets costs no time; one it misses fails at once, at every speed."""
    base = ["fastest", str(INDEX), "--series", "shg-2uh", "--units", "table=SHG-14-50-2UH"]
    cycles = []
    for extra in ([], ["--min-natural-frequency", "20"], ["--max-torsion", "0.3"]):
        out = tmp_path / f"f{len(cycles)}.json"
        assert main([*base, *extra, "--json", str(out)]) == 0
        cycles.append(json.loads(out.read_text())["cycle_time_s"])
    assert cycles[1] == cycles[0] and cycles[2] > cycles[0]
    capsys.readouterr()
    assert main([*base, "--min-natural-frequency", "1000"]) == 1
    assert "natural_frequency rule with SHG-14-50-2UH at every speed" in " ".join(
        capsys.readouterr().out.split())
