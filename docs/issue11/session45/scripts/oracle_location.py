"""fam.py with chosen joints' patches matched at the truth joint's left-image position (the rest as drawn).

    LOC_JOINTS=012 python docs/issue11/session45/scripts/oracle_location.py N SEED NOISE [KEY=VALUE ...]

Splits a joint's depth error into what the patch's position (2 px off the joint) costs and what the
match itself costs: the given disparity, the rays and the selector still see the noisy keypoints.
"""
import os, sys
import numpy as np
sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session33/scripts")
import fam  # noqa: E402
from dip3d_vehicle.perception import given_arm as G, pipeline as P  # noqa: E402

ONLY = [int(c) for c in os.environ.get("LOC_JOINTS", "2")]
state = {}
fam.record_truth(state)
orig_est = P.Perception.estimate_arm
def estimate_arm(self, l, r):
    t = state.get("truth")
    if t is not None:
        state["left"] = fam.truth_joints_px(self.rig, t, "left")
    return orig_est(self, l, r)
P.Perception.estimate_arm = estimate_arm
orig_jd = G.joint_disparities
def joint_disparities(left, right, left_xy, *a, **k):
    xy = np.array(left_xy, float, copy=True)
    if len(xy) == 3 and "left" in state:
        for j in ONLY:
            xy[j] = state["left"][j]
    return orig_jd(left, right, xy, *a, **k)
G.joint_disparities = joint_disparities
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
print(fam.summary(fam.tally_default(n, seed0, noise, sys.argv[4:]), f"{seed0} loc {ONLY}", noise))
