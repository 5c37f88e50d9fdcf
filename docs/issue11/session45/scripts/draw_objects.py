import sys, tempfile
from pathlib import Path
import numpy as np, cv2
from scipy.spatial import cKDTree
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, K, D = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if k != K: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        truth = scene.frame.meta["keypoints_truth"]
        rng = np.random.default_rng(seed0 + k)
        for d in range(D + 1):
            pose.provide(sf.noisy(truth, 2.0, rng))
        r = sf.decided(perception, left, right, base)
        sel = r.selection
        poly = scene.target_polygon
        for i, o in enumerate(sel.objects):
            px = rig.to_original(r.candidates.left_px[list(o.members)], "left")
            share = np.mean([cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in px])
            print(i, "P %.2f" % sel.scores[i], "on %.2f" % share, "n", len(o.members), "xyz", np.round(o.xyz_m, 2), "dsig %.2f" % o.depth_sigma_m,
                  "px box", np.round(r.candidates.left_px[list(o.members)].min(0)), np.round(r.candidates.left_px[list(o.members)].max(0)))
        on = [i for i, o in enumerate(sel.objects) if np.mean([cv2.pointPolygonTest(poly, tuple(map(float, p)), False) >= 0 for p in rig.to_original(r.candidates.left_px[list(o.members)], "left")]) > 0]
        for a in on:
            for b in on:
                if a < b:
                    pa, pb = r.candidates_xyz_m[list(sel.objects[a].members)], r.candidates_xyz_m[list(sel.objects[b].members)]
                    print("pair", a, b, "min 3D gap %.3f" % cKDTree(pa).query(pb)[0].min())
        print("outcome", sf.outcome(scene, r, rig), "target", sel.target.left_px if sel.target is not None else None, "conf %.2f" % sel.confidence, r.status)
        print("arm3d", np.round(r.arm3d.xyz_m, 2).tolist(), "arm left px", np.round(r.arm.left_px).tolist(), "head", r.arm.extra_left_px)
        print("placards", [(p.get("id"), p.get("range_m", None)) for p in scene.frame.meta.get("placards", [])][:8] if isinstance(scene.frame.meta.get("placards"), list) else list(scene.frame.meta.keys()))
