"""The options several commands declare: their flags, defaults and help texts.

Reading what they give is `hdselect.cli.inputs`'s step.
"""

from __future__ import annotations

import argparse

from hdselect.base.bounds import DEFAULT_MAX_SAMPLES
from hdselect.base.scheduler import DEFAULT_TIMEOUT


def catalog_argument(parser: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    """--catalog: extra catalog files (on a parser, or on one of its groups)."""
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog file (TOML; repeatable)")


def json_argument(parser: argparse.ArgumentParser) -> None:
    """--json FILE."""
    parser.add_argument("--json", metavar="FILE",
                        help="also write JSON to FILE ('-': to stdout, instead of the table)")


def scheduler_arguments(parser: argparse.ArgumentParser) -> None:
    """``--scheduler ADDRESS`` and ``--timeout SECONDS``: a Dask cluster and its time limit."""
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="'local': a Dask LocalCluster on this machine; tcp://HOST:PORT: a "
                             "running Dask scheduler (needs pip install 'hdselect[dask]')")
    parser.add_argument("--timeout", type=float, metavar="SECONDS",
                        help="how long connecting to the --scheduler may take, in seconds "
                             f"(default {DEFAULT_TIMEOUT:g}); a peer that is not a Dask "
                             "scheduler is refused")


def xacro_argument(parser: argparse.ArgumentParser, *, motion: bool = True) -> None:
    """--xacro-arg NAME:=VALUE (repeatable): a .xacro robot's arguments.

    Args:
        parser: The command's parser.
        motion: The command reads a motion file (whose ``xacro_args`` the flag overrides).
    """
    parser.add_argument("--xacro-arg", metavar="NAME:=VALUE", action="append",
                        dest="xacro_arg", help="an argument of a .xacro robot file "
                        "(repeatable" + ("; overrides the motion file's xacro_args)" if motion
                                         else ")"))


def robot_motion_arguments(parser: argparse.ArgumentParser, *, mass: bool = True,
                           sizes: bool = True) -> argparse._ArgumentGroup:
    """ROBOT, MOTION and the flags that change the case: payload, mounting, joints, samples.

    Args:
        parser: The command's parser.
        mass: Offer --payload (max-payload finds the mass instead).
        sizes: The command sizes joints (plan only draws them).

    Returns:
        The group of --joints and --exclude, for a command's --joint (the joints shown).
    """
    parser.add_argument("robot", nargs="?", metavar="ROBOT",
                        help="robot file, URDF, xacro or MJCF (default: the motion file's "
                             "`robot`)")
    parser.add_argument("motion", metavar="MOTION", help="motion file (TOML)")
    xacro_argument(parser)
    if mass:
        parser.add_argument("--payload", type=float, metavar="KG",
                            help="payload mass [kg]; the motion file's payload keeps its centre "
                                 "of mass, inertia and frame")
    parser.add_argument("--payload-com", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="payload centre of mass in its frame [m] (changes the motion "
                             + ("file's payload, or the one --payload gives)" if mass else
                                "file's payload; without one, puts a point mass there)"))
    parser.add_argument("--payload-frame", metavar="LINK",
                        help="link carrying the payload (default: the motion file's, else the "
                             "tip of the longest chain of joints not excluded)")
    parser.add_argument("--mounting", metavar="floor|wall|ceiling",
                        help="mounting, overriding the motion file's")
    doing = "size" if sizes else "plot"
    joints = parser.add_argument_group(f"joints {doing}d" if sizes else "joints plotted")
    joints.add_argument("--joints", metavar="A,B", action="append",
                        help=f"{doing} only these joints (comma-separated; overrides the motion "
                             "file's [sizing] joints)" + ("" if sizes else "; the CSV has every "
                                                          "joint, or with --units every "
                                                          "sized joint"))
    joints.add_argument("--exclude", metavar="A,B", action="append",
                        help=f"do not {doing} these joints; they still move and load the others "
                             "(overrides the motion file's [sizing] exclude)")
    parser.add_argument("--max-samples", type=int, metavar="N",
                        default=DEFAULT_MAX_SAMPLES,
                        help="refuse a trajectory of more samples than this, before allocating "
                             f"it (default {DEFAULT_MAX_SAMPLES:,}: an 8-hour log at 1 kHz)")
    return joints


def sizing_arguments(parser: argparse.ArgumentParser) -> None:
    """The flags of the sizing assumptions (`hdselect.sizing.options.Options`)."""
    from hdselect.catalog.select import DEFAULT_PREFER, DEFAULT_PREFER_WITH_MOTORS, PREFERENCES
    from hdselect.motion.motionfile import LIFE_BASES
    from hdselect.sizing.options import Options

    defaults = Options()
    catalog_argument(parser)
    parser.add_argument("--stop-time", type=float, metavar="S",
                        help="emergency-stop and crash time [s] (default: the motion file's "
                             f"[safety] stop_time, else {defaults.stop_time:g})")
    parser.add_argument("--efficiency", type=float,
                        help=f"gear efficiency where a unit has no table (default "
                             f"{defaults.efficiency:g})")
    parser.add_argument("--motor-inertia", type=float, metavar="KG_M2",
                        help="motor rotor inertia [kg m^2] where no motor data is given "
                             "(default 0)")
    motor_arguments(parser)
    parser.add_argument("--prefer", choices=tuple(PREFERENCES),
                        help="; ".join(f"{k}: {v[0]}" for k, v in PREFERENCES.items())
                        + f" (default: {DEFAULT_PREFER_WITH_MOTORS} where motors are given, "
                          f"else {DEFAULT_PREFER})")
    parser.add_argument("--life-hours", type=float, metavar="H",
                        help="required life [h] (default: the motion file's requirement)")
    parser.add_argument("--life-basis", choices=LIFE_BASES,
                        help="basis of the required life: L50, average life, or L10, 90 %% "
                             "survive it (default: the motion file's, else L50)")
    margin_argument(parser)
    parser.add_argument("--max-inertia-ratio", type=float, metavar="R",
                        help="a gearhead and motor pair whose load-to-rotor inertia ratio is "
                             "above R is not feasible (default: the motor file's "
                             "max_inertia_ratio, else none)")
    parser.add_argument("--inertia-target", type=float, metavar="R",
                        help="the load-to-rotor inertia ratio --prefer inertia aims at "
                             f"(default {defaults.inertia_target:g})")


def motor_arguments(parser: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    """--motor-mass, --motor-catalog, --no-mass-coupling: motors and the units' masses.

    Declared on a parser, or on one of its groups.
    """
    parser.add_argument("--motor-mass", type=float, metavar="KG",
                        help="motor mass carried with each gearhead [kg] where no motor data "
                             "is given (default 0)")
    parser.add_argument("--motor-catalog", metavar="FILE",
                        help="motor file (TOML): every sized joint chooses its motor from it, "
                             "with its gearhead (replaces the motion file's [motor])")
    parser.add_argument("--no-mass-coupling", action="store_true",
                        help="do not carry chosen units' masses on the joints nearer the base")


def margin_argument(parser: argparse.ArgumentParser, *, motion: bool = True) -> None:
    """--margin: the design margin every rule must keep.

    Args:
        parser: The command's parser.
        motion: The command reads a motion file (whose ``[requirements] margin`` is the
            default); a duty profile has none.
    """
    parser.add_argument("--margin", type=float, metavar="M",
                        help="design margin: every rule must hold at (1 - M) of its limit, "
                             "e.g. 0.2 for 80 %% (default: " + (
                                 "the motion file's [requirements] margin, else 0)" if motion
                                 else "0)"))
