import sys, numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception import blazepose_model as bm
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
seen = []
orig = bm._crop_levels
def spy(crop):
    lv = orig(crop); seen.append(lv); return lv
bm._crop_levels = spy
pose = bm.BlazePose(crop_stretch=True)
params = load_params()
for spec in sys.argv[1:]:
    scen, seed = spec.split(":")
    sc = load_scenario(scen, int(seed)); v = sc.initial_vehicle_pose
    with StereoRenderer(sc, params) as r:
        f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 1.0)
    seen.clear(); found = pose.process(f.left)
    print(spec, [(l.astype(int).tolist(), h.astype(int).tolist()) for l, h in seen], "contrast", None if found is None or found.contrast is None else [c.astype(int).tolist() for c in found.contrast])
