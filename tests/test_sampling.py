"""Demands do not depend on sampling: any dt, and logs of positions only.

Oracles: the same motion sampled every 0.1 ms (converged: the demands then change by
less than 0.05 % when halved again), and the planned trajectory a log was written from.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import hdselect
from hdselect.motion.planning import plan
from helpers import REPO

TRAJECTORIES = REPO / "trajectories"
FINE = 1e-4
"""The converged sample period [s]."""


def with_dt(tmp_path: Path, name: str, dt: float) -> Path:
    """A copy of a shipped motion with another dt, its robot path made absolute."""
    text = (TRAJECTORIES / name).read_text().replace('"../robots/', f'"{REPO}/robots/')
    out = tmp_path / f"{Path(name).stem}_{dt:g}.toml"
    out.write_text(re.sub(r"(?m)^dt = .*$", f"dt = {dt}", text))
    return out


def demands(result, units=None) -> dict[str, dict[str, float]]:
    """Peak, mean and motor peak and RMS torque per joint, for the units given (or chosen)."""
    out = {}
    for joint in result.joints:
        chosen = joint.selected or joint.strongest
        if units is not None:
            chosen = next(c for c in joint.candidates if c.unit.id == units[joint.name])
        out[joint.name] = {"peak": joint.load.peak_torque, "mean": joint.load.mean_torque or 0.0,
                           "motor peak": chosen.motor.peak_torque,
                           "motor rms": chosen.motor.rms_torque, "unit": chosen.unit.id}
    return out


def worst(found, reference) -> float:
    """The largest relative difference of any demand of any joint [-]."""
    return max(abs(found[j][k] - reference[j][k]) / abs(reference[j][k])
               for j in reference for k in reference[j]
               if k != "unit" and abs(reference[j][k]) > 1e-9)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "dts"), [
    ("benchtop6_pick_place.toml", (0.001, 0.004, 0.008, 0.03)),  # Ruckig, six joints
    ("planar2_pick_place.toml", (0.002, 0.016, 0.1)),
    ("pan_tilt_scan.toml", (0.001, 0.004, 0.016, 0.05)),  # TOPPRA
])
def test_every_dt_gives_the_converged_demands_to_one_percent(tmp_path, name, dts):
    reference = hdselect.size(None, with_dt(tmp_path, name, FINE))
    expected = demands(reference)
    units = {j: d["unit"] for j, d in expected.items()}
    for dt in dts:
        result = hdselect.size(None, with_dt(tmp_path, name, dt))
        assert result.trajectory.dt <= dt
        assert worst(demands(result, units), expected) <= 0.01, dt


@pytest.mark.slow
def test_benchtop6_at_dt_0_008_finds_its_elbow_peak(tmp_path):
    """The battery's case: 4.4 % low before the grid was refined."""
    fine = hdselect.size(None, with_dt(tmp_path, "benchtop6_pick_place.toml", FINE))
    coarse = hdselect.size(None, with_dt(tmp_path, "benchtop6_pick_place.toml", 0.008))
    peak = {j.name: j.load.peak_torque for j in fine.joints}
    assert {j.name: j.load.peak_torque for j in coarse.joints}["elbow"] == pytest.approx(
        peak["elbow"], rel=0.01)
    assert coarse.trajectory.t[::round(0.008 / coarse.trajectory.dt)][:5] == pytest.approx(
        np.arange(5) * 0.008)  # the file's grid points are samples


def write_log(tmp_path: Path, name: str, hz: int) -> tuple[Path, object]:
    """The shipped motion planned every 0.1 ms, logged as t and q only at `hz`."""
    source = with_dt(tmp_path, name, FINE)
    robot, motion = hdselect.load_case(source)
    trajectory = plan(robot, motion)
    step = round(1.0 / hz / FINE)
    log = tmp_path / f"{Path(name).stem}_{hz}.csv"
    header = ",".join(["t", *(f"q_{n}" for n in robot.joint_names)])
    np.savetxt(log, np.column_stack([trajectory.t[::step], trajectory.q[::step]]),
               delimiter=",", header=header, comments="", fmt="%.17g")
    text = source.read_text()
    keep = "\n".join(line for line in text.splitlines()
                     if line.startswith(("robot", "mounting")))
    motion_file = tmp_path / f"{Path(name).stem}_{hz}.toml"
    motion_file.write_text(f'{keep}\nplanner = "samples"\nangle_unit = "rad"\n'
                           f'dt = {1.0 / hz}\n{carried_tables(text, motion, trajectory)}\n'
                           f'[samples]\nfile = "{log.name}"\n')
    return motion_file, trajectory


def carried_tables(text: str, motion, trajectory) -> str:
    """The motion file's [payload] and [payloads.*] tables, and its payload events as the
    log's [[event]] times: an attach on arrival, a release at the end of its dwell."""
    doc = tomllib.loads(text)
    tables = [("payload", doc["payload"])] if "payload" in doc else []
    tables += [(f"payloads.{name}", table) for name, table in doc.get("payloads", {}).items()]
    out = "".join(f"[{key}]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in table.items())
                  for key, table in tables)
    for event in motion.events:
        t = trajectory.waypoint_times[event.waypoint]
        t += 0.0 if event.attach else motion.dwells[event.waypoint]
        key = "attach" if event.attach else "release"
        out += f'[[event]]\nt = {float(t)!r}\n{key} = "{event.part}"\n'
    return out


@pytest.mark.slow
@pytest.mark.parametrize("hz", [1000, 200])
def test_a_log_of_positions_only_gives_the_planned_demands(tmp_path, hz):
    """Velocities and accelerations from positions alone, against the planned ones: 1 %."""
    motion_file, planned = write_log(tmp_path, "planar2_pick_place.toml", hz)
    robot, motion = hdselect.load_case(motion_file)
    logged = plan(robot, motion)
    step = round(1.0 / hz / FINE)
    for name in ("qd", "qdd"):
        truth = getattr(planned, name)[::step][:len(logged.t)]
        error = np.abs(getattr(logged, name) - truth).max(axis=0)
        assert np.all(error <= 0.01 * np.abs(truth).max(axis=0)), name
    assert np.all(logged.qd[logged.t < 0.3 - 1e-9] == 0.0)  # the first dwell exactly at rest
    reference = demands(hdselect.size(None, with_dt(tmp_path, "planar2_pick_place.toml", FINE)))
    units = {j: d["unit"] for j, d in reference.items()}
    result = hdselect.size(robot, motion)
    assert worst(demands(result, units), reference) <= 0.01
    assert not [w for w in result.warnings if "positions only" in w]


@pytest.mark.slow
@pytest.mark.parametrize(("name", "hz"), [
    ("pan_tilt_scan.toml", 1000),  # TOPPRA: its acceleration steps every few ms
    ("pan_tilt_scan.toml", 200),
    ("benchtop6_pick_place.toml", 200),  # Ruckig, six joints
])
def test_a_log_of_positions_only_states_each_peaks_uncertainty(tmp_path, name, hz):
    """Issue 27: each joint's peak torque from a log of positions only is within its stated
    uncertainty of the planned motion's; where none is stated, within 1 %, and a warning
    names exactly the joints whose uncertainty exceeds 1 %."""
    motion_file, _ = write_log(tmp_path, name, hz)
    result = hdselect.size(*hdselect.load_case(motion_file))
    planned = hdselect.size(None, with_dt(tmp_path, name, FINE))
    reference = {load.name: load.peak for load in planned.loads}
    warned = {w.split("'")[1] for w in result.warnings if "positions only" in w}
    for load in result.loads:
        error = abs(load.peak - reference[load.name])
        assert error <= load.peak_uncertainty, load.name
        assert (load.name in warned) == (load.peak_uncertainty > 0.01 * load.peak), load.name
        if load.name not in warned:
            assert error <= 0.01 * reference[load.name], load.name
    moving = {joint.name: joint.load.peak_torque for joint in planned.joints}
    uncertainty = {load.name: load.peak_uncertainty for load in result.loads}
    for joint in result.joints:  # the peak while moving, which the catalog's rules judge
        error = abs(joint.load.peak_torque - moving[joint.name])
        assert error <= uncertainty[joint.name], joint.name
        if joint.name not in warned:
            assert error <= 0.01 * moving[joint.name], joint.name
    expected = demands(planned)  # and the motor peaks of the joints not warned of, to 1 %
    found = demands(result, {j: d["unit"] for j, d in expected.items()})
    for joint in set(expected) - warned:
        assert found[joint]["motor peak"] == pytest.approx(expected[joint]["motor peak"],
                                                           rel=0.01), joint
    assert warned  # TOPPRA's steps and Ruckig's 200 Hz do not fix every peak to 1 %
    (line,) = [w for w in result.warnings if w.startswith(f"cycle: joint '{min(warned)}'")]
    assert "+-" in line and "qd_ and qdd_ columns" in line


def test_the_same_log_with_its_own_columns_needs_no_warning(tmp_path):
    motion_file, planned = write_log(tmp_path, "pan_tilt_scan.toml", 1000)
    robot, motion = hdselect.load_case(motion_file)
    log = motion.samples.path
    step = round(1e-3 / FINE)
    header = ",".join(["t", *(f"{k}_{n}" for k in ("q", "qd", "qdd") for n in robot.joint_names)])
    np.savetxt(log, np.column_stack([planned.t[::step], planned.q[::step], planned.qd[::step],
                                     planned.qdd[::step]]), delimiter=",", header=header,
               comments="", fmt="%.17g")
    result = hdselect.size(*hdselect.load_case(motion_file))
    assert not [w for w in result.warnings if "positions only" in w]


def test_a_joint_at_rest_holds_through_the_gear_whatever_the_sign_of_a_tiny_speed():
    """At rest (speed and acceleration negligible) the motor holds: tau / (N eta), not
    tau eta / N, even where rounding gives the speed a sign."""
    from hdselect.sizing.reflect import reflect

    unit = hdselect.load_catalog()[-1]
    n = 1000
    tau = np.full(n, 2.0)
    qd = np.r_[np.linspace(0, 1, n // 2), np.full(n // 2, 0.0)]
    qd[n // 2:] = np.where(np.arange(n // 2) % 2, 1e-15, -1e-15)  # rounding at rest
    qdd = np.r_[np.full(n // 2, 1.0), np.zeros(n // 2)]
    (r,) = reflect([unit], np.arange(n) * 1e-3, tau, qd, qdd, tau, stop_time=0.1)
    held = r.motor_torque[n // 2:]
    np.testing.assert_allclose(held, 2.0 / (unit.ratio * 0.7), rtol=1e-12)
