"""Every object's extent across the line of sight (metres) and the placards its features fall on, truth keypoints.

python docs/issue11/session46/scripts/object_extents.py SEED [FAMILY ...]   (from the repository root)
"""
import sys

import cv2
import numpy as np
from scipy.spatial.distance import pdist

sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402

seed = int(sys.argv[1])
families = sys.argv[2:] or sf.FAMILIES
for family, k, d, scene, rig, left, right, perception, arm, base in draws(families, 20, seed, 0.0, 1):
    r = sf.decided(perception, left, right, base)
    if r.selection is None:
        continue
    fx = rig.focal_px
    placards = scene.frame.meta["placards"]
    for i, o in enumerate(r.selection.objects):
        mem = np.array(o.members)
        px = r.candidates.left_px[mem]
        extent = float(pdist(px).max()) * o.xyz_m[2] / fx if len(px) > 1 else 0.0
        orig = rig.to_original(px, "left")
        on = {}
        for pid, p in (placards.items() if isinstance(placards, dict) else enumerate(placards)):
            poly = np.asarray(p["left_polygon_px"], np.float32)
            c = sum(cv2.pointPolygonTest(poly, (float(x), float(y)), True) >= -3.0 for x, y in orig)
            if c:
                on[pid] = int(c)
        print(f"{family} {seed} {k} obj{i} n {len(mem)} z {o.xyz_m[2]:.2f} extent_m {extent:.3f} on {on}", flush=True)
