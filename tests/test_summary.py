"""The compact result: small, picklable, and the same answer as the full one."""

from __future__ import annotations

import json
import pickle

import pytest

from hdselect import size
from hdselect.catalog.checks import LIFE_CAP
from hdselect.sizing.summary import summarize
from helpers import REPO
from helpers.dynamics import MOTIONS


@pytest.mark.slow
@pytest.mark.parametrize("path", MOTIONS, ids=lambda p: p.stem)
def test_summary_carries_the_answer_of_the_full_result(path):
    result = size(None, path)
    summary = summarize(result)
    assert summary.feasible == result.feasible
    assert summary.cycle_time == result.cycle_time
    assert summary.samples == len(result.trajectory.t)
    assert summary.motion == str(path)
    assert [j.name for j in summary.joints] == [j.name for j in result.joints]
    assert summary.root_link == result.robot.root_link == "base_link"
    assert summary.payload_frame == result.robot.payload_frame
    assert summary.payload_mass == (result.robot.payload.mass if result.robot.payload else 0.0)
    assert summary.warnings == result.warnings
    for short, joint in zip(summary.joints, result.joints, strict=True):
        chosen = joint.selected or joint.strongest
        assert short.unit == (joint.selected.unit.id if joint.selected else None)
        assert short.candidate == chosen.unit.id
        assert short.binding == chosen.binding
        assert short.utilization == {n: c.utilization for n, c in chosen.checks.items()}
        # lives as every output reports them: at most the cap, flagged when capped
        capped = chosen.life_hours is not None and chosen.life_hours >= LIFE_CAP
        assert short.life_capped == capped
        assert short.life_l50_hours == (LIFE_CAP if capped else chosen.life_hours)
        assert short.life_l10_hours == (None if chosen.l10_hours is None
                                        else min(chosen.l10_hours, LIFE_CAP))
        assert short.motor_rms_torque == chosen.motor.rms_torque
        assert short.motor_peak_torque == chosen.motor.peak_torque
        assert short.motor_max_speed == chosen.motor.max_speed
        assert short.carried_mass == joint.carried_mass
        assert set(short.flags) == {flag.code for flag in chosen.flags}


def test_a_six_axis_summary_pickles_under_20_kb_and_round_trips():
    result = size(None, REPO / "trajectories" / "benchtop6_pick_place.toml")
    summary = summarize(result)
    data = pickle.dumps(summary)
    assert len(data) < 20_000 < len(pickle.dumps(result))
    assert pickle.loads(data) == summary
    json.dumps(summary.to_dict(), allow_nan=False)  # strict JSON: every number finite or null
