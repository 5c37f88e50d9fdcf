"""Per frame: the given arm's shoulder -> wrist direction error with and without pose.match_disparity.

    PYTHONPATH=. python docs/issue11/session22/scripts/arm_direction.py SCENARIO|FILE SEED T0_S N RATE_HZ

The vehicle at its start pose, frames from T0_S at RATE_HZ: for the truth-pose keypoints (truth plus
the scenario's noise) as given and as matched, the angle (deg) between the triangulated shoulder ->
wrist and the body's truth, its tilt toward the camera (deg, + toward), each joint's depth error (m)
and which joints matched. Environment SMS overrides joint_stereo.SHOULDER_MATCH_SIGMA_M.
"""
import sys, numpy as np
sys.path.insert(0, "docs/issue11/session21/scripts")
from matched_arm import depths, tilt_deg
import os
import dip3d_vehicle.perception.joint_stereo as js
js.SHOULDER_MATCH_SIGMA_M = float(os.environ.get("SMS", js.SHOULDER_MATCH_SIGMA_M))
from dip3d_vehicle.bench import make_perception, simulated_frames
sc, seed, t0, n, hz = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
data = simulated_frames(sc, [seed], n, rate_hz=hz, start_s=t0, approach_m_s=0.0)
rig = data.rig
runs = [make_perception("default", rig, {"pose.backend": "keypoints", "pose.match_disparity": False}),
        make_perception("default", rig, {"pose.backend": "keypoints", "pose.match_disparity": True})]
def ang(a, b): return np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))
acc = [[], []]
for k, fr in enumerate(data.frames):
    truth = np.array([rig.R1 @ np.asarray(fr.meta["joints_cam_m"][j]) for j in ("shoulder", "elbow", "wrist")])
    L, R = rig.rectify(fr.left, fr.right)
    tgt = rig.R1 @ np.asarray(fr.meta["placards"][fr.meta["target_id"]]["xyz_cam_m"])
    out = [f"t {t0 + k/hz:.1f}"]
    for i, (per, pose) in enumerate(runs):
        pose.provide(fr.meta.get("keypoints"))
        arm = per.core.estimate_arm(L, R) if hasattr(per, "core") else per.estimate_arm(L, R)
        if arm is None: out.append("none"); continue
        x = depths(arm, rig)
        e = ang(x[2] - x[0], truth[2] - truth[0]); acc[i].append(e)
        out.append(f"| dir err {e:5.1f} tilt {tilt_deg(x) - tilt_deg(truth):+5.1f} depths {np.round(x[:,2]-truth[:,2],2)} m {None if arm.disparity_matched is None else arm.disparity_matched.astype(int)}")
    print(" ".join(out))
print("median dir err", [round(float(np.median(a)),1) for a in acc], "p90", [round(float(np.percentile(a,90)),1) for a in acc])
