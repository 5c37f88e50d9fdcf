"""``dip3d-vehicle evaluate DATASET``: the paper's metrics (Table I, Fig. 6) on an annotated dataset.

Without ``--profile`` or ``--compare`` both ``paper`` and ``default`` run on the same frames.
``--params`` / ``--set`` apply over every evaluated profile.
"""

from __future__ import annotations

import argparse
import json
import sys

from ..config import load_params
from ..dataset import load_dataset
from ..errors import ParamsError
from ..evaluation import Progress, evaluate_dataset, format_summary, format_table, pose_backend_for
from ._common import add_params_arguments

NAME = "evaluate"
HELP = "evaluate perception on an annotated dataset: hit rate, pixel error table, Fig. 6 plots"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    parser.add_argument("dataset", metavar="DATASET", help="dataset folder (calib.yaml, pairs, annotations.json)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (all profiles, every frame)")
    parser.add_argument("--plots", metavar="DIR", help="write chosen_objects.png (Fig. 6) and accuracy_vs_range.png")
    parser.add_argument("--compare", metavar="P1,P2",
                        help="profiles to evaluate on the same frames (default paper,default unless --profile)")
    parser.add_argument("--pose", choices=["auto", "keypoints", "blazepose", "params"], default="auto",
                        help="pose source: auto = the annotations' keypoints when they have them, else "
                             "pose.backend; params = always pose.backend (default auto)")
    parser.add_argument("--progress", action="store_true", help="progress bar on stderr even when it is not a TTY")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_params_arguments(parser)
    parser.set_defaults(profile=None)
    for action in parser._actions:
        if action.dest == "profile":
            action.help = "evaluate only this profile (default: paper and default, see --compare)"


def profile_names(args: argparse.Namespace) -> list[str]:
    """Return the profiles to evaluate."""
    if args.compare:
        names = [n.strip() for n in args.compare.split(",") if n.strip()]
        if not names:
            raise ParamsError(f"--compare {args.compare!r}: expected profile names separated by commas")
        return list(dict.fromkeys(names))
    return [args.profile] if args.profile else ["paper", "default"]


def run(args: argparse.Namespace) -> int:
    """Evaluate each profile, print the tables (or JSON) and write the plots."""
    profiles = {name: load_params(name, args.params, args.set_) for name in profile_names(args)}
    dataset = load_dataset(args.dataset)
    enabled = not args.no_progress and (args.progress or sys.stderr.isatty())
    progress = Progress(len(dataset.frames), sys.stderr, enabled, "evaluate")
    try:
        reports = evaluate_dataset(dataset, profiles, progress, pose=args.pose)
    finally:
        progress.close()
    written = []
    if args.plots:
        from ..plots import FIG6_FILE, RANGE_FILE, plot_accuracy_vs_range, plot_chosen_objects
        from pathlib import Path

        written = [str(plot_chosen_objects(reports, Path(args.plots) / FIG6_FILE)),
                   str(plot_accuracy_vs_range(reports, Path(args.plots) / RANGE_FILE))]
    if args.json:
        print(json.dumps({"dataset": str(dataset.root), "frames": len(dataset.frames),
                          "profiles": {n: r.to_json() for n, r in reports.items()}, "plots": written}))
        return 0
    backend = pose_backend_for(dataset, args.pose)
    print(f"dataset {dataset.root}: {len(dataset.frames)} annotated pairs; pose from "
          f"{'annotated keypoints' if backend == 'keypoints' else backend or 'pose.backend'}")
    for report in reports.values():
        print()
        print(format_summary(report))
        print("  pixel error when correct, mean +- std px (correct/frames), by diver position x target:")
        print("\n".join("  " + line for line in format_table(report).splitlines()))
    for path in written:
        print(f"wrote {path}")
    return 0
