"""The bench's frames one by one with the `default` profile: status, confidence, P(none) and the spots.

    python docs/issue11/session21/bench_frames.py [--only-wrong] [KEY=VALUE ...]

The frames are `dip3d-vehicle bench`'s (paper_pool, seeds 1-4, 30 frames each), rendered once and
cached in /tmp/bench_frames.pkl; every pose is BlazePose's, as in the bench.
"""
from __future__ import annotations

import pickle
import sys
from pathlib import Path

import numpy as np

from dip3d_vehicle.bench import frame_correct, make_perception, simulated_frames, warm_up, _reset
import yaml

CACHE = Path("/tmp/bench_frames.pkl")


def frames():
    """Return the bench's frames (rendered once, then cached)."""
    if CACHE.exists():
        return pickle.loads(CACHE.read_bytes())
    data = simulated_frames("paper_pool", [1, 2, 3, 4], 30)
    CACHE.write_bytes(pickle.dumps(data))
    return data


def main() -> None:
    """Print one line per frame (or per frame not right with --only-wrong), spots of the frames not right."""
    args = sys.argv[1:]
    only_wrong = "--only-wrong" in args
    overrides = dict(a.split("=", 1) for a in args if "=" in a)
    overrides = {k: yaml.safe_load(v) for k, v in overrides.items()}
    data = frames()
    perception, pose = make_perception("default", data.rig, overrides)
    warm_up(perception, pose, data)
    starts = set(data.sequences)
    counts: dict[str, int] = {}
    for i, frame in enumerate(data.frames):
        if i in starts:
            _reset(perception, pose)
        pose.provide(frame.meta.get("keypoints"))
        res = perception.process(frame.left, frame.right)
        doc = res.to_json(data.rig)
        ok = frame_correct(doc, frame.meta)
        counts[res.status if not ok else "right"] = counts.get(res.status if not ok else "right", 0) + 1
        sel = res.selection
        if only_wrong and ok:
            continue
        print(f"frame {i:3d} {res.status:15s} right={ok} conf={getattr(sel, 'confidence', None)} "
              f"none={getattr(sel, 'none_probability', None)} spots={len(res.unrecognised)}")
        if not ok and sel is not None:
            for o, p in zip(sel.objects, sel.scores):
                print(f"    object P {p:.2f} xyz {np.round(o.xyz_m, 2).tolist()} members {len(o.members)}")
            for px, x, s in zip(res.unrecognised.left_px, res.unrecognised.xyz_m, res.unrecognised.depth_sigma_m):
                print(f"    spot px {np.round(px).tolist()} xyz {np.round(x, 2).tolist()} sigma {s:.2f}")
    print(counts)


if __name__ == "__main__":
    main()
