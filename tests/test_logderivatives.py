"""Accelerations from a log of positions only, and the uncertainty stated with them.

Oracles: motions whose accelerations are known in closed form (two sinusoids, quintic
rest-to-rest moves with dwells), logged at several rates with and without an encoder's
quantisation; their exact torques come from the same robot with the closed-form q, qd,
qdd. The stated uncertainty must bound the true error of every joint's peak torque,
and where it is within 1 % so must the error be. The torque bound is checked against
Pinocchio's own joint-space inertia matrix (CRBA).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import hdselect
from hdselect.motion.logderivatives import derivatives, noise_level, peak_uncertainty
from hdselect.motion.planning import Trajectory
from hdselect.robot.dynamics import torque_spread
from helpers import REPO


def sinusoids(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pan 0.6 sin(w t), tilt 0.3 sin(1.7 w t + 0.4), w = 2 pi 0.8 rad/s: q, qd, qdd."""
    w = np.array([2 * np.pi * 0.8, 2 * np.pi * 0.8 * 1.7])
    a, phase = np.array([0.6, 0.3]), np.array([0.0, 0.4])
    x = np.outer(t, w) + phase
    return a * np.sin(x), a * w * np.cos(x), -a * w**2 * np.sin(x)


def quintics(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rest, quintic moves of each joint (pan 0 -> 1 -> 0 rad, tilt 0 -> -0.7 rad), rest."""
    def move(t0, duration, start, end):
        s = np.clip((t - t0) / duration, 0.0, 1.0)
        inside = (t > t0) & (t < t0 + duration)
        return (start + (end - start) * (10 * s**3 - 15 * s**4 + 6 * s**5),
                (end - start) * (30 * s**2 - 60 * s**3 + 30 * s**4) / duration * inside,
                (end - start) * (60 * s - 180 * s**2 + 120 * s**3) / duration**2 * inside)
    out, back, tilt = move(0.3, 0.6, 0.0, 1.0), move(1.2, 0.5, 1.0, 0.0), move(1.2, 0.5, 0.0, -0.7)
    first = t < 1.2
    return tuple(np.column_stack([np.where(first, a, b), c])
                 for a, b, c in zip(out, back, tilt, strict=True))


MOTIONS = {"sinusoids": (sinusoids, 2.5), "quintics": (quintics, 2.2)}
QUANTA = {"exact": None, "17-bit encoder": 2 * math.pi / 2**17,
          "4 decimals of a degree": math.radians(1e-4)}


def log_of(tmp_path, motion: str, hz: int, quantum: float | None):
    """The motion logged at `hz` as t and q only, rounded to `quantum` [rad]; its case."""
    shape, duration = MOTIONS[motion]
    t = np.arange(round(duration * hz) + 1) / hz
    q = shape(t)[0]
    if quantum is not None:
        q = np.round(q / quantum) * quantum
    np.savetxt(tmp_path / "log.csv", np.column_stack([t, q]), delimiter=",",
               header="t,q_pan,q_tilt", comments="", fmt="%.17g")
    (tmp_path / "log.toml").write_text(
        f'robot = "{REPO}/robots/pan_tilt.urdf"\nplanner = "samples"\nangle_unit = "rad"\n'
        f'dt = {1.0 / hz!r}\nmounting = "floor"\n[samples]\nfile = "log.csv"\n')
    return hdselect.load_case(tmp_path / "log.toml")


@pytest.mark.slow
@pytest.mark.parametrize("quantum", QUANTA, ids=str)
@pytest.mark.parametrize("hz", [50, 200, 1000, 4000])
@pytest.mark.parametrize("motion", MOTIONS)
def test_the_stated_uncertainty_bounds_the_true_error_of_every_peak(tmp_path, motion, hz,
                                                                    quantum):
    robot, case = log_of(tmp_path, motion, hz, QUANTA[quantum])
    result = hdselect.size(robot, case)
    logged = result.trajectory
    q, qd, qdd = MOTIONS[motion][0](logged.t)
    exact = Trajectory(logged.joint_names, logged.dt, logged.duration, logged.t, q, qd, qdd)
    truth = hdselect.size_trajectory(robot, exact, result.units)
    for load, true in zip(result.loads, truth.loads, strict=True):
        error = abs(load.peak - true.peak)
        assert error <= load.peak_uncertainty * (1 + 1e-9) + 1e-12, load.name
        if not load.uncertain:  # no warning: the 1 % holds
            assert error <= 0.01 * true.peak, load.name
    if quantum == "exact" and hz >= 1000:  # a clean log at 1 kHz and up: 1 %, said so
        assert not [w for w in result.warnings if "positions only" in w]


def test_a_clean_log_at_a_high_rate_is_exact_and_claims_it():
    t = np.arange(2001) / 1000
    q, _, qdd = sinusoids(t)
    everywhere = np.ones(len(t), dtype=bool)
    _, found, spread = derivatives(t, q, t, everywhere)
    np.testing.assert_allclose(found, qdd, atol=1e-4 * np.abs(qdd).max())
    assert np.all(np.abs(found - qdd) <= spread + 1e-9)
    assert spread.max() <= 1e-3 * np.abs(qdd).max()


def test_the_noise_of_a_quantised_log_is_its_step_over_root_12():
    t = np.arange(4001) / 1000
    q = sinusoids(t)[0][:, 0]
    step = 2 * math.pi / 2**17
    stretches = [(0, len(t) - 1)]
    assert noise_level(np.round(q / step) * step, stretches) == pytest.approx(
        step / math.sqrt(12), rel=0.5)
    assert noise_level(q, stretches) < 1e-3 * step  # a clean motion has next to none
    rng = np.random.default_rng(5)
    noisy = q + rng.normal(0.0, 1e-5, len(q))
    assert noise_level(noisy, stretches) == pytest.approx(1e-5, rel=0.2)


def test_a_crawl_through_equal_positions_is_no_rest():
    """A sinusoid turning within one encoder step repeats its position for a few samples:
    not a rest (acceleration 0 at its largest), part of the moving stretch."""
    t = np.arange(2501) / 1000
    q, _, qdd = sinusoids(t)
    step = 2 * math.pi / 2**17
    _, found, spread = derivatives(t, np.round(q / step) * step, t, np.ones(len(t), bool))
    peak = np.abs(qdd).max(axis=0)
    assert np.all(np.abs(np.abs(found).max(axis=0) - peak) <= 0.02 * peak)
    assert np.all(np.abs(found - qdd).max(axis=0) <= spread.max(axis=0))


def test_peak_uncertainty_by_hand():
    values = np.array([1.0, -3.0, 2.5, 0.0])
    assert peak_uncertainty(values, np.array([0.1, 0.2, 0.3, 0.0])) == pytest.approx(0.2)
    # a sample below the peak whose spread reaches above it sets the bound
    assert peak_uncertainty(values, np.array([0.1, 0.2, 1.0, 0.0])) == pytest.approx(0.5)
    assert peak_uncertainty(np.empty(0), np.empty(0)) == 0.0


def test_the_torque_bound_is_the_inertia_matrix_times_the_acceleration_bound():
    robot = hdselect.load_robot(REPO / "robots" / "benchtop6.urdf")
    rng = np.random.default_rng(3)
    q = rng.uniform(-1.5, 1.5, (7, robot.dof))
    spread = rng.uniform(0.0, 2.0, (7, robot.dof))
    spread[2] = 0.0  # a sample known exactly
    spread[:, 4] = 0.0  # a joint known exactly
    found = torque_spread(robot, q, spread)
    data = robot.model.createData()
    for k in range(len(q)):
        inertia = pin.crba(robot.model, data, robot.configuration(q[k:k + 1])[:, 0])
        inertia = np.triu(inertia) + np.triu(inertia, 1).T
        np.testing.assert_allclose(found[k], np.abs(inertia) @ spread[k], rtol=1e-9,
                                   atol=1e-12)
    assert np.all(found[2] == 0.0)


@pytest.mark.slow
def test_the_terminal_json_and_report_state_an_uncertain_peak(tmp_path, capsys):
    """A quintic logged at 4 kHz through a 17-bit encoder: pan's peak is uncertain by more
    than 1 %, and the terminal, the JSON and the HTML report say so; a planned motion's
    JSON has no uncertainty (null)."""
    import json

    from hdselect.cli.main import main

    log_of(tmp_path, "quintics", 4000, QUANTA["17-bit encoder"])
    status = main(["size", str(tmp_path / "log.toml"), "--json", str(tmp_path / "out.json"),
                   "--report", str(tmp_path / "report")])
    out = " ".join(capsys.readouterr().out.split())
    assert status == 0
    assert "cycle: joint 'pan' peaks at" in out and "gives positions only" in out
    doc = json.loads((tmp_path / "out.json").read_text())
    (line,) = [w for w in doc["warnings"] if "positions only" in w and "'pan'" in w]
    loads = {load["name"]: load for load in doc["joint_loads"]}
    pan = loads["pan"]
    assert pan["peak_torque_uncertainty_nm"] > 0.01 * pan["peak_torque_nm"]
    assert f"+- {pan['peak_torque_uncertainty_nm']:.2g} N m" in line
    html = " ".join((tmp_path / "report" / "index.html").read_text().split())
    assert "cycle: joint &#x27;pan&#x27; peaks at" in html or "cycle: joint 'pan' peaks at" in html
    main(["size", str(REPO / "trajectories" / "pan_tilt_scan.toml"), "--json",
          str(tmp_path / "planned.json")])
    planned = json.loads((tmp_path / "planned.json").read_text())
    assert all(load["peak_torque_uncertainty_nm"] is None for load in planned["joint_loads"])
    assert not [w for w in planned["warnings"] if "positions only" in w]


@pytest.mark.parametrize(("t", "pan"), [
    ([0.0, 0.01], [0.0, 0.1]),  # two samples: a straight line, acceleration unknown
    ([0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06], np.arange(7) * 0.01),  # a ramp, no rest
    (np.arange(100) * 0.01, np.r_[np.zeros(50), np.ones(50)]),  # a jump between rests
])
def test_a_log_too_short_to_check_is_uncertain_by_its_whole_acceleration(tmp_path, t, pan):
    """Hostile logs: no claim of 1 % where the log cannot check its accelerations, the
    warning given (a peak of 0 too), every number finite."""
    t, pan = np.asarray(t, dtype=float), np.asarray(pan, dtype=float)
    np.savetxt(tmp_path / "log.csv", np.column_stack([t, pan, np.zeros(len(t))]), delimiter=",",
               header="t,q_pan,q_tilt", comments="", fmt="%.17g")
    (tmp_path / "log.toml").write_text(
        f'robot = "{REPO}/robots/pan_tilt.urdf"\nplanner = "samples"\nangle_unit = "rad"\n'
        'dt = 0.001\n[samples]\nfile = "log.csv"\n')
    result = hdselect.size(*hdselect.load_case(tmp_path / "log.toml"))
    (load,) = [load for load in result.loads if load.name == "pan"]
    assert math.isfinite(load.peak_uncertainty)
    assert load.peak_uncertainty > 0.0 and load.uncertain
    assert [w for w in result.warnings if w.startswith("cycle: joint 'pan'")
            and "positions only" in w]


def test_plan_says_when_a_logs_accelerations_are_not_known_to_one_percent(tmp_path, capsys):
    from hdselect.cli.main import main

    log_of(tmp_path, "quintics", 4000, QUANTA["17-bit encoder"])
    assert main(["plan", str(tmp_path / "log.toml"), "--out", str(tmp_path / "q.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "positions only" in out and "for 'pan'" in out
    log_of(tmp_path, "sinusoids", 1000, None)  # clean at 1 kHz: nothing to say
    assert main(["plan", str(tmp_path / "log.toml"), "--out", str(tmp_path / "q.csv")]) == 0
    assert "positions only" not in capsys.readouterr().out
