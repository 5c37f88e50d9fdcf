import sys, tempfile
from pathlib import Path
import numpy as np, cv2
from scipy.spatial import cKDTree
sys.path.insert(0, "tests/perception")
import scene_families as sf
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), "line_of_sight", 20, 2900)):
        if k != 19: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        pose.provide(sf.noisy(scene.frame.meta["keypoints_truth"], 2.0, np.random.default_rng(2919)))
        r = sf.decided(perception, left, right, base)
        o = r.selection.objects[0]
        mem = np.array(o.members)
        px = r.candidates.left_px[mem]; z = r.candidates_xyz_m[mem, 2]
        orig = rig.to_original(px, "left")
        pl = scene.frame.meta["placards"]
        lab = np.zeros(len(mem), int)
        for pid in (2, 3):
            poly = np.asarray(pl[pid]["left_polygon_px"], np.float32)
            lab[np.array([cv2.pointPolygonTest(poly, (float(x), float(y)), True) >= -3.0 for x, y in orig])] = pid
        pairs = cKDTree(px).query_pairs(20.0, output_type="ndarray")
        dz = np.abs(z[pairs[:, 0]] - z[pairs[:, 1]]); pairs = pairs[dz <= 0.05]
        cross = pairs[lab[pairs[:, 0]] != lab[pairs[:, 1]]]
        for a, b in cross:
            print("cross", lab[a], lab[b], np.round(px[a]), np.round(px[b]), "d %.1f" % np.linalg.norm(px[a]-px[b]))
        print("labels", {p: int((lab == p).sum()) for p in (0, 2, 3)})
