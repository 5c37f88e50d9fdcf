"""Per frame of a scenario's held point (start pose, truth + noise keypoints): the status, each object's
probability with the placard it lies nearest, "nothing detected", and the unrecognised spots (3D, the
nearest placard and how far from its centre, metres).

Usage (from the repository root):
    PYTHONPATH=. python docs/issue11/session19/spot_where.py SCENARIO_FILE SEED FRAMES
"""
import sys, numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
sc = load_scenario(sys.argv[1], int(sys.argv[2]))
params = sim_params(load_params(), sc); rig = sc.rig(params["calib.alpha"])
pose = GivenKeypoints(sc.diver.arm); core = Perception(rig, params, pose); v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    for k in range(int(sys.argv[3])):
        fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 0.5 + k / 10)
        pose.provide(fr.meta["keypoints"]); res = core.process(fr.left, fr.right)
        pl = {pid: rig.R1 @ np.asarray(p["xyz_cam_m"]) for pid, p in fr.meta["placards"].items()}
        objs = [(round(float(s),2), min(pl, key=lambda q: np.linalg.norm(pl[q]-o.xyz_m))) for o, s in zip(res.selection.objects, res.selection.scores)] if res.selection else []
        spots = [(np.round(x,2).tolist(), min(pl, key=lambda q: np.linalg.norm(pl[q]-x)), round(float(min(np.linalg.norm(pl[q]-x) for q in pl)),2)) for x in res.unrecognised.xyz_m]
        print(k, res.status, "target", sc.target_id, "objs", objs, "none %.2f" % (res.selection.none_probability if res.selection else -1), "spots", spots, "joints", np.round(res.arm3d.xyz_m[2],2).tolist() if res.arm3d is not None else None)
