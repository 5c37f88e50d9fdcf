"""Feasibility: the arm's tilt from a disparity profile along shoulder->wrist vs the joints' own matches.

    python docs/issue11/session42/scripts/limb_profile.py FAMILY N SEED NOISE

Per scene (8 noisy draws each): truth depth difference wrist - shoulder (m), the error of the
pipeline's arm (estimate_arm, triangulated) and of a robust line through patch matches sampled along
the left shoulder->wrist segment.
"""
import sys, tempfile, math
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import match_point, reach_disparities, patch_half_px

family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
PATCH_M = float(sys.argv[5]) if len(sys.argv) > 5 else 0.06
TS = np.linspace(0.15, 0.85, 15)


def profile(left, right, L, body, sign, f, b):
    """Return (d at shoulder, d at wrist) from a robust line fit through matches along the segment, or None."""
    d_lo, d_hi = reach_disparities(body, f * b)
    half = patch_half_px(body, b, PATCH_M)
    ts, ds, ws = [], [], []
    for t in TS:
        x, y = L[0] + t * (L[2] - L[0])
        m = match_point(left, right, int(round(x)), int(round(y)), d_lo, d_hi, sign, half, 0.6, 1.5)
        if m is None:
            continue
        ts.append(t); ds.append(m[0]); ws.append(1.0 / m[1] ** 2)
    if len(ts) < 5:
        return None
    ts, ds, ws = map(np.array, (ts, ds, ws))
    keep = np.ones(len(ts), bool)
    for _ in range(3):
        A = np.c_[np.ones(keep.sum()), ts[keep]]
        W = ws[keep]
        coef = np.linalg.lstsq(A * np.sqrt(W)[:, None], ds[keep] * np.sqrt(W), rcond=None)[0]
        res = ds - (coef[0] + coef[1] * ts)
        mad = 1.4826 * np.median(np.abs(res[keep])) + 0.2
        keep = np.abs(res) < 3 * mad
        if keep.sum() < 4:
            return None
    return sign * coef[0], sign * (coef[0] + coef[1]), int(keep.sum())


rows = []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        J = scene.frame.meta["joints_cam_m"]; T = np.array([J["shoulder"], J["elbow"], J["wrist"]])
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        f, b, sign = rig.focal_px, rig.baseline_m, rig.disparity_sign
        rng = np.random.default_rng(seed0 + k)
        ep, eq, nq = [], [], []
        for _ in range(8):
            pose.provide(sf.noisy(truth, noise, rng))
            a = perception.estimate_arm(left, right)
            if a is None:
                continue
            d = a.left_px[:, 0] - a.right_px[:, 0]
            Z = f * b / np.abs(d)
            ep.append((Z[2] - Z[0]) - (T[2, 2] - T[0, 2]))
            body = float(np.median(d))
            p = profile(left, right, a.left_px, body, sign, f, b)
            if p is not None:
                zs, zw = f * b / abs(p[0]), f * b / abs(p[1])
                eq.append((zw - zs) - (T[2, 2] - T[0, 2])); nq.append(p[2])
        ang = math.degrees(math.atan2(abs(T[2, 0] - T[0, 0]), abs(T[2, 1] - T[0, 1])))
        print(f"{k:2d} S {np.linalg.norm(T[0]):.1f}m dZ {T[2,2]-T[0,2]:+.2f} img-ang {ang:3.0f}  pipeline |err| "
              f"{np.median(np.abs(ep)) if ep else np.nan:.3f}  profile |err| {np.median(np.abs(eq)) if eq else np.nan:.3f}"
              f" ({len(eq)}/8, {np.median(nq) if nq else 0:.0f} pts)", flush=True)
        rows.append((np.median(np.abs(ep)) if ep else np.nan, np.median(np.abs(eq)) if eq else np.nan))
r = np.array(rows)
print("median over scenes: pipeline", np.nanmedian(r[:, 0]), "profile", np.nanmedian(r[:, 1]))
