import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, K = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
over = sys.argv[5:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if k != K: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        rng = np.random.default_rng(seed0 + k)
        outs = []
        for d in range(8):
            pose.provide(sf.noisy(scene.frame.meta["keypoints_truth"], 2.0, rng))
            r = sf.decided(perception, left, right, base)
            sel = r.selection
            outs.append(f"{sf.outcome(scene, r, rig)[:9]}/{sel.confidence:.2f}")
        print(K, " ".join(outs))
