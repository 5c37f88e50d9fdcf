"""The start frame of a scenario seed, perceived with the simulator's keypoints (truth + the scenario's noise):
each object's centre, nearest placard, features, extent across the line of sight, posterior.

    python docs/issue11/session47/scripts/start_frame_objects.py SCENARIO SEED [T_S] [KEY=VALUE ...]
"""
import sys
import numpy as np
from behaviours.loop import FrameProcessor
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.grouping import extent_m
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

name, seed = sys.argv[1], int(sys.argv[2])
t_s = float(sys.argv[3]) if len(sys.argv) > 3 else 3.0
over = dict(kv.split("=", 1) for kv in sys.argv[4:])
sc = load_scenario(name, seed)
params = sim_params(load_params(), sc)
for k, v in over.items():
    params[k] = type(params[k])(v) if not isinstance(params[k], bool) else v.lower() == "true"
rig = sc.rig(params["calib.alpha"])
pose = GivenKeypoints("right")
processor = FrameProcessor(Perception(rig, params, pose), lambda f: pose.provide(f.meta["keypoints"]))
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as renderer:
    frame = renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t_s)
    obs = processor.process(frame, "full")
sel = obs.result.selection
truth = {pid: rig.R1 @ np.asarray(info["xyz_cam_m"]) for pid, info in frame.meta["placards"].items()}
print(f"{name} seed {seed} t {t_s}: target {sc.target_id}, status {obs.result.status}, "
      f"chosen {sel.index if sel else None}, conf {sel.confidence if sel else float('nan'):.2f}, "
      f"none {sel.none_probability if sel else float('nan'):.2f}")
cands, xyz = obs.result.candidates, obs.result.candidates_xyz_m
for i, o in enumerate(sel.objects if sel else ()):
    near = min(truth, key=lambda p: np.linalg.norm(truth[p] - o.xyz_m))
    m = list(o.members)
    print(f"  o{i}: xyz {np.round(o.xyz_m, 2)} nearest placard {near} ({np.linalg.norm(truth[near] - o.xyz_m):.2f} m), "
          f"{len(m)} features, extent {extent_m(cands.left_px[m], float(np.median(xyz[m, 2])), rig.focal_px):.2f} m, "
          f"P {sel.scores[i]:.2f}")
for p, c in truth.items():
    print(f"  placard {p}: {np.round(c, 2)}")
