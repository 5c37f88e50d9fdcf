"""The selector on single frames from a mission's start pose, truth keypoints without noise, zoom off and on.

    PYTHONPATH=. python docs/issue11/session36/scripts/frame_probe.py SCENARIO.yaml SEED [T_S,...]
"""
import sys

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

path, seed = sys.argv[1], int(sys.argv[2])
times = [float(t) for t in (sys.argv[3] if len(sys.argv) > 3 else "4,5,6").split(",")]
sc = load_scenario(path, seed)
v = sc.initial_vehicle_pose
for boxes in (0, 2):
    params = sim_params(load_params(overrides=[f"corridor.zoom_boxes={boxes}"]), sc)
    rig = sc.rig(params["calib.alpha"])
    with StereoRenderer(sc, params) as renderer:
        for t in times:
            frame = renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            if not frame.meta.get("keypoints"):
                continue
            result = Perception(rig, params, GivenKeypoints("right", frame.meta["keypoints"])).process(frame.left,
                                                                                                        frame.right)
            s = result.selection
            chosen = None if s.target is None else np.round(s.target.left_px).astype(int).tolist()
            print(f"zoom_boxes {boxes} t {t:4.1f} s: {result.status}, chosen px {chosen}, confidence "
                  f"{s.confidence}, none {s.none_probability:.3f}, ambiguous {s.ambiguous}")
