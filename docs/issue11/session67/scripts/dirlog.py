"""Log the left-image arm per fused frame: python dirlog.py SCENARIO SEED [KEY=VALUE...] -> dirlog_<name>_<seed>.json
(time, direction, length, source; since session 72 also the joints, confidences, status and triangulated arm)"""
import sys, math, json
import numpy as np
import behaviours.pointing_states as ps
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
LOG = []
orig = ps._fuse_frame
def fuse(bb, result, direction):
    arm = result.arm
    L = None
    if arm is not None:
        L = float(np.linalg.norm(np.asarray(arm.joint("wrist"), float) - np.asarray(arm.joint("shoulder"), float)))
    LOG.append((bb.observation.stamp_s, None if direction is None else math.atan2(direction[1], direction[0]), L,
                None if arm is None else arm.source, None if arm is None else np.asarray(arm.left_px).round(1).tolist(),
                None if arm is None else np.asarray(arm.left_conf).round(2).tolist(), result.status,
                None if result.arm3d is None else np.asarray(result.arm3d.xyz_m).round(3).tolist()))
    return orig(bb, result, direction)
ps._fuse_frame = fuse
scenario, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome)
ang = [a for _, a, *_ in LOG if a is not None]
Ls = [l for _, _, l, *_ in LOG if l is not None]
d = np.diff(np.unwrap(ang))
print("frames", len(ang), "len_px median", np.median(Ls), "consecutive diff rad: median abs", np.median(np.abs(d)), "p90", np.percentile(np.abs(d), 90), "sd", np.std(d))
json.dump(LOG, open(f"dirlog_{scenario.rsplit('/', 1)[-1].removesuffix('.yaml')}_{seed}.json", "w"))
