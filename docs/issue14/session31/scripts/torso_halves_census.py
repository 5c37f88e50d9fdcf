"""Per BlazePose frame: the disparity of each half of the torso (patches between each shoulder and its hip), the
pose model's shoulder order and the truth's.

    python docs/issue14/session31/scripts/torso_halves_census.py OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS [STEP_S]

As ``shoulder_census.py`` (session 30): each seed's frames from the vehicle's start pose while the arm is held,
``BlazePoseEstimator`` as in the mission (``pose.arm: auto``). Per frame with the arm found: for the read arm's
shoulder and the other one, a patch (PATCH_M wide at the body's depth) placed FRACTION of the way from the shoulder
to its hip and INWARD of the shoulders' separation toward the other side, matched along its row (``match_point``);
BlazePose's landmark z order, and whether the read shoulder is truly the nearer (camera z of the body's joints).
"""
import json, sys
import numpy as np
from census_frames import census_args, held_frames
from dip3d_vehicle.perception.blazepose import ARM_INDICES, _OTHER, body_disparity
from dip3d_vehicle.perception.joint_stereo import match_point, patch_half_px, reach_disparities

PATCH_M = (0.1, 0.16)
FRACTION = (0.2, 0.4)
INWARD = 0.2


def halves_of(f, body: float) -> dict:
    """Return each (patch, fraction) placement's match of the read side's torso half and the other's."""
    lm, sign, fb = f.landmarks, f.rig.disparity_sign, f.rig.focal_px * f.rig.baseline_m
    side = f.est.arm_of(lm)
    i_sh, i_o = ARM_INDICES[side][0], ARM_INDICES[_OTHER[side]][0]
    hips = {i_sh: 23 if i_sh == 11 else 24, i_o: 23 if i_o == 11 else 24}
    span = reach_disparities(abs(body), fb, 0.5)
    halves = {}
    for pm in PATCH_M:
        half = patch_half_px(body, f.rig.baseline_m, pm)
        for fr_ in FRACTION:
            got = []
            for i, j in ((i_sh, i_o), (i_o, i_sh)):
                p = lm.xy_px[i] + fr_ * (lm.xy_px[hips[i]] - lm.xy_px[i]) + INWARD * (lm.xy_px[j] - lm.xy_px[i])
                x, y = int(round(p[0])), int(round(p[1]))
                if not (half <= x < f.left.shape[1] - half and half <= y < f.left.shape[0] - half):
                    got.append(None)
                    continue
                m = match_point(f.left, f.right, x, y, span[0], span[1], sign, half, 0.5, 1.5)
                got.append(None if m is None else [round(m[0], 3), round(m[1], 3), round(m[2], 3)])
            halves[f"{pm}_{fr_}"] = got
    return halves


out, names, seeds, step = census_args(sys.argv)
with open(out, "w") as fh:
    for f in held_frames(names, seeds, step):
        lm, sign, d = f.landmarks, f.rig.disparity_sign, f.sc.diver
        body = body_disparity(f.left, f.right, lm, sign, f.est.max_disparity_px)
        if body is None:
            continue
        side = f.est.arm_of(lm)
        i_sh, i_o = ARM_INDICES[side][0], ARM_INDICES[_OTHER[side]][0]
        xyz = f.meta["body_truth"]["xyz_cam_m"]
        z_t, z_o = xyz[f"{d.arm}_shoulder"][2], xyz[f"{_OTHER[d.arm]}_shoulder"][2]
        row = {"scenario": f.scenario, "seed": f.seed, "t": round(f.t_s, 2), "side": side, "true_side": d.arm,
               "near": bool(lm.z_px[i_sh] <= lm.z_px[i_o]), "true_near": bool(z_t < z_o),
               "true_dz_m": round(z_o - z_t, 3), "body_px": round(sign * body, 3), "fb": f.rig.focal_px * f.rig.baseline_m,
               "apart_px": round(float(np.linalg.norm(lm.xy_px[11] - lm.xy_px[12])), 1), "halves": halves_of(f, body)}
        fh.write(json.dumps(row) + "\n")
        fh.flush()
