"""Physical ranges and Python argument types: one refusal, naming the field and the range."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hdselect.base import bounds
from hdselect.base.errors import InputError


@pytest.mark.parametrize(("value", "text"), [
    (0.0, "must be a positive mass, at most 100000 kg, got 0"),
    (-1, "must be a positive mass, at most 100000 kg, got -1"),
    (1e308, "at most 100000 kg, got 1e+308"),
    (math.nan, "must be finite, got nan"),
    (math.inf, "must be finite, got inf"),
    (10**400, "an integer too large for a float"),
    (True, "expected a number, got True"),
    ("1", "expected a number, got '1'"),
    (None, "expected a number, got None"),
])
def test_a_value_out_of_range_is_refused_with_the_range(value, text):
    with pytest.raises(InputError) as info:
        bounds.MASS.check(value, path="robot.urdf", field="link[a].mass")
    assert info.value.field == "link[a].mass" and text in str(info.value)
    assert str(info.value).startswith("robot.urdf: link[a].mass: ")


def test_the_range_is_stated_in_the_unit_the_value_was_given_in():
    limit = bounds.MOTION_LIMITS["velocity"]
    degrees = math.pi / 180
    assert limit.check(100.0, scale=degrees, unit="deg/s") == 100.0
    with pytest.raises(InputError, match=r"between 5.72958e-05 and 5.72958e\+07 deg/s, got 1e\+08"):
        limit.check(1e8, scale=degrees, unit="deg/s")
    assert bounds.DWELL.describe() == "a time of at least 0, at most 1e+12 s"
    assert bounds.EFFICIENCY.describe() == "an efficiency between 0.01 and 1"


def test_the_ranges_keep_every_product_of_valid_inputs_finite():
    """The worst products the dynamics and the rules form from values at their limits."""
    reach, speed = bounds.LENGTH.high, bounds.MOTION_LIMITS["velocity"].high
    torque = bounds.MASS.high * reach * (bounds.GRAVITY.high + reach * speed**2
                                         + reach * bounds.MOTION_LIMITS["acceleration"].high)
    crash = (bounds.GEAR_INERTIA.high + bounds.ROTOR_INERTIA.high) * bounds.RATIO.high**2 \
        / bounds.STOP_TIME.low * bounds.MOTION_LIMITS["velocity"].high
    life = bounds.LIFE.high * bounds.INPUT_SPEED.high * bounds.TORQUE.high**3
    assert all(np.isfinite([torque, crash, life, torque**3])), (torque, crash, life)


@pytest.mark.parametrize("value", [0, 1, -3, 2.5, True, "100", None])
def test_max_samples_is_a_whole_number_of_two_or_more(value):
    with pytest.raises(InputError) as info:
        bounds.check_max_samples(value)
    assert info.value.field == "max_samples"
    assert bounds.check_max_samples(2) == 2


def test_file_arguments():
    assert bounds.file_argument("a.toml", "path") == Path("a.toml")
    assert bounds.files_argument(("a.toml", Path("b.toml")), "extra") == [Path("a.toml"),
                                                                          Path("b.toml")]
    for value in ("a.toml", Path("a.toml"), b"a.toml", 3, ["a.toml", 3]):
        with pytest.raises(InputError) as info:
            bounds.files_argument(value, "extra")
        assert info.value.field == "extra"
    for value in (None, 3, ""):
        with pytest.raises(InputError, match="expected a file name"):
            bounds.file_argument(value, "path")


def test_a_quantity_that_divides_is_zero_or_not_tiny():
    """A rotor inertia divides the load inertia: 0 (none) or at least 1e-12 kg m^2, checked
    as given, so a value in kg cm^2 that would underflow to 0 in SI is refused too."""
    assert bounds.ROTOR_INERTIA.check(0.0) == 0.0
    assert bounds.ROTOR_INERTIA.check(1e-12) == 1e-12
    for value, scale in ((1e-13, 1.0), (5e-324, 1.0), (1e-320, 1e-4), (-0.0 + 1e-9, 1e-4)):
        with pytest.raises(InputError, match="must be 0 or at least"):
            bounds.ROTOR_INERTIA.check(value, scale=scale, unit="kg cm^2")
