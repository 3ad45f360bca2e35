"""Command line: a thin layer over the public API; it formats, it does not compute."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from collections.abc import Sequence

from hdselect import __version__
from hdselect.errors import HdselectError

logger = logging.getLogger("hdselect")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``hdselect`` command.

    Returns:
        Exit status: 0 success, 1 no gearhead fits, 2 bad input.
    """
    parser = _parser()
    args = parser.parse_args(argv)
    logging.basicConfig(format="hdselect: %(levelname)s: %(message)s",
                        level=logging.INFO if args.verbose else logging.WARNING)
    try:
        return int(args.run(args))
    except HdselectError as err:
        print(f"hdselect: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        # The reader went away (e.g. `| head`): not an error of ours.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="hdselect",
        description="Size Harmonic Drive PSA-G gearheads for robot joints.")
    parser.add_argument("--version", action="version", version=f"hdselect {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="print progress notes")
    commands = parser.add_subparsers(title="commands", required=True, metavar="COMMAND")

    catalog = commands.add_parser("catalog", help="list the gearhead catalog")
    _catalog_option(catalog)
    catalog.add_argument("--units", choices=("si", "imperial"), default="si",
                         help="unit system of the table (default: si)")
    catalog.add_argument("--json", action="store_true", help="print JSON instead of a table")
    catalog.set_defaults(run=run_catalog)

    duty = commands.add_parser("duty", help="size from a torque-speed profile (catalog method)")
    duty.add_argument("profile", help="duty-cycle profile (TOML)")
    _catalog_option(duty)
    duty.add_argument("--json", metavar="FILE", help="also write JSON to FILE ('-': stdout "
                      "instead of the table)")
    duty.set_defaults(run=run_duty)
    return parser


def _catalog_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--catalog", metavar="FILE", action="append", default=[],
                        help="add the units of a catalog file (TOML; repeatable)")


def run_catalog(args: argparse.Namespace) -> int:
    """``hdselect catalog``: print the catalog."""
    from hdselect.catalog import load_catalog
    from hdselect.report import catalog_json, catalog_table, console, write_json

    units = load_catalog(args.catalog)
    if args.json:
        write_json("-", catalog_json(units))
    else:
        console().print(catalog_table(units, imperial=args.units == "imperial"))
    return 0


def run_duty(args: argparse.Namespace) -> int:
    """``hdselect duty``: the catalog's torque-speed method for one joint."""
    from hdselect.catalog import load_catalog
    from hdselect.duty import load_duty, size_duty
    from hdselect.report import console, duty_json, duty_table, write_json

    units = load_catalog(args.catalog)
    result = size_duty(load_duty(args.profile), units)
    if args.json:
        write_json(args.json, duty_json(result))
    if args.json != "-":
        console().print(duty_table(result))
    return 0 if result.selected is not None else 1


if __name__ == "__main__":
    sys.exit(main())
