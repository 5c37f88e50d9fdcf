"""One family scene, chosen draws: the joints' patch matches (disparity, sigma, score) and the disparities the arm ends with.

    PYTHONPATH=.:tests/perception python docs/issue11/session27/scripts/wrist_match.py FAMILY SCENE SEED0 DRAWS [NOISE_PX]

e.g. ``line_of_sight 15 900 0,1,4``: the truth joints' disparities, then per draw (2 px unless NOISE_PX) every
``joint_stereo.joint_disparities`` call (the arm's 0.06 m patches, then the head's) and the arm ``estimate_arm`` returns.
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from dip3d_vehicle.perception import joint_stereo as JS

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import draws as dr  # noqa: E402  (the families' own draws)

orig = JS.joint_disparities


def traced(*a, **k):
    """``joint_disparities``, printing what it found."""
    r = orig(*a, **k)
    print("   joint_disparities", np.round(r.disparity_px, 2).tolist(), "sig", np.round(r.sigma_px, 2).tolist(),
          "score", np.round(r.score, 2).tolist(), "patch", k.get("patch_m"))
    return r


JS.joint_disparities = traced
family, want, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
wanted = [int(x) for x in sys.argv[4].split(",")]
sigma = float(sys.argv[5]) if len(sys.argv) > 5 else 2.0
with tempfile.TemporaryDirectory() as tmp:
    scene = dr.nth_scene(Path(tmp), family, seed0, want)
    rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
    fb = rig.focal_px * rig.baseline_m
    for d, keypoints, joints in dr.draws(scene, seed0, want, sigma):
        if d == 0:
            J = np.array([joints[j] for j in ("shoulder", "elbow", "wrist")])
            print("truth disparity", np.round(fb / J[:, 2], 2).tolist(), "fB", round(fb, 1))
        if d not in wanted:
            continue
        pose.provide(keypoints)
        print("draw", d)
        a = perception.estimate_arm(left, right)
        print("   final disparity", np.round(a.left_px[:, 0] - a.right_px[:, 0], 2).tolist(), "sig", a.disparity_sigma_px,
              "matched", a.disparity_matched)
