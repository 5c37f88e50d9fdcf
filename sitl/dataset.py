"""Write an evaluation dataset (``dip3d_vehicle.dataset`` format) from a simulator scenario.

For each seed the scenario is resolved (the seed picks the diver position, the pointed placard,
the pointing error and the noise), and ``frames_per_seed`` stereo pairs are rendered from the
vehicle's start pose at times while the diver holds the point. Each pair is annotated with the
intended placard, every placard's projected centre and outline (original left px), the simulated
pose source's noisy keypoints (``meta["keypoints"]``; absent on a dropout, so the frame counts as
``no_pose`` with the keypoints backend), the diver position's name and the ranges.

Usage::

    python -m sitl.dataset --scenario paper_pool --seeds 0-15 --frames 3 --out DATASET
    dip3d-vehicle dataset --scenario paper_pool --seeds 0-15 --frames 3 --out DATASET
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import cv2
import numpy as np

from dip3d_vehicle.dataset import ANNOTATIONS_FILE, CALIB_FILE
from dip3d_vehicle.errors import DatasetError
from dip3d_vehicle.frames import StereoFrame
from dip3d_vehicle.perception.calibration_io import write_opencv_calibration
from dip3d_vehicle.sources import FolderWriter

from .render import StereoRenderer
from .scenario import Scenario, load_scenario

__all__ = ["write_dataset", "frame_times", "parse_seeds", "main"]


def frame_times(scenario: Scenario, n: int, spacing_s: float = 1.0) -> list[float]:
    """Return ``n`` times while the diver holds the point: 0.5 s after it starts, ``spacing_s`` apart."""
    d = scenario.diver
    times = [d.start_s + 0.5 + k * spacing_s for k in range(n)]
    last = d.start_s + d.hold_s
    return [min(t, last - 1e-3) for t in times]


def _object_points(scenario: Scenario, meta: Mapping[str, Any]) -> tuple[dict, dict, dict]:
    """Return ({id: centre px}, {id: polygon px}, {id: range m}) of the placards in the left image."""
    cam = scenario.camera
    w, h = cam.image_size
    points, polygons, ranges = {}, {}, {}
    for pid, info in meta["placards"].items():
        if info["left_polygon_px"] is None or info["xyz_cam_m"][2] <= 0.05:
            continue
        xyz = np.asarray(info["xyz_cam_m"], float).reshape(1, 1, 3)
        px = cv2.projectPoints(xyz, np.zeros(3), np.zeros(3), cam.K, cam.D1)[0].reshape(2)
        if not (0 <= px[0] <= w - 1 and 0 <= px[1] <= h - 1):
            continue
        key = str(pid)
        points[key] = [round(float(px[0]), 2), round(float(px[1]), 2)]
        polygons[key] = [[round(float(x), 2), round(float(y), 2)] for x, y in info["left_polygon_px"]]
        ranges[key] = round(float(info["range_m"]), 4)
    return points, polygons, ranges


def _annotation(index: int, scenario: Scenario, frame: StereoFrame) -> dict | None:
    """Return the frame's annotation (None when the intended placard is not in the left image)."""
    points, polygons, ranges = _object_points(scenario, frame.meta)
    target = str(scenario.target_id)
    if target not in points:
        return None
    ann: dict[str, Any] = {"index": index, "target": target, "objects": points, "polygons": polygons,
                           "diver_position": scenario.diver.position_name, "range_m": ranges,
                           "seed": scenario.seed, "t_s": frame.stamp_s}
    shoulder = frame.meta.get("joints_cam_m", {}).get("shoulder")
    if shoulder is not None:
        ann["diver_range_m"] = round(float(np.linalg.norm(shoulder)), 4)
    if frame.meta.get("keypoints") is not None:
        ann["keypoints"] = frame.meta["keypoints"]
    return ann


def write_dataset(scenario_name: str, seeds: Sequence[int], out_dir: str | Path, frames_per_seed: int = 3,
                  times: Sequence[float] | None = None, image_format: str = "png",
                  params: Mapping[str, Any] | None = None,
                  progress: Callable[[int, int], None] | None = None) -> Path:
    """Render a scenario's seeds into a dataset folder; return the folder.

    Args:
        scenario_name: built-in scenario name or scenario file.
        seeds: the seeds (each one diver position / target / noise draw).
        out_dir: dataset folder to create (must not already hold a dataset).
        frames_per_seed: pairs per seed (ignored when ``times`` is given).
        times: scenario times to render (default: ``frame_times``).
        image_format: ``png`` (exact) or ``jpg``.
        params: parameters for the renderer (``world.*``); schema defaults when None.
        progress: called with (pairs done, pairs total).

    Raises:
        DatasetError: the folder already holds a dataset, or the seeds' cameras differ.
    """
    out = Path(out_dir)
    if (out / ANNOTATIONS_FILE).exists():
        raise DatasetError(f"{out}: already holds {ANNOTATIONS_FILE} (choose an empty folder)")
    out.mkdir(parents=True, exist_ok=True)
    frames, objects, camera, index = [], {}, None, 0
    total = len(seeds) * (len(times) if times is not None else frames_per_seed)
    writer = FolderWriter(out, fmt=image_format)
    try:
        for seed in seeds:
            scenario = load_scenario(scenario_name, int(seed))
            if camera is None:
                camera = scenario.camera
                write_opencv_calibration(scenario.rig(), out / CALIB_FILE)
            elif scenario.camera != camera:
                raise DatasetError(f"{scenario.source}: seed {seed} has another camera than seed {seeds[0]} "
                                   "(a dataset has one calibration)")
            for p in scenario.placards:
                objects[str(p.id)] = {"label": str(p.id), "role": p.role}
            pose = scenario.initial_vehicle_pose
            with StereoRenderer(scenario, params) as renderer:
                for t_s in (times if times is not None else frame_times(scenario, frames_per_seed)):
                    frame = renderer.render(pose.north_m, pose.east_m, pose.depth_m, pose.yaw_rad, float(t_s))
                    ann = _annotation(index, scenario, frame)
                    if ann is not None:
                        writer.write(StereoFrame(frame.left, frame.right, frame.stamp_s, index))
                        frames.append(ann)
                        index += 1
                    if progress is not None:
                        progress(len(frames), total)
    finally:
        writer.close()
    doc = {"description": f"simulator scenario {scenario_name}, seeds {list(map(int, seeds))}",
           "objects": objects, "frames": frames}
    (out / ANNOTATIONS_FILE).write_text(json.dumps(doc, indent=1) + "\n")
    return out


def parse_seeds(text: str) -> list[int]:
    """Parse ``0-15``, ``1,4,7`` or a mix (``0-3,9``) into a list of seeds."""
    seeds: list[int] = []
    for part in str(text).split(","):
        part = part.strip()
        lo, sep, hi = part.partition("-")
        try:
            seeds += list(range(int(lo), int(hi) + 1)) if sep else [int(part)]
        except ValueError:
            raise DatasetError(f"--seeds {text!r}: expected e.g. 0-15 or 1,4,7") from None
    if not seeds or min(seeds) < 0:
        raise DatasetError(f"--seeds {text!r}: expected seeds >= 0")
    return seeds


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments shared by ``python -m sitl.dataset`` and ``dip3d-vehicle dataset``."""
    parser.add_argument("--scenario", default="paper_pool", help="scenario name or file (default paper_pool)")
    parser.add_argument("--seeds", default="0-15", help="seeds, e.g. 0-15 or 1,4,7 (default 0-15)")
    parser.add_argument("--frames", type=int, default=3, help="pairs per seed (default 3)")
    parser.add_argument("--format", choices=["png", "jpg"], default="png", help="image format (default png)")
    parser.add_argument("--out", required=True, help="dataset folder to create")


def run_args(args: argparse.Namespace, params: Mapping[str, Any] | None = None) -> int:
    """Write the dataset the arguments describe and print where it is."""
    seeds = parse_seeds(args.seeds)
    tty = sys.stderr.isatty()

    def show(done: int, total: int) -> None:
        if tty:
            sys.stderr.write(f"\rdataset: {done}/{total} pairs")
            sys.stderr.flush()

    out = write_dataset(args.scenario, seeds, args.out, args.frames, image_format=args.format,
                        params=params, progress=show)
    if tty:
        sys.stderr.write("\n")
    n = len(json.loads((out / ANNOTATIONS_FILE).read_text())["frames"])
    print(f"{out}: {n} annotated pairs from {args.scenario} seeds {args.seeds}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python -m sitl.dataset``."""
    from dip3d_vehicle.errors import Dip3dError

    parser = argparse.ArgumentParser(prog="python -m sitl.dataset", description=__doc__.splitlines()[0])
    add_arguments(parser)
    args = parser.parse_args(argv)
    try:
        return run_args(args)
    except Dip3dError as exc:
        print(f"python -m sitl.dataset: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
