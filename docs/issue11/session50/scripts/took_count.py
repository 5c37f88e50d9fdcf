"""Count the tracker's frames by what it took: the pointed placard, another placard (the taken object's nearest truth
placard within 0.2 m), something else, or nothing; one line per run.

    PYTHONPATH=TREE python docs/issue11/session50/scripts/took_count.py SCENARIO SEED...
"""
import json
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session47/scripts")
from behaviours import tracker as T  # noqa: E402
from sim_tap import run_mission, tap_placards  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402

name = sys.argv[1]
last: dict = {}
tap_placards(last)
orig_find = T.TargetTracker._find
state = {"R1": None, "target": None, "count": {}}


def find(self, candidates, xyz_m, predicted, stamp_s):
    """The tracker's own _find; count what it took."""
    out = orig_find(self, candidates, xyz_m, predicted, stamp_s)
    key = "nothing"
    if out is not None:
        truth = {p: state["R1"] @ x for p, x in last.get("placards", {}).items()}
        p = min(truth, key=lambda k: np.linalg.norm(truth[k] - out.xyz_m)) if truth else None
        near = p is not None and np.linalg.norm(truth[p] - out.xyz_m) <= 0.2
        key = "pointed" if near and p == state["target"] else "other placard" if near else "elsewhere"
    state["count"][key] = state["count"].get(key, 0) + 1
    return out


T.TargetTracker._find = find
for seed in (int(s) for s in sys.argv[2:]):
    sc = load_scenario(name, seed)
    state.update(R1=sc.rig().R1, target=sc.target_id, count={})
    run_mission(name, seed)
    print(json.dumps({"scenario": name, "seed": seed, "frames": state["count"]}), flush=True)
