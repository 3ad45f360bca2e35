"""Made-up series for the output-bearing tests: PSA-G's rules, and a strong gear on a weak
bearing."""

from __future__ import annotations

from helpers import REPO

PICK = REPO / "trajectories" / "benchtop6_pick_place.toml"
SPIN_RULES = """[rules]
rated_input_speed_rpm = 1750
rated_life_hours = 35000
life_basis = "L50"
mean_torque_limit = "speed-adjusted"
mean_speed = "moving"
max_momentary_events = 10000
"""
"""The rules of the made-up series (PSA-G's, by the catalog page)."""

BEARING_BOUND = """series = "XB"
source = "test: a strong gear on a weak bearing"
""" + SPIN_RULES + """[[unit]]
size = 20
ratio = 100
rated_torque_nm = 30
repeated_torque_nm = 60
momentary_torque_nm = 100
static_torque_nm = 100
max_input_speed_rpm = 7000
input_inertia_kg_cm2 = 0.1
mass_kg = 0.5
[unit.bearing]
pitch_diameter_m = 0.05
max_moment_nm = 15.0
"""
