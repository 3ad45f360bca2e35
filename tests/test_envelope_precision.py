"""The envelope and the precision targets: its file's ``[precision]`` keys, its figures.

The envelope's figures are its duty's with its units: the oracle is the core's own
check of those units along the duty (`check_units`), a separate path to the figures.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdselect import load_catalog
from hdselect.base.errors import InputError
from hdselect.catalog.stiffness import torsion
from hdselect.catalog.units import RAD_PER_ARCMIN
from hdselect.cli.main import main
from hdselect.envelope import SearchSettings, envelope
from hdselect.envelope.records import envelope_json
from hdselect.envelope.torques import PRECISION_NOTE
from hdselect.sizing.core import check_units
from helpers import REPO

PLANAR = REPO / "robots" / "planar2.urdf"
LIMITS = {"velocity": 3.0, "acceleration": 15.0}
QUICK = SearchSettings(starts=64, refine=1, rounds=0, iterations=5)
"""A search that only has to run: the options reach the sizing whatever it finds."""


@pytest.fixture(scope="module")
def shg():
    return load_catalog(["shg-2uh"], series=["SHG-2UH"])


@pytest.fixture(scope="module")
def planar(shg):
    return envelope(PLANAR, catalog=shg, **LIMITS)


def _relative(a: float, b: float) -> float:
    return 0.0 if a == b else abs(a - b) / max(abs(a), abs(b))


def test_the_figures_are_the_duty_s_with_the_envelope_s_units(planar):
    result = planar
    figures = result.sizing.precision
    assert figures is not None and figures.tool is not None and figures.modes is not None
    task = result.duty.tasks[0]
    units = {joint.name: joint.selected.unit for joint in result.joints}
    oracle = check_units(task.robot, task.trajectory, units, result.sizing.options).precision
    assert oracle is not None and oracle.tool is not None and oracle.modes is not None
    for mine, theirs in zip(figures.joints, oracle.joints, strict=True):
        assert mine.unit is units[mine.name] and mine.rated
        for name in ("max_torsion", "holding_torsion", "lowest_frequency"):
            assert _relative(getattr(mine, name), getattr(theirs, name)) < 1e-12, name
    assert _relative(figures.tool.max_holding, oracle.tool.max_holding) < 1e-12
    assert _relative(figures.tool.max_translation, oracle.tool.max_translation) < 1e-12
    assert _relative(figures.modes.lowest_frequency, oracle.modes.lowest_frequency) < 1e-12
    # the duty's samples, not the worst states (which stand for no time)
    assert len(figures.joints[0].torsion) == len(task.trajectory.t)
    assert envelope_json(result)["precision_note"] == PRECISION_NOTE


@pytest.mark.slow
def test_no_precision_leaves_the_figures_out(shg):
    result = envelope(PLANAR, catalog=shg, precision=False, settings=QUICK, **LIMITS)
    assert result.sizing.precision is None
    document = envelope_json(result)
    assert document["precision"] is None and document["precision_note"] is None


def _spec(folder, precision: str):
    path = folder / "spec.toml"
    path.write_text(f"""robot = "{PLANAR}"
angle_unit = "rad"
[limits]
velocity = {LIMITS['velocity']}
acceleration = {LIMITS['acceleration']}
[precision]
{precision}
""")
    return path


@pytest.mark.slow
def test_the_envelope_file_s_precision_keys_reach_the_sizing(tmp_path, shg):
    spec = _spec(tmp_path, "max_torsion_arcmin = {shoulder = 20.0, \"*\" = 30.0}\n"
                           "min_natural_frequency_hz = \"slow-turntables\"")
    result = envelope(spec, catalog=shg, settings=QUICK)
    options = result.sizing.options
    assert math.isclose(options.joint_value("max_torsion", "shoulder"), 20.0 * RAD_PER_ARCMIN)
    assert math.isclose(options.joint_value("max_torsion", "elbow"), 30.0 * RAD_PER_ARCMIN)
    assert options.joint_value("min_natural_frequency", "elbow") == 4.0
    for joint in result.joints:  # the targets are rules of the envelope's selection
        assert {"torsion", "natural_frequency"} <= set(joint.selected.checks)
    given = envelope(spec, catalog=shg, max_torsion={"*": 10.0 * RAD_PER_ARCMIN},
                     settings=QUICK)
    assert given.sizing.options.joint_value("max_torsion", "shoulder") == pytest.approx(
        10.0 * RAD_PER_ARCMIN)  # an argument replaces the file's


@pytest.mark.parametrize(("line", "field"), [
    ("max_torsion_arcmin = {wrist = 2.0}", "precision.max_torsion_arcmin"),
    ("min_natural_frequency_hz = \"hands\"", "precision.min_natural_frequency_hz"),
    ("max_tool_deflection_mm = -1.0", "precision.max_tool_deflection_mm"),
    ("stiff = true", "precision.stiff"),
])
def test_a_bad_precision_key_is_refused_naming_it(tmp_path, shg, line, field):
    with pytest.raises(InputError) as caught:
        envelope(_spec(tmp_path, line), catalog=shg)
    assert caught.value.path == tmp_path / "spec.toml"
    assert str(caught.value.field).startswith(field)


@pytest.mark.parametrize("key", ["max_tool_deflection_mm = 5.0", "min_arm_frequency_hz = 2.0"])
def test_a_whole_arm_target_is_refused_naming_where_it_came_from(tmp_path, shg, key, capsys):
    spec = _spec(tmp_path, key)
    with pytest.raises(InputError) as caught:
        envelope(spec, catalog=shg)
    assert caught.value.path == spec and caught.value.field == "precision." + key.split()[0]
    assert "per-joint precision targets only" in caught.value.reason
    flag = "--max-tool-deflection" if "tool" in key else "--min-arm-frequency"
    status = main(["envelope", str(PLANAR), "--velocity", "180", "--acceleration", "900",
                   flag, "2"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and f"error: {flag}: " in err


@pytest.mark.slow
def test_a_torsion_target_is_judged_at_the_worst_states(planar, shg):
    free = planar.joints[0]  # the shoulder
    worst = float(np.max(np.abs(free.sizing.torque)))
    assert free.worst["peak"].source == "search"  # its largest torque is a worst state's
    twist = torsion(free.selected.unit.stiffness, worst)
    bound = envelope(PLANAR, catalog=shg, max_torsion={"shoulder": 0.7 * twist}, **LIMITS)
    shoulder = bound.joints[0]
    check = shoulder.selected.checks["torsion"]
    largest = float(np.max(np.abs(shoulder.sizing.torque)))  # over the duty and the states
    assert check.ok and shoulder.selected.unit is not free.selected.unit
    assert math.isclose(check.value * RAD_PER_ARCMIN,
                        torsion(shoulder.selected.unit.stiffness, largest), rel_tol=1e-12)
    assert check.value * RAD_PER_ARCMIN <= 0.7 * twist
