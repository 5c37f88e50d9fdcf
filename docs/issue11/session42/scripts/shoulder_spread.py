"""Per scene: the shoulder/wrist raw patch match's error (px) across 8 noisy draws, at the noisy keypoint and
as the median of a grid of patches around it (does the draw-to-draw spread come from where the patch sits?).

    python docs/issue11/session42/scripts/shoulder_spread.py FAMILY N SEED NOISE [GRID_STEP_PX]
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import joint_disparities

family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
step = float(sys.argv[5]) if len(sys.argv) > 5 else 3.0
offs = np.array([(dx, dy) for dx in (-step, 0, step) for dy in (-step, 0, step)])
allr = []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        f, b, sign = rig.focal_px, rig.baseline_m, rig.disparity_sign
        t = arm  # truth arm, rectified
        td = t.left_px[:, 0] - t.right_px[:, 0]
        rng = np.random.default_rng(seed0 + k)
        one, grid = [], []
        for _ in range(8):
            pose.provide(sf.noisy(truth, noise, rng))
            a = pose.estimate(left, right, rig)
            d = a.left_px[:, 0] - a.right_px[:, 0]
            body = float(np.median(d))
            found = joint_disparities(left, right, a.left_px, body, sign, f, b, patch_m=0.06)
            one.append(np.where(found.matched, found.disparity_px - td, np.nan))
            pts = np.concatenate([a.left_px + o for o in offs])
            g = joint_disparities(left, right, pts, body, sign, f, b, patch_m=0.06)
            gd = np.where(g.matched, g.disparity_px, np.nan).reshape(len(offs), 3)
            grid.append(np.nanmedian(gd, axis=0) - td)
        one, grid = np.array(one), np.array(grid)
        allr.append((np.nanstd(one, 0), np.nanstd(grid, 0), np.nanmean(one, 0), np.nanmean(grid, 0)))
        print(f"{k:2d} Z {f*b/abs(td[0]):.1f} one sd S/E/W {np.nanstd(one,0).round(2)} mean {np.nanmean(one,0).round(2)} | "
              f"grid sd {np.nanstd(grid,0).round(2)} mean {np.nanmean(grid,0).round(2)}", flush=True)
r = np.array(allr)
print("median sd one", np.nanmedian(r[:, 0], 0).round(2), "grid", np.nanmedian(r[:, 1], 0).round(2),
      "| |mean| one", np.nanmedian(np.abs(r[:, 2]), 0).round(2), "grid", np.nanmedian(np.abs(r[:, 3]), 0).round(2))
