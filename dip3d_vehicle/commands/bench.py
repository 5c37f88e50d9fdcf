"""``dip3d-vehicle bench``: perception speed of the ``paper`` profile and the project's profiles."""

from __future__ import annotations

import argparse
import json

from ..errors import SourceError

NAME = "bench"
HELP = "time the perception profiles (paper, default, fast, ...) on the same 1600x1200 stereo frames"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--profiles", default="paper,default,fast",
                        help="comma-separated profiles (paper is the reference of the ratios); PROFILE+followN[bg]: "
                             "the profile on every N-th frame, the chosen object followed in between (bg: keyframes "
                             "in a background thread)")
    parser.add_argument("--scenario", default="paper_pool", help="simulator scenario (default paper_pool)")
    parser.add_argument("--seeds", default="1,2,3,4", help="comma-separated scenario seeds, one sequence each")
    parser.add_argument("--frames", type=int, default=30,
                        help="frames per seed (default 30 = 3 s at 10 Hz: long enough that the start-up frame of each"
                             " sequence does not dominate a following profile)")
    parser.add_argument("--size", default=None, metavar="WxH", help="render size (default the scenario camera's)")
    parser.add_argument("--source", default=None, help="a stereo folder (or source spec) instead of the simulator")
    parser.add_argument("--calib", action="append", default=[], help="calibration file(s) for --source")
    parser.add_argument("--latency-profile", default="default,fast",
                        help="comma-separated profiles of the worker latency runs ('' to skip)")
    parser.add_argument("--run-rss", default="default,fast",
                        help="profiles whose 'dip3d-vehicle run' peak RSS is measured on the first sequence written "
                             "as a folder ('' to skip)")
    parser.add_argument("--camera-hz", type=float, default=15.0,
                        help="camera rate of the worker latency runs, Hz (default 15)")
    parser.add_argument("--latency-s", type=float, default=10.0, help="duration of the latency run, seconds")


def run(args: argparse.Namespace) -> int:
    """Run the bench and print the table (or JSON)."""
    from ..bench import folder_frames, format_table, run_bench, simulated_frames

    if args.source:
        if not args.calib:
            raise SourceError(f"{args.source}: --source needs --calib")
        data = folder_frames(args.source, args.calib, max_frames=0)
    else:
        size = None
        if args.size:
            try:
                w, h = (int(v) for v in args.size.lower().split("x"))
            except ValueError:
                raise SourceError(f"--size {args.size!r}: expected WIDTHxHEIGHT, e.g. 1600x1200") from None
            size = (w, h)
        seeds = [int(s) for s in args.seeds.split(",") if s.strip()]
        data = simulated_frames(args.scenario, seeds, args.frames, size=size)
    profiles = [p.strip() for p in args.profiles.split(",") if p.strip()]
    latency = [p.strip() for p in args.latency_profile.split(",") if p.strip()]
    report = run_bench(data, profiles, latency_profile=latency, latency_s=args.latency_s,
                       camera_hz=args.camera_hz,
                       run_memory_profiles=[p.strip() for p in args.run_rss.split(",") if p.strip()])
    print(json.dumps(report) if args.json else format_table(report))
    return 0
