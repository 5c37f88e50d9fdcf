"""Outcome per draw of one family at one noise level (the families' own draws), with optional BlobFinder settings.

    PYTHONPATH=.:tests/perception python docs/issue11/session28/scripts/outcomes.py FAMILY N SEED0 NOISE [edge=R] [maxb=M] [sharp=S] [K=V ...]

edge: the spots' edge ratio; maxb: max_blobs; sharp: the largest row-match sigma (px) of any spot kept
(an experiment: BlobFinder reads ``max_sigma_px`` only where it has been patched to); K=V: parameters.
Prints one line per draw (outcome, status, confidence, P(nothing), a spot on the pointed placard) and a summary.
"""
import sys, tempfile, collections, time
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import blobs as B

family, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
over = []
init = B.BlobFinder.__init__
kw = {}
for a in sys.argv[5:]:
    k, v = a.split("=", 1)
    if k == "edge": kw["edge_ratio"] = float(v)
    elif k == "maxb": kw["max_blobs"] = int(v)
    elif k == "inner": kw["inner_sigma_px"] = float(v)
    elif k == "sharp": kw["max_sigma_px"] = float(v)
    else: over.append(a)
def patched(self, *a, **k):
    init(self, *a, **k)
    for kk, vv in kw.items(): setattr(self, kk, vv)
B.BlobFinder.__init__ = patched
tally = collections.Counter()
t0 = time.time()
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", over)
        for d, keypoints, joints in dr.draws(scene, seed0, k, sigma):
            pose.provide(keypoints)
            result = sf.decided(perception, left, right, base)
            out = sf.outcome(scene, result, rig)
            sel = result.selection
            spots = getattr(result, "unrecognised", None)
            on_spot = spots is not None and len(spots) > 0 and sf.target_detected(scene, rig.to_original(np.asarray(spots.left_px), "left"))
            tally[out] += 1
            print(f"{family} {seed0} scene {k:2d} {scene.band} draw {d} {out:15s} {result.status:15s} "
                  f"conf {sel.confidence if sel else float('nan'):.2f} none {sel.none_probability if sel else float('nan'):.2f} spot {int(on_spot)}", flush=True)
print("SUMMARY", family, seed0, sigma, " ".join(sys.argv[5:]), dict(tally), f"{time.time()-t0:.0f}s", flush=True)
