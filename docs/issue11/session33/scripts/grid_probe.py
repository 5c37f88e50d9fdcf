"""Raw joint matches vs truth (px): one patch at the keypoint vs the median of a grid of patches around it."""
import os, sys, tempfile
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import draws as dr
from dip3d_vehicle.perception import joint_stereo as JS
STEP_M = float(os.environ.get("STEP_M", "0.02")); NG = int(os.environ.get("NG", "1"))
fam, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
E = {"one": [], "grid": []}
with tempfile.TemporaryDirectory() as tmp:
    for rig, left, right, raw, body, dt in dr.given_arms(tmp, fam, n, seed0, sigma):
        fb = rig.focal_px * rig.baseline_m
        d_lo, d_hi = JS.reach_disparities(body, fb)
        half = JS.patch_half_px(body, rig.baseline_m, 0.06)
        step = max(1, int(round(STEP_M * abs(body) / rig.baseline_m)))
        one, grid = np.full(3, np.nan), np.full(3, np.nan)
        for j in range(3):
            x, y = (int(round(v)) for v in raw.left_px[j])
            vals = []
            for dy in range(-NG, NG + 1):
                for dx in range(-NG, NG + 1):
                    m = JS.match_point(left, right, x + dx * step, y + dy * step, d_lo, d_hi, rig.disparity_sign, half, 0.6, 1.5)
                    if m is not None:
                        vals.append(rig.disparity_sign * m[0])
                        if dx == 0 and dy == 0:
                            one[j] = vals[-1]
            if len(vals) >= 3:
                grid[j] = float(np.median(vals))
        E["one"].append(one - dt); E["grid"].append(grid - dt)
for key, v in E.items():
    v = np.array(v); ab = np.abs(v)
    print(f"{fam} {seed0} {key} step {STEP_M} matched {np.isfinite(v).sum(0).tolist()}/{len(v)} signed median {np.round(np.nanmedian(v,0),2).tolist()} |err| median {np.round(np.nanmedian(ab,0),2).tolist()} p90 {np.round(np.nanpercentile(ab,90,0),2).tolist()}")
