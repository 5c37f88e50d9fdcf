"""Trace the tracker through one mission: per track frame, every object in the gate with its anchored and total
descriptor matches, its distance from the prediction and the true placard nearest it; the object taken is marked.

    PYTHONPATH=TREE python docs/issue11/session47/scripts/tracker_trace.py SCENARIO SEED [T_END_S]
"""
import sys
import numpy as np
from behaviours import tracker as T
from sim_tap import run_mission, tap_placards

name, seed = sys.argv[1], int(sys.argv[2])
t_end = float(sys.argv[3]) if len(sys.argv) > 3 else 9.0
last = {}
tap_placards(last)
orig_find = T.TargetTracker._find


def find(self, candidates, xyz_m, predicted, stamp_s):
    """Print the objects the tracker weighs."""
    found = orig_find(self, candidates, xyz_m, predicted, stamp_s)
    if stamp_s > t_end:
        return found
    c = self.config
    objects = T.group_objects(candidates, xyz_m, self.rig, c.group_radius_px, c.group_radius_m,
                              c.min_object_features, c.object_radius_m, c.max_extent_m)
    first = self._matched_descriptors(self._first, candidates.descriptors)
    truth = {p: self.rig.R1 @ x for p, x in last.get("placards", {}).items()}
    rows = []
    for o in objects:
        m = list(o.members)
        d = float(np.linalg.norm(o.xyz_m - predicted))
        if d > c.gate_max_m + 0.3:
            continue
        near = min(truth, key=lambda p: np.linalg.norm(truth[p] - o.xyz_m)) if truth else None
        mark = "*" if found is not None and list(found.obj.members) == m else " "
        rows.append(f"{mark}placard {near} ({np.linalg.norm(truth[near] - o.xyz_m):.2f} m) n {len(m)} "
                    f"anchored {T._distinct(first[m])} dist {d:.2f}")
    print(f"t {stamp_s:.1f} pred {np.round(predicted, 2)}: " + " | ".join(rows), flush=True)
    return found


T.TargetTracker._find = find
run_mission(name, seed)
