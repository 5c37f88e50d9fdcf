import sys, tempfile, math
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception import selection as S
orig = S.DefaultSelector._log_odds
def lo(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad=None, n_objects=None):
    out = orig(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad, n_objects)
    L = max(float(np.linalg.norm(arm3d.joint("wrist") - arm3d.joint("shoulder"))), 0.1)
    tilt = min(float(np.hypot(arm3d.depth_sigma_m[0], arm3d.depth_sigma_m[2])) / L, S.MAX_TILT_SIGMA_RAD)
    print("   costs", np.round(costs, 2), "arm_cost %.2f" % arm_cost, "tilt %.3f rad" % tilt, "len %.2f" % L, "dsig", np.round(arm3d.depth_sigma_m, 3), "psig %.3f" % pointing_sigma_rad, "log_odds", np.round(out, 2))
    return out
S.DefaultSelector._log_odds = lo
fam, n, seed0, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        if k != want: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        rng = np.random.default_rng(seed0 + k)
        truth = scene.frame.meta["keypoints_truth"]
        print("truth joints", {j: np.round(v, 2).tolist() for j, v in scene.frame.meta["joints_cam_m"].items()})
        for _ in range(2):
            pose.provide(sf.noisy(truth, 2.0, rng))
            r = sf.decided(perception, left, right, base)
            print(" ->", r.status, np.round(r.selection.scores, 2), "none %.2f" % r.selection.none_probability)
