"""Per draw (2 px): the head's matched surface minus the shoulder joint's depth, and |sx|, the torso's turn read in the image.

``head_offset_bins.py`` reads the useful part (the ``head-surface`` and ``|sx|`` columns). The "model" columns are a
first guess (the head's surface 0.10 m BEFORE the head's centre) that the data contradicted: the surface lies behind
the near shoulder by 0.02-0.14 m, by the turn; ``shoulder_model.head_torso_shoulder`` is the model that came of it.

The torso model: the shoulder joint lies ``HALF_M`` to the side of the head's vertical axis, the head's matched
surface ``HEAD_R_M`` before the head's centre; the side's camera-x component comes from the image offset of
shoulder and head, its z component is +- sqrt(1 - sx^2).

    python docs/issue11/session44/scripts/head_offset.py N SEED
"""
import sys, math
import numpy as np
sys.path.insert(0, "docs/issue11/session44/scripts")
from draws import noisy_draws  # noqa: E402
from dip3d_vehicle.perception.joint_stereo import head_disparity, joint_disparities  # noqa: E402

HALF_M, HEAD_R_M = 0.19, 0.10
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
rows = []
for family, k, draw, rig, left, right, perception, arm, g in noisy_draws(n, seed0, 2.0, 4):
    fb, f = rig.focal_px * rig.baseline_m, rig.focal_px
    cx = rig.principal_point_px[0]
    td = arm.left_px[:, 0] - arm.right_px[:, 0]
    zs_true = fb / abs(td[0])
    gd = g.left_px[:, 0] - g.right_px[:, 0]
    body = float(np.median(gd))
    sign = rig.disparity_sign
    head_px = (g.extra_left_px or {}).get("head")
    head = head_disparity(head_px, left, right, body, sign, f, rig.baseline_m)
    own = joint_disparities(left, right, g.left_px[:1], body, sign, f, rig.baseline_m, patch_m=0.06)
    if head is None:
        print(f"{family:14s}{k:3d} d{draw} no head", flush=True)
        continue
    zh = fb / abs(head[0]) + HEAD_R_M
    xs = (g.left_px[0, 0] - cx) / f
    xh = (head_px[0] - cx) / f
    # lateral offset in metres at the two depths (shoulder at ~zh)
    sx = float(np.clip((xs - xh) * zh / HALF_M, -1, 1))
    sz = math.sqrt(max(1 - sx * sx, 0.0))
    cands = np.array([zh - HALF_M * sz, zh + HALF_M * sz])
    err = cands - zs_true
    best = err[np.argmin(abs(err))]
    zown = fb / abs(own.disparity_px[0]) + 0.03 if own.matched[0] else np.nan
    zg = fb / abs(gd[0])
    ref = zown if np.isfinite(zown) else zg
    pick = err[np.argmin(abs(cands - ref))]
    rows.append((zs_true, fb / abs(head[0]) - zs_true, best, pick, zown - zs_true, zg - zs_true, abs(sx)))
    print(f"{family:14s}{k:3d} d{draw} Z {zs_true:4.2f} |sx| {abs(sx):.2f} head-surface {rows[-1][1]:+.3f} "
          f"model best {best:+.3f} by-ref {pick:+.3f} own {rows[-1][4]:+.3f} given {rows[-1][5]:+.3f}", flush=True)
a = np.array(rows)
for lab, i in (("head surface", 1), ("model best sign", 2), ("model sign by own/given", 3), ("own match +0.03", 4), ("given", 5)):
    e = a[:, i]; e = e[np.isfinite(e)]
    print(f"{lab:26s} n {len(e)} median {np.median(e):+.3f} |e| med {np.median(abs(e)):.3f} p90 {np.percentile(abs(e), 90):.3f} m")
