"""Per detectable draw (default, NOISE px): outcome and the arm's joint disparity errors / sigmas vs truth."""
import sys, tempfile, json
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import pipeline as P
n, seed0, noise = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
fams = sys.argv[4].split(",") if len(sys.argv) > 4 else ["line_of_sight", "far", "elbow", "far_diver"]
last = {}
orig = P.Perception.estimate_arm
def est(self, l, r):
    a = orig(self, l, r); last["arm"] = a; return a
P.Perception.estimate_arm = est
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for fam in fams:
        for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
            dt = dr.truth_disparities(rig, truth)
            rng = np.random.default_rng(seed0 + k)
            for sigma in (noise,):
                for _ in range(8 if sigma > 0 else 1):
                    kp = sf.noisy(truth, sigma, rng)
                    if sigma != noise:
                        continue
                    pose.provide(kp); last.clear()
                    res = sf.decided(perception, left, right, base)
                    a = last.get("arm")
                    e = (a.left_px[:, 0] - a.right_px[:, 0] - dt).tolist() if a is not None else None
                    s = a.disparity_sigma_px.tolist() if a is not None and a.disparity_sigma_px is not None else None
                    rows.append(dict(fam=fam, k=k, det=scene.detectable, band=scene.band, out=sf.outcome(scene, res, rig),
                                     status=res.status, err=e, sig=s, dt=dt.tolist()))
json.dump(rows, sys.stdout)
