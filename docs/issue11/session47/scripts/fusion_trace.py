"""Trace the decision's fusion through one mission: per fused frame, each object (true placard nearest it, its
probability) and the hypothesis it fell on, with the hypotheses' mean positions' nearest placards.

    PYTHONPATH=TREE python docs/issue11/session47/scripts/fusion_trace.py SCENARIO SEED
"""
import sys
import numpy as np
from behaviours import fusion as F
from sim_tap import run_mission, tap_placards
from sitl.scenario import load_scenario

name, seed = sys.argv[1], int(sys.argv[2])
R1 = load_scenario(name, seed).rig().R1
last = {}
tap_placards(last)
orig_add = F.PointFusion.add


def add(self, result, stamp_s, arm_frames=1):
    """Print what each object of the frame fell on."""
    ev = orig_add(self, result, stamp_s, arm_frames)
    if ev is None or result.selection is None:
        return ev
    truth = {p: R1 @ x for p, x in last.get("placards", {}).items()}

    def near(xyz):
        p = min(truth, key=lambda k: np.linalg.norm(truth[k] - xyz))
        return f"{p}({np.linalg.norm(truth[p] - xyz):.2f})"

    sel = result.selection
    objs = [f"{near(o.xyz_m)} p{sel.scores[i]:.2f}->{getattr(self.match(np.asarray(o.xyz_m)), 'key', '-')}"
            for i, o in enumerate(sel.objects) if sel.scores[i] > 0.02]
    hyps = [f"{h.key}@{near(h.xyz_m)}" for h in self.hypotheses]
    print(f"t {stamp_s:.1f} frame: {', '.join(objs)} | none {ev.probabilities.get('none', 0):.2f} | hyps {' '.join(hyps)} | part "
          + " ".join(f"{k}:{v:.2f}" for k, v in ev.probabilities.items()), flush=True)
    return ev


F.PointFusion.add = add
run_mission(name, seed)
