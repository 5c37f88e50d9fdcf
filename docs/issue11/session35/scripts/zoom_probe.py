"""Matches on the pointed placard from a box around it scanned with the corridor's settings at several scales.

    python docs/issue11/session35/scripts/zoom_probe.py FAMILY N SEED0 K[,K...]

Truth keypoints; the box is the placard's rectified bounding box grown by its size on each side. Prints scene,
scale, SIFT contrast threshold, matches in the box and matches on the placard.
"""
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402
from dip3d_vehicle.perception.corridor import CorridorDetector  # noqa: E402


def on_target(scene, rig, left_rect_px) -> int:
    """Return how many rectified left points lie on the pointed placard."""
    if len(left_rect_px) == 0:
        return 0
    px = rig.to_original(np.asarray(left_rect_px, float), "left")
    return sum(cv2.pointPolygonTest(scene.target_polygon, (float(x), float(y)), False) >= 0 for x, y in px)


family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
want = [int(x) for x in sys.argv[4].split(",")]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if k not in want:
            continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        poly = rig.to_rectified(scene.target_polygon.astype(float), "left")
        x0, y0 = poly.min(0)
        x1, y1 = poly.max(0)
        s = max(x1 - x0, y1 - y0)
        box = (x0 - s, y0 - s, x1 + s, y1 + s)
        for scale in (0.5, 1.0, 1.5, 2.0):
            for ct in (0.01, 0.005):
                det = CorridorDetector(image_scale=scale, max_area_px=1e9, contrast_threshold=ct)
                c = det.detect_box(left, right, box, rig)
                print(k, scale, ct, len(c), on_target(scene, rig, c.left_px))
