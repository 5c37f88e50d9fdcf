"""How well the tracker carries the decision's other objects and the diver's points (offsets from the target,
turned by the dead-reckoned yaw) against the truth, over a run's tracked frames:
    python docs/issue11/session59/scripts/offsets.py SCENARIO SEED [KEY=VALUE ...]
Truth: each neighbour offset against the nearest true placard offset from the tracked placard; the diver's shoulder
offset against the true shoulder (the first diver point is the triangulated shoulder). Camera frame, m."""
import sys
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).parent))
from hooked import placards_cam_m, run_hooked  # noqa: E402

scenario, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
rows = []


def hook(self, sim, stamp_s, pred, out):
    meta = sim.last_meta
    if meta and self.last is not None:
        pl = placards_cam_m(sim, meta)
        tid = min(pl, key=lambda k: np.linalg.norm(pl[k] - self.last.xyz_m))
        errs = [min(np.linalg.norm(n - (pl[p] - pl[tid])) for p in pl if p != tid) for n in self.neighbours_m]
        j = meta.get("joints_cam_m")
        sh = (j["shoulder"] if isinstance(j, dict) else j[0]) if j is not None else None
        d = (float(np.linalg.norm(self.diver_m[0] - (sim.rig.R1 @ np.asarray(sh) - pl[tid])))
             if sh is not None and len(self.diver_m) else None)
        rows.append((stamp_s, max(errs) if errs else None, d))


res, _ = run_hooked(scenario, seed, sets, hook)
n = sorted(r[1] for r in rows if r[1] is not None)
d = sorted(r[2] for r in rows if r[2] is not None)
q = lambda v: f"median {v[len(v) // 2]:.3f} p90 {v[int(len(v) * 0.9)]:.3f} max {v[-1]:.3f}" if v else "-"
print(f"{scenario} s{seed} {res.outcome} {res.time_to_arrive_s}: neighbours' worst offset error {q(n)}; "
      f"diver shoulder offset error {q(d)} ({len(rows)} frames)")
