"""Per BlazePose frame: each arm landmark's 2D offset from the body's joint centre, in metres at the body.

    python docs/issue14/session31/scripts/landmark_offsets_census.py OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS

Frames as ``wrist_census.py`` (every 0.6 s of the hold, from the start pose, ``pose.arm: auto``). Per frame: the
left image's shoulder / elbow / wrist offsets (landmark - truth, pixels), the image scale at the body's depth
(pixels per metre, from the truth shoulder's disparity), and the truth shoulder-to-wrist direction in the image.
"""
import json, sys
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = 0.6
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"])
            est = BlazePoseEstimator.from_params(params)
            truth_pose = GivenKeypoints(sc.diver.arm)
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
                    if arm is None:
                        continue
                    truth_pose.provide(fr.meta["keypoints_truth"])
                    tr = truth_pose.estimate(L, R, rig)
                    disp = float(tr.left_px[0, 0] - tr.right_px[0, 0])
                    row = {"scenario": name, "seed": seed, "t": round(t - step, 2),
                           "offset_px": (arm.left_px - tr.left_px).round(2).tolist(),
                           "px_per_m": round(abs(disp) / rig.baseline_m, 2),
                           "truth_px": tr.left_px.round(1).tolist(), "conf": np.round(arm.left_conf, 3).tolist()}
                    fh.write(json.dumps(row) + "\n")
                    fh.flush()
