"""Per detectable draw that is not correct: the pointed placard's own objects (those with a member feature on it)
and their probability, against the chosen object's, and whether the chosen object itself touches the placard.

    python docs/issue11/session45/scripts/miss_anatomy.py FAMILY N SEED NOISE DRAWS [KEY=VALUE ...]
"""
import sys
import numpy as np, cv2
sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402

family, n, seed0, noise, per = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
for family, k, d, scene, rig, left, right, perception, arm, base in draws([family], n, seed0, noise, per, sys.argv[6:]):
    poly = scene.target_polygon
    r = sf.decided(perception, left, right, base)
    what = sf.outcome(scene, r, rig)
    if what == "correct":
        continue
    sel = r.selection
    if sel is None or not sel.objects:
        print(f"{family} {k:2d} d{d} {what} {r.status} no selection", flush=True)
        continue
    on = []
    for i, o in enumerate(sel.objects):
        px = rig.to_original(r.candidates.left_px[list(o.members)], "left")
        share = np.mean([cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in px])
        on.append(share)
    on = np.array(on)
    tmass = float(sel.scores[on > 0].sum()) if np.any(on > 0) else 0.0
    best = int(np.argmax(sel.scores))
    print(f"{family} {k:2d} d{d} {what:15s} {r.status:14s} chosen P {sel.scores[best]:.2f} (on placard {on[best]:.2f}) "
          f"placard's objects {int(np.sum(on > 0))} P {tmass:.2f} none {sel.none_probability:.2f}", flush=True)
