"""Per BlazePose frame: the pointing shoulder's disparity from the torso model, the shoulder's own match, the
head's match, and the truth.

    python docs/issue14/session30/scripts/shoulder_census.py OUT.jsonl SCENARIO[,SCENARIO...|FILE.yaml] SEEDS [STEP_S]

Renders each seed's frames from the vehicle's start pose while the arm is held (start_s .. start_s + hold_s,
every STEP_S, default 0.6 s), runs ``BlazePoseEstimator`` as the mission does (``pose.arm: auto``), and writes one
JSON line per frame with the arm found: the shoulders' landmark z (read arm, other), their image separation, the
body's disparity, the torso model's disparity and sigma for ``near`` as BlazePose says and for the other sign, the
shoulder's own patch match (disparity, sigma, matched), the head's match, the truth shoulder disparity (the
body's joint centre) and whether the read shoulder is truly nearer than the other (camera z).
"""
import json, math, sys
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator, JOINT_PATCH_M, body_disparity, ARM_INDICES, _OTHER
from dip3d_vehicle.perception.joint_stereo import head_disparity, joint_disparities
from dip3d_vehicle.perception.shoulder_model import shoulder_disparity
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.render import StereoRenderer

out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = float(sys.argv[4]) if len(sys.argv) > 4 else 0.6
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"])
            sign = rig.disparity_sign
            fb = rig.focal_px * rig.baseline_m
            est = BlazePoseEstimator.from_params(params)
            truth_pose = GivenKeypoints(sc.diver.arm)
            v = sc.initial_vehicle_pose
            d = sc.diver
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
                    truth_pose.provide(fr.meta["keypoints_truth"])
                    tr = truth_pose.estimate(L, R, rig)
                    true_d = float(tr.left_px[0, 0] - tr.right_px[0, 0])
                    body = body_disparity(L, R, lm, sign, est.max_disparity_px)
                    if body is None:
                        continue
                    side = est.arm_of(lm)
                    i_sh, i_o = ARM_INDICES[side][0], ARM_INDICES[_OTHER[side]][0]
                    near = bool(lm.z_px[i_sh] <= lm.z_px[i_o])
                    apart = float(np.linalg.norm(lm.xy_px[11] - lm.xy_px[12]))
                    dn, sn = shoulder_disparity(sign * body, apart, near, rig.focal_px, rig.baseline_m)
                    df, sf = shoulder_disparity(sign * body, apart, not near, rig.focal_px, rig.baseline_m)
                    js = joint_disparities(L, R, arm.left_px, sign * body, sign, rig.focal_px, rig.baseline_m,
                                           patch_m=JOINT_PATCH_M)
                    head = head_disparity((arm.extra_left_px or {}).get("head"), L, R, sign * body, sign, rig.focal_px, rig.baseline_m)
                    xyz = fr.meta["body_truth"]["xyz_cam_m"]
                    arm_t = sc.diver.arm
                    z_t, z_o = xyz[f"{arm_t}_shoulder"][2], xyz[f"{_OTHER[arm_t]}_shoulder"][2]
                    row = {"scenario": name, "seed": seed, "t": round(t - step, 2), "side": side,
                           "true_side": sc.diver.arm,
                           "vis": [round(float(lm.visibility[i]), 3) for i in (i_sh, i_o)],
                           "z_sh": round(float(lm.z_px[i_sh]), 1), "z_other": round(float(lm.z_px[i_o]), 1),
                           "apart_px": round(apart, 1), "body_px": round(sign * body, 3),
                           "model_near": [round(dn, 3), round(sn, 3)], "model_far": [round(df, 3), round(sf, 3)],
                           "near": near, "true_d_px": round(true_d, 3),
                           "true_near": bool(z_t < z_o), "true_dz_m": round(z_o - z_t, 3),
                           "own": [round(float(js.disparity_px[0]), 3), round(float(js.sigma_px[0]), 3),
                                   bool(js.matched[0]), round(float(js.score[0]), 3)],
                           "head": None if head is None else [round(head[0], 3), round(head[1], 3)],
                           "nose_vis": round(float(lm.visibility[0]), 3),
                           "ears_vis": [round(float(lm.visibility[i]), 3) for i in (7, 8)],
                           "z_nose_minus_shoulders": round(float(lm.z_px[0] - 0.5 * (lm.z_px[11] + lm.z_px[12])), 1),
                           "nose_x_from_ears": round(float(lm.xy_px[0, 0] - 0.5 * (lm.xy_px[7, 0] + lm.xy_px[8, 0])), 1),
                           "true_nose_dz_m": round(xyz["nose"][2] - 0.5 * (z_t + z_o), 3),
                           "fb": fb, "turbidity": float(sc.water.turbidity_per_m)}
                    fh.write(json.dumps(row) + "\n")
                    fh.flush()
