"""``dip3d-vehicle params show|check``: effective parameter values, and file validation."""

from __future__ import annotations

import argparse
import json

from ..config import check_file, load_params, schema
from ._common import add_params_arguments

NAME = "params"
HELP = "show effective parameters with their sources, or check a parameter file"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the show/check sub-actions."""
    sub = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    show = sub.add_parser("show", help="print every parameter's effective value, unit and source")
    show.add_argument("file", nargs="?", help="parameter file applied over the profile")
    add_params_arguments(show)
    show.add_argument("--json", action="store_true", help="print JSON instead of a table")
    show.add_argument("--doc", action="store_true", help="also print each parameter's allowed range and doc")
    check = sub.add_parser("check", help="validate a parameter file (exit 2 with file:line on any error)")
    check.add_argument("file", help="parameter file (YAML key: value)")


def run(args: argparse.Namespace) -> int:
    """Show or check parameters."""
    if args.action == "check":
        n = check_file(args.file)
        print(f"{args.file}: ok ({n} parameters)")
        return 0
    files = ([args.file] if args.file else []) + list(args.params)
    params = load_params(args.profile, files, args.set_)
    spec = schema()
    if args.json:
        print(json.dumps({k: {"value": params[k], "unit": spec[k].unit, "source": params.source(k)}
                          for k in params}, indent=1))
        return 0
    width = max(len(k) for k in params)
    for key in params:
        p = spec[key]
        value = json.dumps(params[key]) if not isinstance(params[key], str) else params[key]
        unit = f" {p.unit}" if p.unit else ""
        print(f"{key:<{width}}  {value + unit:<16}  [{params.source(key)}]")
        if args.doc:
            print(f"{'':<{width}}    {p.allowed()}: {p.doc}")
    return 0
