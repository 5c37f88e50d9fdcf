import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
over = sys.argv[1:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), "undetectable", 4, 0)):
        if k != 3: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        poly = scene.target_polygon.reshape(-1, 2)
        tgt = rig.to_rectified(poly.astype(float), "left")
        print("target rect px", tgt.mean(0).round(1), "width", (tgt[:,0].max()-tgt[:,0].min()).round(1))
        truth = scene.frame.meta["keypoints_truth"]
        rng = np.random.default_rng(3)
        for d in range(8):
            pose.provide(sf.noisy(truth, 2.0 if d else 0.0, rng))
            r = sf.decided(perception, left, right, base)
            sel = r.selection
            print(d, r.status, sf.outcome(scene, r, rig), "conf %.2f none %.2f" % (sel.confidence, sel.none_probability),
                  "blobs", [tuple(np.round(p, 0)) for p in r.unrecognised.left_px], [round(float(z), 2) for z in r.unrecognised.xyz_m[:, 2]])
