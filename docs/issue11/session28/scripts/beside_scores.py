"""Every spot beside an object that passed ``_apart_from`` over a family's draws at 2 px: its row match's score,
sigma and disparity, the object's disparity there, and whether any kept spot lies on the pointed placard.

    PYTHONPATH=.:tests/perception python docs/issue11/session28/scripts/beside_scores.py FAMILY N SEED0
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import blobs as B
rec = []
o_ap = B._apart_from
def ap(match, on):
    r = o_ap(match, on); rec.append((match, on, r)); return r
B._apart_from = ap
o_find = B.BlobFinder.find
family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", ())
        for d, kp, joints in dr.draws(scene, seed0, k, 2.0):
            pose.provide(kp); rec.clear()
            r = sf.decided(perception, left, right, base)
            out = sf.outcome(scene, r, rig)
            u = r.unrecognised
            on = [sf.target_detected(scene, rig.to_original(np.asarray(p)[None], "left")) for p in u.left_px]
            for m, o, ok in rec:
                if ok and o is not None:
                    print(f"{family} {seed0} scene {k} draw {d} {out} kept-beside score {m[2]:.3f} sigma {m[1]:.2f} disp {m[0]:.1f} obj_disp {o[0]:.1f} any_spot_on_target {int(any(on))}", flush=True)
