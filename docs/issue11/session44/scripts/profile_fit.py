"""Per draw (2 px, 3 a scene): the arm's disparity profile (patches along upper arm and forearm, affine fit) against the truth.

    python docs/issue11/session44/scripts/profile_fit.py N SEED [STEPS]
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session44/scripts")
from draws import noisy_draws, patch_match  # noqa: E402

n, seed0 = int(sys.argv[1]), int(sys.argv[2])
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 6


def profile(left, right, xy, body, sign, f, b, steps):
    """Return samples (weights on s, e, w), disparity, sigma along the arm."""
    rows = []
    ts = (np.arange(steps) + 0.5) / steps
    for seg in (0, 1):
        a, c = xy[seg], xy[seg + 1]
        for t in ts:
            p = (1 - t) * a + t * c
            got = patch_match(left, right, p[0], p[1], body, sign, f, b)
            if got is None:
                continue
            wgt = np.zeros(3); wgt[seg] = 1 - t; wgt[seg + 1] = t
            rows.append((wgt, got[0], got[1]))
    return rows


def fit(rows):
    """Robust weighted least squares of (d_s, d_e, d_w); None if under-determined."""
    if len(rows) < 4:
        return None
    A = np.array([r[0] for r in rows]); y = np.array([r[1] for r in rows]); s = np.array([r[2] for r in rows])
    keep = np.ones(len(y), bool)
    for _ in range(4):
        if keep.sum() < 4 or np.linalg.matrix_rank(A[keep]) < 3:
            return None
        w = 1 / s[keep]
        x, *_ = np.linalg.lstsq(A[keep] * w[:, None], y[keep] * w, rcond=None)
        r = (y - A @ x) / s
        scale = max(1.4826 * np.median(np.abs(r[keep])), 1.0)
        new = np.abs(r) <= 3 * scale
        if np.array_equal(new, keep):
            break
        keep = new
    return x, keep.sum(), len(y)



def main():
    rows = []
    for family, k, draw, rig, left, right, perception, arm, given in noisy_draws(n, seed0, 2.0, 3):
        td = arm.left_px[:, 0] - arm.right_px[:, 0]
        gd = given.left_px[:, 0] - given.right_px[:, 0]
        est = perception.estimate_arm(left, right)
        md = est.left_px[:, 0] - est.right_px[:, 0]
        body = float(np.median(gd))
        got = fit(profile(left, right, given.left_px, body, rig.disparity_sign, rig.focal_px, rig.baseline_m, steps))
        if got is None:
            print(f"{family:14s}{k:3d} d{draw} no fit", flush=True)
            continue
        x, used, tot = got
        e_main = md - td; e_prof = x - td
        rows.append((*e_main, *e_prof, td[0]))
        print(f"{family:14s}{k:3d} d{draw} td {td[0]:5.1f} main s {e_main[0]:+.2f} w {e_main[2]:+.2f} tilt {e_main[2]-e_main[0]:+.2f} | prof s {e_prof[0]:+.2f} e {e_prof[1]:+.2f} w {e_prof[2]:+.2f} tilt {e_prof[2]-e_prof[0]:+.2f} ({used}/{tot})", flush=True)
    a = np.array(rows)
    for name, i in (("shoulder", 0), ("elbow", 1), ("wrist", 2)):
        for lab, off in (("main", 0), ("prof", 3)):
            e = a[:, off + i]
            print(f"{name:8s} {lab} median {np.median(e):+.2f} |e| med {np.median(abs(e)):.2f} p90 {np.percentile(abs(e), 90):.2f}")
    for lab, off in (("main", 0), ("prof", 3)):
        t = a[:, off + 2] - a[:, off]
        print(f"tilt {lab} median {np.median(t):+.2f} |e| med {np.median(abs(t - np.median(t))):.2f} p90 {np.percentile(abs(t - np.median(t)), 90):.2f}")


main()
