import sys, collections, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception import given_arm as G
rec = {}
orig = G.torso_shoulder
def ts(*a, **k):
    out = orig(*a, **k); rec["t"] = out; return out
G.torso_shoulder = ts
n, seed0, noise, draws = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
over = ["pose.match_disparity_shoulder=head_torso"]
with tempfile.TemporaryDirectory() as tmp:
    for family in sf.FAMILIES:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
            td = arm.left_px[:, 0] - arm.right_px[:, 0]
            truth = scene.frame.meta["keypoints_truth"]
            rng = np.random.default_rng(seed0 + k)
            for d in range(draws):
                pose.provide(sf.noisy(truth, noise, rng))
                rec.clear()
                est = perception.estimate_arm(left, right)
                e = (est.left_px[:, 0] - est.right_px[:, 0]) - td
                t = rec.get("t")
                te = (t[0] - td[0]) if t else np.nan
                m = est.disparity_matched[0] if est.disparity_matched is not None else None
                sig = est.disparity_sigma_px[0] if est.disparity_sigma_px is not None else np.nan
                if abs(e[0]) > 1.0:
                    print(f"{family:14s}{k:3d} d{d} final {e[0]:+.2f} (sig {sig:.2f}, matched {m}) torso {te:+.2f} (sig {t[1] if t else float('nan'):.2f}) Z {rig.focal_px*rig.baseline_m/abs(td[0]):.2f}", flush=True)
