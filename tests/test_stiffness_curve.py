"""The torsion curve and the single-axis resonance against Harmonic Drive's own examples."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdselect.catalog.stiffness import (
    natural_frequency,
    rates_torsion,
    resonance_speed,
    torque_at_torsion,
    torsion,
)
from hdselect.catalog.units import RAD_PER_ARCMIN, Stiffness

HFUC_32_100 = Stiffness(t1=29.0, k1=6.7e4, k2=1.1e5)
"""Harmonic Drive's torsion example (HFUC-32-100; its T2 is not reached at 60 N m)."""


def test_harmonic_drives_torsion_example():
    # 29 / 6.7e4 + (60 - 29) / 1.1e5 = 4.328e-4 + 2.818e-4 = 7.146e-4 rad = 2.46 arcmin
    twist = float(torsion(HFUC_32_100, 60.0))
    assert twist == pytest.approx(29.0 / 6.7e4 + 31.0 / 1.1e5, rel=1e-12)
    assert twist == pytest.approx(7.15e-4, abs=5e-7)
    assert twist / RAD_PER_ARCMIN == pytest.approx(2.5, abs=0.05)


def test_the_three_segments_by_hand():
    curve = Stiffness(t1=10.0, t2=30.0, k1=1e4, k2=2e4, k3=4e4)
    torques = np.array([-50.0, -10.0, 0.0, 5.0, 10.0, 20.0, 30.0, 50.0])
    by_hand = np.array([-(1e-3 + 1e-3 + 20 / 4e4), -1e-3, 0.0, 5e-4, 1e-3,
                        1e-3 + 10 / 2e4, 2e-3, 2e-3 + 20 / 4e4])
    np.testing.assert_allclose(torsion(curve, torques), by_hand, rtol=1e-12, atol=0)


@pytest.mark.parametrize("curve", [
    Stiffness(k1=1e4),
    Stiffness(t1=10.0, k1=1e4),  # K2 missing: K1 goes on
    Stiffness(t1=10.0, t2=30.0, k1=1e4, k2=2e4),  # K3 missing: K2 goes on
    Stiffness(t1=10.0, t2=30.0, k1=1e4, k2=2e4, k3=4e4),
])
def test_a_segment_not_rated_continues_the_one_before(curve):
    segments = [(0.0, 1e4), (10.0, 2e4), (30.0, 4e4)]
    used = 1 + (curve.k2 is not None) + (curve.k3 is not None)
    by_hand = 0.0
    for k, (corner, rate) in enumerate(segments[:used]):
        end = segments[k + 1][0] if k + 1 < used else 100.0
        by_hand += (min(100.0, end) - corner) / rate
    assert float(torsion(curve, 100.0)) == pytest.approx(by_hand, rel=1e-12)
    # never below the full curve: the curve stiffens
    assert float(torsion(curve, 100.0)) >= float(torsion(segments_curve(), 100.0))


def segments_curve() -> Stiffness:
    return Stiffness(t1=10.0, t2=30.0, k1=1e4, k2=2e4, k3=4e4)


@pytest.mark.parametrize("torque", [0.0, 3.0, 10.0, 17.0, 30.0, 123.0])
def test_torque_at_torsion_inverts_torsion(torque):
    curve = segments_curve()
    assert torque_at_torsion(curve, float(torsion(curve, torque))) == pytest.approx(torque,
                                                                                   rel=1e-12)


def test_rated_only_with_k1():
    assert not rates_torsion(None)
    assert not rates_torsion(Stiffness(hysteresis_loss=1e-4))
    assert rates_torsion(Stiffness(k1=1.0))
    with pytest.raises(ValueError):
        torsion(Stiffness(hysteresis_loss=1e-4), 1.0)


def test_single_axis_resonance_as_the_csf_manual_computes_it():
    # K = 6.7e4 N m/rad on J = 1 kg m^2: sqrt(6.7e4) / 2 pi = 41.2 Hz
    assert float(natural_frequency(6.7e4, 1.0)) == pytest.approx(math.sqrt(6.7e4) / (2 * math.pi))
    assert float(natural_frequency(1.0, 0.0)) == math.inf
    # CSF-3 manual, chapter 8: a 15 Hz system is excited at N = 15 / 2 x 60 = 450 r/min
    assert float(resonance_speed(15.0)) == pytest.approx(450.0)
