"""Arguments shared by several commands (parameter profile, files, overrides)."""

from __future__ import annotations

import argparse

from ..config import Params, load_params

__all__ = ["add_params_arguments", "params_from_args"]


def add_params_arguments(parser: argparse.ArgumentParser, default_profile: str = "default") -> None:
    """Add --profile, --params and --set to a command's parser."""
    parser.add_argument("--profile", default=default_profile,
                        help=f"built-in parameter profile (params/<name>.yaml; default {default_profile})")
    parser.add_argument("--params", action="append", default=[], metavar="FILE",
                        help="parameter file applied over the profile (repeatable)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="set_",
                        help="override one parameter (repeatable), e.g. --set candidates.lowe_ratio=0.3")


def params_from_args(args: argparse.Namespace) -> Params:
    """Return the effective parameters named by a command's arguments."""
    return load_params(args.profile, args.params, args.set_)
