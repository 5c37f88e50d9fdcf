"""Every pair of objects within selection.same_target_gap_m (0.1 m): their union's extent and whether they share a placard.

Truth keypoints (the objects do not depend on them). Prints one line per pair:
family seed scene  n_a n_b  union_extent_m  same|different  placards_a placards_b
    python docs/issue11/session46/scripts/touching_unions.py SEED [FAMILY ...]   (repository root; PYTHONPATH=tree)
"""
import sys

import cv2
import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402
from dip3d_vehicle.perception.grouping import extent_m  # noqa: E402


def on_placards(scene, rig, px):
    """Return {placard id: features on it (3 px tolerance)} for rectified left px."""
    orig = rig.to_original(px, "left")
    out = {}
    placards = scene.frame.meta["placards"]
    for pid, p in (placards.items() if isinstance(placards, dict) else enumerate(placards)):
        poly = np.asarray(p["left_polygon_px"], np.float32)
        c = sum(cv2.pointPolygonTest(poly, (float(x), float(y)), True) >= -3.0 for x, y in orig)
        if c:
            out[pid] = int(c)
    return out


seed = int(sys.argv[1])
for family, k, d, scene, rig, left, right, perception, arm, base in draws(sys.argv[2:] or sf.FAMILIES, 20, seed, 0.0, 1):
    r = sf.decided(perception, left, right, base)
    if r.selection is None:
        continue
    objs, xyz, px = r.selection.objects, r.candidates_xyz_m, r.candidates.left_px
    for a in range(len(objs)):
        tree = cKDTree(xyz[list(objs[a].members)])
        for b in range(a + 1, len(objs)):
            if float(tree.query(xyz[list(objs[b].members)], k=1)[0].min()) > 0.1:
                continue
            union = list(objs[a].members) + list(objs[b].members)
            e = extent_m(px[union], float(np.median(xyz[union, 2])), rig.focal_px)
            pa, pb = on_placards(scene, rig, px[list(objs[a].members)]), on_placards(scene, rig, px[list(objs[b].members)])
            main_a, main_b = max(pa, key=pa.get, default=None), max(pb, key=pb.get, default=None)
            print(f"{family} {seed} {k} {len(objs[a].members)} {len(objs[b].members)} {e:.3f} "
                  f"{'same' if main_a == main_b else 'different'} {pa} {pb}", flush=True)
