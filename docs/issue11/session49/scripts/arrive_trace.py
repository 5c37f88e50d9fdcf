"""Trace the approach of one mission: per servo / arrive frame, the tracked object (nearest truth placard, its
member count, centre px) and the servo errors (pixel px, range m); each state's answer.

    PYTHONPATH=TREE python docs/issue11/session49/scripts/arrive_trace.py SCENARIO SEED
"""
import sys
from behaviours import approach_states as A
sys.path.insert(0, "docs/issue11/session49/scripts")
from trace_common import near, run_mission, setup  # noqa: E402

name, seed, last, R1 = setup()


def traced(cls):
    """Wrap ``cls.seen`` and ``cls.missed`` to print each frame."""
    seen, missed = cls.seen, cls.missed

    def seen_(self, bb, found):
        out = seen(self, bb, found)
        e = bb.errors
        print(f"t {bb.observation.stamp_s:.1f} {cls.name}: {near(last, found.xyz_m, R1)} n{len(found.obj.members)} "
              f"px ({found.left_px[0]:.0f},{found.left_px[1]:.0f}) "
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
