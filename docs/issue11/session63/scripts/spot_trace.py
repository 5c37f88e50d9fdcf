"""Per frame of one mission between T0 and T1 (s): the default selector's objects (centre, features, probability),
"nothing detected", and each unrecognised spot it scored (``Selection.spots``: its point, probability, distance from
the shoulder) with,
for each object, how near the line from the shoulder to the spot passes the object's centre and how far along it:

    PYTHONPATH=TREE python docs/issue11/session63/scripts/spot_trace.py SCENARIO SEED T0 T1 [KEY=VALUE ...]

then the run's outcome, trajectory and story (session 58's ``story.py``).
"""
import runpy
import sys
from pathlib import Path

import numpy as np

import behaviours.pointing_states as ps
import dip3d_vehicle.perception.selection as sel

scenario, seed, T0, T1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
NOW = {"t": -1.0}
orig_select, orig_fuse = sel.DefaultSelector.select, ps._fuse_frame


def select(self, arm, arm3d, candidates, xyz_m, rig, unrecognised=None):
    """Print the frame's hypotheses."""
    res = orig_select(self, arm, arm3d, candidates, xyz_m, rig, unrecognised)
    if T0 <= NOW["t"] <= T1:
        s = arm3d.joint("shoulder")
        print(f"t={NOW['t']:.2f} chosen {res.index} "
              f"conf {res.confidence:.2f} p_none {res.none_probability:.2f}")
        for o, p in zip(res.objects, res.scores):
            if p > 0.01:
                print(f"   obj {np.round(o.xyz_m, 2)} n={len(o.members)} P {p:.2f} from S {np.linalg.norm(o.xyz_m - s):.2f}")
        for xyz, p in res.spots:
            d = xyz - s
            L = float(np.linalg.norm(d))
            u = d / L
            near = []
            for o in res.objects:
                v = o.xyz_m - s
                t = float(v @ u)
                near.append(f"{np.linalg.norm(v - t * u):.2f}@{t:.2f}")
            print(f"   spot {np.round(xyz, 2)} P {p:.2f} from S {L:.2f}; line to it passes objects at "
                  + " ".join(near))
    return res


def fuse(bb, result, direction):
    """Follow the frame's stamp."""
    NOW["t"] = bb.observation.stamp_s
    return orig_fuse(bb, result, direction)


sel.DefaultSelector.select, ps._fuse_frame = select, fuse
sys.argv = ["story", scenario, str(seed), *sys.argv[5:]]  # the run itself, its outcome and story: session 58's
runpy.run_path(str(Path(__file__).resolve().parents[2] / "session58" / "scripts" / "story.py"), run_name="__main__")
