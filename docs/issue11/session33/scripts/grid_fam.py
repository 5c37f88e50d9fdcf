"""Families (default only) with the given arm's joint matches taken as the median of a grid of patches (GRID_JOINTS; FALLBACK=1: only where the single patch does not match). Run on the previous main (PYTHONPATH=a worktree of 3290069): it patches joint_stereo.joint_disparities."""
import os, sys
import numpy as np
sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session33/scripts")
from fam import summary, tally_default  # noqa: E402
from dip3d_vehicle.perception import joint_stereo as JS
STEP_M = float(os.environ.get("STEP_M", "0.02")); JOINTS = [int(c) for c in os.environ.get("GRID_JOINTS", "0")]
MIN_N = int(os.environ.get("MIN_N", "3"))
orig = JS.joint_disparities
def joint_disparities(left, right, left_xy, body, sign, focal_px, baseline_m, patch_m=0.12, min_score=JS.MATCH_MIN_SCORE,
                      lr_tolerance_px=JS.MATCH_LR_TOLERANCE_PX):
    found = orig(left, right, left_xy, body, sign, focal_px, baseline_m, patch_m, min_score, lr_tolerance_px)
    d_lo, d_hi = JS.reach_disparities(body, focal_px * baseline_m)
    half = JS.patch_half_px(body, baseline_m, patch_m)
    step = max(1, int(round(STEP_M * abs(body) / baseline_m)))
    for j in JOINTS:
        if len(left_xy) != 3:
            continue
        x, y = (int(round(v)) for v in left_xy[j])
        vals, sigs, scs = [], [], []
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                m = JS.match_point(left, right, x + dx * step, y + dy * step, d_lo, d_hi, sign, half, min_score, lr_tolerance_px)
                if m is not None:
                    vals.append(m[0]); sigs.append(m[1]); scs.append(m[2])
        if len(vals) >= MIN_N and not (os.environ.get("FALLBACK") and found.matched[j]):
            v = np.array(vals)
            med = float(np.median(v))
            found.disparity_px[j] = sign * med
            found.sigma_px[j] = max(float(np.median(sigs)), 1.4826 * float(np.median(np.abs(v - med))))
            found.matched[j] = True
            found.score[j] = float(np.median(scs))
    return found
JS.joint_disparities = joint_disparities
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
over = sys.argv[4:]
print(summary(tally_default(n, seed0, noise, over), f"{seed0} grid {JOINTS} step {STEP_M} min {MIN_N} {' '.join(over)}",
              noise))
