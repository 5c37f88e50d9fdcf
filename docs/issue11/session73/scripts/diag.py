import sys, numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose_model import BlazePose
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
scen, seed = sys.argv[1], int(sys.argv[2])
sc = load_scenario(scen, seed); params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc)
rig = sc.rig(params["calib.alpha"])
pose = BlazePose.from_params(params)
print("diver", sc.diver.arm, "start", sc.diver.start_s)
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    for k in range(3):
        f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 0.5 * k)
        L = rig.rectify_image(f.left, "left")
        d0 = pose.detect(L); d1 = pose.detect(L, contrast=True); d2 = pose.detect_in_squares(L)
        print("t", k, "detect", d0 and round(d0.score, 2), "stretched", d1 and round(d1.score, 2), "squares", d2 and round(d2.score, 2))
        found = pose.process(L)
        if found is None:
            print("  no pose"); continue
        print("  pose_flag", round(found.pose_flag, 2), "vis arms R", found.visibility[[12, 14, 16]].round(2), "L", found.visibility[[11, 13, 15]].round(2))
        t = f.meta["keypoints_truth"]
        print("  truth left", np.round(t["left"]["shoulder"]), np.round(t["left"]["wrist"]), "lm R sh/wr", found.xy_px[[12, 16]].round(), "L sh/wr", found.xy_px[[11, 15]].round())
print("--- landmarks on each detection's ROI")
with StereoRenderer(sc, params) as r:
    for k in range(6):
        f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 0.5 * k)
        L = rig.rectify_image(f.left, "left")
        out = []
        for name, det in (("stretched", pose.detect(L, contrast=True)), ("squares", pose.detect_in_squares(L))):
            if det is None: out.append(f"{name} none"); continue
            lm = pose.landmarks(L, det.roi(), contrast=det.contrast)
            lm2 = pose.landmarks(L, det.roi(), contrast=None) if True else None
            out.append(f"{name} roi {det.roi().size_px:.0f}px flag {lm.pose_flag:.2f} (crop-own {lm2.pose_flag:.2f})")
        print(k, " | ".join(out))
