"""Per tracking frame in [T0, T1]: the tracked object's size and extent, its features matching the first sighting
(count, extent, height percentiles) and the part the tracker took (``TargetTracker._matched_part``), beside every
placard's true position (camera frame, metres).

    PYTHONPATH=TREE python docs/issue11/session53/scripts/track_trace.py SCENARIO SEED T0 T1 [KEY=VALUE ...]
"""
import sys
import numpy as np
import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.grouping import extent_m
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

scenario, seed, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
sets = dict(a.split("=", 1) for a in sys.argv[5:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
orig = T.TargetTracker._matched_part

def traced(self, obj, first, candidates, xyz_m, *rest):
    part = orig(self, obj, first, candidates, xyz_m, *rest)
    t = self.last_frame_s
    if t0 <= t <= t1:
        members = np.asarray(obj.members)
        matched = members[first[members] >= 0]
        d = float(np.median(xyz_m[matched, 2])) if len(matched) else float("nan")
        ext = extent_m(candidates.left_px[members], d, self.rig.focal_px)
        mext = extent_m(candidates.left_px[matched], d, self.rig.focal_px) if len(matched) > 1 else 0
        truth = {pid: np.round(sim.rig.R1 @ np.asarray(i["xyz_cam_m"]), 2).tolist() for pid, i in sim.last_meta["placards"].items()}
        print(f"{t:6.2f} obj n{len(members)} ext {ext:.2f} matched n{len(matched)} ext {mext:.2f} "
              f"ymatched {np.round(np.percentile(xyz_m[matched,1],[5,50,95]),2).tolist()} -> part n{len(part.members)} "
              f"xyz {np.round(part.xyz_m, 2).tolist()} truth {truth}")
    return part

T.TargetTracker._matched_part = traced
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome)
