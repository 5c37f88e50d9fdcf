"""The corridor's cost per decision frame with and without the zoom boxes (ms, truth arm, 1600x1200).

    python docs/issue11/session35/scripts/zoom_cost.py N SEED0 [FAMILY ...]

Per scene: ``CorridorDetector.detect`` timed 5 times with ``corridor.zoom_boxes=0`` and with the default
(the median of each), and the number of zoom boxes. Prints per-family and overall median / p90 / max of both and of
the difference.
"""
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402
from dip3d_vehicle.perception import corridor as C  # noqa: E402

n, seed0 = int(sys.argv[1]), int(sys.argv[2])
families = sys.argv[3:] or list(sf.FAMILIES)


def timed(det, left, right, arm, rig) -> float:
    """Return the median of 5 runs of the corridor's detect, ms."""
    out = []
    for _ in range(5):
        t0 = time.perf_counter()
        det.detect(left, right, arm, rig)
        out.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(out))


rows = {}
with tempfile.TemporaryDirectory() as tmp:
    for family in families:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
            det = perception.corridor
            zoom = det.zoom_boxes
            det.zoom_boxes = 0
            off = timed(det, left, right, arm, rig)
            det.zoom_boxes = zoom
            on = timed(det, left, right, arm, rig)
            poly = det.wedge(arm, left.shape[1], left.shape[0], rig)
            det.zoom_boxes = 0
            wedge = det.detect(left, right, arm, rig)
            det.zoom_boxes = zoom
            nb = len(C.zoom_boxes(wedge, poly, rig.focal_px, rig.baseline_m, left.shape[1], left.shape[0], zoom)) if len(wedge) else 0
            rows.setdefault(family, []).append((off, on, nb))
            print(family, k, f"off {off:.1f} on {on:.1f} boxes {nb}", flush=True)


def stats(v) -> str:
    """Return median / p90 / max of values, ms."""
    v = np.asarray(v)
    return f"{np.median(v):.1f} / {np.percentile(v, 90):.1f} / {v.max():.1f}"


every = [r for rs in rows.values() for r in rs]
for family, rs in list(rows.items()) + [("all", every)]:
    a = np.array(rs)
    print(f"{family:14s} off {stats(a[:, 0])}  on {stats(a[:, 1])}  added {stats(a[:, 1] - a[:, 0])}  boxes {stats(a[:, 2])}")
