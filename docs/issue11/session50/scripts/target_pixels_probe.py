"""Print, for the tracker frames between T0 and T1 (s), where the pointed placard lies (truth, camera frame, and its
projection in the rectified left image, px), how many of the frame's tracking features fall on it (inside its
projected square, 0.3 m), and the span of all the frame's tracking features (the search box's reach), px; then
those features' depths (p10 / p50 / p90, m) and the tracker's objects they fall in (features on the placard, the
object's size, its nearest truth placard), or in none.

    PYTHONPATH=TREE python docs/issue11/session50/scripts/target_pixels_probe.py SCENARIO SEED T0 T1
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session49/scripts")
from behaviours import tracker as T  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402
from trace_common import near, run_mission, setup  # noqa: E402

name, seed, last, R1 = setup()
T0, T1 = float(sys.argv[3]), float(sys.argv[4])
TARGET = load_scenario(name, seed).target_id
orig = T.TargetTracker._find


def find(self, candidates, xyz_m, predicted, stamp_s):
    """Print the pointed placard's pixels and the features on it, then run the tracker's own _find."""
    out = orig(self, candidates, xyz_m, predicted, stamp_s)
    if T0 <= stamp_s <= T1 and "placards" in last:
        p = R1 @ np.asarray(last["placards"][TARGET])
        u, v = T.project_px(p, self.rig)
        half = self.rig.focal_px * 0.15 / p[2]
        px = candidates.left_px
        on = int(np.count_nonzero((abs(px[:, 0] - u) <= half) & (abs(px[:, 1] - v) <= half))) if len(px) else 0
        span = (f"x {px[:, 0].min():.0f}-{px[:, 0].max():.0f} y {px[:, 1].min():.0f}-{px[:, 1].max():.0f}"
                if len(px) else "no features")
        mask = (abs(px[:, 0] - u) <= half) & (abs(px[:, 1] - v) <= half) if len(px) else np.zeros(0, bool)
        z = xyz_m[mask, 2] if len(px) else np.zeros(0)
        c = self.config
        objects = T.group_objects(candidates, xyz_m, self.rig, c.group_radius_px, c.group_radius_m,
                                  c.min_object_features, c.object_radius_m, c.max_extent_m)
        member = {int(i): k for k, o in enumerate(objects) for i in o.members}
        held = [member.get(int(i), -1) for i in np.flatnonzero(mask)]
        sizes = sorted((held.count(k), len(objects[k].members), near(last, objects[k].xyz_m, R1))
                       for k in set(held) if k >= 0)
        print(f"t {stamp_s:.1f} placard {TARGET} at ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) m, px ({u:.0f}, {v:.0f}) "
              f"+-{half:.0f}: {on} features on it; frame's {len(px)} features span {span}; "
              f"taken {'yes' if out is not None else 'no'}")
        if len(z):
            print(f"   their depth p10/p50/p90 {np.percentile(z, 10):.2f} / {np.median(z):.2f} / "
                  f"{np.percentile(z, 90):.2f} m; in no object: {held.count(-1)}; in objects (on it, object size, its nearest truth placard): {sizes}")
    return out


T.TargetTracker._find = find
run_mission(name, seed)
