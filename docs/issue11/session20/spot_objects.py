"""Per frame of a scenario's held point: each spot found (kept or explained) against each object:
2D distance to the object's feature hull (px), the object's median depth and the spot's (m), the spot's
depth sigma, and the nearest placard (truth). Truth + noise keypoints, start pose.

    PYTHONPATH=. python docs/issue11/session20/spot_objects.py SCENARIO_FILE SEED FRAMES [KEY=VALUE ...]
"""
import sys

import cv2
import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

sc = load_scenario(sys.argv[1], int(sys.argv[2]))
params = sim_params(load_params(overrides=sys.argv[4:]), sc)
rig = sc.rig(params["calib.alpha"])
pose = GivenKeypoints(sc.diver.arm)
core = Perception(rig, params, pose)
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    for k in range(int(sys.argv[3])):
        fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 0.5 + k / 10)
        pose.provide(fr.meta["keypoints"])
        res = core.process(fr.left, fr.right)
        pl = {pid: rig.R1 @ np.asarray(p["xyz_cam_m"]) for pid, p in fr.meta["placards"].items()}
        sel = res.selection
        print(f"frame {k} {res.status} target {sc.target_id} none "
              f"{sel.none_probability if sel else -1:.2f} {sel.reason if sel else ''}")
        if sel is None:
            continue
        hulls = []
        for i, (o, s) in enumerate(zip(sel.objects, sel.scores)):
            px = res.candidates.left_px[list(o.members)]
            z = float(np.median(res.candidates_xyz_m[list(o.members), 2]))
            near = min(pl, key=lambda q: np.linalg.norm(pl[q] - o.xyz_m))
            hulls.append((cv2.convexHull(px.astype(np.float32).reshape(-1, 1, 2)), z))
            print(f"  obj {i} P {s:.2f} placard {near} z {z:.2f} members {len(o.members)} "
                  f"width {np.ptp(px[:, 0]):.0f}px")
        for px, x, sg in zip(res.unrecognised.left_px, res.unrecognised.xyz_m, res.unrecognised.depth_sigma_m):
            near = min(pl, key=lambda q: np.linalg.norm(pl[q] - x))
            rel = [f"o{i}:{-cv2.pointPolygonTest(h, (float(px[0]), float(px[1])), True):.0f}px/dz{x[2] - z:+.2f}"
                   for i, (h, z) in enumerate(hulls)]
            print(f"  spot z {x[2]:.2f} sd {sg:.2f} placard {near} ({np.linalg.norm(pl[near] - x):.2f} m) {' '.join(rel)}")
