"""One faulted paper_pool mission with a hook on every tracker update: stamp, the prediction, what was found (which
placard that truly is, matches) and each placard's true centre (rectified left camera frame, m), from T0 to T1:
    python docs/issue11/session61/scripts/fault_track.py PLAN SEED T0 T1 [KEY=VALUE ...]   (PYTHONPATH=TREE)"""
import sys

import numpy as np

import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission

plan, seed, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
sets = dict(a.split("=", 1) for a in sys.argv[5:])
orig = T.TargetTracker.update
sims = []


def placards(sim) -> dict:
    meta = getattr(sim, "last_meta", None)
    if not meta:
        return {}
    return {pid: sim.rig.R1 @ np.asarray(i["xyz_cam_m"]) for pid, i in meta["placards"].items()}


def update(self, candidates, xyz_m, stamp_s, command=None):
    pred = self.predicted_xyz(stamp_s, command)
    out = orig(self, candidates, xyz_m, stamp_s, command)
    if t0 <= stamp_s <= t1 and sims:
        pl = placards(sims[0])
        near = (lambda p: min(pl, key=lambda k: np.linalg.norm(pl[k] - p)) if pl else None)
        f = (f"found {np.round(out.xyz_m, 2)} = placard {near(out.xyz_m)} ({out.matches} matches)"
             if out is not None else "missed")
        p = f"pred {np.round(pred, 2)} (~{near(pred)})" if pred is not None else "pred None"
        truth = " ".join(f"{k}:{np.round(v, 2)}" for k, v in sorted(pl.items()))
        print(f"{stamp_s:6.2f} {len(candidates):4d} feats  {p}  {f}  | truth {truth}", flush=True)
    return out


T.TargetTracker.update = update
from sitl.simulation import Simulation  # noqa: E402
cls = Simulation
orig_init = cls.__init__


def init(self, *a, **k):
    orig_init(self, *a, **k)
    sims.append(self)


cls.__init__ = init
result, sim = run_faulted_mission("paper_pool", seed, plan, load_params(overrides=sets) if sets else load_params())
print(result.outcome, result.target_id)
