"""Per-frame dissection of the default selector in one mission (arm, objects, costs, log odds) between T0 and T1 s:
    python docs/issue11/session58/scripts/dissect.py SCENARIO SEED T0 T1 [KEY=VALUE ...]"""
import sys, math
import numpy as np
import dip3d_vehicle.perception.selection as sel

T0, T1 = float(sys.argv[3]), float(sys.argv[4])
orig = sel.DefaultSelector._log_odds
NOW = {"t": 0.0}

def traced(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad=None, n_objects=None):
    out = orig(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad, n_objects)
    if T0 <= NOW["t"] <= T1:
        s, e, w = arm3d.xyz_m
        length = max(float(np.linalg.norm(w - s)), 0.1)
        tilt = min(float(np.hypot(arm3d.depth_sigma_m[0], arm3d.depth_sigma_m[2])) / length, sel.MAX_TILT_SIGMA_RAD)
        u = (w - s) / np.linalg.norm(w - s)
        print(f"t={NOW['t']:.2f} arm S {np.round(s,3)} E {np.round(e,3)} W {np.round(w,3)} dsig {np.round(arm3d.depth_sigma_m,3)} tilt {tilt:.3f} ps {pointing_sigma_rad}")
        for ob, c, lo in zip(objects, costs, out):
            v = ob.xyz_m - s
            ang = math.degrees(math.acos(np.clip(v @ u / np.linalg.norm(v), -1, 1)))
            print(f"   obj {np.round(ob.xyz_m,3)} n={len(ob.members)} cost-arm {c - arm_cost:6.2f} log_odds {lo:6.2f} angle_from_S {ang:5.1f} dist {np.linalg.norm(v):.2f}")
    return out

sel.DefaultSelector._log_odds = traced
import behaviours.pointing_states as ps
orig_fuse = ps._fuse_frame
def fuse(bb, result, direction):
    NOW["t"] = bb.observation.stamp_s
    return orig_fuse(bb, result, direction)
ps._fuse_frame = fuse
# note: the selector runs before _fuse_frame of the same frame; stamp lags by one frame at most
import runpy
sys.argv = ["story", sys.argv[1], sys.argv[2], *sys.argv[5:]]
import os
runpy.run_path(os.path.join(os.path.dirname(os.path.abspath(__file__)), "story.py"), run_name="__main__")
