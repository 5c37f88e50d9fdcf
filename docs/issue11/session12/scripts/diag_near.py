"""Per scene, 0 px: truth disparity vs matched, and the outcome off / on."""
import sys, tempfile, math
from pathlib import Path
import numpy as np, cv2
sys.path.insert(0, "tests/perception")
import test_synthetic_accuracy as t
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.joint_stereo import joint_disparities
from scene_families import noisy
N = int(sys.argv[1]) if len(sys.argv) > 1 else 40
with tempfile.TemporaryDirectory() as tmp:
    for k, (scenario, frame) in enumerate(t.scenes(Path(tmp), N, True, 1000, 0.0)):
        truth = frame.meta["keypoints_truth"]
        polygon = np.asarray(frame.meta["placards"][scenario.target_id]["left_polygon_px"], np.float32)
        rig = scenario.rig()
        L, R = rig.rectify(frame.left, frame.right)
        outs = []
        for ov in ((), ("pose.match_disparity=true",)):
            pose = GivenKeypoints("right", truth)
            per = Perception(rig, load_params("default", overrides=ov), pose)
            arm0 = pose.estimate(L, R, rig)
            cands = per.detector.detect(L, R, arm0, rig)
            pose.provide(noisy(truth, 0.0, np.random.default_rng(0)))
            arm = per.estimate_arm(L, R)
            checked = per.check_arm(arm)
            res = per.decide(checked, cands) if checked.status == "ok" else checked
            hit = False
            if res.target_rect_px is not None:
                px = rig.to_original(res.target_rect_px, "left")[0]
                hit = cv2.pointPolygonTest(polygon, (float(px[0]), float(px[1])), False) >= 0
            sel = res.selection
            outs.append(f"{'HIT' if hit else 'miss'} {res.status} c={sel.confidence if sel else float('nan'):.2f}")
            if ov:
                d0 = arm0.left_px[:, 0] - arm0.right_px[:, 0]
                d1 = arm.left_px[:, 0] - arm.right_px[:, 0]
                f = joint_disparities(L, R, arm0.left_px, float(np.median(d0)), rig.disparity_sign, rig.focal_px, rig.baseline_m)
        print(k, "|", outs[0], "|", outs[1], "| truth d", d0.round(1), "match", np.where(f.matched, f.disparity_px, np.nan).round(1),
              "sig", f.sigma_px.round(2), "sc", f.score.round(2), "final", d1.round(1), flush=True)
