"""Print every object the tracker's known-neighbours rule refused: time, the object's nearest truth placard, its
feature count and distinct first-sighting matches, its distance to the prediction and to the nearest neighbour's
predicted position (m), and where the prediction and that neighbour lie (nearest truth placard); then the outcome.
Also prints the neighbours the tracker was started with (each one's nearest truth placard), and for every tracker
frame the misses before it, the prediction's and the taken object's nearest truth placards; at the end, how many
refused objects lay within 0.2 m of the pointed placard (its nearest) and how many elsewhere.

    PYTHONPATH=TREE python docs/issue11/session50/scripts/refusal_trace.py SCENARIO SEED
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session49/scripts")
from behaviours import tracker as T  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402
from trace_common import near, run_mission, setup  # noqa: E402

name, seed, last, R1 = setup()
TARGET = load_scenario(name, seed).target_id
count = {"target": 0, "other": 0}
orig_refused, orig_start, orig_find = T.TargetTracker._refused, T.TargetTracker.start, T.TargetTracker._find
now = {"t": 0.0}


def start(self, obj, candidates, stamp_s, pool=None, neighbours_m=None):
    """Print the neighbours at the start, then start."""
    orig_start(self, obj, candidates, stamp_s, pool, neighbours_m)
    print(f"t {stamp_s:.1f} start on {near(last, obj.xyz_m, R1)}; neighbours: "
          + ", ".join(near(last, obj.xyz_m + n, R1) for n in self.neighbours_m))


def find(self, candidates, xyz_m, predicted, stamp_s):
    """Remember the frame's time, then find."""
    now["t"] = stamp_s
    out = orig_find(self, candidates, xyz_m, predicted, stamp_s)
    print(f"t {stamp_s:.1f} misses {self.misses} pred at {near(last, predicted, R1)} took "
          f"{near(last, out.xyz_m, R1) if out else None}")
    return out


def refused(self, obj, distance_m, predicted, candidates):
    """The rule's own answer, printed when it refuses."""
    out = orig_refused(self, obj, distance_m, predicted, candidates)
    if out:
        pid, dist = near(last, obj.xyz_m, R1).rstrip(" m)").split("(")
        count["target" if pid == str(TARGET) and float(dist) <= 0.2 else "other"] += 1
        nb = predicted + self.neighbours_m
        k = int(np.argmin(np.linalg.norm(nb - obj.xyz_m, axis=1)))
        print(f"t {now['t']:.1f} refused n{len(obj.members)} at {near(last, obj.xyz_m, R1)}: to prediction "
              f"{distance_m:.2f} m (pred at {near(last, predicted, R1)}), to neighbour {np.linalg.norm(nb[k] - obj.xyz_m):.2f}"
              f" m (at {near(last, nb[k], R1)})")
    return out


T.TargetTracker._refused, T.TargetTracker.start, T.TargetTracker._find = refused, start, find
run_mission(name, seed)
print(f"refused: {count['target']} objects within 0.2 m of the pointed placard {TARGET}, {count['other']} others")
