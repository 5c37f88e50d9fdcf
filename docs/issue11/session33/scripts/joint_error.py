"""The given arm's joint disparity errors against the truth joints (pixels), as Perception.estimate_arm makes them.

    PYTHONPATH=. python docs/issue11/session33/scripts/joint_error.py FAMILY N SEED0 [NOISE_PX] [KEY=VALUE ...]

Per joint (shoulder, elbow, wrist): signed median error, |error| median / p90, the claimed sigma's median, and
|error / sigma| median / p90 (a calibrated sigma gives 0.67 / 1.64); also |error(shoulder) - error(wrist)|, which
sets the arm's tilt toward the camera. The draws are the families' own (8 per scene, truth keypoints + noise).
"""
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf  # noqa: E402
import draws as dr  # noqa: E402

fam, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
sigma = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
over = sys.argv[5:]
err, sig = [], []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", over)
        truth = scene.frame.meta["keypoints_truth"]
        dt = dr.truth_disparities(rig, truth)
        for d, kp, joints in dr.draws(scene, seed0, k, sigma):
            pose.provide(kp)
            cur = perception.estimate_arm(left, right)
            dc = cur.left_px[:, 0] - cur.right_px[:, 0]
            s = cur.disparity_sigma_px if cur.disparity_sigma_px is not None else np.full(3, np.nan)
            s = np.where(np.isfinite(s), s, math.sqrt(2.0) * 2.0)
            err.append(dc - dt)
            sig.append(s)
e, s = np.array(err), np.array(sig)
z = np.abs(e / s)
r = lambda v: np.round(v, 2).tolist()  # noqa: E731
print(f"{fam} seed {seed0} {sigma:.0f} px, {len(e)} draws: signed median {r(np.median(e, 0))} |err| median {r(np.median(np.abs(e), 0))}"
      f" p90 {r(np.percentile(np.abs(e), 90, 0))} sigma median {r(np.median(s, 0))} |z| median {r(np.median(z, 0))}"
      f" p90 {r(np.percentile(z, 90, 0))} |S-W| median {np.median(np.abs(e[:, 0] - e[:, 2])):.2f} p90 {np.percentile(np.abs(e[:, 0] - e[:, 2]), 90):.2f}")
