"""Trace the approach of one mission: per servo / arrive frame, the tracked object (nearest truth placard, its
member count, centre px) and the servo errors (pixel px, range m); each state change.

    PYTHONPATH=TREE python docs/issue11/session49/scripts/arrive_trace.py SCENARIO SEED
"""
import sys
import numpy as np
from behaviours import approach_states as A
sys.path.insert(0, "docs/issue11/session47/scripts")
from sim_tap import run_mission, tap_placards  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402

name, seed = sys.argv[1], int(sys.argv[2])
R1 = load_scenario(name, seed).rig().R1
last = {}
tap_placards(last)


def traced(cls):
    """Wrap ``cls.seen`` and ``cls.missed`` to print each frame."""
    seen, missed = cls.seen, cls.missed

    def seen_(self, bb, found):
        out = seen(self, bb, found)
        truth = {p: R1 @ x for p, x in last.get("placards", {}).items()}
        p = min(truth, key=lambda k: np.linalg.norm(truth[k] - found.xyz_m)) if truth else None
        e = bb.errors
        print(f"t {bb.observation.stamp_s:.1f} {cls.name}: {p}({np.linalg.norm(truth[p] - found.xyz_m):.2f} m) "
              f"n{len(found.obj.members)} px ({found.left_px[0]:.0f},{found.left_px[1]:.0f}) "
              f"err {e.pixel_px:.1f} px range {e.range_m:+.3f} m -> {out}", flush=True)
        return out

    def missed_(self, bb):
        out = missed(self, bb)
        print(f"t {bb.observation.stamp_s:.1f} {cls.name}: missed -> {out}", flush=True)
        return out

    cls.seen, cls.missed = seen_, missed_


for c in (A.Servo, A.Arrive):
    traced(c)
run_mission(name, seed)
