import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception import given_arm as G
rec = {}
oh = G.head_disparity
def hd(*a, **k):
    r = oh(*a, **k); rec["head"] = r; return r
G.head_disparity = hd
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
allr = []
for family in ["line_of_sight", "far", "elbow", "far_diver", "undetectable"]:
  with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
        fb = rig.focal_px * rig.baseline_m
        bt = scene.frame.meta.get("body_truth", {}).get("xyz_cam_m", {})
        S = np.array(scene.frame.meta["joints_cam_m"]["shoulder"])
        rng = np.random.default_rng(seed0 + k)
        hs = []
        for _ in range(4):
            pose.provide(sf.noisy(truth, 2.0, rng)); rec.clear()
            perception.estimate_arm(left, right)
            h = rec.get("head")
            if h is not None: hs.append(fb / abs(h[0]) - S[2])
        nose = bt.get("nose"); ls = bt.get("left_shoulder"); rs = bt.get("right_shoulder")
        dn = nose[2] - S[2] if nose else np.nan
        dls = ls[2] - S[2] if ls else np.nan
        # facing: torso normal approx
        print(f"{family[:5]} {k:2d} zS {S[2]:.1f} head-S(m) {np.mean(hs) if hs else np.nan:+.3f} nose-S {dn:+.3f} otherS-S {dls:+.3f} arm {scene.frame.meta.get('arm', '')}", flush=True)
