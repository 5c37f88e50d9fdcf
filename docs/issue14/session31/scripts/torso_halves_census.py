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
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import ARM_INDICES, _OTHER, BlazePoseEstimator, body_disparity
from dip3d_vehicle.perception.joint_stereo import match_point, patch_half_px, reach_disparities
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

PATCH_M = (0.1, 0.16)
FRACTION = (0.2, 0.4)
INWARD = 0.2

out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = float(sys.argv[4]) if len(sys.argv) > 4 else 0.6
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"])
            sign, fb = rig.disparity_sign, rig.focal_px * rig.baseline_m
            est = BlazePoseEstimator.from_params(params)
            v, d = sc.initial_vehicle_pose, sc.diver
            with StereoRenderer(sc, params) as r:
                t = d.start_s
                while t < d.start_s + d.hold_s:
                    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
                    t += step
                    if d.raised_fraction(t - step) < 0.99 or fr.meta["keypoints_truth"] is None:
                        continue
                    L, R = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
                    arm = est.estimate(L, R, rig)
                    lm = est.last[0]
                    if arm is None or lm is None:
                        continue
                    body = body_disparity(L, R, lm, sign, est.max_disparity_px)
                    if body is None:
                        continue
                    side = est.arm_of(lm)
                    i_sh, i_o = ARM_INDICES[side][0], ARM_INDICES[_OTHER[side]][0]
                    hips = {i_sh: 23 if i_sh == 11 else 24, i_o: 23 if i_o == 11 else 24}
                    span = reach_disparities(abs(body), fb, 0.5)
                    halves = {}
                    for pm in PATCH_M:
                        half = patch_half_px(body, rig.baseline_m, pm)
                        for fr_ in FRACTION:
                            got = []
                            for i, j in ((i_sh, i_o), (i_o, i_sh)):
                                p = lm.xy_px[i] + fr_ * (lm.xy_px[hips[i]] - lm.xy_px[i]) + INWARD * (lm.xy_px[j] - lm.xy_px[i])
                                x, y = int(round(p[0])), int(round(p[1]))
                                if not (half <= x < L.shape[1] - half and half <= y < L.shape[0] - half):
                                    got.append(None)
                                    continue
                                m = match_point(L, R, x, y, span[0], span[1], sign, half, 0.5, 1.5)
                                got.append(None if m is None else [round(m[0], 3), round(m[1], 3), round(m[2], 3)])
                            halves[f"{pm}_{fr_}"] = got
                    xyz = fr.meta["body_truth"]["xyz_cam_m"]
                    z_t, z_o = xyz[f"{d.arm}_shoulder"][2], xyz[f"{_OTHER[d.arm]}_shoulder"][2]
                    row = {"scenario": name, "seed": seed, "t": round(t - step, 2), "side": side, "true_side": d.arm,
                           "near": bool(lm.z_px[i_sh] <= lm.z_px[i_o]), "true_near": bool(z_t < z_o),
                           "true_dz_m": round(z_o - z_t, 3), "body_px": round(sign * body, 3), "fb": fb,
                           "apart_px": round(float(np.linalg.norm(lm.xy_px[11] - lm.xy_px[12])), 1), "halves": halves}
                    fh.write(json.dumps(row) + "\n")
                    fh.flush()
