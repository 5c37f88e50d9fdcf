"""``dip3d-vehicle dataset``: write an evaluation dataset from a simulator scenario (see sitl/dataset.py)."""

from __future__ import annotations

import argparse

from ._common import add_params_arguments, params_from_args

NAME = "dataset"
HELP = "render a simulator scenario's seeds into an annotated evaluation dataset (for evaluate)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    from sitl.dataset import add_arguments as dataset_arguments

    dataset_arguments(parser)
    add_params_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Write the dataset and print where it is."""
    from sitl.dataset import run_args

    return run_args(args, params_from_args(args))
