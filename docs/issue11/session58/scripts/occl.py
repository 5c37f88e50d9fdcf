"""python docs/issue11/session58/scripts/occl.py SCENARIO:SEED ...
For each run: at the frames the tracker missed (streaks of >= 3), was the target occluded by another placard
(truth: a placard nearer the camera whose centre lies within its half-size of the camera-target line of sight)?"""
import sys
import numpy as np
import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

def run(spec):
    name, seed = spec.rsplit(":", 1)
    sc = load_scenario(name, int(seed))
    sim = Simulation(sc, sim_params(load_params(), sc))
    rows = []
    orig = T.TargetTracker.update
    def update(self, candidates, xyz_m, stamp_s, command=None):
        out = orig(self, candidates, xyz_m, stamp_s, command)
        meta = sim.last_meta
        if meta and self.last is not None:
            # the tracked placard: nearest the tracker's last sighting
            pl = {pid: sim.rig.R1 @ np.asarray(i["xyz_cam_m"]) for pid, i in meta["placards"].items()}
            tid = min(pl, key=lambda k: np.linalg.norm(pl[k] - self.last.xyz_m))
            t = pl[tid]; u = t / np.linalg.norm(t)
            occ = []
            for pid, c in pl.items():
                if pid == tid: continue
                along = c @ u
                perp = np.linalg.norm(c - along * u)
                half = [p for p in sc.placards if p.id == pid][0].size_m / 2
                if 0.1 < along < np.linalg.norm(t) - 0.05 and perp < half + 0.05:
                    occ.append(f"p{pid} perp {perp:.2f}")
            rows.append((stamp_s, out is not None, tid, occ))
        return out
    T.TargetTracker.update = update
    try:
        res = sim.run()
    finally:
        sim.close()
        T.TargetTracker.update = orig
    # miss streaks
    streaks, cur = [], []
    for r in rows:
        if not r[1]:
            cur.append(r)
        else:
            if len(cur) >= 3: streaks.append(cur)
            cur = []
    if len(cur) >= 3: streaks.append(cur)
    desc = []
    for s in streaks:
        occl = sum(1 for r in s if r[3])
        desc.append(f"miss {s[0][0]:.1f}-{s[-1][0]:.1f}s tracking p{s[0][2]} (target p{sc.target_id}) occluded in {occl}/{len(s)} {s[0][3] or ''}")
    print(f"{name.split('/')[-1]} s{seed}: {res.outcome}; " + ("; ".join(desc) or "no miss streak"), flush=True)

for spec in sys.argv[1:]:
    run(spec)
