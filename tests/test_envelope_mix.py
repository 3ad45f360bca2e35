"""`hdselect envelope --duty MIXFILE`: a mix's tasks pooled by share as the duty.

Oracles: the same motion given as a motion file (a motion is a mix of one task), and
`hdselect size` of the mix itself (its pooled mean torque and speed: a worst state
stands for no time, so the envelope adds nothing to the averaged rules).
"""

from __future__ import annotations

import math

import pytest

from hdselect.base.errors import InputError
from hdselect.cli.main import main
from hdselect.envelope import SearchSettings, envelope
from hdselect.envelope.records import envelope_json
from hdselect.robot.payload import Payload
from hdselect.sizing.core import size
from helpers import REPO

DEG = math.pi / 180.0
PLANAR2 = REPO / "robots" / "planar2.urdf"
PLANAR2_MOTION = REPO / "trajectories" / "planar2_pick_place.toml"
BENCHTOP = REPO / "robots" / "benchtop6.urdf"
PICK_INSPECT = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
QUICK = SearchSettings(starts=256)
GRIPPER = Payload(0.4, (0.0, 0.0, 0.03), ((1.7e-4, 0, 0), (0, 1.7e-4, 0), (0, 0, 1.7e-4)),
                  "tool0")


def one_task_mix(tmp_path, motion=PLANAR2_MOTION, robot=PLANAR2):
    path = tmp_path / "one.toml"
    path.write_text(f'robot = "{robot}"\n[[task]]\nname = "only"\nmotion = "{motion}"\n'
                    "share = 1.0\n")
    return path


def without_origin(document):
    """The envelope's JSON without what names the duty file or times the run."""
    document = dict(document)
    document["duty"] = {k: v for k, v in document["duty"].items() if k not in ("label", "motion")}
    document["search"] = {k: v for k, v in document["search"].items() if k != "seconds"}
    document.pop("duty_sizing")
    document.pop("warnings")
    return document


AVERAGED = ("mean", "average_speed", "life")
"""The rules judged on the duty alone (a worst state stands for no time)."""


def assert_same_averages(envelope_joint, size_joint):
    """Every unit's averaged rules: the envelope's values are `size`'s, to rounding."""
    assert len(envelope_joint.candidates) == len(size_joint.candidates)
    checked = 0
    for mine, own in zip(envelope_joint.candidates, size_joint.candidates, strict=True):
        assert mine.unit.id == own.unit.id
        for name in AVERAGED:
            if name in own.checks and own.checks[name].value is not None:
                assert mine.checks[name].value == pytest.approx(own.checks[name].value,
                                                                rel=1e-12)
                checked += 1
    assert checked > 0


def test_a_one_task_mix_duty_is_the_motion_duty(tmp_path):
    """A motion is a mix of one task: the same units, worst states and averages, bit for bit."""
    spec = {"velocity": 180 * DEG, "acceleration": 900 * DEG, "stop_time": 0.1,
            "settings": QUICK}
    motion = envelope(PLANAR2, duty=PLANAR2_MOTION, **spec)
    mix = envelope(PLANAR2, duty=one_task_mix(tmp_path), **spec)
    assert mix.duty.mix is not None and not mix.duty.default
    assert envelope_json(mix)["duty"]["motion"] == str(tmp_path / "one.toml")
    assert without_origin(envelope_json(mix)) == without_origin(envelope_json(motion))
    for a, b in zip(mix.joints, motion.joints, strict=True):
        assert a.sizing.load.mean_torque == b.sizing.load.mean_torque


def test_a_two_task_mix_duty_pools_its_tasks_as_size_does():
    """The envelope's mean torque and mean speed are the mix's own pooled ones from `size`.

    Without mass coupling no rule's torque depends on the units chosen, so the envelope
    (worst states of no duration beside the pooled tasks) and `size` of the mix judge the
    averaged rules on the same samples.
    """
    options = {"mass_coupling": False, "stop_time": 0.15}
    result = envelope(BENCHTOP, duty=PICK_INSPECT, payload=GRIPPER, acceleration=2000 * DEG,
                      settings=QUICK, **options)
    pooled = size(None, PICK_INSPECT, **options)
    assert [task.label for task in result.duty.tasks] == ["pick", "inspect"]
    assert [task.share for task in result.duty.tasks] == [0.7, 0.3]
    for joint, alone in zip(result.joints, pooled.joints, strict=True):
        assert joint.name == alone.name
        mine, own = joint.sizing.load, alone.load
        assert mine.mean_torque == pytest.approx(own.mean_torque, rel=1e-12)
        assert mine.mean_speed == pytest.approx(own.mean_speed, rel=1e-12)
        assert mine.peak_torque >= own.peak_torque  # the worst states add to the peaks
        assert_same_averages(joint.sizing, alone)
    # the duty alone is `size` of the mix: the same units, task by task
    assert ([j.selected.unit.id if j.selected else None for j in result.duty_sizing.joints]
            == [j.selected.unit.id if j.selected else None for j in pooled.joints])
    assert result.duty_sizing.mix is not None and len(result.duty_sizing.tasks) == 2


def test_a_mix_whose_tasks_carry_different_payloads_needs_the_envelopes(capsys, tmp_path):
    """The worst states need one payload: the tasks' differ, so the envelope asks for it."""
    with pytest.raises(InputError, match="different payloads") as info:
        envelope(BENCHTOP, duty=PICK_INSPECT, acceleration=2000 * DEG, settings=QUICK)
    assert info.value.field == "payload"
    out = tmp_path / "out.json"
    status = main(["envelope", str(BENCHTOP), "--acceleration", "2000", "--duty",
                   str(PICK_INSPECT), "--starts", "64", "--json", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and not out.exists()
    assert err.count("\n") == 1 and "--payload" in err and "different payloads" in err


def test_a_mix_giving_motors_is_refused(tmp_path):
    mix = tmp_path / "motors.toml"
    motors = REPO / "motors" / "example_motors.toml"
    mix.write_text(f'robot = "{PLANAR2}"\n[motor]\ncatalog = "{motors}"\n'
                   f'[[task]]\nmotion = "{PLANAR2_MOTION}"\nshare = 1.0\n')
    with pytest.raises(InputError, match="does not choose motors yet") as info:
        envelope(PLANAR2, duty=mix, acceleration=900 * DEG, settings=QUICK)
    assert info.value.path == mix and info.value.field == "motor"


def test_an_envelope_files_duty_may_be_a_mix_and_the_cli_names_its_tasks(capsys, tmp_path):
    """``[duty] motion`` takes a mix file too; the table's duty samples name their task."""
    mix = one_task_mix(tmp_path)
    spec = tmp_path / "spec.toml"
    spec.write_text(f'robot = "{PLANAR2}"\nangle_unit = "deg"\n[limits]\nvelocity = 180\n'
                    f'acceleration = 900\n[duty]\nmotion = "{mix}"\n')
    out = tmp_path / "out.json"
    assert main(["envelope", str(spec), "--starts", "256", "--json", str(out)]) in (0, 1)
    assert "one.toml" in capsys.readouterr().out
    assert '"motion": "' + str(mix) in out.read_text()
    status = main(["envelope", str(BENCHTOP), "--acceleration", "2000", "--duty",
                   str(PICK_INSPECT), "--payload", "0.4", "--starts", "64"])
    text = capsys.readouterr().out
    assert status in (0, 1) and "benchtop6_pick_inspect.toml" in text
    assert "(duty inspect t = " in text or "(duty pick t = " in text


def two_mountings(tmp_path):
    path = tmp_path / "mounted.toml"
    path.write_text(f'robot = "{PLANAR2}"\n'
                    f'[[task]]\nname = "floor"\nmotion = "{PLANAR2_MOTION}"\nshare = 0.5\n'
                    f'[[task]]\nname = "ceiling"\nmotion = "{PLANAR2_MOTION}"\nshare = 0.5\n'
                    'mounting = "ceiling"\n')
    return path


def test_a_mix_whose_tasks_are_mounted_differently_needs_the_envelopes_mounting(tmp_path):
    spec = {"velocity": 180 * DEG, "acceleration": 900 * DEG, "settings": QUICK}
    with pytest.raises(InputError, match="different mountings") as info:
        envelope(PLANAR2, duty=two_mountings(tmp_path), **spec)
    assert info.value.field == "mounting"
    # given: every task runs with it (as `size --mounting` of the mix), and the search too
    result = envelope(PLANAR2, duty=two_mountings(tmp_path), mounting="floor", **spec)
    alone = envelope(PLANAR2, duty=PLANAR2_MOTION, mounting="floor", **spec)
    for a, b in zip(result.joints, alone.joints, strict=True):
        assert a.sizing.load.mean_torque == pytest.approx(b.sizing.load.mean_torque, rel=1e-12)


def test_a_mix_in_cycles_per_hour_keeps_its_idle_time(tmp_path):
    """The idle part of the hour counts as `size` counts it: the same mean speed and life.

    A series whose mean speed is over the whole cycle, pauses included, sees the idle
    time; `size` of the mix is the oracle for every unit's averaged rules.
    """
    catalog = tmp_path / "whole_cycle.toml"
    text = (REPO / "catalogs" / "example_rated_bearing.toml").read_text()
    catalog.write_text(text.replace('mean_speed = "moving"', 'mean_speed = "whole-cycle"'))
    assert 'mean_speed = "whole-cycle"' in catalog.read_text()
    path = tmp_path / "hourly.toml"
    path.write_text(f'robot = "{PLANAR2}"\n'
                    f'[[task]]\nmotion = "{PLANAR2_MOTION}"\ncycles_per_hour = 200\n')
    options = {"mass_coupling": False, "stop_time": 0.1}
    result = envelope(PLANAR2, duty=path, velocity=180 * DEG, acceleration=900 * DEG,
                      settings=QUICK, catalog=[catalog], **options)
    pooled = size(None, path, catalog=[catalog], **options)
    assert 0.0 < result.duty.idle == pooled.idle < 1.0
    for joint, own in zip(result.joints, pooled.joints, strict=True):
        assert joint.sizing.load.mean_speed == pytest.approx(own.load.mean_speed, rel=1e-12)
        assert joint.sizing.load.mean_torque == pytest.approx(own.load.mean_torque, rel=1e-12)
        assert_same_averages(joint.sizing, own)
    assert ([j.selected.unit.id if j.selected else None for j in result.duty_sizing.joints]
            == [j.selected.unit.id if j.selected else None for j in pooled.joints])
