import sys, tempfile
from pathlib import Path
import numpy as np, cv2
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.corridor import _pieces, _clip_box, _polygon_mask
from dip3d_vehicle.perception.joint_stereo import _grey
fam, n, seed, K = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed)):
        if k != K: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        L, R = rig.rectify_pair(scene.frame.left, scene.frame.right) if hasattr(rig, "rectify_pair") else (None, None)
        truth = scene.frame.meta["keypoints_truth"]
        pose.provide(sf.noisy(truth, 0.0, np.random.default_rng(0)))
        est = perception.estimate_arm(left, right)
        poly = perception.corridor.wedge(est, left.shape[1], left.shape[0], rig)
        tgt = rig.to_rectified(scene.target_polygon.reshape(-1, 2).astype(float), "left").mean(0)
        print("target", tgt.round(1), "in wedge", cv2.pointPolygonTest(poly.astype(np.float32).reshape(-1,1,2), tuple(map(float, tgt)), True))
        bf = perception.blobs
        resp = bf.responses(left, poly)
        d = np.hypot(resp[:, 0] - tgt[0], resp[:, 1] - tgt[1]) if len(resp) else np.array([])
        print("responses", len(resp), "nearest to target", (resp[np.argmin(d)] if len(d) else None), "dist", d.min() if len(d) else None)
        # raw DoG at target, and the wedge level
        x, y = int(tgt[0]), int(tgt[1])
        g = _grey(left)
        patch = g[y-12:y+13, x-12:x+13]
        print("target patch grey min/max/mean", patch.min(), patch.max(), patch.mean().round(1), "centre", g[y-2:y+3, x-2:x+3].mean().round(1))
        for piece in _pieces(poly, 4):
            box = _clip_box(piece, left.shape[1], left.shape[0], margin_px=15)
            if box is None: continue
            x0, y0, x1, y1 = box
            if not (x0 <= x < x1 and y0 <= y < y1): continue
            kk = 0.5
            grey = cv2.resize(_grey(left[y0:y1, x0:x1]), None, fx=kk, fy=kk, interpolation=cv2.INTER_AREA)
            dog = cv2.GaussianBlur(grey, (0, 0), 1.0) - cv2.GaussianBlur(grey, (0, 0), 2.5)
            inside = cv2.resize(_polygon_mask(piece, box), (dog.shape[1], dog.shape[0]), interpolation=cv2.INTER_NEAREST) > 0
            vals = dog[inside]
            noise = 1.4826 * float(np.median(np.abs(vals - np.median(vals))))
            ty, tx = int((y - y0) * kk), int((x - x0) * kk)
            print("piece box", box, "noise", round(noise, 3), "level", round(max(6 * noise, 2.5), 3), "dog at target", dog[ty-1:ty+2, tx-1:tx+2].round(2).tolist(), "inside", inside[ty, tx])
