"""Per tracker frame between T0 and T1 s: predicted target vs truth (camera frame), features near the target, found or miss:
    python docs/issue11/session58/scripts/track_trace.py SCENARIO SEED T0 T1"""
import sys
import numpy as np
import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

scenario, seed, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(), sc))
orig_update = T.TargetTracker.update
orig_matched = T.TargetTracker._matched_descriptors
def update(self, candidates, xyz_m, stamp_s, command=None):
    pred = self.predicted_xyz(stamp_s, command)
    out = orig_update(self, candidates, xyz_m, stamp_s, command)
    if t0 <= stamp_s <= t1:
        meta = sim.last_meta
        tgt = sim.rig.R1 @ np.asarray(meta["placards"][sc.target_id]["xyz_cam_m"]) if meta else None
        first = orig_matched(self, self._first, candidates.descriptors) if len(candidates) else np.array([])
        near = xyz_m[np.linalg.norm(xyz_m - tgt, axis=1) < 0.25] if tgt is not None and len(xyz_m) else []
        fm = int(np.sum(first[np.linalg.norm(xyz_m - tgt, axis=1) < 0.25] >= 0)) if len(near) else 0
        print(f"{stamp_s:6.2f} pred {np.round(pred, 2)} truth {np.round(tgt, 2)} err {np.linalg.norm(pred - tgt):.2f} "
              f"cands {len(candidates)} near-target feats {len(near)} first-model matches there {fm} "
              f"-> {'found ' + str(np.round(out.xyz_m, 2)) + ' m' + str(out.matches) if out is not None else 'MISS'} misses {self.misses}")
    return out
T.TargetTracker.update = update
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome)
