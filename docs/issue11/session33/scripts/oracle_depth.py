"""Families at given noise with the arm's joint disparities replaced by the truth's (oracle), sigma ORACLE_SIGMA px."""
import os, sys, dataclasses
import numpy as np
sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session33/scripts")
from fam import record_truth, summary, tally_default, truth_joints_px  # noqa: E402
from dip3d_vehicle.perception import pipeline as P

SIG = float(os.environ.get("ORACLE_SIGMA", "0.3"))
state = {}
ORNG = np.random.default_rng(12345)
record_truth(state)
orig_est = P.Perception.estimate_arm
def estimate_arm(self, l, r):
    arm = orig_est(self, l, r)
    if arm is None or "truth" not in state or SIG < 0:
        return arm
    t = state["truth"]
    L, R = truth_joints_px(self.rig, t, "left"), truth_joints_px(self.rig, t, "right")
    d = L[:, 0] - R[:, 0] + ORNG.normal(0.0, SIG, 3) * float(os.environ.get('ORACLE_NOISE', '0'))
    only = [int(c) for c in os.environ.get("ORACLE_JOINTS", "012")]
    right = np.array(arm.right_px, float, copy=True)
    sig = np.array(arm.disparity_sigma_px if arm.disparity_sigma_px is not None else np.full(3, np.nan), float)
    matched = np.array(arm.disparity_matched if arm.disparity_matched is not None else np.zeros(3, bool), bool)
    for j in only:
        if not os.environ.get('ORACLE_KEEP'):
            right[j, 0] = arm.left_px[j, 0] - d[j]; right[j, 1] = arm.left_px[j, 1]
        sig[j] = SIG; matched[j] = True
    return dataclasses.replace(arm, right_px=right, disparity_sigma_px=sig, disparity_matched=matched)
P.Perception.estimate_arm = estimate_arm
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
print(summary(tally_default(n, seed0, noise), f"sigma {SIG}", noise))
