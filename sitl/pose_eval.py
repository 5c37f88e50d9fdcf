"""BlazePose on rendered frames of the simulated diver: arm found and keypoint error vs the truth joints.

For each cell (diver range, facing angle, water) a few frames are rendered with the diver straight
ahead of the vehicle, pointing with the scenario's arm, and BlazePose (``BlazePose.process``: a
fresh detection, then the landmarks, on each ORIGINAL image, no tracking) runs on the left and the
right image separately. Per eye: arm found = a person and every arm keypoint's visibility at least
``pose.min_confidence``; error = pixel distance of shoulder / elbow / wrist to the truth joints'
projections (``meta["keypoints_truth"]``), over the frames where the arm was found. ``swapped``
counts found arms closer to the truth of the OTHER arm (BlazePose took the diver's left for right).

Facing: 0 = chest toward the camera, 90 = the pointing arm's side toward the camera;
``mission`` = the scenario's own heading and target (``paper_pool``: the pointing side toward the
placards on the right, turned 45 degrees toward them); ``behind`` = the same without the turn (the
diver seen from behind-left, as ``paper_pool`` stood before issue 14). For 0/45/90 the arm aims 30
degrees forward of the diver's side, level, at a small placard 6 m away. The diver stands 8 degrees
left of the camera's axis, chest at the camera's depth.

Command line::

    python -m sitl.pose_eval [--ranges 1.5 2.5 3.5 4.5] [--facings 0 45 90 behind mission]
                             [--waters paper_pool murky] [--frames 6] [--json OUT.json]
                             [--jobs N | --ray auto|local[:N]|ADDRESS]
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import yaml

from .scenario import load_scenario

__all__ = ["cell_scenario", "evaluate_cell", "run", "format_table"]

_JOINTS = ("shoulder", "elbow", "wrist")
_CAMERA_START = (0.25, -0.06)  # paper_pool's left camera at the start (vehicle at the origin, mount)


def cell_scenario(base: str, range_m: float, facing: str, seed: int, folder: Path):
    """Return a scenario: ``base``'s water and camera, the diver ``range_m`` ahead facing ``facing``."""
    doc: dict[str, Any] = {"base": base, "description": f"pose_eval {base} {range_m} m facing {facing}"}
    if facing in ("mission", "behind"):
        doc["diver"] = {"positions": [{"name": "eval", "range_m": range_m, "bearing_deg": -8.0, "depth_m": 1.0}]}
        if facing == "behind":
            doc["diver"]["turn_to_placards_deg"] = 0.0
    else:
        phi = math.radians(float(facing))
        bearing = math.radians(-8.0)
        chest = np.array([_CAMERA_START[0] + range_m * math.cos(bearing),
                          _CAMERA_START[1] + range_m * math.sin(bearing), 1.0])
        to_cam = math.atan2(_CAMERA_START[1] - chest[1], _CAMERA_START[0] - chest[0])
        heading = to_cam - phi                     # the right side turns toward the camera
        fwd = np.array([math.cos(heading), math.sin(heading), 0.0])
        right = np.array([-math.sin(heading), math.cos(heading), 0.0])
        aim = math.cos(math.radians(30)) * right + math.sin(math.radians(30)) * fwd
        target = chest + 6.0 * aim
        doc["placards"] = [{"id": 7, "ned_m": [float(v) for v in target], "size_m": 0.3}]
        doc["track_line"] = None
        doc["diver"] = {"positions": [{"name": "eval", "ned_m": [float(v) for v in chest]}],
                        "heading_deg": math.degrees(heading), "target": 7}
    path = folder / f"eval_{base}_{range_m}_{facing}.yaml"
    path.write_text(yaml.safe_dump(doc))
    return load_scenario(str(path), seed)


def _arm_error(lm, truth: dict, arm: str) -> tuple[np.ndarray, bool]:
    """Return (per-joint pixel error of BlazePose's ``arm``, whether the other arm's truth fits better)."""
    from dip3d_vehicle.perception.pose import ARM_INDICES

    other = "left" if arm == "right" else "right"
    xy = lm.xy_px[list(ARM_INDICES[arm])]
    t = np.array([truth[j] for j in _JOINTS])
    err = np.linalg.norm(xy - t, axis=1)
    swapped = False
    if "other" in truth:
        t_other = np.array([truth["other"][j] for j in _JOINTS])
        swapped = bool(np.linalg.norm(xy - t_other, axis=1).mean() < err.mean())
    del other
    return err, swapped


def evaluate_cell(sc, pose, frames: int, min_confidence: float) -> dict:
    """Render ``frames`` frames of scenario ``sc`` and run BlazePose on each eye; return the counts."""
    from .render import StereoRenderer

    out = {eye: {"frames": 0, "found": 0, "swapped": 0, "err": []} for eye in ("left", "right")}
    v = sc.initial_vehicle_pose
    with StereoRenderer(sc) as renderer:
        for k in range(frames):
            t = sc.diver.start_s + 0.5 + 0.7 * k
            frame = renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            truth = frame.meta["keypoints_truth"]
            if truth is None:
                continue
            for eye, img in (("left", frame.left), ("right", frame.right)):
                cell = out[eye]
                cell["frames"] += 1
                lm = pose.process(img)
                if lm is None:
                    continue
                _, vis = lm.arm(sc.diver.arm)
                if float(vis.min()) < min_confidence:
                    continue
                t_eye = dict(truth[eye])
                other = (frame.meta.get("body_truth") or {}).get(eye, {})
                o = "left" if sc.diver.arm == "right" else "right"
                if all(f"{o}_{j}" in other for j in _JOINTS):
                    t_eye["other"] = {j: other[f"{o}_{j}"] for j in _JOINTS}
                err, swapped = _arm_error(lm, t_eye, sc.diver.arm)
                cell["found"] += 1
                cell["swapped"] += int(swapped)
                cell["err"].append(err.tolist())
    return out


def _summary(cell: dict) -> dict:
    """Return found %, and median / p90 error per joint of one eye's results."""
    err = np.array(cell["err"]).reshape(-1, 3)
    res: dict[str, Any] = {"frames": cell["frames"], "found": cell["found"], "swapped": cell["swapped"],
                           "found_pct": round(100.0 * cell["found"] / cell["frames"], 1) if cell["frames"] else None}
    for k, j in enumerate(_JOINTS):
        res[j] = ([round(float(np.median(err[:, k])), 1), round(float(np.percentile(err[:, k], 90)), 1)]
                  if len(err) else None)
    return res


def run(ranges: Sequence[float], facings: Sequence[str], waters: Sequence[str], frames: int,
        seed: int = 0, jobs: int = 1, ray: str | None = None) -> list[dict]:
    """Evaluate every (water, range, facing) cell; return one row per cell.

    Cells are independent (BlazePose runs without tracking), so they run here (``jobs`` 1), in
    ``jobs`` processes, or on Ray (``ray``: see sitl/parallel.py), with the same rows.
    """
    from .parallel import map_runs

    items = [(water, rng, facing, frames, seed) for water in waters for rng in ranges for facing in facings]
    rows = []
    for row in map_runs(evaluate_row, items, jobs, ray):
        rows.append(row)
        print(format_table([row], header=False), flush=True)
    return rows


_POSE: list = []
"""This process's BlazePose (loaded once per worker process)."""


def evaluate_row(args: tuple) -> dict:
    """One cell (water, range_m, facing, frames, seed) as a table row (in whatever process runs it)."""
    from dip3d_vehicle.config import load_params
    from dip3d_vehicle.perception.blazepose import BlazePose

    water, rng, facing, frames, seed = args
    params = load_params()
    if not _POSE:
        _POSE.append(BlazePose.from_params(params))
    with tempfile.TemporaryDirectory() as tmp:
        sc = cell_scenario(water, rng, facing, seed, Path(tmp))
        cell = evaluate_cell(sc, _POSE[0], frames, float(params["pose.min_confidence"]))
    row = {"water": water, "range_m": rng, "facing": facing}
    row.update({eye: _summary(cell[eye]) for eye in ("left", "right")})
    return row


def _fmt(v) -> str:
    return "-" if v is None else f"{v[0]:.0f} / {v[1]:.0f}"


def format_table(rows: list[dict], header: bool = True) -> str:
    """Return a Markdown table: found % and shoulder / elbow / wrist median / p90 px per eye."""
    lines = []
    if header:
        lines.append("| water | range m | facing | L found % (swapped) | L sh | L el | L wr "
                     "| R found % (swapped) | R sh | R el | R wr |")
        lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        cells = []
        for eye in ("left", "right"):
            e = r[eye]
            cells += [f"{e['found_pct']} ({e['swapped']})", _fmt(e["shoulder"]), _fmt(e["elbow"]), _fmt(e["wrist"])]
        lines.append(f"| {r['water']} | {r['range_m']} | {r['facing']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _pooled(rows: list[dict]) -> str:
    """Return one line per water: found % and pooled errors over all cells (both eyes)."""
    out = []
    for water in sorted({r["water"] for r in rows}):
        sel = [r for r in rows if r["water"] == water]
        frames = sum(r[e]["frames"] for r in sel for e in ("left", "right"))
        found = sum(r[e]["found"] for r in sel for e in ("left", "right"))
        swapped = sum(r[e]["swapped"] for r in sel for e in ("left", "right"))
        out.append(f"{water}: arm found {found}/{frames} ({100.0 * found / max(frames, 1):.1f} %), swapped {swapped}")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    """Command line (see the module docstring)."""
    from .parallel import add_executor_arguments

    ap = argparse.ArgumentParser(prog="python -m sitl.pose_eval")
    ap.add_argument("--ranges", type=float, nargs="+", default=[1.5, 2.5, 3.5, 4.5])
    ap.add_argument("--facings", nargs="+", default=["0", "45", "90", "behind", "mission"])
    ap.add_argument("--waters", nargs="+", default=["paper_pool", "murky"])
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", default=None, help="write the rows here")
    add_executor_arguments(ap)
    args = ap.parse_args(argv)
    rows = run(args.ranges, args.facings, args.waters, args.frames, args.seed, args.jobs, args.ray)
    print(format_table(rows))
    print(_pooled(rows))
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
