"""Other-wrist visibility in stop-gesture frames and false 'stop seen' in ordinary frames, BlazePose from pixels (scratch)."""
import sys, numpy as np
from dataclasses import replace
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator, ARM_INDICES
from behaviours.gesture import stop_gesture_seen
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
base = sys.argv[1]; seeds = range(int(sys.argv[2])); stop = sys.argv[3] == "stop"
TH = (0.5, 0.3, 0.2, 0.1)
seen = {t: 0 for t in TH}; n = 0; vis = []
for seed in seeds:
    open('/tmp/s72/sv.yaml', 'w').write(f"base: {base}\n" + ("diver:\n  stop_gesture_at_s: 3.0\n" if stop else ""))
    sc = load_scenario('/tmp/s72/sv.yaml', seed)
    params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc)
    rig = sc.rig(params["calib.alpha"]); est = BlazePoseEstimator.from_params(params)
    v = sc.initial_vehicle_pose
    with StereoRenderer(sc, params) as r:
        for i in range(8):
            t = (4.0 if stop else 2.0) + 0.25 * i
            f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            L, R = rig.rectify_image(f.left, "left"), rig.rectify_image(f.right, "right")
            arm = est.estimate(L, R, rig)
            lm = est.last[0]
            if arm is None or lm is None: continue
            n += 1
            o = ARM_INDICES["left" if arm.arm == "right" else "right"][2]
            vis.append(float(lm.visibility[o]))
            for th in TH:
                ex = dict(arm.extra_left_px or {})
                ex.pop("other_wrist", None)
                if lm.visibility[o] >= th:
                    ex["other_wrist"] = tuple(lm.xy_px[o])
                a = replace(arm, extra_left_px=ex)
                seen[th] += stop_gesture_seen(a, 5.0, 0.1, abs(rig.baseline_m))
print(base, "stop" if stop else "no stop", "frames", n, "seen per visibility threshold", seen, "other-wrist vis median", np.median(vis).round(2), "p10/p90", np.percentile(vis, [10, 90]).round(2))
