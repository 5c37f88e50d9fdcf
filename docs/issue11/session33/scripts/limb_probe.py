"""Joint disparity errors (px) vs truth: the current match_arm vs a limb-line fit of many patches along each limb."""
import sys, tempfile, math
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import joint_stereo as JS

import os
T = np.linspace(float(os.environ.get('T0', 0.2)), float(os.environ.get('T1', 0.8)), int(os.environ.get('NT', 7)))
ERR = {'given': [], 'cur': [], 'limb': [], 'fused': []}

def limb_fit(left, right, lp, given_d, sign, f, B, prior_sigma, width_m=0.06, half_scale=0.5):
    prior_sigma = np.broadcast_to(np.asarray(prior_sigma, float), (3,))
    fb = f * B
    d0 = float(np.median(given_d))
    d_lo, d_hi = JS.reach_disparities(d0, fb)
    half = int(np.clip(round(half_scale * width_m * abs(d0) / B), 4, 24))
    rows, vals, sig = [], [], []
    for (a, b) in ((0, 1), (1, 2)):
        for t in T:
            p = lp[a] + t * (lp[b] - lp[a])
            m = JS.match_point(left, right, int(round(p[0])), int(round(p[1])), abs(d_lo), abs(d_hi), sign, half, 0.6, 1.5)
            if m is None:
                continue
            r = np.zeros(3); r[a] = 1 - t; r[b] = t
            rows.append(r); vals.append(sign * m[0]); sig.append(max(m[1], 0.5))
    rows = np.array(rows).reshape(-1, 3); vals = np.array(vals); sig = np.array(sig)
    # prior: given disparities
    A = np.vstack([rows, np.eye(3)]); y = np.concatenate([vals, given_d]); s = np.concatenate([sig, prior_sigma])
    keep = np.ones(len(y), bool)
    for _ in range(4):
        w = 1 / s[keep]
        x, *_ = np.linalg.lstsq(A[keep] * w[:, None], y[keep] * w, rcond=None)
        res = (A @ x - y) / s
        newkeep = np.abs(res) < 3; newkeep[-3:] = True
        if (newkeep == keep).all():
            break
        keep = newkeep
    return x, int(keep[:-3].sum())

fam, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default")
        truth = scene.frame.meta["keypoints_truth"]
        dt = dr.truth_disparities(rig, truth)
        for d, kp, joints in dr.draws(scene, seed0, k, sigma):
            pose.provide(kp)
            raw = pose.estimate(left, right, rig)
            given = raw.left_px[:, 0] - raw.right_px[:, 0]
            cur = perception.estimate_arm(left, right)
            dc = cur.left_px[:, 0] - cur.right_px[:, 0]
            sc = cur.disparity_sigma_px if cur.disparity_sigma_px is not None else np.full(3, np.nan)
            x, used = limb_fit(left, right, raw.left_px, given, rig.disparity_sign, rig.focal_px, rig.baseline_m, math.sqrt(2) * max(sigma, 0.5))
            sc2 = np.where(np.isfinite(sc), sc, math.sqrt(2) * max(sigma, 0.5))
            xf, _ = limb_fit(left, right, raw.left_px, dc, rig.disparity_sign, rig.focal_px, rig.baseline_m, sc2)
            for key, v in (('given', given), ('cur', dc), ('limb', x), ('fused', xf)):
                ERR[key].append(v - dt)
            if os.environ.get('QUIET'):
                continue
            print(f"{fam} {seed0} {k} {d} Z {rig.focal_px*rig.baseline_m/dt.mean():.2f} truth {np.round(dt,2).tolist()} "
                  f"given_err {np.round(given-dt,2).tolist()} cur_err {np.round(dc-dt,2).tolist()} cur_sig {np.round(sc,2).tolist()} "
                  f"limb_err {np.round(x-dt,2).tolist()} used {used}", flush=True)

for key, v in ERR.items():
    a = np.abs(np.array(v))
    sw = np.abs(np.array(v)[:, 0] - np.array(v)[:, 2])
    print(f"{fam} {key:6s} median {np.round(np.median(a, 0), 2).tolist()} p90 {np.round(np.percentile(a, 90, 0), 2).tolist()}  |S-W| median {np.median(sw):.2f} p90 {np.percentile(sw, 90):.2f}")
