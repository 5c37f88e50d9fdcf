"""Raw patch-match error vs truth joint centres, per family (px and m), with keypoint noise; no selector."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import joint_disparities
n, seed0, noise, draws = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
fams = sys.argv[5].split(",") if len(sys.argv) > 5 else list(sf.FAMILIES)
with tempfile.TemporaryDirectory() as tmp:
    for family in fams:
        rows = []
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
            f, b, sign = rig.focal_px, rig.baseline_m, rig.disparity_sign
            td = arm.left_px[:, 0] - arm.right_px[:, 0]
            rng = np.random.default_rng(seed0 + k)
            for _ in range(draws):
                pose.provide(sf.noisy(truth, noise, rng))
                a0 = pose.estimate(left, right, rig)
                d0 = a0.left_px[:, 0] - a0.right_px[:, 0]
                raw = joint_disparities(left, right, a0.left_px, float(np.median(d0)), sign, f, b, patch_m=0.06)
                err = np.where(raw.matched, raw.disparity_px - td, np.nan)
                zt = f * b / np.abs(td); zr = f * b / np.abs(np.where(raw.matched, raw.disparity_px, np.nan))
                rows.append(np.r_[err, zt - zr, td, k])
        a = np.array(rows)
        print(family, len(a), "matched", np.round(np.mean(np.isfinite(a[:, :3]), 0), 2))
        for j, name in enumerate(("shoulder", "elbow", "wrist")):
            e, m = a[:, j], a[:, 3 + j]
            ok = np.isfinite(e)
            print(f"  {name:8s} px med {np.median(e[ok]):+.2f} p10 {np.percentile(e[ok],10):+.2f} p90 {np.percentile(e[ok],90):+.2f}"
                  f"   m (in front +) med {np.median(m[ok]):+.3f} p10 {np.percentile(m[ok],10):+.3f} p90 {np.percentile(m[ok],90):+.3f}")
