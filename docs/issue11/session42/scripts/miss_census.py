"""Every detectable miss at one noise level: status, the leading object's probability, on target or not.

    python docs/issue11/session42/scripts/miss_census.py N SEED NOISE [KEY=VALUE ...]

One line per missed draw (fam.py's order and draws), then counts: how many misses had the pointed
placard as the leading object (a right lean the rules held back) and how many leaned elsewhere.
"""
import sys, tempfile
from collections import Counter
from pathlib import Path
import cv2
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf

n, seed0, noise = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
over = sys.argv[4:]
lean = Counter()
with tempfile.TemporaryDirectory() as tmp:
    for family in sf.FAMILIES:
        if family == "undetectable":
            continue
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            if not scene.detectable:
                continue
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
            rng = np.random.default_rng(seed0 + k)
            for d in range(8):
                pose.provide(sf.noisy(truth, noise, rng))
                r = sf.decided(perception, left, right, base)
                out = sf.outcome(scene, r, rig)
                if out == "correct":
                    lean["correct"] += 1
                    continue
                sel = r.selection
                best, on = None, None
                if sel is not None and len(sel.objects):
                    i = int(np.argmax(sel.scores))
                    best = float(sel.scores[i])
                    px = rig.to_original(np.asarray(sel.objects[i].left_px, float)[None], "left")[0]
                    on = cv2.pointPolygonTest(scene.target_polygon, (float(px[0]), float(px[1])), False) >= 0
                kind = "none-lean" if sel is not None and best is not None and sel.none_probability > best else (
                    "right-lean" if on else ("wrong-lean" if on is not None else "no-object"))
                lean[kind] += 1
                print(f"{family:13s} {k:2d} d{d} {out:15s} {r.status:15s} best {best if best is not None else float('nan'):.2f} "
                      f"none {sel.none_probability if sel else float('nan'):.2f} amb {sel.ambiguous if sel else None} "
                      f"{kind} {scene.band} {(r.reason or '')[:70] if hasattr(r, 'reason') else ''}", flush=True)
print(dict(lean))
