"""Per draw of one generated family: outcome, the arm-only fit's cost, each joint's depth error (m and its sigmas) against the truth joint.

    PYTHONPATH=.:tests/perception python docs/issue11/session27/scripts/scan.py FAMILY N SEED0 [NOISE_PX] [KEY=VALUE ...]

The draws are the families' own (``scene_families``: 8 per noise level, truth keypoints + Gaussian noise), profile ``default``.
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from dip3d_vehicle.perception import pointing_fit as PF

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import draws as dr  # noqa: E402  (the families' own draws)

last = {}
orig = PF._PointingFit.arm_cost


def arm_cost(self, iterations=25):
    """The arm-only fit's cost, remembered for the line."""
    c = orig(self, iterations)
    last["arm_cost"] = c
    return c


PF._PointingFit.arm_cost = arm_cost

family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
sigma = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
overrides = sys.argv[5:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
        for d, keypoints, joints in dr.draws(scene, seed0, k, sigma):
            pose.provide(keypoints)
            J = np.array([joints[j] for j in ("shoulder", "elbow", "wrist")])
            last.clear()
            result = sf.decided(perception, left, right, base)
            sel = result.selection
            out = sf.outcome(scene, result, rig)
            line = (f"{family} {seed0} scene {k:2d} {scene.band} margin {sf.pointing_margin_deg(scene):5.1f} draw {d} "
                    f"{out:15s} {result.status:15s}")
            if result.arm3d is not None:
                dz = result.arm3d.xyz_m[:, 2] - J[:, 2]
                ns = dz / np.maximum(result.arm3d.depth_sigma_m, 0.01)
                line += (f" armcost {last.get('arm_cost', float('nan')):6.2f} dz {np.round(dz, 2).tolist()}"
                         f" nsig {np.round(ns, 1).tolist()}")
            if sel is not None:
                line += f" conf {sel.confidence:.2f} none {sel.none_probability:.2f} amb {int(sel.ambiguous)}"
                objs = [o.left_px for o in sel.objects]
                spots = getattr(result, "unrecognised", None)
                on_obj = bool(objs) and sf.target_detected(scene, rig.to_original(np.array(objs), "left"))
                on_spot = spots is not None and len(spots) > 0 and sf.target_detected(
                    scene, rig.to_original(np.asarray(spots.left_px), "left"))
                line += f" target_object {int(on_obj)} target_spot {int(on_spot)}"
            print(line, flush=True)
