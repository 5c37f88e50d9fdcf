"""With ``head_torso``: the draws whose final shoulder disparity is over 1 px off the truth joint, beside the torso
model's own value (``given_arm.torso_shoulder``; nan where the head did not match and the model was not used).

    python docs/issue11/session45/scripts/shoulder_stages.py N SEED NOISE DRAWS
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402
from dip3d_vehicle.perception import given_arm as G  # noqa: E402

rec = {}
orig = G.torso_shoulder


def recorded(*a, **k):
    """``torso_shoulder``, its result kept for the draw."""
    rec["t"] = orig(*a, **k)
    return rec["t"]


G.torso_shoulder = recorded
n, seed0, noise, per = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
for family, k, d, scene, rig, left, right, perception, arm, base in draws(
        sf.FAMILIES, n, seed0, noise, per, ["pose.match_disparity_shoulder=head_torso"]):
    td = arm.left_px[:, 0] - arm.right_px[:, 0]
    rec.clear()
    est = perception.estimate_arm(left, right)
    e = (est.left_px[:, 0] - est.right_px[:, 0]) - td
    t = rec.get("t")
    te, ts = (t[0] - td[0], t[1]) if t else (np.nan, np.nan)
    m = est.disparity_matched[0] if est.disparity_matched is not None else None
    sig = est.disparity_sigma_px[0] if est.disparity_sigma_px is not None else np.nan
    if abs(e[0]) > 1.0:
        print(f"{family:14s}{k:3d} d{d} final {e[0]:+.2f} (sig {sig:.2f}, matched {m}) torso {te:+.2f} (sig {ts:.2f}) "
              f"Z {rig.focal_px * rig.baseline_m / abs(td[0]):.2f}", flush=True)
