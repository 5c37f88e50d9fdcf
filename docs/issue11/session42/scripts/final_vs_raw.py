"""Per scene: the raw patch match (0.06 m patch) and the pipeline's final joint disparity, error vs the truth
joint centres (px), over 8 noisy draws; the final arm's tilt error (deg).

    python docs/issue11/session42/scripts/final_vs_raw.py FAMILY N SEED NOISE [SCENES]
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import joint_disparities

family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
want = None if len(sys.argv) < 6 else {int(x) for x in sys.argv[5].split(",")}
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if want is not None and k not in want:
            continue
        truth = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        f, b, sign = rig.focal_px, rig.baseline_m, rig.disparity_sign
        td = arm.left_px[:, 0] - arm.right_px[:, 0]
        rng = np.random.default_rng(seed0 + k)
        print(f"{k:2d} Z {f*b/abs(td).round(1)} d {td.round(1)}")
        for _ in range(8):
            pose.provide(sf.noisy(truth, noise, rng))
            a0 = pose.estimate(left, right, rig)
            d0 = a0.left_px[:, 0] - a0.right_px[:, 0]
            raw = joint_disparities(left, right, a0.left_px, float(np.median(d0)), sign, f, b, patch_m=0.06)
            a = perception.estimate_arm(left, right)
            d = a.left_px[:, 0] - a.right_px[:, 0]
            r = sf.decided(perception, left, right, base)
            print(f"   given {np.round(d0 - td, 2)} raw {np.round(np.where(raw.matched, raw.disparity_px - td, np.nan), 2)}"
                  f" final {np.round(d - td, 2)} m {a.disparity_matched} sig {np.round(a.disparity_sigma_px, 2)} {sf.outcome(scene, r, rig)}")
