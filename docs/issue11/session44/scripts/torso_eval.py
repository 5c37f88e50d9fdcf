"""Per draw: the shoulder's disparity from the head and the torso's turn (``shoulder_model.head_torso_shoulder``)
against the truth joint, beside the shoulder's own 0.06 m patch match and the keypoints' given disparity (px).

    python docs/issue11/session44/scripts/torso_eval.py N SEED [NOISE_PX] [DRAWS]
"""
import sys, math
import numpy as np
sys.path.insert(0, "docs/issue11/session44/scripts")
from draws import noisy_draws  # noqa: E402
from dip3d_vehicle.perception import shoulder_model as sm  # noqa: E402
from dip3d_vehicle.perception.given_arm import torso_shoulder  # noqa: E402
from dip3d_vehicle.perception.joint_stereo import head_match, joint_disparities  # noqa: E402

n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
draws = int(sys.argv[4]) if len(sys.argv) > 4 else 4
rows = []
for family, k, draw, rig, left, right, perception, arm, g in noisy_draws(n, seed0, noise, draws):
    fb, f = rig.focal_px * rig.baseline_m, rig.focal_px
    td = arm.left_px[:, 0] - arm.right_px[:, 0]
    gd = g.left_px[:, 0] - g.right_px[:, 0]
    body = float(np.median(gd))
    sign = rig.disparity_sign
    head_px = (g.extra_left_px or {}).get("head")
    head = head_match(head_px, left, right, body, sign, f, rig.baseline_m)
    if head is None:
        print(f"{family:14s}{k:3d} d{draw} no head", flush=True)
        continue
    near, far = sm.head_torso_shoulder(head, head_px, g.left_px[0], f, rig.baseline_m,
                                       rig.principal_point_px[0], max(noise, 1.0))
    given_sigma = math.sqrt(2) * max(noise, 0.5)
    t = sm.two_way(near, far, 1 / (1 + math.exp(-sm.side_log_odds((gd[0], given_sigma), near, far))))
    own = joint_disparities(left, right, g.left_px[:1], body, sign, f, rig.baseline_m, patch_m=0.06)
    o = (sign * fb / (fb / abs(own.disparity_px[0]) + 0.03), max(own.sigma_px[0], own.disparity_px[0] ** 2 / fb * 0.05)) if own.matched[0] else None
    r = sm.reconcile([o, t]) if o else t
    landed = torso_shoulder(g, left, right, sign, f, rig.baseline_m, rig.principal_point_px[0], body, given_sigma,
                            head, (o[0], max(o[1], 1.0)) if o else None)
    zt = fb / abs(td[0])
    best = min((near, far), key=lambda c: abs(c[0] - td[0]))
    row = [zt, best[0] - td[0], t[0] - td[0], t[1], (o[0] - td[0]) if o else np.nan, r[0] - td[0], r[1],
           gd[0] - td[0], (fb / abs(best[0]) - zt), landed[0] - td[0], landed[1]]
    rows.append(row)
    print(f"{family:14s}{k:3d} d{draw} Z {zt:4.2f} torso best {row[1]:+.2f} picked {row[2]:+.2f} (sig {t[1]:.2f}) "
          f"own {row[4]:+.2f} both {row[5]:+.2f} (sig {r[1]:.2f}) given {row[7]:+.2f} | best-side depth err {row[8]:+.3f} m", flush=True)
a = np.array(rows)
print("depth error of the nearer side (m): median %+.3f mad %.3f p90|.| %.3f" % (np.median(a[:, 8]), np.median(abs(a[:, 8] - np.median(a[:, 8]))), np.percentile(abs(a[:, 8]), 90)))
for lab, i in (("torso, better side", 1), ("torso, picked by given", 2), ("own match", 4), ("own + torso", 5), ("given", 7),
               ("landed (given+own+other)", 9)):
    e = a[:, i]; e = e[np.isfinite(e)]
    print(f"{lab:24s} n {len(e):3d} median {np.median(e):+.2f} |e| med {np.median(abs(e)):.2f} p90 {np.percentile(abs(e), 90):.2f} >1px {np.mean(abs(e) > 1):.1%} px")
z = a[:, 2] / a[:, 3]
print("landed |z| p50 %.2f p90 %.2f" % (np.median(abs(a[:, 9] / a[:, 10])), np.percentile(abs(a[:, 9] / a[:, 10]), 90)))
print("torso |z| p50 %.2f p90 %.2f; own+torso |z| p50 %.2f p90 %.2f" % (np.median(abs(z)), np.percentile(abs(z), 90), np.median(abs(a[:, 5] / a[:, 6])), np.percentile(abs(a[:, 5] / a[:, 6]), 90)))
