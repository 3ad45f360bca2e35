"""``hdselect catalog`` and ``hdselect duty``: the catalog, and its own sizing method."""

from __future__ import annotations

import argparse
import sys

from hdselect.base.errors import InputError
from hdselect.cli.output import EXIT_NO_FIT, EXIT_OK, rendered, say_written


def run_catalog(args: argparse.Namespace) -> int:
    """``hdselect catalog``: print the catalog (``--list``: the built-in catalogs)."""
    from hdselect.cli.inputs import catalog_of
    from hdselect.report.catalog_tables import catalog_table
    from hdselect.report.export import catalog_json, write_json

    if args.list:
        return _list_catalogs(args)
    units = catalog_of(args)
    if args.json:
        write_json("-", catalog_json(units))
    else:
        sys.stdout.write(rendered(catalog_table(units, imperial=args.units == "imperial")))
    return EXIT_OK


def _list_catalogs(args: argparse.Namespace) -> int:
    """``hdselect catalog --list``: the built-in catalogs, as a table or JSON."""
    from hdselect.catalog.builtin import builtin_catalogs
    from hdselect.catalog.catalogfile import load_catalog
    from hdselect.report.catalog_tables import catalog_list_table
    from hdselect.report.export import catalog_list_json, write_json

    for flag, given in (("--series", args.series), ("--catalog", args.catalog),
                        ("--units", args.units != "si")):  # --series loads built-ins too
        if given:
            raise InputError("--list lists the built-in catalogs; give it alone (with "
                             "--json)", field=flag)
    found = builtin_catalogs()
    every = load_catalog([c.name for c in found])
    document = catalog_list_json((c, [u for u in every if u.source == c.file]) for c in found)
    if args.json:
        write_json("-", document)
    else:
        sys.stdout.write(rendered(catalog_list_table(document)))
    return EXIT_OK


def run_duty(args: argparse.Namespace) -> int:
    """``hdselect duty``: the catalog's torque-speed method for one joint."""
    from hdselect.base.outputs import Outputs
    from hdselect.catalog.duty import load_duty, size_duty
    from hdselect.cli.inputs import catalog_of
    from hdselect.report.catalog_tables import duty_table
    from hdselect.report.export import duty_json, write_json

    units = catalog_of(args)
    cycle = load_duty(args.profile)
    with Outputs([args.profile, *args.catalog]) as outputs:
        json_file = outputs.file(args.json, "--json") if args.json is not None else None
        try:
            result = size_duty(cycle, units, margin=0.0 if args.margin is None else args.margin)
        except InputError as err:
            if err.field != "margin":
                raise
            raise InputError(err.reason, field="--margin") from err
        if json_file is not None:
            write_json(json_file, duty_json(result))
        table = rendered(duty_table(result)) if args.json != "-" else ""
        outputs.commit()
    sys.stdout.write(table)
    say_written([(args.json, None)], args)
    return EXIT_OK if result.selected is not None else EXIT_NO_FIT
