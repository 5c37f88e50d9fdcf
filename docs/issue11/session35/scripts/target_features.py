"""Per scene: how many matched features lie on the pointed placard, from the main pass and from the corridor.

    python docs/issue11/session35/scripts/target_features.py FAMILY N SEED0 [KEY=VALUE ...]

Truth keypoints. Prints scene index, target width (px) and range (m), the main pass's and the corridor's matches on
the target (rectified left px inside the target's polygon), and whether an object was made on it.
"""
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402


def on_target(scene, rig, left_rect_px) -> int:
    """Return how many rectified left points lie on the pointed placard."""
    if len(left_rect_px) == 0:
        return 0
    px = rig.to_original(np.asarray(left_rect_px, float), "left")
    poly = scene.target_polygon
    return sum(cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in px)


family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
over = sys.argv[4:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        found = perception._corridor_found(left, right, arm)
        merged = perception.add_corridor(left, right, arm, base)
        clean = perception.decide(perception.check_arm(arm), merged)
        objs = clean.selection.objects if clean.selection else ()
        n_obj = on_target(scene, rig, [o.left_px for o in objs]) if objs else 0
        print(k, f"{scene.target_width_px:.0f}px {scene.target_range_m:.2f}m det={scene.detectable}",
              f"base={on_target(scene, rig, base.left_px)} corridor={on_target(scene, rig, found.left_px) if found is not None else None}",
              f"merged={on_target(scene, rig, merged.left_px)} object={n_obj} status={clean.status}")
