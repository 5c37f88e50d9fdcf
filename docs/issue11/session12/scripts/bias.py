"""Depth bias (match - truth, metres) per joint at 0 px over near scenes and families."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import test_synthetic_accuracy as t
import scene_families as sf
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.joint_stereo import joint_disparities
rows = []
def one(scenario, frame, tag):
    truth = frame.meta["keypoints_truth"]; rig = scenario.rig()
    L, R = rig.rectify(frame.left, frame.right)
    arm0 = GivenKeypoints("right", truth).estimate(L, R, rig)
    d0 = arm0.left_px[:, 0] - arm0.right_px[:, 0]
    f = joint_disparities(L, R, arm0.left_px, float(np.median(d0)), rig.disparity_sign, rig.focal_px, rig.baseline_m)
    fb = rig.focal_px * rig.baseline_m
    z0 = fb / np.abs(d0); z1 = np.where(f.matched, fb / np.abs(f.disparity_px), np.nan)
    rows.append((tag, z0, z1 - z0))
with tempfile.TemporaryDirectory() as tmp:
    for sc, fr in t.scenes(Path(tmp), int(sys.argv[1]), True, 2000, 0.0):
        one(sc, fr, "near")
    for fam in ("far", "elbow", "far_diver"):
        for s in sf.scenes(Path(tmp), fam, int(sys.argv[2]), 700):
            one(s.scenario, s.frame, fam)
for tag in ("near", "far", "elbow", "far_diver"):
    z = np.array([r[1] for r in rows if r[0] == tag]); dz = np.array([r[2] for r in rows if r[0] == tag])
    if not len(z): continue
    print(tag, "n", len(z), "body z median", np.median(z, 0).round(2))
    for j, name in enumerate(("shoulder", "elbow", "wrist")):
        e = dz[:, j]; e = e[np.isfinite(e)]
        print(f"  {name:8s} matched {len(e)} dz median {np.median(e):+.3f} m  p25 {np.percentile(e,25):+.3f} p75 {np.percentile(e,75):+.3f}  |gross>0.2| {np.mean(np.abs(e)>0.2):.2f}")
