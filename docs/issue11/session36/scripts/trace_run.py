"""Where a mission's decision and track went, against the truth placards (pixels, left rectified image).

    PYTHONPATH=. python docs/issue11/session36/scripts/trace_run.py SCENARIO.yaml SEED RUN_DIR [T_S]

RUN_DIR is a `dip3d-vehicle sitl --out` folder of that run. Prints every placard's left pixel from the vehicle's start
pose at T_S (default 5 s: the vehicle holds still until it decides), then each frame's state, status, chosen object's
pixel and the tracker's pixel up to the servo's first seconds.
"""
import sys

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.record.mcap_log import McapRunReader
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

path, seed, run_dir = sys.argv[1], int(sys.argv[2]), sys.argv[3]
t_s = float(sys.argv[4]) if len(sys.argv) > 4 else 5.0
sc = load_scenario(path, seed)
params = sim_params(load_params(), sc)
rig = sc.rig(params["calib.alpha"])
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as renderer:
    frame = renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t_s)
print("pointed placard", sc.target_id)
(cx, cy), f = rig.principal_point_px, rig.focal_px
for pid, info in frame.meta["placards"].items():
    p = rig.R1 @ np.asarray(info["xyz_cam_m"])
    print(f"placard {pid}: xyz {p.round(2).tolist()} m, left px ({f * p[0] / p[2] + cx:.0f}, {f * p[1] / p[2] + cy:.0f})")
servo_from = None
for fr in McapRunReader(f"{run_dir}/run.mcap").frames():
    if fr.get("state") == "servo" and servo_from is None:
        servo_from = fr["t_s"]
    if fr.get("state") in ("select_target", "acknowledge") or (servo_from is not None and fr["t_s"] < servo_from + 2):
        target, tracked = fr.get("target"), fr.get("tracked_left_px")
        print(f"{fr['t_s']:5.1f} {fr['state']:14s} {fr.get('status'):15s} "
              f"chosen {None if target is None else [round(x) for x in target['left_px']]} "
              f"tracked {None if tracked is None else [round(x) for x in tracked]}")
