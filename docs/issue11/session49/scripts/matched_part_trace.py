"""Print every frame where the tracker's matched part replaced the tracked object: the object's feature count and
width across the line of sight, the matched features, the part's count and width, and the truth placard nearest each.

    PYTHONPATH=TREE python docs/issue11/session49/scripts/matched_part_trace.py SCENARIO SEED
"""
import sys
import numpy as np
from behaviours import tracker as T
from dip3d_vehicle.perception.grouping import extent_m
sys.path.insert(0, "docs/issue11/session49/scripts")
from trace_common import near, run_mission, setup  # noqa: E402

name, seed, last, R1 = setup()
orig = T.TargetTracker._matched_part


def part(self, obj, first, candidates, xyz_m, *rest):
    """Print the replacement, if any."""
    out = orig(self, obj, first, candidates, xyz_m, *rest)
    if out is obj:
        return out
    members = np.asarray(obj.members)
    z = float(np.median(xyz_m[members[first[members] >= 0], 2]))

    def width(m):
        return extent_m(candidates.left_px[np.asarray(m)], z, self.rig.focal_px)

    print(f"object n{len(members)} {width(members):.2f} m at {near(last, obj.xyz_m, R1)}, "
          f"matched {int(np.sum(first[members] >= 0))}, part n{len(out.members)} {width(out.members):.2f} m at "
          f"{near(last, out.xyz_m, R1)}, depth {z:.2f} m", flush=True)
    return out


T.TargetTracker._matched_part = part
run_mission(name, seed)
