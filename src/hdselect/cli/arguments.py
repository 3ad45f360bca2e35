"""The options several commands declare: their flags, defaults and help texts.

Reading what they give is `hdselect.cli.inputs`'s step.
"""

from __future__ import annotations

import argparse

from hdselect.base.scheduler import DEFAULT_TIMEOUT
from hdselect.motion.option_specs import OPTION, OPTIONS

_Parser = argparse.ArgumentParser | argparse._ArgumentGroup


def catalog_argument(parser: argparse.ArgumentParser | argparse._ArgumentGroup, *,
                     series: bool = True) -> None:
    """--catalog and (with `series`) --series, on a parser or one of its groups.

    --catalog adds catalogs (built-in names or files); --series keeps only the units of
    the series named.
    """
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog: a built-in one by name (`hdselect "
                             "catalog --list`) or a file (TOML; repeatable)")
    if series:
        parser.add_argument("--series", metavar="NAME", action=_Series, default=[],
                            help="choose only among the units of this series, e.g. CSG-2UH "
                                 "or its catalog's name csg-2uh, a built-in one loaded as "
                                 "if given with --catalog (repeatable; default: every unit "
                                 "loaded)")


class _Series(argparse._AppendAction):
    """--series NAME: kept, and a built-in catalog it names added to --catalog."""

    def __call__(self, parser, namespace, values, option_string=None):  # type: ignore[no-untyped-def]
        from hdselect.catalog.builtin import series_catalogs

        super().__call__(parser, namespace, values, option_string)
        catalog = list(getattr(namespace, "catalog", None) or [])
        catalog += [name for name in series_catalogs([str(values)]) if name not in catalog]
        namespace.catalog = catalog


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
    base_argument(parser, "the motion file's angle_unit (a mix file's own)")
    parser.add_argument("--allow-flip", action="store_true",
                        help="a tool pose's near hint that cannot be honoured takes the "
                             "solver's branch with a warning (else an error); as the motion "
                             "file's [tool] allow_flip = true")
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
    option_arguments(parser, "case")
    return joints


def base_argument(parser: _Parser, angles: str) -> None:
    """--base X,Y,Z,ROLL,PITCH,YAW: the robot's base placed in the world, beside --mounting.

    Args:
        parser: The command's parser.
        angles: The unit of the angles, in words.
    """
    parser.add_argument("--base", metavar="X,Y,Z,ROLL,PITCH,YAW",
                        help="the base's pose in the world (z up): its origin [m] and roll, "
                             f"pitch, yaw about fixed x, y, z [{angles}], as a file's base = "
                             "{xyz, rpy}; overrides the file's mounting or base (not with "
                             "--mounting; a first number below 0: --base=-0.5,...)")


def option_help(name: str, kind: str | None = "motion", then: tuple[str, ...] = ()) -> str:
    """An option's flag's help as argparse takes it (`Option.flag_help`, % escaped)."""
    return OPTION[name].flag_help(kind, then).replace("%", "%%")


def option_argument(parser: _Parser, name: str, *, kind: str | None = "motion") -> None:
    """One option's flag as `hdselect.motion.option_specs.OPTIONS` declares it.

    The flag's value is None where it is not given (a switch's: False), except for a
    "case" flag, whose default is the option's.

    Args:
        parser: The command's parser, or one of its groups.
        name: The option.
        kind: The kind of file whose key gives the option's default, where the command
            reads one (`hdselect.motion.option_specs.FILE_KINDS`).
    """
    option = OPTION[name]
    if option.flag is None:
        raise ValueError(f"option {name} has no flag")
    kwargs: dict[str, object] = {"help": option_help(name, kind)}
    if option.kind == "switch":
        kwargs["action"] = "store_true"
    else:
        kwargs["type"] = ({"number": float, "count": int, "samples": int}.get(option.kind, str)
                          if not option.classes else str)  # a class's name, or a number
        if option.kind == "joints":  # VALUE or JOINT=VALUE, each flag once more
            kwargs["action"] = "append"
        if option.choices:
            kwargs["choices"] = option.choices
        if option.metavar is not None:
            kwargs["metavar"] = option.metavar
        if option.group == "case":
            kwargs["default"] = option.default
    parser.add_argument(option.flag, **kwargs)  # type: ignore[arg-type]


def option_arguments(parser: _Parser, group: str) -> None:
    """The flags of a group of options (`hdselect.motion.option_specs.Option.group`)."""
    for option in OPTIONS:
        if option.group == group:
            option_argument(parser, option.name)


def sizing_arguments(parser: argparse.ArgumentParser) -> None:
    """The flags of the sizing assumptions (`hdselect.sizing.options.Options`).

    The options of the groups "sizing" and "motors", ``--catalog`` and ``--motor-catalog``.
    """
    catalog_argument(parser)
    motors = False
    for option in OPTIONS:
        if option.group == "sizing":
            option_argument(parser, option.name)
        elif option.group == "motors" and not motors:
            motor_arguments(parser)
            motors = True


def motor_arguments(parser: _Parser) -> None:
    """--motor-catalog, then the flags of the "motors" group: motors and the units' masses.

    Declared on a parser, or on one of its groups.
    """
    parser.add_argument("--motor-catalog", metavar="FILE",
                        help="motor file (TOML): every sized joint chooses its motor from it, "
                             "with its gearhead (replaces the motion file's [motor])")
    option_arguments(parser, "motors")


def margin_argument(parser: argparse.ArgumentParser, *, motion: bool = True) -> None:
    """--margin: the design margin every rule must keep.

    Args:
        parser: The command's parser.
        motion: The command reads a motion file (whose ``[requirements] margin`` is the
            default); a duty profile has none.
    """
    option_argument(parser, "margin", kind="motion" if motion else None)
