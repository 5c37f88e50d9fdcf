"""The perception core alone on frames of a scenario's held point (start pose), one frame each: each placard's
probability and "nothing detected" (no fusion, no mission).

Usage (from the repository root):
    PYTHONPATH=. python docs/issue11/session18/look.py SCENARIO_FILE SEED FRAMES keypoints|keypoints_truth
``keypoints``: the simulator's truth plus the scenario's noise (the missions' pose source);
``keypoints_truth``: the exact joints.
"""
import sys, json, math
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

def probs(sel, meta, rig):
    out = {}
    if sel is None: return out
    for pid, p in meta["placards"].items():
        c = rig.R1 @ np.asarray(p["xyz_cam_m"])
        best = 0.0
        for o, pr in zip(sel.objects, sel.scores):
            if np.linalg.norm(np.asarray(o.xyz_m) - c) < 0.25: best += float(pr)
        out[pid] = round(best, 2)
    out["none"] = round(float(sel.none_probability), 2)
    return out

scen, seed, frames, which = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
sc = load_scenario(scen, seed)
params = sim_params(load_params(), sc)
rig = sc.rig(params["calib.alpha"])
pose = GivenKeypoints(sc.diver.arm)
core = Perception(rig, params, pose)
v = sc.initial_vehicle_pose
print("target", sc.target_id)
with StereoRenderer(sc, params) as r:
    for k in range(frames):
        t = sc.diver.start_s + 0.5 + k / float(params["sitl.camera_rate_hz"])
        fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
        kp = fr.meta.get(which)
        pose.provide(kp)
        res = core.process(fr.left, fr.right)
        print(k, res.status, probs(res.selection, fr.meta, rig))
