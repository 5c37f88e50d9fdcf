"""Per family: elbow / wrist matched at the 0.06 m patch, and at 0.12 m where 0.06 m did not; disparity errors (px).

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session25/scripts/patch_census.py SEED0 [N] [NOISE_PX]

The evidence for the 0.12 m retry that session 25 tried and reverted (README); "given there" is the
noisy keypoints' own disparity error in the draws the retry matched.
"""
import numpy as np
from draws import family_arm_draws
from dip3d_vehicle.perception import joint_stereo as js
JOINTS = ("shoulder", "elbow", "wrist")
for family, family_draws in family_arm_draws():
    rows = {1: [], 2: []}
    for d in family_draws:
        given = d.given_px
        truth = np.array([d.fb / d.joints[j][2] for j in JOINTS])
        a, b = (js.joint_disparities(d.left, d.right, d.arm.left_px, d.body_px, d.rig.disparity_sign, d.rig.focal_px,
                                     d.rig.baseline_m, patch_m=p) for p in (0.06, 0.12))
        for j in (1, 2):
            rows[j].append((a.matched[j], a.disparity_px[j] - truth[j], b.matched[j], b.disparity_px[j] - truth[j],
                            b.sigma_px[j], given[j] - truth[j]))
    for j in (1, 2):
        r = rows[j]
        n06 = sum(1 for x in r if x[0])
        fb_ = [x for x in r if not x[0] and x[2]]
        none = [x for x in r if not x[0] and not x[2]]
        e06 = np.array([abs(x[1]) for x in r if x[0]])
        efb = np.array([abs(x[3]) for x in fb_]); eg = np.array([abs(x[5]) for x in fb_])
        gross_fb = np.array([abs(x[3] - x[5]) > 3 * np.hypot(max(x[4], js.JOINT_FLOOR_FACTOR[j]), 2.83) for x in fb_])
        def q(v): return f"med {np.median(v):.2f} p90 {np.percentile(v,90):.2f} >3px {np.mean(v>3)*100:.0f}%" if len(v) else "-"
        print(f"{family:14s} {JOINTS[j]:6s} draws {len(r)} 0.06 matched {n06} ({q(e06)}) | fallback 0.12 matched {len(fb_)}: err {q(efb)} gross {int(gross_fb.sum() if len(fb_) else 0)} | given there {q(eg)} | neither {len(none)}", flush=True)
