"""One family scene, chosen draws: each object's log odds against "nothing detected" and the fit's cost over the arm's own.

    PYTHONPATH=.:tests/perception python docs/issue11/session27/scripts/log_odds.py FAMILY SCENE SEED0 NOISE_PX DRAWS

e.g. ``line_of_sight 15 900 2 0,1,5``: the placards (rectified px, depth), then per draw the arm's tilt sigma, its
joints' depth sigmas and depths, the arm-only fit's cost, and per object its position, depth, fit cost over the
arm's own and log odds; the outcome and the posterior.
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from dip3d_vehicle.perception import selection as S

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import draws as dr  # noqa: E402  (the families' own draws)

orig_log_odds = S.DefaultSelector._log_odds


def traced(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad=None, n_objects=None):
    """``_log_odds``, printing its terms."""
    out = orig_log_odds(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad, n_objects)
    length_m = max(float(np.linalg.norm(arm3d.joint("wrist") - arm3d.joint("shoulder"))), 0.1)
    tilt = min(float(np.hypot(arm3d.depth_sigma_m[0], arm3d.depth_sigma_m[2])) / length_m, S.MAX_TILT_SIGMA_RAD)
    print(f"    tilt_sigma {tilt:.3f} dsig {np.round(arm3d.depth_sigma_m, 3).tolist()} "
          f"z {np.round(arm3d.xyz_m[:, 2], 2).tolist()} arm_cost {arm_cost:.2f} n {n_objects}")
    for ob, c, lo in zip(objects, costs, out):
        print(f"      obj px {np.round(ob.left_px).tolist()} z {ob.xyz_m[2]:.2f} dcost {c - arm_cost:7.2f} logodds {lo:6.2f}")
    return out


S.DefaultSelector._log_odds = traced

family, want, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
sigma = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
wanted = [int(x) for x in sys.argv[5].split(",")] if len(sys.argv) > 5 else [0]
with tempfile.TemporaryDirectory() as tmp:
    scene = dr.nth_scene(Path(tmp), family, seed0, want)
    rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
    J = {k: np.asarray(v) for k, v in scene.frame.meta["joints_cam_m"].items()}
    print("truth joints z", {k: round(float(v[2]), 2) for k, v in J.items()}, "margin", round(sf.pointing_margin_deg(scene), 1))
    for pid, p in scene.frame.meta["placards"].items():
        xyz = rig.R1 @ np.asarray(p["xyz_cam_m"])
        px = rig.focal_px * xyz[:2] / xyz[2] + np.asarray(rig.principal_point_px)
        print(f"placard {pid}{'*' if pid == scene.scenario.target_id else ' '} rect px {np.round(px).tolist()} z {xyz[2]:.2f}")
    for d, keypoints, _ in dr.draws(scene, seed0, want, sigma):
        if d not in wanted:
            continue
        pose.provide(keypoints)
        print(f"--- noise {sigma} draw {d}")
        result = sf.decided(perception, left, right, base)
        sel = result.selection
        print(f"  => {sf.outcome(scene, result, rig)} {result.status} conf {sel.confidence:.2f} "
              f"none {sel.none_probability:.2f} amb {sel.ambiguous} {sel.reason}")
        print("  post", np.round(sel.scores, 3).tolist())
