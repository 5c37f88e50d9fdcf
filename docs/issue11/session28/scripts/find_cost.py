"""Median / p90 / max milliseconds of BlobFinder.find per decision over a family's draws at 2 px.

    PYTHONPATH=.:tests/perception python docs/issue11/session28/scripts/find_cost.py FAMILY N SEED0
"""
import sys, tempfile, time
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import blobs as B
t = []
of = B.BlobFinder.find
def find(self, *a, **k):
    t0 = time.perf_counter(); r = of(self, *a, **k); t.append(1e3 * (time.perf_counter() - t0)); return r
B.BlobFinder.find = find
family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", ())
        for d, kp, joints in dr.draws(scene, seed0, k, 2.0):
            pose.provide(kp); sf.decided(perception, left, right, base)
a = np.array(t)
print(family, seed0, f"find ms: median {np.median(a):.2f} p90 {np.percentile(a, 90):.2f} max {a.max():.2f} n {len(a)}")
