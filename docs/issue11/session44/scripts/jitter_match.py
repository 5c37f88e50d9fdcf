"""Per draw (2 px): a joint's raw 0.06 m patch match at the noisy keypoint vs the median over a small jitter grid.

    python docs/issue11/session44/scripts/jitter_match.py N SEED [STEP_PX]
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session44/scripts")
from draws import noisy_draws, patch_match  # noqa: E402

n, seed0 = int(sys.argv[1]), int(sys.argv[2])
step = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0


def raw(left, right, x, y, body, sign, f, b):
    """One patch's match disparity (signed px) or nan."""
    got = patch_match(left, right, x, y, body, sign, f, b)
    return np.nan if got is None else got[0]


rows = []
for family, k, draw, rig, left, right, perception, arm, g in noisy_draws(n, seed0, 2.0, 4):
    td = arm.left_px[:, 0] - arm.right_px[:, 0]
    body = float(np.median(g.left_px[:, 0] - g.right_px[:, 0]))
    out = []
    for j in (0, 2):
        x, y = g.left_px[j]
        one = raw(left, right, x, y, body, rig.disparity_sign, rig.focal_px, rig.baseline_m)
        grid = [raw(left, right, x + dx * step, y + dy * step, body, rig.disparity_sign, rig.focal_px,
                    rig.baseline_m) for dx in (-1, 0, 1) for dy in (-1, 0, 1)]
        med = np.nanmedian(grid) if np.any(np.isfinite(grid)) else np.nan
        t0 = raw(left, right, *arm.left_px[j], body, rig.disparity_sign, rig.focal_px, rig.baseline_m)
        out += [one - td[j], med - td[j], t0 - td[j]]
    rows.append(out)
    print(f"{family:14s}{k:3d} d{draw} s one {out[0]:+.2f} med {out[1]:+.2f} at-truth {out[2]:+.2f} | "
          f"w one {out[3]:+.2f} med {out[4]:+.2f} at-truth {out[5]:+.2f}", flush=True)
a = np.array(rows)
for name, off in (("shoulder", 0), ("wrist", 3)):
    for lab, i in (("one", 0), ("med", 1), ("at-truth-kp", 2)):
        e = a[:, off + i]; e = e[np.isfinite(e)]
        c = e - np.median(e)
        print(f"{name:8s} {lab:12s} n {len(e)} median {np.median(e):+.2f} |e-med| med {np.median(abs(c)):.2f} p90 {np.percentile(abs(c), 90):.2f} >2px {np.mean(abs(c) > 2):.1%}")
