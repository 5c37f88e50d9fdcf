"""Time of group_objects (ms, median of 20) on a scene with and without selection.target_max_extent_m.

    python docs/issue11/session46/scripts/split_cost.py FAMILY N SEED SCENE   (repository root)
"""
import sys
import time

import numpy as np

sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402
from dip3d_vehicle.perception.grouping import group_objects  # noqa: E402

family, n, seed, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
for family, k, d, scene, rig, left, right, perception, arm, base in draws([family], n, seed, 0.0, 1, only={want}):
    r = sf.decided(perception, left, right, base)
    for limit in (np.inf, 0.6):
        times = []
        for _ in range(20):
            t0 = time.perf_counter()
            objs = group_objects(r.candidates, r.candidates_xyz_m, rig, 20.0, 0.05, 3, 0.15, limit)
            times.append(time.perf_counter() - t0)
        print(f"{family} {seed} {k} limit {limit}: {len(r.candidates)} features, {len(objs)} objects, "
              f"{1000 * np.median(times):.1f} ms")
