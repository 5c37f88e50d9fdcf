"""One generated family scene in detail: placards (3D, left px), objects' probabilities, spots found and kept.

    PYTHONPATH=.:tests/perception python docs/issue11/session20/scene_detail.py FAMILY SEED0 SCENE [NOISE_PX DRAW] [KEY=VALUE ...]
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf


def main() -> None:
    """Print the scene's placards, the decision, each object and spot."""
    family, seed0, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    sigma = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    want_draw = int(sys.argv[5]) if len(sys.argv) > 5 else 0
    overrides = sys.argv[6:]
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, want + 1, seed0)):
            if k != want:
                continue
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
            rng = np.random.default_rng(seed0 + k)
            pl = {pid: rig.R1 @ np.asarray(p["xyz_cam_m"]) for pid, p in scene.frame.meta["placards"].items()}
            for pid, p in scene.frame.meta["placards"].items():
                poly = p["left_polygon_px"]
                c = np.mean(np.asarray(poly), axis=0).round(0).tolist() if poly is not None else None
                print(f"placard {pid}{' (target)' if pid == scene.scenario.target_id else ''} xyz {np.round(pl[pid], 2).tolist()} left px {c}")
            print("truth joints rect", np.round(rig.R1 @ np.asarray(scene.frame.meta['joints_cam_m']['wrist']), 2))
            for s in (0.0, 1.0, 2.0, 4.0):
                for d in range(8 if s > 0 else 1):
                    pose.provide(sf.noisy(truth, s, rng))
                    if s != sigma or d != want_draw:
                        continue
                    res = sf.decided(perception, left, right, base)
                    sel = res.selection
                    print(res.status, res.reason, "none %.2f" % sel.none_probability if sel else "")
                    if sel is None:
                        return
                    for o, p in zip(sel.objects, sel.scores):
                        near = min(pl, key=lambda q: np.linalg.norm(pl[q] - o.xyz_m))
                        print(f"  object P {p:.2f} xyz {np.round(o.xyz_m, 2).tolist()} placard {near} "
                              f"({np.linalg.norm(pl[near] - o.xyz_m):.2f} m) members {len(o.members)}")
                    for px, x in zip(res.unrecognised.left_px, res.unrecognised.xyz_m):
                        near = min(pl, key=lambda q: np.linalg.norm(pl[q] - x))
                        print(f"  spot px {np.round(rig.to_original(px[None], 'left')[0][0]).tolist()} xyz "
                              f"{np.round(x, 2).tolist()} placard {near} ({np.linalg.norm(pl[near] - x):.2f} m)")
            return


if __name__ == "__main__":
    main()
