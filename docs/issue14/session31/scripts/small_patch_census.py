"""Per BlazePose frame with the wrist matched: whether ``on_background`` sets it aside, and the wrist's match with
smaller patches (0.04 / 0.06 / 0.08 m: the hand alone), each checked by ``on_background`` again.

    python docs/issue14/session31/scripts/small_patch_census.py OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS

Frames as ``wrist_census.py`` (every 0.6 s of the hold, from the start pose).
"""
import json, math, sys
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator, JOINT_PATCH_M, body_disparity
from dip3d_vehicle.perception.joint_stereo import joint_disparities, on_background, reach_disparities
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.render import StereoRenderer
out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = 0.6
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"]); sign = rig.disparity_sign
            est = BlazePoseEstimator.from_params(params); truth_pose = GivenKeypoints(sc.diver.arm)
            v, d = sc.initial_vehicle_pose, sc.diver
            with StereoRenderer(sc, params) as r:
                t = d.start_s
                while t < d.start_s + d.hold_s:
                    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t); t += step
                    if d.raised_fraction(t - step) < 0.99 or fr.meta["keypoints_truth"] is None: continue
                    L, R = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
                    arm = est.estimate(L, R, rig); lm = est.last[0]
                    if arm is None or lm is None: continue
                    body = body_disparity(L, R, lm, sign, est.max_disparity_px)
                    if body is None: continue
                    truth_pose.provide(fr.meta["keypoints_truth"]); tr = truth_pose.estimate(L, R, rig)
                    xy = arm.left_px
                    found = joint_disparities(L, R, xy, sign * body, sign, rig.focal_px, rig.baseline_m, patch_m=JOINT_PATCH_M)
                    if not found.matched[2]: continue
                    aside = not on_background(found, L, R, xy, sign * body, sign, rig.focal_px, rig.baseline_m, JOINT_PATCH_M).matched[2]
                    row = {"scenario": name, "seed": seed, "t": round(t - step, 2), "aside": aside,
                           "err2d": np.linalg.norm(xy - tr.left_px, axis=1).round(1).tolist(),
                           "true": round(float(tr.left_px[2, 0] - tr.right_px[2, 0]), 3), "d": round(float(found.disparity_px[2]), 3),
                           "small": {}}
                    for pm in (0.04, 0.06, 0.08):
                        f2 = joint_disparities(L, R, xy, sign * body, sign, rig.focal_px, rig.baseline_m, patch_m=pm)
                        again = on_background(f2, L, R, xy, sign * body, sign, rig.focal_px, rig.baseline_m, pm)
                        row["small"][str(pm)] = [bool(f2.matched[2]), round(float(f2.disparity_px[2]), 3), round(float(f2.sigma_px[2]), 3),
                                                 None if not f2.matched[2] else round(float(f2.score[2]), 3), bool(again.matched[2])]
                    fh.write(json.dumps(row) + "\n"); fh.flush()
