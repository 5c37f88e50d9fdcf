"""Per scene of one family at one noise level: default's outcomes over 8 draws, for each of several settings.

    python docs/issue11/session35/scripts/per_scene.py FAMILY N SEED0 NOISE "KEY=VALUE ..." ["KEY=VALUE ..." ...]

An empty string stands for the defaults. With ``LEVELS=fam`` in the environment the draws are ``fam.py``'s (the one
noise level only); by default they are the full tables' (0, 1, 2, 4 px in turn). Prints scene, then per setting the outcome letters
(c correct, a abstained: ambiguous or pose rejected, n abstained: "nothing detected" won,
w wrong, W confidently wrong) and the median number of objects.
"""
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402

family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
settings = [s.split() for s in sys.argv[5:]] or [[]]
levels = (noise,) if os.environ.get("LEVELS") == "fam" else (0.0, 1.0, 2.0, 4.0)
letter = {"correct": "c", "abstained": "a", "wrong": "w", "confident_wrong": "W"}
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        row = [f"{k:2d} {scene.target_range_m:.1f}m"]
        for over in settings:
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
            rng = np.random.default_rng(seed0 + k)
            for sigma in levels:                        # the tally's draw order, so the draws are the same
                outs, n_obj = [], []
                for _ in range(8 if sigma > 0 else 1):
                    pose.provide(sf.noisy(truth, sigma, rng))
                    result = sf.decided(perception, left, right, base)
                    what = letter[sf.outcome(scene, result, rig)]
                    outs.append("n" if what == "a" and result.status == "nothing_on_ray" else what)
                    n_obj.append(len(result.selection.objects) if result.selection else 0)
                if sigma == noise:
                    row.append(f"{''.join(outs)} obj{int(np.median(n_obj))}")
        print("  ".join(row), flush=True)
