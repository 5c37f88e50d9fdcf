"""Per scene and draw: outcome, status, chosen probability, "nothing detected" probability (default profile).

    python docs/issue11/session42/scripts/draws_outcomes.py FAMILY N SEED NOISE DRAWS [KEY=VALUE ...]
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf

family, n, seed0, noise, draws = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
over = sys.argv[6:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        rng = np.random.default_rng(seed0 + k)
        outs = []
        for _ in range(draws):
            pose.provide(sf.noisy(truth, noise, rng))
            r = sf.decided(perception, left, right, base)
            sel = r.selection
            outs.append(f"{sf.outcome(scene, r, rig)[:9]}/{r.status[:7]}/"
                        f"{sel.confidence if sel is not None else float('nan'):.2f}/{sel.none_probability if sel is not None else float('nan'):.2f}")
        print(k, " ".join(outs), flush=True)
