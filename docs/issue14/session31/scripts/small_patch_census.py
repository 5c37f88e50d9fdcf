"""Per BlazePose frame with the wrist matched: whether ``on_background`` sets it aside, and the wrist's match with
smaller patches (0.04 / 0.06 / 0.08 m: the hand alone), each checked by ``on_background`` again.

    python docs/issue14/session31/scripts/small_patch_census.py OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS [STEP_S]

Frames as ``wrist_census.py`` (every 0.6 s of the hold, from the start pose).
"""
import json, sys
import numpy as np
from census_frames import census_args, held_frames
from dip3d_vehicle.perception.blazepose import JOINT_PATCH_M, body_disparity
from dip3d_vehicle.perception.joint_stereo import joint_disparities, on_background

out, names, seeds, step = census_args(sys.argv)
with open(out, "w") as fh:
    for f in held_frames(names, seeds, step):
        sign, rig, xy, tr = f.rig.disparity_sign, f.rig, f.arm.left_px, f.truth
        body = body_disparity(f.left, f.right, f.landmarks, sign, f.est.max_disparity_px)
        if body is None:
            continue
        found = joint_disparities(f.left, f.right, xy, sign * body, sign, rig.focal_px, rig.baseline_m,
                                  patch_m=JOINT_PATCH_M)
        if not found.matched[2]:
            continue
        aside = not on_background(found, f.left, f.right, xy, sign * body, sign, rig.focal_px, rig.baseline_m,
                                  JOINT_PATCH_M).matched[2]
        row = {"scenario": f.scenario, "seed": f.seed, "t": round(f.t_s, 2), "aside": aside,
               "err2d": np.linalg.norm(xy - tr.left_px, axis=1).round(1).tolist(),
               "true": round(float(tr.left_px[2, 0] - tr.right_px[2, 0]), 3), "d": round(float(found.disparity_px[2]), 3),
               "small": {}}
        for pm in (0.04, 0.06, 0.08):
            f2 = joint_disparities(f.left, f.right, xy, sign * body, sign, rig.focal_px, rig.baseline_m, patch_m=pm)
            again = on_background(f2, f.left, f.right, xy, sign * body, sign, rig.focal_px, rig.baseline_m, pm)
            row["small"][str(pm)] = [bool(f2.matched[2]), round(float(f2.disparity_px[2]), 3),
                                     round(float(f2.sigma_px[2]), 3),
                                     None if not f2.matched[2] else round(float(f2.score[2]), 3), bool(again.matched[2])]
        fh.write(json.dumps(row) + "\n")
        fh.flush()
