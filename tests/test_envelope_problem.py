"""The envelope's duty resolved by the one resolver: a mounting blamed as given, a mix's figures.

Oracles: the input that gave a mounting (the parameter, the envelope file's key), which
a tool pose it cannot place must name; and the figures of each task's own trajectory (a
duty's cycle time and samples are one cycle of each task in turn, a motion's its own).
"""

from __future__ import annotations

import math

import pytest

from hdselect import InputError
from hdselect.cli.main import main
from hdselect.envelope import SearchSettings, envelope
from hdselect.envelope.records import envelope_json
from hdselect.robot.payload import Payload
from helpers import REPO
from helpers.mixes import PLANAR2, PLANAR2_MOTION, POSES, poses_mix, two_mountings

DEG = math.pi / 180.0
BENCHTOP = REPO / "robots" / "benchtop6.urdf"
QUICK = SearchSettings(starts=64)
GRAVITY = (0.0, 0.0, -9.81)
"""A mounting as a gravity vector: it places no base, so tool poses cannot be solved."""
GRIPPER = Payload(0.4, (0.0, 0.0, 0.03), ((1.7e-4, 0, 0), (0, 1.7e-4, 0), (0, 0, 1.7e-4)),
                  "tool0")


def test_an_envelopes_mounting_is_blamed_where_it_was_given(tmp_path, capsys):
    """The parameter (``mounting``), else the envelope file's ``mounting``; one line, exit 2."""
    mix = poses_mix(tmp_path)
    for duty in (mix, POSES):
        with pytest.raises(InputError, match="does not place the base") as info:
            envelope(BENCHTOP, duty=duty, payload=GRIPPER, mounting=GRAVITY,
                     acceleration=2000 * DEG, settings=QUICK)
        assert info.value.path is None and info.value.field == "mounting", duty
    file = tmp_path / "spec.toml"
    file.write_text(f'robot = "{BENCHTOP}"\nangle_unit = "deg"\n'
                    "mounting = [0.0, 0.0, -9.81]\n"
                    f'[limits]\nacceleration = 2000\n[duty]\nmotion = "{mix}"\n')
    for duty in (mix, POSES):
        with pytest.raises(InputError, match="does not place the base") as info:
            envelope(file, duty=duty, payload=GRIPPER, settings=QUICK)
        assert info.value.path == file and info.value.field == "mounting", duty
    out = tmp_path / "out.json"
    status = main(["envelope", str(file), "--payload", "0.4", "--starts", "64",
                   "--json", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and not out.exists() and err.count("\n") == 1
    assert f"{file}: mounting: " in err and "benchtop6_pick_place_poses.toml" in err


def test_a_mix_duty_gives_the_figures_of_every_task(tmp_path):
    """cycle_time_s and samples: one cycle of each task in turn; each task's own below."""
    spec = {"mounting": "floor", "velocity": 180 * DEG, "acceleration": 900 * DEG,
            "settings": QUICK}
    result = envelope(PLANAR2, duty=two_mountings(tmp_path), **spec)
    duty = envelope_json(result)["duty"]
    trajectories = [task.trajectory for task in result.duty.tasks]
    assert duty["tasks"] == [
        {"name": name, "share": 0.5, "cycle_time_s": t.duration, "samples": len(t.t)}
        for name, t in zip(("floor", "ceiling"), trajectories, strict=True)]
    assert duty["cycle_time_s"] == pytest.approx(2 * trajectories[0].duration, rel=1e-15)
    assert duty["samples"] == 2 * len(trajectories[0].t) > len(trajectories[0].t)
    alone = envelope_json(envelope(PLANAR2, duty=PLANAR2_MOTION, **spec))["duty"]
    assert "tasks" not in alone and alone["samples"] == len(trajectories[0].t)
    assert alone["cycle_time_s"] == trajectories[0].duration
