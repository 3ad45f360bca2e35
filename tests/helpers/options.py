"""The command-line options each test of an option's effect sets, with the files
they read, and the check of a one-line error.
"""

from __future__ import annotations

import argparse

from helpers import REPO

PLANAR2 = REPO / "robots" / "planar2.urdf"


PLANAR2_MOTION = REPO / "trajectories" / "planar2_pick_place.toml"


def one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hdselect: error: "), err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, err)


ENVELOPE_EFFECTS = [
    ("--velocity", ["90"]), ("--acceleration", ["600"]), ("--jerk", ["2000"]),
    ("--angle-unit", ["rad"]), ("--payload", ["0.5"]), ("--payload-com", ["0", "0", "0.1"]),
    ("--payload-frame", ["link2"]), ("--mounting", ["wall"]), ("--base", ["0,0,0.5,90,0,0"]),
    ("--joints", ["shoulder"]),
    ("--exclude", ["elbow"]), ("--duty", [PLANAR2_MOTION]), ("--moves", ["3"]),
    ("--seed", ["1"]), ("--starts", ["128"]), ("--max-samples", ["100"]),
    ("--catalog", ["acme.toml"]), ("--stop-time", ["0.3"]), ("--efficiency", ["0.5"]),
    ("--motor-inertia", ["1e-5"]), ("--motor-mass", ["1.0"]),
    ("--motor-catalog", [REPO / "motors" / "example_motors.toml"]),
    ("--no-mass-coupling", []), ("--prefer", ["margin"]), ("--life-hours", ["1e5"]),
    ("--life-basis", ["L10"]), ("--margin", ["0.5"]), ("--max-inertia-ratio", ["3"]),
    ("--inertia-target", ["2"]), ("--series", ["ACME", "--catalog", "acme.toml"]),
    ("--max-torsion", ["1"]), ("--min-natural-frequency", ["hand-axes"]),
    ("--max-tool-deflection", ["1"]), ("--min-arm-frequency", ["5"]), ("--no-precision", []),
]
"""Each option of ``hdselect envelope`` that changes its answer, with a value that must."""


ENVELOPE_OUTPUTS = ("--json", "--report", "--workers", "--scheduler", "--timeout")
"""Options that change where the answer goes or how it is computed (tested above; --timeout
in test_scheduler)."""


ONE_MOVE = """\
robot = "../robots/planar2.urdf"
planner = "ruckig"
angle_unit = "deg"
dt = 0.002
[payload]
mass = 0.4
com = [0.03, 0.0, 0.0]
frame = "tool"
[limits]
velocity = 180
acceleration = 900
jerk = 9000
[requirements]
life_hours = 20000
[[waypoint]]
q = {shoulder = 40, elbow = -80}
dwell = 0.2
[[waypoint]]
q = {shoulder = -30, elbow = 20}
dwell = 0.2
"""
"""planar2's first move and back: co-design in a second."""


NO_FIGURES = ("--no-precision",)
"""fastest and max-payload print no precision figures: --no-precision only spares their
inner sizings the figures' cost (test_precision_figures checks what it leaves out)."""
STIFFNESS_TARGETS = ("--max-torsion", "--min-natural-frequency")
"""The per-joint precision targets: PSA-G rates no stiffness, so on envelope's PSA-G
table they act on nothing; test_precision_rules runs envelope with SHG-2UH units."""


OTHER = {
    "catalog": ["--catalog", "--units", "--json", "--series", "--list"],
    "duty": ["--catalog", "--json", "--margin", "--series"],  # test_margins: the duty example
    # by hand; test_catalog_schema: --series and --list
    "joints": ["--json", "--xacro-arg"], "init": ["--out", "--tool-poses", "--xacro-arg"],
    "study": ["--out", "--workers", "--scheduler", "--timeout", "--no-grouping", "--retry-failed",
              "--plot"],
    "plan": ["--out", "--xacro-arg"],
    "size": ["--json", "--bom", "--xacro-arg"],
    "compare": ["--json", "--bom", "--xacro-arg"],
    "fastest": ["--json", "--xacro-arg", *NO_FIGURES],
    "max-payload": ["--json", "--prefer", "--xacro-arg", *NO_FIGURES],
    "envelope": [*(row[0] for row in ENVELOPE_EFFECTS), *ENVELOPE_OUTPUTS, "--xacro-arg"],
}
"""Options covered elsewhere (test_cli, test_study, test_outputs, test_bad_input): outputs,
executors and listings, which change where a result goes or how it runs, not the result.
init's --tool-poses writes another starter: test_toolposes solves, plans and sizes it.
max-payload's --prefer orders the units that pass at the largest payload, where the joint
that binds has one: `test_max_payload_selects_in_the_order_preferred` checks it is used.
--xacro-arg needs a .xacro robot: `test_xacro.test_every_command_takes_xacro_arguments`.
envelope's options take a robot file, not a motion file: test_envelope_cli runs its own
table of effects (`ENVELOPE_EFFECTS`)."""


def effect_options(parser: argparse.ArgumentParser) -> dict[str, set[str]]:
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {name: {o for a in sub._actions for o in a.option_strings
                   if o.startswith("--") and o not in ("--help", "--verbose")}
            for name, sub in commands.choices.items()}
