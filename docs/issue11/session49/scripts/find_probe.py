"""Print, for the tracker's frames between T0 and T1 (s), the predicted target's nearest placard, the one taken, and
every object within 1 m of the prediction: feature count, nearest truth placard, distinct matches to the first
sighting's model ("anchored"), distance to the prediction (m).

    PYTHONPATH=TREE python docs/issue11/session49/scripts/find_probe.py SCENARIO SEED T0 T1
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session49/scripts")
from behaviours import tracker as T  # noqa: E402
from trace_common import near, run_mission, setup  # noqa: E402

name, seed, last, R1 = setup()
T0, T1 = float(sys.argv[3]), float(sys.argv[4])
orig = T.TargetTracker._find
orig_md = T.TargetTracker._matched_descriptors


def find(self, candidates, xyz_m, predicted, stamp_s):
    """Run the tracker's own _find, then print the frame's objects near the prediction."""
    out = orig(self, candidates, xyz_m, predicted, stamp_s)
    if not (T0 <= stamp_s <= T1) or len(candidates) == 0:
        return out
    c = self.config
    objects = T.group_objects(candidates, xyz_m, self.rig, c.group_radius_px, c.group_radius_m,
                              c.min_object_features, c.object_radius_m, c.max_extent_m)
    first = orig_md(self, self._first, candidates.descriptors)
    print(f"t {stamp_s:.1f} pred {near(last, predicted, R1)} took {near(last, out.xyz_m, R1) if out else None}")
    for o in objects:
        m = list(o.members)
        d = float(np.linalg.norm(o.xyz_m - predicted))
        if d < 1.0:
            print(f"   obj n{len(m)} at {near(last, o.xyz_m, R1)} anchored {T._distinct(first[m])} dist {d:.2f}")
    return out


T.TargetTracker._find = find
run_mission(name, seed)
