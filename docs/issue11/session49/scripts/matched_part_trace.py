"""Print every frame where the tracker's matched part replaced the tracked object: the object's feature count and
width across the line of sight, the matched features, the part's count and width, and the truth placard nearest each.

    PYTHONPATH=TREE python docs/issue11/session49/scripts/matched_part_trace.py SCENARIO SEED
"""
import sys
import numpy as np
from behaviours import tracker as T
from dip3d_vehicle.perception.grouping import extent_m
sys.path.insert(0, "docs/issue11/session47/scripts")
from sim_tap import run_mission, tap_placards  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402

name, seed = sys.argv[1], int(sys.argv[2])
R1 = load_scenario(name, seed).rig().R1
last = {}
tap_placards(last)
orig = T.TargetTracker._matched_part


def part(self, obj, first, candidates, xyz_m):
    """Print the replacement, if any."""
    out = orig(self, obj, first, candidates, xyz_m)
    if out is obj:
        return out
    members = np.asarray(obj.members)
    matched = members[first[members] >= 0]
    z = float(np.median(xyz_m[matched, 2]))
    truth = {p: R1 @ x for p, x in last.get("placards", {}).items()}

    def near(xyz):
        p = min(truth, key=lambda k: np.linalg.norm(truth[k] - xyz))
        return f"{p}({np.linalg.norm(truth[p] - xyz):.2f} m)"

    def width(m):
        return extent_m(candidates.left_px[np.asarray(m)], z, self.rig.focal_px)

    print(f"object n{len(members)} {width(members):.2f} m at {near(np.asarray(obj.xyz_m))}, matched {len(matched)}, "
          f"part n{len(out.members)} {width(out.members):.2f} m at {near(np.asarray(out.xyz_m))}, depth {z:.2f} m",
          flush=True)
    return out


T.TargetTracker._matched_part = part
run_mission(name, seed)
