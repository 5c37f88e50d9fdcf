"""Per scene of one family: is the pointed placard detectable, and is a candidate on it (truth keypoints)?

    python docs/issue11/session35/scripts/recall_scenes.py FAMILY N SEED0 [OUTDIR]

Prints scene index, width (px), range (m), water, detected; with OUTDIR writes a crop of each missed target
(rectified left image, 4x the placard's box) for a look.
"""
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402

family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
out = Path(sys.argv[4]) if len(sys.argv) > 4 else None
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if not scene.detectable:
            print(k, "not detectable", f"{scene.target_width_px:.0f}px")
            continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        clean = perception.decide(perception.check_arm(arm), perception.add_corridor(left, right, arm, base))
        objs = clean.selection.objects if clean.selection else ()
        px = rig.to_original(np.array([o.left_px for o in objs]), "left") if objs else np.zeros((0, 2))
        hit = sf.target_detected(scene, px)
        water = scene.scenario.water
        print(k, f"{scene.target_width_px:.0f}px {scene.target_range_m:.2f}m", "hit" if hit else "MISS",
              f"att={getattr(water, 'attenuation_per_m', None)} status={clean.status} n_obj={len(objs)}",
              f"base={len(base.objects) if hasattr(base, 'objects') else '?'}")
        if out is not None and not hit:
            out.mkdir(parents=True, exist_ok=True)
            poly = scene.target_polygon
            x0, y0 = poly.min(0); x1, y1 = poly.max(0)
            cx, cy, s = (x0 + x1) / 2, (y0 + y1) / 2, 2 * max(x1 - x0, y1 - y0)
            img = scene.frame.left
            crop = img[int(max(cy - s, 0)):int(cy + s), int(max(cx - s, 0)):int(cx + s)]
            cv2.imwrite(str(out / f"{family}_{seed0}_{k}.png"), cv2.resize(crop, None, fx=2, fy=2))
