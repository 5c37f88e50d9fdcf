import sys, tempfile
from pathlib import Path
import numpy as np
from scipy.sparse.csgraph import minimum_spanning_tree
from scipy.spatial.distance import pdist, squareform
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, K = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if K >= 0 and k != K: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        truth = scene.frame.meta["keypoints_truth"]
        pose.provide(sf.noisy(truth, 0.0, np.random.default_rng(0)))
        r = sf.decided(perception, left, right, base)
        if r.selection is None: continue
        for i, o in enumerate(r.selection.objects):
            px = r.candidates.left_px[list(o.members)]
            if len(px) < 6: continue
            T = minimum_spanning_tree(squareform(pdist(px))).toarray()
            e = np.sort(T[T > 0])
            print(k, i, "n", len(px), "median edge %.1f" % np.median(e), "p90 %.1f" % np.percentile(e, 90), "top", np.round(e[-3:], 1), "ratio %.1f" % (e[-1] / np.median(e)))
