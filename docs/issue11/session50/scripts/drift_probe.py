"""Print, for the tracker frames between 3.4 and 5.4 s, how far the prediction moved since its last fix and where it
lies (nearest truth placard): the nod's dead reckoning (issue 11 session 50, side_by_side_far seed 6).

    PYTHONPATH=TREE python docs/issue11/session50/scripts/drift_probe.py SCENARIO SEED
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session49/scripts")
from behaviours import tracker as T
from trace_common import near, run_mission, setup
name, seed, last, R1 = setup()
orig = T.TargetTracker._find
def find(self, candidates, xyz_m, predicted, stamp_s):
    if 3.4 <= stamp_s <= 5.4:
        print(f"t {stamp_s:.1f} move since fix {np.linalg.norm(predicted - self.fix_xyz_m):.2f} m; pred at {near(last, predicted, R1)}")
    return orig(self, candidates, xyz_m, predicted, stamp_s)
T.TargetTracker._find = find
run_mission(name, seed)
