"""Signed left-image errors of BlazePose's arm against the body's joints (pixels, and cm at the joint's depth) and the 2D
shoulder->wrist / elbow->wrist direction errors, from the start pose (issue 14 session 72):
    python docs/issue11/session72/scripts/signed_errors.py SCENARIO SEED,SEED,... FRAMES"""
import sys, math, numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
scen = sys.argv[1]; seeds = [int(s) for s in sys.argv[2].split(",")]; frames = int(sys.argv[3])
out = []
for seed in seeds:
    sc = load_scenario(scen, seed)
    params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc)
    rig = sc.rig(params["calib.alpha"])
    est = BlazePoseEstimator.from_params(params)
    tp = GivenKeypoints(sc.diver.arm)
    v = sc.initial_vehicle_pose
    with StereoRenderer(sc, params) as r:
        for k in range(frames):
            t = sc.diver.start_s + 0.2 * k
            f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            L, R = rig.rectify_image(f.left, "left"), rig.rectify_image(f.right, "right")
            arm = est.estimate(L, R, rig)
            if arm is None or f.meta["keypoints_truth"] is None: continue
            tp.provide(f.meta["keypoints_truth"]); tr = tp.estimate(L, R, rig)
            d = tr.left_px[:, 0] - tr.right_px[:, 0]
            z = rig.focal_px * rig.baseline_m / np.abs(d)
            e = arm.left_px - tr.left_px
            a_t = math.atan2(*(tr.left_px[2] - tr.left_px[0])[::-1]); a_b = math.atan2(*(arm.left_px[2] - arm.left_px[0])[::-1])
            a_te = math.atan2(*(tr.left_px[2] - tr.left_px[1])[::-1]); a_be = math.atan2(*(arm.left_px[2] - arm.left_px[1])[::-1])
            L_arm = np.linalg.norm(tr.left_px[2] - tr.left_px[0])
            print(seed, sc.diver.position_name, f"z {z.mean():.2f} arm {L_arm:.0f}px",
                  "err_px S", np.round(e[0], 1), "E", np.round(e[1], 1), "W", np.round(e[2], 1),
                  "err_cm S", np.round(e[0]*z[0]/rig.focal_px*100, 1), "W", np.round(e[2]*z[2]/rig.focal_px*100, 1),
                  f"dirSW {math.degrees(a_b-a_t):+.1f} dirEW {math.degrees(a_be-a_te):+.1f}", flush=True)
