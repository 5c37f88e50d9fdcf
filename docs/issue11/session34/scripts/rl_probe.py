"""Per joint: L->R and R->L raw matches vs truth disparity, with their sigmas (draws as joint_error.py)."""
import sys, tempfile, json
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf, draws as dr
from dip3d_vehicle.perception import given_arm as G, pipeline as P
from dip3d_vehicle.perception.joint_stereo import joint_disparities
cap = {}
orig = G.match_arm
def rec(arm, left, right, sign, focal_px, baseline_m, *a, **k):
    cap.update(arm=arm, left=left, right=right, sign=sign, f=focal_px, b=baseline_m, patch=k.get("patch_m", 0.06))
    return orig(arm, left, right, sign, focal_px, baseline_m, *a, **k)
G.match_arm = rec
import dip3d_vehicle.perception.pose as PO
for mod in (P, PO):
    if hasattr(mod, "match_arm"): mod.match_arm = rec
fam, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", ())
        dt = dr.truth_disparities(rig, scene.frame.meta["keypoints_truth"])
        for d, kp, joints in dr.draws(scene, seed0, k, 2.0):
            pose.provide(kp); cap.clear()
            perception.estimate_arm(left, right)
            if not cap: continue
            a = cap["arm"]; disp = a.left_px[:, 0] - a.right_px[:, 0]; body = float(np.median(disp)); s = cap["sign"]
            f1 = joint_disparities(cap["left"], cap["right"], a.left_px, body, s, cap["f"], cap["b"], patch_m=cap["patch"])
            f2 = joint_disparities(cap["right"], cap["left"], a.right_px, -body, -s, cap["f"], cap["b"], patch_m=cap["patch"])
            rows.append(dict(k=k, dt=dt.tolist(), lr=f1.disparity_px.tolist(), lrs=f1.sigma_px.tolist(), lrm=f1.matched.tolist(),
                             rl=(-f2.disparity_px).tolist(), rls=f2.sigma_px.tolist(), rlm=f2.matched.tolist(), given=disp.tolist(), lpx=a.left_px.tolist(), fb=cap["f"]*cap["b"], b=cap["b"]))
json.dump(rows, sys.stdout)
