"""Dead reckoning while the target is unseen: per miss streak, the tracker's predicted position against the truth.
    python docs/issue11/session59/scripts/reckon.py SCENARIO:SEED ... [-- KEY=VALUE ...]
Prints, per streak of >= 3 missed frames, the error |predicted - true| (camera frame, m) at 1, 2, 3 s after the last
sighting and at the streak's end, and the prediction's own displacement against the truth's."""
import sys
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).parent))
from hooked import placards_cam_m, run_hooked  # noqa: E402

args = sys.argv[1:]
sets = args[args.index("--") + 1:] if "--" in args else []
specs = args[:args.index("--")] if "--" in args else args


def run(spec):
    name, seed = spec.rsplit(":", 1)
    rows, state = [], {}

    def hook(self, sim, stamp_s, pred, out):
        meta = sim.last_meta
        if meta and self.last is not None:
            pl = placards_cam_m(sim, meta)
            if out is not None:
                state["tid"] = min(pl, key=lambda k: np.linalg.norm(pl[k] - out.xyz_m))
                state["seen"] = (stamp_s, out.xyz_m.copy(), pl[state["tid"]].copy())
            elif "tid" in state:
                t0, fix, truth0 = state["seen"]
                truth = pl[state["tid"]]
                rows.append((stamp_s, stamp_s - t0, float(np.linalg.norm(pred - truth)),
                             float(np.linalg.norm(pred - fix)), float(np.linalg.norm(truth - truth0))))
        if out is not None:
            rows.append((stamp_s, None, 0, 0, 0))
    res, _ = run_hooked(name, int(seed), dict(kv.split("=", 1) for kv in sets), hook)
    streaks, cur = [], []
    for r in rows:
        if r[1] is None:
            if len(cur) >= 3:
                streaks.append(cur)
            cur = []
        else:
            cur.append(r)
    if len(cur) >= 3:
        streaks.append(cur)
    out = []
    for s in streaks:
        at = {k: next((r for r in s if r[1] >= k), None) for k in (1.0, 2.0, 3.0)}
        parts = [f"{k:.0f}s err {r[2]:.2f}" for k, r in at.items() if r]
        e = s[-1]
        out.append(f"miss {s[0][0]:.1f}-{e[0]:.1f}s: " + ", ".join(parts)
                   + f", end err {e[2]:.2f} (predicted moved {e[3]:.2f}, truth moved {e[4]:.2f})")
    print(f"{name.split('/')[-1]} s{seed}: {res.outcome}; " + ("; ".join(out) or "no miss streak"), flush=True)


for spec in specs:
    run(spec)
