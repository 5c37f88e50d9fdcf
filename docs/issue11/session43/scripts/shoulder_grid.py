"""Shoulder depth from one patch vs robust combos of several patches; error (m, + = in front) vs the truth joint."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import joint_disparities, patch_half_px
n, seed0, noise, draws = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
res = {k: [] for k in ("one", "grid3", "grid3_w", "big09", "small04", "med_sizes")}
with tempfile.TemporaryDirectory() as tmp:
    for family in sf.FAMILIES:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
            f, b, sign = rig.focal_px, rig.baseline_m, rig.disparity_sign
            fb = f * b
            td = arm.left_px[:, 0] - arm.right_px[:, 0]
            zt = fb / abs(td[0])
            rng = np.random.default_rng(seed0 + k)
            for _ in range(draws):
                pose.provide(sf.noisy(truth, noise, rng))
                a0 = pose.estimate(left, right, rig)
                d0 = a0.left_px[:, 0] - a0.right_px[:, 0]
                body = float(np.median(d0))
                half = patch_half_px(body, b, 0.06)
                s = a0.left_px[0]
                def z_of(pts, patch):
                    r = joint_disparities(left, right, np.asarray(pts, float), body, sign, f, b, patch_m=patch)
                    return np.where(r.matched, fb / np.abs(r.disparity_px), np.nan), r.sigma_px
                z1, _ = z_of([s], 0.06)
                res["one"].append(zt - z1[0])
                offs = np.array([(dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)], float) * half
                zg, sg = z_of(s + offs, 0.06)
                res["grid3"].append(zt - np.nanmedian(zg) if np.sum(np.isfinite(zg)) >= 3 else np.nan)
                w = np.where(np.isfinite(zg), 1.0 / np.maximum(sg, 0.5) ** 2, 0)
                res["grid3_w"].append(zt - np.nansum(w * np.nan_to_num(zg)) / w.sum() if w.sum() > 0 else np.nan)
                res["big09"].append(zt - z_of([s], 0.09)[0][0])
                res["small04"].append(zt - z_of([s], 0.04)[0][0])
                zs = np.array([z_of([s], p)[0][0] for p in (0.04, 0.06, 0.09)])
                res["med_sizes"].append(zt - np.nanmedian(zs) if np.sum(np.isfinite(zs)) >= 2 else np.nan)
for key, v in res.items():
    v = np.array(v, float); ok = np.isfinite(v)
    e = v[ok] - 0.03
    print(f"{key:10s} matched {ok.mean():.2f} med {np.median(v[ok]):+.3f} |e-0.03| med {np.median(np.abs(e)):.3f} p90 {np.percentile(np.abs(e),90):.3f} >0.06 {np.mean(np.abs(e)>0.06):.3f}")
