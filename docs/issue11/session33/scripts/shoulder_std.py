"""Shoulder raw match error (px, vs truth joint) with the patch's flatness floor at 2.0 vs lower."""
import math, os, sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import joint_stereo as JS
orig = JS._textured_patch
fam, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
floors = (2.0, 1.5, 1.0, 0.5)
E = {f: [] for f in floors}
cnt = 0
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default")
        truth = scene.frame.meta["keypoints_truth"]
        L = rig.to_rectified(np.array([truth["left"]["shoulder"]], float), "left")
        R = rig.to_rectified(np.array([truth["right"]["shoulder"]], float), "right")
        dt = float(L[0, 0] - R[0, 0])
        fb = rig.focal_px * rig.baseline_m
        for d, kp, joints in dr.draws(scene, seed0, k, sigma):
            cnt += 1
            pose.provide(kp)
            raw = pose.estimate(left, right, rig)
            given = raw.left_px[:, 0] - raw.right_px[:, 0]
            body = float(np.median(given))
            half = JS.patch_half_px(body, rig.baseline_m, 0.06)
            x, y = (int(round(v)) for v in raw.left_px[0])
            d_lo, d_hi = JS.reach_disparities(body, fb)
            for f in floors:
                JS._textured_patch = lambda im, x, y, h, min_std=f: orig(im, x, y, h, min(min_std, f))
                m = JS.match_point(left, right, x, y, d_lo, d_hi, rig.disparity_sign, half, 0.6, 1.5)
                JS._textured_patch = orig
                if m is not None:
                    E[f].append(rig.disparity_sign * m[0] - dt)
for f, v in E.items():
    v = np.array(v)
    print(f"{fam} {seed0} floor {f}: matched {len(v)}/{cnt} signed median {np.median(v):.2f} |err| median {np.median(np.abs(v)):.2f} p90 {np.percentile(np.abs(v), 90):.2f}")
